// UniformTurnPath: frames sampled evenly along a loop are equally many degrees apart, the last to
// the first included, whatever the wrapped path's own speed, and frame 0 stays where it was.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <vector>

#include "pathgen/camera_path.h"
#include "pathgen/feature_orbit.h"

namespace {

using namespace meshtour;
constexpr double kTwoPi = 2.0 * std::numbers::pi;

// An orbit that speeds up and slows down along its parameter (the azimuth runs ahead by up to
// 0.1 of a turn) and climbs and dips, looking at a point that moves: its view turns between
// about 0.4 and 1.8 times its mean rate.
class UnevenOrbit final : public CameraPath {
public:
  CameraPose pose(double t) const override {
    const double azimuth = kTwoPi * (t + 0.1 * std::sin(kTwoPi * t));
    const double elevation = 0.4 * std::sin(kTwoPi * t) + 0.15 * std::cos(2.0 * kTwoPi * t);
    const Eigen::Vector3d eye(3.0 * std::cos(elevation) * std::cos(azimuth), 3.0 * std::sin(elevation),
                              3.0 * std::cos(elevation) * std::sin(azimuth));
    const Eigen::Vector3d target(0.2 * std::cos(kTwoPi * t), 0.1 * std::sin(2.0 * kTwoPi * t), 0.0);
    return CameraPose{eye, target, Eigen::Vector3d::UnitY()};
  }
};

class StillCamera final : public CameraPath {
public:
  CameraPose pose(double t) const override {
    return CameraPose{Eigen::Vector3d(0, 0, 3.0 + 0.5 * std::sin(kTwoPi * t)), Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY()};
  }
};

struct Steps {
  double smallest = 1e9, largest = 0.0, mean = 0.0;
  double spread() const { return (largest - smallest) / mean; }  ///< (largest − smallest) / mean
};

// The angles between the view directions of consecutive frames of a loop of `frames`, the last
// to the first included (where the loop closes).
Steps view_steps(const CameraPath& path, int frames) {
  Steps s;
  const auto view = [&](int k) {
    const CameraPose p = frame_pose(path, k % frames, frames);
    return Eigen::Vector3d(p.target - p.eye).normalized();
  };
  for (int k = 0; k < frames; ++k) {
    const Eigen::Vector3d a = view(k), b = view(k + 1);
    const double angle = std::atan2(a.cross(b).norm(), a.dot(b));
    s.smallest = std::min(s.smallest, angle);
    s.largest = std::max(s.largest, angle);
    s.mean += angle / frames;
  }
  return s;
}

TEST(UniformTurn, FramesAreEquallyManyDegreesApartAtAnyFrameCount) {
  const Steps before = view_steps(UnevenOrbit(), 600);
  EXPECT_GT(before.spread(), 1.0) << "the test path must be uneven for the test to mean anything";
  const UniformTurnPath even(std::make_unique<UnevenOrbit>());
  EXPECT_GT(even.unevenness(), 1.5);
  // The turn is measured along the path, a step between frames as the chord angle: at 15 degrees a
  // step (24 frames) where the view curves they differ by 2.3 %; from 119 frames on, by under 1 %.
  for (const int frames : {24, 119, 600, 2400, 14400}) {
    const Steps after = view_steps(even, frames);
    std::printf("%d frames: step spread %.2e\n", frames, after.spread());
    EXPECT_LT(after.spread(), frames < 100 ? 0.05 : 0.01) << frames << " frames: steps " << after.smallest << " .. " << after.largest;
  }
}

TEST(UniformTurn, KeepsTheFirstFrameAndTheLoop) {
  const UnevenOrbit uneven;
  const UniformTurnPath even(std::make_unique<UnevenOrbit>());
  EXPECT_EQ(even.parameter(0.0), 0.0);
  EXPECT_LT((even.pose(0.0).eye - uneven.pose(0.0).eye).norm(), 1e-12);
  // Periodic: t and t + 1 give the same pose; the parameter rises with t.
  for (const double t : {0.1, 0.37, 0.5, 0.93}) {
    EXPECT_NEAR(even.parameter(t + 1.0), even.parameter(t) + 1.0, 1e-12);
    EXPECT_NEAR(even.parameter(t - 1.0), even.parameter(t) - 1.0, 1e-12);
  }
  double previous = -1.0;
  for (int k = 0; k <= 1000; ++k) {
    const double s = even.parameter(k / 1000.0);
    EXPECT_GT(s, previous);
    previous = s;
  }
  EXPECT_NEAR(previous, 1.0, 1e-12);
}

TEST(UniformTurn, LeavesAStillViewAsItIs) {
  const UniformTurnPath still(std::make_unique<StillCamera>());
  for (const double t : {0.0, 0.25, 0.6}) EXPECT_EQ(still.parameter(t), t);
}

// The feature orbit at constant azimuth speed turns its view unevenly when it climbs and dips;
// wrapped, its frames are evenly spaced, and the best view stays frame 0.
TEST(UniformTurn, EvensOutAClimbingFeatureOrbit) {
  FeatureOrbitGeometry g;
  g.elevation.base = 0.3;
  g.elevation.swing = 0.6;  // 34 degrees
  g.elevation.ripple = 0.2;
  g.elevation.ripple_phase = 0.1;
  g.start = 0.3;
  const FeatureOrbitPath orbit(g);
  const Steps before = view_steps(orbit, 600);
  const UniformTurnPath even(std::make_unique<FeatureOrbitPath>(g));
  const Steps after = view_steps(even, 600);
  EXPECT_GT(before.spread(), 0.3);
  EXPECT_LT(after.spread(), 0.01);
  EXPECT_LT((even.pose(0.0).eye - orbit.pose(0.0).eye).norm(), 1e-12);
  std::printf("feature orbit, 600 frames: step spread %.4f at constant azimuth speed, %.2e evened out\n", before.spread(),
              after.spread());
}

}  // namespace
