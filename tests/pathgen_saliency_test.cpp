// Mesh saliency (pathgen/saliency.h, docs/SALIENCY.md): the mean curvature it starts from, where
// it finds features, its independence of the tessellation and of the thread count, and that
// broken input gives zeros instead of exceptions.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include "core/error.h"
#include "pathgen/features.h"
#include "pathgen/saliency.h"
#include "test_meshes.h"

namespace meshtour {
namespace {

using namespace test_meshes;

/// Unit icosphere with one smooth bump of height 0.08 and angular width 0.2 rad around `centre`.
TriangleMesh sphere_with_bump(int level, const Eigen::Vector3d& centre) {
  TriangleMesh m = icosphere(level);
  for (auto& p : m.positions) {
    const double angle = std::acos(std::clamp(p.dot(centre), -1.0, 1.0));
    p *= 1.0 + 0.08 * std::exp(-(angle / 0.2) * (angle / 0.2));
  }
  return m;
}

/// The cube [−1, 1]³, each side an n × n grid of split quads, sides sharing their edge vertices
/// (a closed, watertight mesh with outward faces).
TriangleMesh cube(int n) {
  TriangleMesh m;
  std::map<std::array<long, 3>, std::uint32_t> index;
  const auto vertex = [&](const Eigen::Vector3d& p) {
    const std::array<long, 3> key{std::lround(p.x() * n), std::lround(p.y() * n), std::lround(p.z() * n)};
    const auto [it, added] = index.try_emplace(key, static_cast<std::uint32_t>(m.positions.size()));
    if (added) m.positions.push_back(p);
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (double side : {-1.0, 1.0}) {
      Eigen::Vector3d normal = Eigen::Vector3d::Zero(), u = Eigen::Vector3d::Zero();
      normal[axis] = side;
      u[(axis + 1) % 3] = 1.0;
      const Eigen::Vector3d v = normal.cross(u);  // u × v = normal: counter-clockwise from outside
      const auto at = [&](int i, int j) { return vertex(normal + u * (2.0 * i / n - 1.0) + v * (2.0 * j / n - 1.0)); };
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
          m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    }
  return m;
}

/// Area of the faces flagged in `a` or `b` and of those flagged in both, where face f of `a`
/// corresponds to faces 4f..4f+3 of `b` (split_at_midpoints).
struct Overlap {
  double both = 0.0, either = 0.0;
  double ratio() const { return either > 0.0 ? both / either : 1.0; }
};
Overlap overlap_with_split(const TriangleMesh& coarse, const std::vector<std::uint8_t>& a, const TriangleMesh& fine,
                           const std::vector<std::uint8_t>& b) {
  const std::vector<double> area = face_areas(fine);
  Overlap o;
  for (std::size_t f = 0; f < coarse.triangles.size(); ++f)
    for (std::size_t c = 4 * f; c < 4 * f + 4; ++c) {
      if (a[f] && b[c]) o.both += area[c];
      if (a[f] || b[c]) o.either += area[c];
    }
  return o;
}

TEST(MeanCurvature, SphereOfRadiusTwoHasHalf) {
  const TriangleMesh m = transformed(icosphere(4), 2.0, Eigen::Matrix3d::Identity(), Eigen::Vector3d(1, 2, 3));
  const std::vector<double> h = vertex_mean_curvature(m);
  // Within 0.5% except at the 12 vertices of valence 5, where the barycentric area is off by ~15%.
  int off = 0;
  for (double value : h) {
    EXPECT_NEAR(value, 0.5, 0.08);
    off += std::abs(value - 0.5) > 0.0025;
  }
  EXPECT_LE(off, 12);
}

TEST(MeanCurvature, PlaneIsFlatIncludingItsBoundary) {
  for (double value : vertex_mean_curvature(plane(16))) EXPECT_NEAR(value, 0.0, 1e-12);
}

TEST(MeanCurvature, InsideOutSphereIsNegative) {
  TriangleMesh m = icosphere(3);
  for (auto& t : m.triangles) std::swap(t[1], t[2]);
  for (double value : vertex_mean_curvature(m)) EXPECT_NEAR(value, -1.0, 0.15);
}

TEST(Saliency, SphereHasNoFeatures) {
  // Only tessellation noise, which the noise floor keeps far below the saliency of a real bump.
  const std::vector<double> sphere = vertex_saliency(icosphere(5));
  const std::vector<double> bump = vertex_saliency(sphere_with_bump(5, Eigen::Vector3d::UnitY()));
  EXPECT_LT(*std::max_element(sphere.begin(), sphere.end()), 0.01);
  EXPECT_GT(*std::max_element(bump.begin(), bump.end()), 1.0);
}

TEST(Saliency, BumpIsWhereTheSaliencyIs) {
  const Eigen::Vector3d centre = Eigen::Vector3d(1, 2, -1).normalized();
  const TriangleMesh m = sphere_with_bump(5, centre);
  const std::vector<double> s = vertex_saliency(m);
  const auto angle = [&](std::size_t v) { return std::acos(std::clamp(m.positions[v].normalized().dot(centre), -1.0, 1.0)); };
  const auto top = static_cast<std::size_t>(std::max_element(s.begin(), s.end()) - s.begin());
  EXPECT_LT(angle(top), 0.5);
  // The bump (within 0.5 rad: its flank reaches ~0.4) against the rest of the sphere.
  double near = 0.0, far = 0.0;
  int near_count = 0, far_count = 0;
  for (std::size_t v = 0; v < s.size(); ++v) {
    const bool on_bump = angle(v) < 0.5;
    (on_bump ? near : far) += s[v];
    ++(on_bump ? near_count : far_count);
  }
  EXPECT_GT(near / near_count, 50.0 * far / far_count);
}

TEST(Saliency, CubeCornersAndEdgesAreSalientItsFacesAreNot) {
  const TriangleMesh m = cube(32);
  const std::vector<double> s = vertex_saliency(m);
  double corner_min = 1e300, face_max = 0.0, edge_mean = 0.0;
  int edge_count = 0;
  for (std::size_t v = 0; v < s.size(); ++v) {
    const Eigen::Vector3d a = m.positions[v].cwiseAbs();
    const int outer = (a.x() > 0.999) + (a.y() > 0.999) + (a.z() > 0.999);  // 3: corner, 2: edge
    const double from_edges = 1.0 - std::max({std::min(a.x(), a.y()), std::min(a.y(), a.z()), std::min(a.x(), a.z())});
    if (outer == 3) corner_min = std::min(corner_min, s[v]);
    if (outer == 2 && a.minCoeff() < 0.5) {  // the middle of an edge, away from the corners
      edge_mean += s[v];
      ++edge_count;
    }
    // Farther than the widest Gaussian (24ε ≈ 0.25) from every edge: flat at every scale.
    if (from_edges > 0.3) face_max = std::max(face_max, s[v]);
  }
  edge_mean /= edge_count;
  EXPECT_EQ(face_max, 0.0);
  EXPECT_GT(edge_mean, 0.1);
  EXPECT_GT(corner_min, 1.1 * edge_mean);  // where three edges meet stands out of the edges (1.61 vs 1.35)
}

TEST(Saliency, MidpointSplitGivesTheSameFeatures) {
  // 1-to-4 split at edge midpoints: the same surface with four times the faces. The saliency at
  // the shared vertices and the top-quartile feature areas must agree.
  const TriangleMesh coarse = bumpy_sphere(4);
  const TriangleMesh fine = split_at_midpoints(coarse);
  const std::vector<double> a = vertex_saliency(coarse), b = vertex_saliency(fine);
  double mean_a = 0.0, mean_b = 0.0;
  for (std::size_t v = 0; v < a.size(); ++v) {
    mean_a += a[v] / a.size();
    mean_b += b[v] / a.size();
  }
  double ab = 0.0, aa = 0.0, bb = 0.0;
  for (std::size_t v = 0; v < a.size(); ++v) {
    ab += (a[v] - mean_a) * (b[v] - mean_b);
    aa += (a[v] - mean_a) * (a[v] - mean_a);
    bb += (b[v] - mean_b) * (b[v] - mean_b);
  }
  EXPECT_GT(ab / std::sqrt(aa * bb), 0.97);  // measured 0.99
  const Overlap o = overlap_with_split(coarse, feature_faces(face_saliency(coarse, a), face_areas(coarse), 0.75), fine,
                                       feature_faces(face_saliency(fine, b), face_areas(fine), 0.75));
  EXPECT_GE(o.ratio(), 0.9);  // intersection over union; measured 0.94
}

TEST(Saliency, SameResultForAnyThreadCount) {
  const TriangleMesh m = bumpy_sphere(4, 0.002);
  std::vector<double> one, two;
  tbb::task_arena(1).execute([&] { one = vertex_saliency(m); });
  tbb::task_arena(2).execute([&] { two = vertex_saliency(m); });
  EXPECT_EQ(one, two);
  EXPECT_EQ(vertex_saliency(m), one);
}

TEST(Saliency, BrokenInputGivesZerosNotExceptions) {
  const auto expect_finite = [](const std::vector<double>& s) {
    for (double v : s) EXPECT_TRUE(std::isfinite(v) && v >= 0.0);
  };
  EXPECT_TRUE(vertex_saliency(TriangleMesh{}).empty());

  TriangleMesh one;
  one.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  one.triangles = {{0, 1, 2}};
  expect_finite(vertex_saliency(one));

  // Duplicate faces (both orientations), degenerate faces (a repeated corner, collinear corners),
  // isolated vertices, a non-manifold fin: nothing throws, unused vertices get 0.
  TriangleMesh broken = bumpy_sphere(3);
  const std::size_t faces = broken.triangles.size();
  for (std::size_t f = 0; f < faces; f += 7) broken.triangles.push_back(broken.triangles[f]);
  for (std::size_t f = 0; f < faces; f += 11) {
    auto t = broken.triangles[f];
    std::swap(t[1], t[2]);
    broken.triangles.push_back(t);
  }
  broken.triangles.push_back({0, 0, 1});
  const auto isolated = static_cast<std::uint32_t>(broken.positions.size());
  broken.positions.push_back({5, 5, 5});
  broken.positions.push_back(0.5 * (broken.positions[1] + broken.positions[2]));
  broken.triangles.push_back({1, 2, isolated + 1});  // collinear
  broken.positions.push_back(broken.positions[0] * 1.3);
  broken.triangles.push_back({0, 1, isolated + 2});  // a fin sticking out of the surface
  const std::vector<double> s = vertex_saliency(broken);
  ASSERT_EQ(s.size(), broken.positions.size());
  expect_finite(s);
  EXPECT_EQ(s[isolated], 0.0);
  EXPECT_GT(*std::max_element(s.begin(), s.end()), 0.0);
  expect_finite(face_saliency(broken, s));

  // Every vertex at one point: no size, no saliency.
  TriangleMesh point;
  point.positions.assign(3, Eigen::Vector3d(1, 2, 3));
  point.triangles = {{0, 1, 2}, {0, 1, 2}};
  for (double v : vertex_saliency(point)) EXPECT_EQ(v, 0.0);
}

TEST(Saliency, FaceSaliencyIsTheMeanOfItsVertices) {
  TriangleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  m.triangles = {{0, 1, 2}, {1, 3, 2}};
  const std::vector<double> f = face_saliency(m, {3.0, 6.0, 0.0, 9.0});
  ASSERT_EQ(f.size(), 2u);
  EXPECT_DOUBLE_EQ(f[0], 3.0);
  EXPECT_DOUBLE_EQ(f[1], 5.0);
  EXPECT_THROW(face_saliency(m, {1.0, 2.0}), InputError);
}

TEST(Saliency, EpsilonOutOfRangeIsAnInputError) {
  SaliencyOptions o;
  for (double bad : {0.0, -0.01, 0.0005, 0.2, std::nan("")}) {
    o.epsilon_fraction = bad;
    EXPECT_THROW(vertex_saliency(icosphere(1), o), InputError) << bad;
  }
}

}  // namespace
}  // namespace meshtour
