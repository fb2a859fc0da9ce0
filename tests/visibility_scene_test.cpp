// The visibility module (visibility/visibility.h) on its own: which sample points a view sees,
// with hand-placed points whose answer is known (in front of a plane, behind it, outside the
// frame, behind the eye, grazing), a convex shape seen from far away (exactly the faces turned
// to the eye), the same answer for any thread count and for a surface far from the origin, the
// stride as an exact subset, and the refusals the header promises.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "core/error.h"
#include "test_meshes.h"
#include "visibility/visibility.h"

namespace {

using namespace meshtour;

View view_from(const Eigen::Vector3d& eye, const Eigen::Vector3d& target = Eigen::Vector3d::Zero(), double fov = 40.0,
               double aspect = 1.0) {
  return View{Camera{eye, target, Eigen::Vector3d::UnitY(), fov}, aspect};
}

// Samples placed by hand: visible() reads only the points and their normals.
SurfaceSamples samples_at(const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& points_and_normals) {
  SurfaceSamples s;
  for (const auto& [point, normal] : points_and_normals) {
    s.points.push_back(point);
    s.normals.push_back(normal.normalized());
    s.faces.push_back(0);
    s.barycentric.emplace_back(1.0 / 3.0, 1.0 / 3.0);
  }
  s.area_per_sample = 1.0;
  return s;
}

// The unit cube centred at the origin, 12 outward triangles.
TriangleMesh cube() {
  TriangleMesh m;
  for (int k = 0; k < 8; ++k) m.positions.emplace_back((k & 1) - 0.5, ((k >> 1) & 1) - 0.5, ((k >> 2) & 1) - 0.5);
  m.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                 {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  return m;
}

// A unit sphere (icosphere) and a square plate in front of it, between it and +z: a scene in
// which occlusion decides much of the answer.
TriangleMesh sphere_behind_plate() {
  TriangleMesh m = test_meshes::icosphere(4);
  const auto base = static_cast<std::uint32_t>(m.positions.size());
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(-0.6, -0.6, 1.5), Eigen::Vector3d(0.6, -0.6, 1.5), Eigen::Vector3d(0.6, 0.6, 1.5),
                                  Eigen::Vector3d(-0.6, 0.6, 1.5)})
    m.positions.push_back(p);
  m.triangles.push_back({base, base + 1, base + 2});
  m.triangles.push_back({base, base + 2, base + 3});
  return m;
}

TEST(VisibilityScene, HandPlacedPointsInFrontBehindOutsideAndGrazing) {
  // The plane z = 0 over [-0.5, 0.5]², seen from 3 units above its centre.
  const TriangleMesh plane = test_meshes::plane(4);
  const VisibilityScene scene(plane);
  const Eigen::Vector3d up_z = Eigen::Vector3d::UnitZ();
  const SurfaceSamples samples = samples_at({
      {{0.1, 0.1, 0.0}, up_z},                        // 0: on the plane, facing the eye: seen
      {{0.0, 0.0, -1.0}, up_z},                       // 1: behind the plane, straight under the eye: hidden
      {{0.2, 0.0, 0.0}, -up_z},                       // 2: on the plane, normal away from the eye: seen (either side counts)
      {{0.0, 0.0, 1.0}, up_z},                        // 3: in front of the plane: seen
      {{0.0, 0.0, 4.0}, up_z},                        // 4: behind the eye: not seen
      {{1.5, 0.0, 0.0}, up_z},                        // 5: outside the 40° frame: not seen
      {{0.3, 0.3, 0.0}, Eigen::Vector3d::UnitX()},    // 6: grazing (|cos| about 0.1): seen only within 89°
      {{0.0, 0.9, -1.0}, up_z},                       // 7: behind the plane's level but its ray to the eye passes beside it: seen
  });
  const View view = view_from({0, 0, 3});

  const VisibleSamples wide = scene.visible(view, samples, 89.0);
  EXPECT_EQ(wide.samples, (std::vector<std::uint32_t>{0, 2, 3, 6, 7}));
  ASSERT_EQ(wide.cosines.size(), wide.samples.size());
  // |cos| of the angle between the normal and the direction to the eye.
  const auto expected_cosine = [&](std::uint32_t i) {
    const Eigen::Vector3d to_eye = view.camera.eye - samples.points[i];
    return std::abs(samples.normals[i].dot(to_eye)) / to_eye.norm();
  };
  for (std::size_t k = 0; k < wide.samples.size(); ++k)
    EXPECT_NEAR(wide.cosines[k], expected_cosine(wide.samples[k]), 1e-6) << "sample " << wide.samples[k];

  // A stricter angle drops the grazing sample and keeps the others with the same cosines.
  const VisibleSamples strict = scene.visible(view, samples, 60.0);
  EXPECT_EQ(strict.samples, (std::vector<std::uint32_t>{0, 2, 3, 7}));

  // Seen from below, the plane hides what was in front of it and shows what was behind it.
  const VisibleSamples below = scene.visible(view_from({0, 0, -3}), samples, 89.0);
  EXPECT_TRUE(std::find(below.samples.begin(), below.samples.end(), 1u) != below.samples.end());
  EXPECT_TRUE(std::find(below.samples.begin(), below.samples.end(), 3u) == below.samples.end());
}

TEST(VisibilityScene, ConvexShapeSeenFromFarShowsExactlyTheFacesTurnedToTheEye) {
  // A cube from far away along (1, 2, 3): the three faces turned to the eye are seen, the three
  // others are hidden by the cube itself, so half of the area-spread samples are seen.
  const TriangleMesh mesh = cube();
  const SurfaceSamples samples = sample_surface(mesh, 6000);
  const VisibilityScene scene(mesh);
  const Eigen::Vector3d eye = 1000.0 * Eigen::Vector3d(1, 2, 3).normalized();
  const VisibleSamples seen = scene.visible(view_from(eye, Eigen::Vector3d::Zero(), 1.0), samples, 90.0);
  // A sample is on every face whose plane it lies in (one, or two on an edge: sample 0 is the
  // midpoint of an edge), and seen when one of those faces is turned to the eye.
  std::vector<std::uint32_t> facing;
  for (std::uint32_t i = 0; i < samples.size(); ++i) {
    const Eigen::Vector3d& p = samples.points[i];
    bool turned = false;
    for (int axis = 0; axis < 3; ++axis)
      if (std::abs(p[axis]) > 0.5 - 1e-12) turned = turned || std::copysign(1.0, p[axis]) * (eye[axis] - p[axis]) > 0.0;
    if (turned) facing.push_back(i);
  }
  EXPECT_EQ(seen.samples, facing);
  EXPECT_NEAR(static_cast<double>(seen.samples.size()) / static_cast<double>(samples.size()), 0.5, 0.002);

  // A sphere from 100 radii away: the cap seen is (1 - 1/100) / 2 of its surface.
  const TriangleMesh sphere = test_meshes::icosphere(4);
  const SurfaceSamples sphere_samples = sample_surface(sphere, 1u << 14);
  const VisibleSamples sphere_seen =
      VisibilityScene(sphere).visible(view_from({0, 0, 100}, Eigen::Vector3d::Zero(), 2.0), sphere_samples, 90.0);
  EXPECT_NEAR(static_cast<double>(sphere_seen.samples.size()) / static_cast<double>(sphere_samples.size()), 0.495, 0.01);
  for (std::uint32_t i : sphere_seen.samples) ASSERT_GT(sphere_samples.points[i].z(), 0.0) << "a far-side sample was seen";
}

TEST(VisibilityScene, SameSamplesAndCosinesForOneAndTwoThreads) {
  // 2^15 samples: 16 blocks of the parallel loop, which must come back in sample order.
  const TriangleMesh mesh = sphere_behind_plate();
  const SurfaceSamples samples = sample_surface(mesh, 1u << 15);
  const View view = view_from({1.0, 0.5, 4.0}, Eigen::Vector3d::Zero(), 50.0, 16.0 / 9.0);
  const auto visible_with = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    const VisibilityScene scene(mesh);
    return scene.visible(view, samples, 80.0);
  };
  const VisibleSamples one = visible_with(1), two = visible_with(2);
  EXPECT_EQ(one.samples, two.samples);
  EXPECT_EQ(one.cosines, two.cosines);
  EXPECT_TRUE(std::is_sorted(two.samples.begin(), two.samples.end()));
  EXPECT_TRUE(std::adjacent_find(two.samples.begin(), two.samples.end()) == two.samples.end()) << "a sample listed twice";
  // The scene has something to agree on: part of the sphere is seen, part hidden by the plate.
  EXPECT_GT(two.samples.size(), samples.size() / 10);
  EXPECT_LT(two.samples.size(), samples.size() / 2);
}

TEST(VisibilityScene, AStrideTestsExactlyEveryStrideThSample) {
  const TriangleMesh mesh = sphere_behind_plate();
  const SurfaceSamples samples = sample_surface(mesh, 10000);  // not a multiple of the block size
  const VisibilityScene scene(mesh);
  const View view = view_from({0.5, 1.0, 4.0});
  const VisibleSamples all = scene.visible(view, samples, 75.0);
  for (const std::size_t stride : {2u, 8u, 64u, 2048u}) {
    VisibleSamples expected;
    for (std::size_t k = 0; k < all.samples.size(); ++k)
      if (all.samples[k] % stride == 0) {
        expected.samples.push_back(all.samples[k]);
        expected.cosines.push_back(all.cosines[k]);
      }
    const VisibleSamples strided = scene.visible(view, samples, 75.0, stride);
    EXPECT_EQ(strided.samples, expected.samples) << "stride " << stride;
    EXPECT_EQ(strided.cosines, expected.cosines) << "stride " << stride;
  }
}

// sample_surface() lists the samples along a Z-order curve for tracing (SurfaceSamples::trace),
// for speed only: every stride's list holds each of its samples once, and visible() gives the
// very same answer, in sample order, as it gives tracing in index order.
TEST(VisibilityScene, TheTraceOrderChangesNothingButTheSpeed) {
  const TriangleMesh mesh = sphere_behind_plate();
  const SurfaceSamples samples = sample_surface(mesh, 10000);
  ASSERT_EQ(samples.trace.size(), 7u);
  for (std::size_t k = 0; k < samples.trace.size(); ++k) {
    std::vector<std::uint32_t> listed;
    for (const auto& t : samples.trace[k]) {
      listed.push_back(t.index);
      EXPECT_EQ(t.point, samples.points[t.index]);
      EXPECT_EQ(t.normal, samples.normals[t.index]);
    }
    std::sort(listed.begin(), listed.end());
    std::vector<std::uint32_t> expected;
    for (std::uint32_t i = 0; i < samples.size(); i += 1u << k) expected.push_back(i);
    EXPECT_EQ(listed, expected) << "stride " << (1u << k);
  }
  SurfaceSamples in_index_order = samples;
  in_index_order.trace.clear();
  const VisibilityScene scene(mesh);
  for (const Eigen::Vector3d& eye : {Eigen::Vector3d(0.5, 1.0, 4.0), Eigen::Vector3d(-3.0, 0.2, -2.0)})
    for (const std::size_t stride : {1u, 4u, 64u}) {
      const View view = view_from(eye);
      const VisibleSamples traced = scene.visible(view, samples, 75.0, stride), plain = scene.visible(view, in_index_order, 75.0, stride);
      EXPECT_EQ(traced.samples, plain.samples) << "stride " << stride;
      EXPECT_EQ(traced.cosines, plain.cosines) << "stride " << stride;
      EXPECT_EQ(traced.front, plain.front) << "stride " << stride;
      EXPECT_GT(plain.samples.size(), samples.size() / stride / 10);
    }
}

TEST(VisibilityScene, ASurfaceFarFromTheOriginDoesNotHideItself) {
  // A tilted plane a million units from the origin: in float the samples would sit up to 0.06
  // units off the surface, far more than the ray's clearance, were the scene not stored
  // relative to its centre.
  const Eigen::Matrix3d tilt = test_meshes::rotation(Eigen::Vector3d(1, 2, 0), 0.7);
  const Eigen::Vector3d far(1.0e6, -2.0e6, 5.0e5);
  const TriangleMesh mesh = test_meshes::transformed(test_meshes::plane(8), 1.0, tilt, far);
  const SurfaceSamples samples = sample_surface(mesh, 4096);
  const VisibilityScene scene(mesh);
  const Eigen::Vector3d normal = tilt * Eigen::Vector3d::UnitZ();
  for (const double side : {1.0, -1.0}) {
    const View view{Camera{far + side * 3.0 * normal, far, tilt * Eigen::Vector3d::UnitY(), 40.0}, 1.0};
    EXPECT_EQ(scene.visible(view, samples, 89.0).samples.size(), samples.size()) << "seen from side " << side;
  }
}

TEST(VisibilityScene, EmptyAndDegenerateInputs) {
  // No triangles: nothing to build.
  EXPECT_THROW(VisibilityScene(TriangleMesh{}), InputError);

  const TriangleMesh plane = test_meshes::plane(2);
  const VisibilityScene scene(plane);
  EXPECT_NEAR(scene.diagonal(), std::sqrt(2.0), 1e-12);
  const View view = view_from({0, 0, 3});

  // No samples: nothing seen.
  const VisibleSamples none = scene.visible(view, SurfaceSamples{}, 60.0);
  EXPECT_TRUE(none.samples.empty());
  EXPECT_TRUE(none.cosines.empty());

  // The seen-well angle must be in (0, 90], the aspect positive, the stride a divisor of 2048.
  const SurfaceSamples one = samples_at({{{0, 0, 0}, Eigen::Vector3d::UnitZ()}});
  for (const double angle : {0.0, -10.0, 90.5, std::numeric_limits<double>::quiet_NaN()})
    EXPECT_THROW(scene.visible(view, one, angle), InputError) << angle;
  EXPECT_EQ(scene.visible(view, one, 90.0).samples.size(), 1u);
  for (const double aspect : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN()})
    EXPECT_THROW(scene.visible(view_from({0, 0, 3}, Eigen::Vector3d::Zero(), 40.0, aspect), one, 60.0), InputError) << aspect;
  for (const std::size_t stride : {0u, 3u, 4096u}) EXPECT_THROW(scene.visible(view, one, 60.0, stride), InputError) << stride;

  // A sample at the eye itself has no direction to be seen from: not seen, no NaN cosine.
  const SurfaceSamples at_eye = samples_at({{{0, 0, 3}, Eigen::Vector3d::UnitZ()}});
  EXPECT_TRUE(scene.visible(view, at_eye, 89.0).samples.empty());

  // Faces without area (collinear corners, a corner at NaN) get no samples; the others get all.
  TriangleMesh mixed;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  mixed.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {nan, 0, 0}};
  mixed.triangles = {{0, 1, 2}, {0, 1, 3}, {4, 1, 3}};
  const SurfaceSamples s = sample_surface(mixed, 500);
  ASSERT_EQ(s.size(), 500u);
  EXPECT_TRUE(std::all_of(s.faces.begin(), s.faces.end(), [](std::uint32_t f) { return f == 1; }));
  EXPECT_DOUBLE_EQ(s.area_per_sample, 0.5 / 500.0);
  for (const auto& p : s.points) EXPECT_TRUE(p.allFinite());
}

}  // namespace
