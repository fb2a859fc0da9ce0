// The coverage module (pathgen/coverage.h) and the visibility it stands on (visibility/): samples
// spread by area, occlusion and the seen-well angle on shapes with known answers, features that
// do not change when the same shape is tessellated more finely, and results that do not depend
// on the thread count.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include "core/error.h"
#include "mesh/vertex_clustering.h"
#include "pathgen/coverage.h"
#include "test_meshes.h"
#include "visibility/visibility.h"

namespace {

using namespace meshtour;

View view_from(const Eigen::Vector3d& eye, double fov = 40.0, double aspect = 1.0) {
  return View{Camera{eye, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY(), fov}, aspect};
}

TEST(Visibility, SamplesFollowTheAreaAndAreTheSameEveryTime) {
  TriangleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {3, 0, 1}, {0, 2, 1}};
  m.triangles = {{0, 1, 2}, {3, 4, 5}};  // areas 0.5 and 3
  const SurfaceSamples s = sample_surface(m, 7000);
  ASSERT_EQ(s.size(), 7000u);
  const auto second = std::count(s.faces.begin(), s.faces.end(), 1u);
  EXPECT_NEAR(static_cast<double>(second), 6000.0, 1.0);
  EXPECT_DOUBLE_EQ(s.area_per_sample, 3.5 / 7000.0);
  for (std::size_t i = 0; i < s.size(); ++i) {
    const Eigen::Vector2d& b = s.barycentric[i];
    EXPECT_TRUE(b.x() >= 0 && b.y() >= 0 && b.x() + b.y() <= 1.0 + 1e-12);
  }
  const SurfaceSamples again = sample_surface(m, 7000);
  EXPECT_EQ(again.points, s.points);
  EXPECT_THROW(sample_surface(m, 0), InputError);
  TriangleMesh flat;
  flat.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  flat.triangles = {{0, 1, 2}};
  EXPECT_THROW(sample_surface(flat, 10), InputError);
}

TEST(Visibility, SphereSeenWellCapMatchesTheAnalyticAngleAndHidesTheFarSide) {
  // A unit sphere seen from distance D: the seen-well cap has a closed form (test_meshes.h).
  const TriangleMesh mesh = test_meshes::icosphere(5);
  const double D = 4.0;
  const SurfaceSamples samples = sample_surface(mesh, 1u << 16);
  const VisibilityScene scene(mesh);
  for (double angle : {75.0, 60.0, 89.0}) {
    const VisibleSamples seen = scene.visible(view_from({0, 0, D}), samples, angle);
    const double share = static_cast<double>(seen.samples.size()) / static_cast<double>(samples.size());
    EXPECT_NEAR(share, test_meshes::sphere_seen_well_share(D, angle), 0.005) << angle;
    for (std::uint32_t i : seen.samples) ASSERT_GT(samples.points[i].z(), 0.0);
  }
  // Behind another object nothing is seen: a big plate between the eye and the sphere.
  TriangleMesh both = test_meshes::icosphere(4);
  const std::size_t sphere_faces = both.triangles.size();
  const auto base = static_cast<std::uint32_t>(both.positions.size());
  for (Eigen::Vector3d p : {Eigen::Vector3d(-3, -3, 2), Eigen::Vector3d(3, -3, 2), Eigen::Vector3d(3, 3, 2), Eigen::Vector3d(-3, 3, 2)})
    both.positions.push_back(p);
  both.triangles.push_back({base, base + 1, base + 2});
  both.triangles.push_back({base, base + 2, base + 3});
  const SurfaceSamples s2 = sample_surface(both, 1u << 14);
  const VisibleSamples hidden = VisibilityScene(both).visible(view_from({0, 0, 6}, 60.0), s2, 75.0);
  for (std::uint32_t i : hidden.samples) EXPECT_GE(s2.faces[i], sphere_faces) << "a sphere sample behind the plate was seen";
  EXPECT_FALSE(hidden.samples.empty());
}

TEST(Visibility, OutsideTheFrameIsNotSeen) {
  const TriangleMesh mesh = test_meshes::icosphere(4);
  const SurfaceSamples samples = sample_surface(mesh, 1u << 14);
  const VisibilityScene scene(mesh);
  // A narrow lens aimed at the sphere's centre sees only a small disc of it.
  const auto narrow = scene.visible(view_from({0, 0, 4}, 5.0), samples, 89.0);
  for (std::uint32_t i : narrow.samples) EXPECT_LT(std::hypot(samples.points[i].x(), samples.points[i].y()), 0.25);
  // A wide frame keeps what a tall one cuts off.
  const auto wide = scene.visible(view_from({0, 0, 2.2}, 40.0, 2.0), samples, 89.0);
  const auto tall = scene.visible(view_from({0, 0, 2.2}, 40.0, 0.5), samples, 89.0);
  EXPECT_GT(wide.samples.size(), tall.samples.size() + 100);
}

CoverageOptions fast_coverage_options() {
  CoverageOptions o;
  o.samples = 1u << 15;
  return o;
}

TEST(Coverage, GivenFeaturesAreCountedAndTheStricterAngleSeesLess) {
  const TriangleMesh mesh = test_meshes::icosphere(4);
  CoverageOptions options = fast_coverage_options();
  options.face_features.resize(mesh.triangles.size());
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) options.face_features[f] = mesh.positions[mesh.triangles[f][0]].z() > 0.5;
  const CoverageModel model(mesh, options);
  const ViewCoverage front = model.coverage(view_from({0, 0, 4}));
  const ViewCoverage back = model.coverage(view_from({0, 0, -4}));
  const CoverageScores f = model.scores(front), b = model.scores(back);
  EXPECT_GT(f.feature_share[0], 0.95);  // the cap around +z faces the front camera
  EXPECT_EQ(b.feature_share[0], 0.0);
  EXPECT_LT(f.surface_share[1], f.surface_share[0]);
  const ViewCoverage* both[] = {&front, &back};
  const CoverageScores u = model.scores(both);
  EXPECT_NEAR(u.surface_share[0], f.surface_share[0] + b.surface_share[0], 1e-12);  // disjoint halves
  EXPECT_GT(u.objective, f.objective);
  EXPECT_EQ(model.region_count(FeatureMeasure::patch_density), 1);
}

TEST(Coverage, FeatureRegionsAreConnectedParts) {
  const TriangleMesh mesh = test_meshes::icosphere(4);
  CoverageOptions options = fast_coverage_options();
  options.face_features.resize(mesh.triangles.size());
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
    options.face_features[f] = std::abs(mesh.positions[mesh.triangles[f][0]].y()) > 0.8;  // two polar caps
  const CoverageModel model(mesh, options);
  EXPECT_EQ(model.region_count(FeatureMeasure::patch_density), 2);
  const auto& region = model.sample_region(FeatureMeasure::patch_density);
  for (std::size_t i = 0; i < region.size(); ++i)
    if (region[i] >= 0) {
      const int expected = region[i];
      const bool top = model.samples().points[i].y() > 0;
      for (std::size_t j = i + 1; j < region.size(); ++j)
        if (region[j] >= 0 && (model.samples().points[j].y() > 0) == top) {
          ASSERT_EQ(region[j], expected);
        }
      break;
    }
}

// Features fixed by position (the same part of the shape in both tessellations): what views see
// of them must not depend on the tessellation, for every seen-well angle.
std::vector<std::uint8_t> features_above(const TriangleMesh& mesh, double height) {
  std::vector<std::uint8_t> f(mesh.triangles.size());
  for (std::size_t i = 0; i < f.size(); ++i) {
    const auto& t = mesh.triangles[i];
    f[i] = (mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]).y() / 3.0 > height;
  }
  return f;
}

TEST(Coverage, SameShapeFinerTessellationSameFiguresUnderEveryAngle) {
  const TriangleMesh coarse = test_meshes::bumpy_sphere(3);
  const TriangleMesh fine = test_meshes::split_at_midpoints(test_meshes::split_at_midpoints(coarse));
  CoverageOptions oa = fast_coverage_options(), ob = fast_coverage_options();
  oa.face_features = features_above(coarse, 0.3);
  ob.face_features = features_above(fine, 0.3);
  const CoverageModel a(coarse, oa), b(fine, ob);
  for (const Eigen::Vector3d& eye : {Eigen::Vector3d(0, 0, 4), Eigen::Vector3d(3, 2, 1), Eigen::Vector3d(-1, -3, 2)}) {
    const CoverageScores sa = a.scores(a.coverage(view_from(eye))), sb = b.scores(b.coverage(view_from(eye)));
    for (int d = 0; d < kFeatureDefinitions; ++d)
      EXPECT_NEAR(sa.feature_share[d], sb.feature_share[d], 0.01) << "definition " << d << " eye " << eye.transpose();
    for (int angle = 0; angle < kSeenAngles; ++angle) EXPECT_NEAR(sa.surface_share[angle], sb.surface_share[angle], 0.01);
  }
}

// The search's estimate: every stride-th sample is an even subset of the surface, so its shares
// are close to those on every sample, it tests only that subset, and views on different subsets
// are not mixed.
TEST(Coverage, AStrideEstimatesTheSharesOnASubsetOfTheSamples) {
  const TriangleMesh mesh = test_meshes::bumpy_sphere(3);
  CoverageOptions options = fast_coverage_options();
  options.face_features = features_above(mesh, 0.3);
  const CoverageModel model(mesh, options);
  for (const Eigen::Vector3d& eye : {Eigen::Vector3d(0, 0, 4), Eigen::Vector3d(3, 2, 1), Eigen::Vector3d(-1, -3, 2)}) {
    const ViewCoverage all = model.coverage(view_from(eye)), quarter = model.coverage(view_from(eye), 4);
    const CoverageScores sa = model.scores(all), sq = model.scores(quarter);
    for (int d = 0; d < kFeatureDefinitions; ++d) EXPECT_NEAR(sq.feature_share[d], sa.feature_share[d], 0.02) << "definition " << d;
    for (int angle = 0; angle < kSeenAngles; ++angle) {
      EXPECT_NEAR(sq.surface_share[angle], sa.surface_share[angle], 0.02);
      // The subset's bits are exactly the full set's bits at every 4th sample.
      for (std::size_t w = 0; w < all.seen[angle].size(); ++w)
        ASSERT_EQ(quarter.seen[angle][w], all.seen[angle][w] & 0x1111111111111111ull) << "word " << w;
    }
    const ViewCoverage* mixed[] = {&all, &quarter};
    EXPECT_THROW(model.scores(mixed), InputError);
  }
  EXPECT_THROW(model.coverage(view_from({0, 0, 4}), 3), InputError);
}

TEST(Coverage, ResultsDoNotDependOnTheThreadCount) {
  const TriangleMesh mesh = test_meshes::bumpy_sphere(3);
  std::vector<std::uint64_t> one_bits;
  std::vector<std::uint8_t> one_features;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    const CoverageModel model(mesh, fast_coverage_options());
    one_bits = model.coverage(view_from({1, 2, 3})).seen[0];
    one_features = model.features(FeatureMeasure::saliency);
  }
  const CoverageModel model(mesh, fast_coverage_options());
  EXPECT_EQ(model.coverage(view_from({1, 2, 3})).seen[0], one_bits);
  EXPECT_EQ(model.features(FeatureMeasure::saliency), one_features);
}

TEST(VertexClustering, CellsFollowTheAreaAndAFinerTessellationGivesTheSameProxy) {
  // The proxy is made of the surface (its area per cell and where it crosses the cell edges), not
  // of the input's vertices: the same sphere split twice (16 times the faces, 4 times the vertex
  // density) gives the same vertices, to rounding, and the same triangles.
  const TriangleMesh coarse = test_meshes::icosphere(4);
  const TriangleMesh fine = test_meshes::split_at_midpoints(test_meshes::split_at_midpoints(coarse));
  const ClusteredMesh a = cluster_surface(coarse, 300), b = cluster_surface(fine, 300);  // cells over twice the coarse edges
  EXPECT_NEAR(a.cell_size, b.cell_size, 1e-12 * a.cell_size);  // the same area: the same cells
  EXPECT_LT(a.mesh.positions.size(), coarse.positions.size());
  ASSERT_EQ(a.mesh.positions.size(), b.mesh.positions.size());
  for (std::size_t v = 0; v < a.mesh.positions.size(); ++v)
    ASSERT_LT((a.mesh.positions[v] - b.mesh.positions[v]).norm(), 1e-9 * a.cell_size) << "vertex " << v;
  EXPECT_EQ(a.mesh.triangles, b.mesh.triangles);
  for (const auto& p : b.mesh.positions) EXPECT_NEAR(p.norm(), 1.0, 0.5 * b.cell_size);  // stays on the sphere
  // A closed surface gives a closed proxy facing outwards: every edge in two triangles, opposite ways.
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const auto& t : a.mesh.triangles) {
    for (int e = 0; e < 3; ++e) ++directed[{t[e], t[(e + 1) % 3]}];
    const Eigen::Vector3d &p0 = a.mesh.positions[t[0]], &p1 = a.mesh.positions[t[1]], &p2 = a.mesh.positions[t[2]];
    EXPECT_GT((p1 - p0).cross(p2 - p0).dot(p0 + p1 + p2), 0.0);
  }
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(directed.count({edge.second, edge.first}), 1u);
  }
  for (std::size_t v = 0; v < fine.positions.size(); ++v)
    ASSERT_LT((fine.positions[v] - b.mesh.positions[b.vertex_near(fine.positions[v])]).norm(), 2.0 * b.cell_size);
}

// With the grid centred on the bounds (mesh/up_axis.cpp's flat-cut proxy), a mesh mirrored and
// turned by a signed permutation of its axes gets the same cells and the same proxy, turned. With
// the grid started at the bounds' corner, the cells shift by up to a cell under a mirror: --up auto
// then found a column's capital as a sawn base in two of its six orientations and not in the others.
TEST(VertexClustering, CentredGridTurnsWithTheMesh) {
  TriangleMesh mesh = test_meshes::icosphere(4);
  for (Eigen::Vector3d& p : mesh.positions) p = Eigen::Vector3d(1.3 * p.x() + 0.3 * p.y() * p.y(), 0.8 * p.y(), p.z() + 0.2 * p.x() * p.y());
  const Eigen::Matrix3d turn = (Eigen::Matrix3d() << 0, 0, -1, 1, 0, 0, 0, -1, 0).finished();  // a signed permutation
  TriangleMesh turned = mesh;
  for (Eigen::Vector3d& p : turned.positions) p = turn * p;
  for (const bool centred : {true, false}) {
    const ClusteredMesh a = cluster_surface(mesh, 400, centred), b = cluster_surface(turned, 400, centred);
    std::size_t matched = 0;
    for (const Eigen::Vector3d& p : a.mesh.positions) {
      const Eigen::Vector3d q = turn * p;
      matched += std::any_of(b.mesh.positions.begin(), b.mesh.positions.end(),
                             [&](const Eigen::Vector3d& r) { return (r - q).norm() < 1e-9 * a.cell_size; });
    }
    if (centred) {
      EXPECT_EQ(a.mesh.positions.size(), b.mesh.positions.size());
      EXPECT_EQ(a.mesh.triangles.size(), b.mesh.triangles.size());
      EXPECT_EQ(matched, a.mesh.positions.size());
    } else {
      EXPECT_LT(matched, a.mesh.positions.size() / 2) << "the corner-anchored grid was expected to move under the turn";
    }
  }
}

TEST(VertexClustering, SameBitsForAnyThreadCount) {
  const TriangleMesh mesh = test_meshes::icosphere(6);  // 81,920 faces: several chunks of faces
  ClusteredMesh one;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = cluster_surface(mesh, 5000);
  }
  const ClusteredMesh many = cluster_surface(mesh, 5000);
  EXPECT_EQ(one.mesh.positions, many.mesh.positions);
  EXPECT_EQ(one.mesh.triangles, many.mesh.triangles);
  EXPECT_EQ(one.cell_keys, many.cell_keys);
}

// The features themselves (patch density and saliency computed on the proxy, not given): the same
// shape split twice keeps its feature samples. Sample i lies in the same coarse face at both
// levels (the split keeps the face order and the area) but not at the same point of it, so the
// masks differ only where a sample moved across the top quartile's edge. With a proxy of the
// input's vertices (plain vertex clustering) the overlap here was 0.51 (patch density) and 0.56
// (saliency); on the bunny 0.40 and 0.78 after one split.
TEST(Coverage, SameShapeFinerTessellationSameComputedFeatures) {
  const TriangleMesh coarse = test_meshes::bumpy_sphere(4);
  const TriangleMesh fine = test_meshes::split_at_midpoints(test_meshes::split_at_midpoints(coarse));
  CoverageOptions options = fast_coverage_options();
  options.proxy_cells = 2000;  // cells of about twice the coarse edges
  const CoverageModel a(coarse, options), b(fine, options);
  // Achieved: 0.93 (patch density) and 0.89 (saliency), shares within 0.002.
  const std::pair<FeatureMeasure, double> least_overlap[] = {{FeatureMeasure::patch_density, 0.9}, {FeatureMeasure::saliency, 0.85}};
  for (const auto& [m, least] : least_overlap) {
    const auto &fa = a.features(m), &fb = b.features(m);
    ASSERT_EQ(fa.size(), fb.size());
    std::size_t both = 0, either = 0;
    for (std::size_t i = 0; i < fa.size(); ++i) {
      both += fa[i] && fb[i];
      either += fa[i] || fb[i];
    }
    ASSERT_GT(either, 0u);
    EXPECT_GT(static_cast<double>(both) / static_cast<double>(either), least) << "measure " << static_cast<int>(m);
  }
  for (const Eigen::Vector3d& eye : {Eigen::Vector3d(0, 0, 4), Eigen::Vector3d(3, 2, 1), Eigen::Vector3d(-1, -3, 2)}) {
    const CoverageScores sa = a.scores(a.coverage(view_from(eye))), sb = b.scores(b.coverage(view_from(eye)));
    for (int d = 0; d < kFeatureDefinitions; ++d)
      EXPECT_NEAR(sa.feature_share[d], sb.feature_share[d], 0.005) << "definition " << d << " eye " << eye.transpose();
  }
}

}  // namespace
