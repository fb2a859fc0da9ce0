// Action-safe framing: at every frame of every path mode, at least 5 % of the frame's smaller side
// stays free between the model and each edge. Measured on what a viewer sees: the alpha of a
// plain (no ground, so no shadow in the alpha), transparent render, where any pixel the model
// touches (alpha above 0, the pixel filter's soft edge included) counts as the model.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <ostream>
#include <string>

#include "helpers.h"
#include "scenes/scene_options.h"
#include "tour/tour.h"

namespace {

using namespace meshtour;

// The narrowest gap between the model's pixels and an edge of `image`, in shares of its smaller
// side; 0.5 for an empty image.
double narrowest_gap(const Image& image) {
  int left = image.width, right = -1, top = image.height, bottom = -1;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      if (image.rgba[(static_cast<std::size_t>(y) * image.width + x) * 4 + 3] > 0.0f) {
        left = std::min(left, x);
        right = std::max(right, x);
        top = std::min(top, y);
        bottom = std::max(bottom, y);
      }
  if (right < 0) return 0.5;
  const int gap = std::min({left, image.width - 1 - right, top, image.height - 1 - bottom});
  return static_cast<double>(gap) / std::min(image.width, image.height);
}

struct Case {
  std::string mesh, mode, size;
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.mesh << " " << c.mode << " " << c.size; }

class ActionSafe : public ::testing::TestWithParam<Case> {};

TEST_P(ActionSafe, EveryFrameKeepsFivePercentOfTheSmallerSideFree) {
  MESHTOUR_SKIP_UNDER_SANITIZERS("path searches and 720p renders; the Release pass measures the framing");
  const Case& c = GetParam();
  MESHTOUR_SHARED_MESH(mesh, c.mesh);
  const Scene scene = resolve_scene(mesh.string(), {{"size", c.size},
                                                    {"frame-count", "8"},
                                                    {"path", c.mode},
                                                    {"spp", "1"},
                                                    {"denoise", "off"},
                                                    {"preset", "plain"},
                                                    {"background", "transparent"}});
  const PreparedTour tour = prepare_tour(scene, true);
  double narrowest = 1.0;
  for (int k = 0; k < scene.frames; ++k) {
    const double gap = narrowest_gap(tour.render_frame(k));
    EXPECT_GE(gap, 0.05) << "frame " << k;
    narrowest = std::min(narrowest, gap);
  }
  std::printf("%s, %s, %s: narrowest gap %.2f %% of the smaller side\n", c.mesh.c_str(), c.mode.c_str(), c.size.c_str(), 100.0 * narrowest);
  // Not framed needlessly loose either: the model comes within 8 % of some edge.
  EXPECT_LT(narrowest, 0.08);
}

INSTANTIATE_TEST_SUITE_P(SharedMeshes, ActionSafe,
                         ::testing::Values(Case{"bunny.ply", "feature-orbit", "vertical-720"}, Case{"bunny.ply", "paper", "720p"},
                                           Case{"bunny.ply", "turntable", "square"}, Case{"horse.ply", "feature-orbit", "720p"},
                                           Case{"horse.ply", "paper", "vertical-720"}, Case{"horse.ply", "turntable", "720p"}),
                         [](const auto& info) {
                           std::string name = info.param.mesh.substr(0, info.param.mesh.find('.')) + "_" + info.param.mode + "_" + info.param.size;
                           std::erase(name, '-');
                           return name;
                         });

}  // namespace
