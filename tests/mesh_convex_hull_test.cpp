// The convex hull's vertices: checked with real numbers. The property every user relies on is
// that the largest value of a linear function over the kept points equals (exactly, in floating
// point) its largest value over all points; it is checked in 1000 random directions.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "core/error.h"
#include "mesh/convex_hull.h"
#include "test_meshes.h"

namespace meshtour {
namespace {

// Portable random numbers (test_meshes.h: the standard distributions differ between library
// implementations), each vector's coordinates drawn x, y, z in turn.
using test_meshes::uniform;
Eigen::Vector3d gaussian3(std::mt19937_64& rng) {
  Eigen::Vector3d v;
  for (int k = 0; k < 3; ++k) v[k] = test_meshes::gaussian(rng);
  return v;
}
Eigen::Vector3d random_direction(std::mt19937_64& rng) { return gaussian3(rng).normalized(); }

double max_dot(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& d) {
  double best = -std::numeric_limits<double>::infinity();
  for (const auto& p : points) best = std::max(best, p.dot(d));
  return best;
}

// Every kept index is an input point, ascending, and in 1000 random directions (plus the six axis
// directions) the largest dot product over the kept points is exactly the one over all points.
void expect_same_support(const std::vector<Eigen::Vector3d>& points, const std::vector<std::size_t>& kept) {
  ASSERT_TRUE(std::is_sorted(kept.begin(), kept.end()));
  ASSERT_TRUE(std::adjacent_find(kept.begin(), kept.end()) == kept.end());
  std::vector<Eigen::Vector3d> hull;
  for (std::size_t i : kept) {
    ASSERT_LT(i, points.size());
    hull.push_back(points[i]);
  }
  std::mt19937_64 rng(7);
  std::vector<Eigen::Vector3d> directions;
  for (int axis = 0; axis < 3; ++axis) {
    directions.push_back(Eigen::Vector3d::Unit(axis));
    directions.push_back(-Eigen::Vector3d::Unit(axis));
  }
  for (int k = 0; k < 1000; ++k) directions.push_back(random_direction(rng));
  int mismatches = 0;
  for (const auto& d : directions)
    if (max_dot(hull, d) != max_dot(points, d)) ++mismatches;
  EXPECT_EQ(mismatches, 0) << "of " << directions.size() << " directions";
}

std::vector<Eigen::Vector3d> ball(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<Eigen::Vector3d> points;
  for (std::size_t i = 0; i < n; ++i) points.push_back(random_direction(rng) * std::cbrt(uniform(rng)));
  return points;
}

TEST(ConvexHull, RandomBallKeepsFewPointsAndTheSameSupport) {
  // More points than one block, so that the merging rounds run too.
  const auto points = ball(40000, 1);
  const auto kept = convex_hull_vertex_indices(points);
  expect_same_support(points, kept);
  EXPECT_GT(kept.size(), 50u);
  EXPECT_LT(kept.size(), 5000u);
}

TEST(ConvexHull, GaussianCloudFarFromTheOriginKeepsTheSameSupport) {
  std::mt19937_64 rng(2);
  std::vector<Eigen::Vector3d> points;
  const Eigen::Vector3d offset(1e4, -3e3, 250.0);
  for (int i = 0; i < 50000; ++i) points.push_back(offset + gaussian3(rng).cwiseProduct(Eigen::Vector3d(3, 1, 0.2)));
  expect_same_support(points, convex_hull_vertex_indices(points));
}

TEST(ConvexHull, EveryPointOnASphereIsKept) {
  std::mt19937_64 rng(3);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 3000; ++i) points.push_back(random_direction(rng));
  const auto kept = convex_hull_vertex_indices(points);
  EXPECT_EQ(kept.size(), points.size());
  expect_same_support(points, kept);
}

TEST(ConvexHull, CubeWithInteriorPointsKeepsExactlyItsCorners) {
  std::mt19937_64 rng(4);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 5000; ++i)
    points.push_back(test_meshes::drawn_vector([&] { return 1.8 * uniform(rng) - 0.9; }));
  std::vector<std::size_t> corners;
  for (int c = 0; c < 8; ++c) {
    corners.push_back(points.size());
    points.emplace_back(c & 1 ? 1.0 : -1.0, c & 2 ? 1.0 : -1.0, c & 4 ? 1.0 : -1.0);
    for (int i = 0; i < 700; ++i)  // corners among the interior points, not at the end
      points.push_back(test_meshes::drawn_vector([&] { return 1.8 * uniform(rng) - 0.9; }));
  }
  EXPECT_EQ(convex_hull_vertex_indices(points), corners);
}

TEST(ConvexHull, PointsOnTheCubesFacesAndEdgesAreDropped) {
  // A CAD-like part: many points exactly on the faces and edges of a cube (enough to go through
  // the filter of the sample hull), the corners among them. Only the corners are vertices.
  std::mt19937_64 rng(5);
  std::vector<Eigen::Vector3d> points;
  std::vector<std::size_t> corners;
  for (int i = 0; i < 40000; ++i) {
    if (i % 4000 == 3 && corners.size() < 8) {
      const auto c = corners.size();
      corners.push_back(points.size());
      points.emplace_back(c & 1 ? 1.0 : -1.0, c & 2 ? 1.0 : -1.0, c & 4 ? 1.0 : -1.0);
    }
    // Grid coordinates strictly between -1 and 1, so that no other point falls on a corner.
    const auto grid = [&] { return (std::floor(uniform(rng) * 511.0) + 1.0) / 256.0 - 1.0; };
    Eigen::Vector3d p = test_meshes::drawn_vector(grid);
    p[i % 3] = i % 2 ? 1.0 : -1.0;
    if (i % 5 == 0) p[(i + 1) % 3] = 1.0;  // some on edges
    points.push_back(p);
  }
  ASSERT_EQ(corners.size(), 8u);
  const auto kept = convex_hull_vertex_indices(points);
  EXPECT_EQ(kept, corners);
  expect_same_support(points, kept);
}

TEST(ConvexHull, BumpySurfaceWithInteriorPointsKeepsTheSameSupport) {
  // Like a scanned model: a bumpy closed surface (many of its points are hull vertices, many are
  // in dents) and points inside; more than the filter's threshold.
  std::mt19937_64 rng(12);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 50000; ++i) {
    const Eigen::Vector3d d = random_direction(rng);
    const double radius = 1.0 + 0.08 * std::sin(9.0 * d.x()) * std::cos(7.0 * d.y() + 2.0 * d.z());
    points.push_back(Eigen::Vector3d(1.7, 1.0, 0.6).cwiseProduct(d) * (i % 4 == 0 ? radius * uniform(rng) : radius));
  }
  const auto kept = convex_hull_vertex_indices(points);
  expect_same_support(points, kept);
  EXPECT_LT(kept.size(), points.size() / 4);
}

TEST(ConvexHull, CoplanarPointsKeepTheirPolygon) {
  // Exactly coplanar (small integers times powers of two): the plane x + 2y - z/3 ... spanned by
  // u and v through o. The hull of a disc of points in it: its boundary polygon.
  std::mt19937_64 rng(6);
  const Eigen::Vector3d o(0.5, -2.0, 3.0), u(1, 2, 0), v(0, 1, 3);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 20000; ++i) {
    const double s = std::floor(uniform(rng) * 2048.0) / 1024.0 - 1.0, t = std::floor(uniform(rng) * 2048.0) / 1024.0 - 1.0;
    if (s * s + t * t <= 1.0) points.push_back(o + s * u + t * v);
  }
  const auto kept = convex_hull_vertex_indices(points);
  expect_same_support(points, kept);
  EXPECT_LT(kept.size(), points.size() / 10);
  // The same in the plane z = 0, and in an axis plane that Qhull's own scaling might treat alike.
  std::vector<Eigen::Vector3d> flat;
  for (const auto& p : points) flat.emplace_back(p.x(), p.y(), 0.0);
  const auto kept_flat = convex_hull_vertex_indices(flat);
  expect_same_support(flat, kept_flat);
  EXPECT_LT(kept_flat.size(), flat.size() / 10);
}

TEST(ConvexHull, CollinearPointsKeepTheirEnds) {
  const Eigen::Vector3d o(1, 2, 3), d(1, -2, 4);
  std::vector<Eigen::Vector3d> points;
  std::mt19937_64 rng(8);
  for (int i = 0; i < 1000; ++i) points.push_back(o + (std::floor(uniform(rng) * 4096.0) / 256.0 - 2.0) * d);
  points.insert(points.begin() + 300, o + 15.0 * d);  // the far end, in the middle of the list
  points.insert(points.begin() + 10, o - 3.0 * d);    // the near end
  const auto kept = convex_hull_vertex_indices(points);
  EXPECT_EQ(kept, (std::vector<std::size_t>{10, 301}));
  expect_same_support(points, kept);
}

TEST(ConvexHull, DuplicatesAreKeptOnce) {
  auto points = ball(2000, 9);
  const std::size_t n = points.size();
  for (std::size_t i = 0; i < n; ++i) points.push_back(points[(i * 7919) % n]);
  for (std::size_t i = 0; i < n; ++i) points.push_back(points[i]);
  const auto kept = convex_hull_vertex_indices(points);
  std::vector<std::array<double, 3>> coordinates;
  for (std::size_t i : kept) coordinates.push_back({points[i].x(), points[i].y(), points[i].z()});
  std::sort(coordinates.begin(), coordinates.end());
  EXPECT_TRUE(std::adjacent_find(coordinates.begin(), coordinates.end()) == coordinates.end());
  expect_same_support(points, kept);
  // A tetrahedron given 1000 times.
  std::vector<Eigen::Vector3d> tetra;
  for (int r = 0; r < 1000; ++r)
    for (const Eigen::Vector3d& p : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0),
                                     Eigen::Vector3d(0, 0, 1)})
      tetra.push_back(p);
  EXPECT_EQ(convex_hull_vertex_indices(tetra), (std::vector<std::size_t>{0, 1, 2, 3}));
}

TEST(ConvexHull, TinyInputs) {
  EXPECT_TRUE(convex_hull_vertex_indices({}).empty());
  const std::vector<Eigen::Vector3d> one{{1, 2, 3}};
  EXPECT_EQ(convex_hull_vertex_indices(one), (std::vector<std::size_t>{0}));
  const std::vector<Eigen::Vector3d> same(50, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(convex_hull_vertex_indices(same), (std::vector<std::size_t>{0}));
  const std::vector<Eigen::Vector3d> two{{1, 2, 3}, {1, 2, 3}, {4, 5, 6}};
  EXPECT_EQ(convex_hull_vertex_indices(two), (std::vector<std::size_t>{0, 2}));
  const std::vector<Eigen::Vector3d> triangle{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.25, 0.25, 0}, {0, 1, 0}};
  EXPECT_EQ(convex_hull_vertex_indices(triangle), (std::vector<std::size_t>{0, 1, 2}));
}

TEST(ConvexHull, RejectsCoordinatesThatAreNotFinite) {
  auto points = ball(100, 10);
  points[42].y() = std::numeric_limits<double>::quiet_NaN();
  try {
    convex_hull_vertex_indices(points);
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("point 42"), std::string::npos) << e.what();
  }
}

TEST(ConvexHull, SameResultForAnyThreadCount) {
  const auto points = ball(300000, 11);
  std::vector<std::size_t> one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = convex_hull_vertex_indices(points);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = convex_hull_vertex_indices(points);
  }
  EXPECT_EQ(one, two);
  EXPECT_EQ(one, convex_hull_vertex_indices(points));
}

TEST(ConvexHull, MeshOverloadIgnoresUnreferencedVertices) {
  TriangleMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.1, 0.1, 0.1}, {50, 50, 50}};
  mesh.triangles = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}, {4, 1, 2}};
  const auto hull = convex_hull_vertices(mesh);
  ASSERT_EQ(hull.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(hull[i], mesh.positions[i]);
}

}  // namespace
}  // namespace meshtour
