// A seamless loop at any --fps: the tour's view turns by the same angle from each frame to the
// next, the last frame to the first included, in every path mode. Measured on the camera path of a
// vertical 1080x1920, 60 fps tour (no frame is rendered).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdio>
#include <numbers>
#include <string>

#include "helpers.h"
#include "scenes/scene_options.h"
#include "tour/tour.h"

namespace {

using namespace meshtour;

struct Steps {
  double smallest = 1e9, largest = 0.0, mean = 0.0;
};

Steps view_steps(const CameraPath& path, int frames) {
  Steps s;
  const auto view = [&](int k) {
    const CameraPose p = frame_pose(path, k % frames, frames);
    return Eigen::Vector3d(p.target - p.eye).normalized();
  };
  Eigen::Vector3d a = view(0);
  for (int k = 0; k < frames; ++k) {
    const Eigen::Vector3d b = view(k + 1);  // k + 1 = frames: back to frame 0
    const double angle = std::atan2(a.cross(b).norm(), a.dot(b));
    s.smallest = std::min(s.smallest, angle);
    s.largest = std::max(s.largest, angle);
    s.mean += angle / frames;
    a = b;
  }
  return s;
}

class VerticalLoop : public ::testing::TestWithParam<std::string> {};

// Measured on the built-in sculpture, 600 frames: (largest - smallest) / mean step below 0.00005
// in all three modes (mean steps 0.591, 0.571 and 0.601 degrees: feature orbit, turntable, paper).
TEST_P(VerticalLoop, ViewTurnsEvenlyAllAroundTheLoop) {
  MESHTOUR_SKIP_UNDER_SANITIZERS("a 600-frame path search of the built-in scene; the Release pass measures it");
  const Scene scene =
      resolve_scene("", {{"size", "vertical"}, {"fps", "60"}, {"seconds", "10"}, {"path", GetParam()}, {"spp", "1"}});
  ASSERT_EQ(scene.render.width, 1080);
  ASSERT_EQ(scene.render.height, 1920);
  ASSERT_EQ(scene.frames, 600);
  const PreparedTour tour = prepare_tour(scene, true);
  const Steps s = view_steps(*tour.path, scene.frames);
  const double spread = (s.largest - s.smallest) / s.mean;
  std::printf("%s: steps %.5f .. %.5f degrees, mean %.5f; spread %.4f\n", GetParam().c_str(), s.smallest * 180 / std::numbers::pi,
              s.largest * 180 / std::numbers::pi, s.mean * 180 / std::numbers::pi, spread);
  EXPECT_LT(spread, 0.10);
  EXPECT_GT(s.mean * scene.frames, 0.5);  // the view does turn (half a radian or more per loop)
}

INSTANTIATE_TEST_SUITE_P(EveryMode, VerticalLoop, ::testing::Values("feature-orbit", "turntable", "paper"),
                         [](const auto& info) {
                           std::string name = info.param;
                           std::erase(name, '-');
                           return name;
                         });

}  // namespace
