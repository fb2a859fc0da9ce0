// The --overview picture of `meshtour path` (tour/path_overview.h): the bounding cylinder, the
// scene of model plus coloured tubes, and a tiny render of it: the size asked for, not blank, the
// same pixels every time.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <set>
#include <tuple>

#include "test_meshes.h"
#include "tour/path_overview.h"

namespace {

using namespace meshtour;

// A level circle of radius 3 around the origin at height 0.5, looking at the origin.
class CirclePath final : public CameraPath {
public:
  CameraPose pose(double t) const override {
    const double a = 2.0 * std::numbers::pi * t;
    return {Eigen::Vector3d(3.0 * std::sin(a), 0.5, 3.0 * std::cos(a)), Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY()};
  }
};

// The same circle looking at a point that moves: the gaze path is a loop, not a point.
class WanderingGazePath final : public CameraPath {
public:
  CameraPose pose(double t) const override {
    const double a = 2.0 * std::numbers::pi * t;
    return {Eigen::Vector3d(3.0 * std::sin(a), 0.5, 3.0 * std::cos(a)), Eigen::Vector3d(0.0, 0.3 * std::sin(a), 0.0),
            Eigen::Vector3d::UnitY()};
  }
};

TEST(TourPathOverview, BoundingCylinderHoldsEveryVertexTightly) {
  // A box 2 wide (x), 4 tall (y), 1 deep (z), centred at (10, 20, 30).
  TriangleMesh box;
  for (int k = 0; k < 8; ++k)
    box.positions.emplace_back(10.0 + ((k & 1) ? 1.0 : -1.0), 20.0 + ((k & 2) ? 2.0 : -2.0), 30.0 + ((k & 4) ? 0.5 : -0.5));
  box.triangles = {{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1}, {2, 3, 7}, {2, 7, 6}};
  const OverviewCylinder up_y = bounding_cylinder(box, Eigen::Vector3d(0, 3, 0));
  EXPECT_TRUE(up_y.up.isApprox(Eigen::Vector3d::UnitY()));
  EXPECT_TRUE(up_y.base_center.isApprox(Eigen::Vector3d(10, 18, 30)));
  EXPECT_NEAR(up_y.height, 4.0, 1e-12);
  EXPECT_NEAR(up_y.radius, std::sqrt(1.0 + 0.25), 1e-12);
  const OverviewCylinder up_x = bounding_cylinder(box, -Eigen::Vector3d::UnitX());
  EXPECT_TRUE(up_x.base_center.isApprox(Eigen::Vector3d(11, 20, 30)));
  EXPECT_NEAR(up_x.height, 2.0, 1e-12);
  EXPECT_NEAR(up_x.radius, std::sqrt(4.0 + 0.25), 1e-12);
}

TEST(TourPathOverview, SceneIsTheModelPlusColouredTubes) {
  const TriangleMesh sphere = test_meshes::icosphere(2);
  const CirclePath path;
  const OverviewCylinder cylinder = bounding_cylinder(sphere, Eigen::Vector3d::UnitY());
  const TriangleMesh scene = overview_scene(sphere, path, cylinder, 90);
  // The model comes first, unchanged; everything added has a colour per vertex.
  ASSERT_GT(scene.triangles.size(), sphere.triangles.size());
  for (std::size_t f = 0; f < sphere.triangles.size(); ++f) ASSERT_EQ(scene.triangles[f], sphere.triangles[f]);
  for (std::size_t v = 0; v < sphere.positions.size(); ++v) ASSERT_EQ(scene.positions[v], sphere.positions[v]);
  ASSERT_EQ(scene.colors.size(), scene.positions.size());
  for (const auto& t : scene.triangles)
    for (const std::uint32_t v : t) ASSERT_LT(v, scene.positions.size());
  // The position path (magenta) runs around the eyes' circle: its vertices lie within a tube's
  // width of radius 3 at height 0.5.
  const Eigen::Vector3f magenta(0.9f, 0.2f, 0.85f);
  int on_path = 0;
  for (std::size_t v = sphere.positions.size(); v < scene.positions.size(); ++v) {
    if (!scene.colors[v].isApprox(magenta)) continue;
    const Eigen::Vector3d& p = scene.positions[v];
    EXPECT_NEAR(std::hypot(p.x(), p.z()), 3.0, 0.1);
    EXPECT_NEAR(p.y(), 0.5, 0.1);
    ++on_path;
  }
  EXPECT_GE(on_path, 90);
  // More path samples, more tube; the same inputs, the same scene.
  EXPECT_GT(overview_scene(sphere, path, cylinder, 180).triangles.size(), scene.triangles.size());
  const TriangleMesh again = overview_scene(sphere, path, cylinder, 90);
  EXPECT_EQ(again.positions, scene.positions);
  EXPECT_EQ(again.triangles, scene.triangles);
  // A moving gaze is drawn as a tube rather than a ball: more geometry.
  EXPECT_GT(overview_scene(sphere, WanderingGazePath(), cylinder, 90).triangles.size(), scene.triangles.size());
}

TEST(TourPathOverview, TinyRenderHasTheSizeAskedForIsNotBlankAndRepeats) {
  const TriangleMesh sphere = test_meshes::icosphere(2);
  const CirclePath path;
  const OverviewCylinder cylinder = bounding_cylinder(sphere, Eigen::Vector3d::UnitY());
  const Image image = render_overview(sphere, path, cylinder, 48, 36, 1);
  ASSERT_EQ(image.width, 48);
  ASSERT_EQ(image.height, 36);
  ASSERT_EQ(image.rgba.size(), 48u * 36u * 4u);
  std::set<std::tuple<float, float, float>> colours;
  for (std::size_t p = 0; p < image.rgba.size(); p += 4) colours.emplace(image.rgba[p], image.rgba[p + 1], image.rgba[p + 2]);
  EXPECT_GT(colours.size(), 20u) << "the overview is (nearly) one colour";
  const Image again = render_overview(sphere, path, cylinder, 48, 36, 1);
  EXPECT_EQ(again.rgba, image.rgba);
}

}  // namespace
