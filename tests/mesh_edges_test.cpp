// Edges by the triangles that use them (mesh/mesh_edges.h): the counts `meshtour info` reports and
// the holes `--up auto` reads an open scan's base from.
#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <algorithm>
#include <set>

#include "mesh/mesh_edges.h"
#include "test_meshes.h"

namespace meshtour {
namespace {

// Whether some triangle runs from a to b.
bool runs_in_a_triangle(const TriangleMesh& mesh, std::uint32_t a, std::uint32_t b) {
  return std::any_of(mesh.triangles.begin(), mesh.triangles.end(), [&](const auto& t) {
    return (t[0] == a && t[1] == b) || (t[1] == a && t[2] == b) || (t[2] == a && t[0] == b);
  });
}

TEST(MeshEdges, ClosedSurfaceHasNoBoundary) {
  const TriangleMesh sphere = test_meshes::icosphere(3);
  const EdgeTally tally = tally_edges(sphere);
  EXPECT_EQ(tally.edges, 3 * sphere.triangles.size() / 2);
  EXPECT_EQ(tally.non_manifold_edges, 0u);
  EXPECT_TRUE(tally.boundary.empty());
  EXPECT_TRUE(boundary_loops(sphere, tally).empty());
}

// A tube open at both ends: 128 boundary edges per end, each directed as in its triangle, in two
// loops, whatever the numbering of the vertices and faces and the corners' order.
TEST(MeshEdges, TubeHasTwoLoopsDirectedAsItsTriangles) {
  const TriangleMesh tube = test_meshes::open_cylinder(0.2, 0.8, 128, 16);
  const EdgeTally tally = tally_edges(tube);
  EXPECT_EQ(tally.edges, 128u * 16u * 3u + 128u);  // per quad: a rung, a rail, a diagonal; plus the top ring
  EXPECT_EQ(tally.boundary.size(), 256u);
  for (const auto& [a, b] : tally.boundary) {
    EXPECT_TRUE(runs_in_a_triangle(tube, a, b)) << a << " -> " << b;
    EXPECT_FALSE(runs_in_a_triangle(tube, b, a)) << b << " -> " << a;
  }
  const auto loops = boundary_loops(tube, tally);
  ASSERT_EQ(loops.size(), 2u);
  for (const auto& loop : loops) {
    EXPECT_EQ(loop.size(), 128u);
    std::set<double> heights;  // each loop is one end of the tube
    for (const std::uint32_t e : loop) heights.insert(tube.positions[tally.boundary[e][0]].y());
    EXPECT_EQ(heights.size(), 1u);
  }
  const test_meshes::Permuted shuffled = test_meshes::permuted(tube, 11);
  const EdgeTally again = tally_edges(shuffled.mesh);
  EXPECT_EQ(again.edges, tally.edges);
  ASSERT_EQ(again.boundary.size(), tally.boundary.size());
  for (const auto& [a, b] : again.boundary) EXPECT_TRUE(runs_in_a_triangle(shuffled.mesh, a, b));
  EXPECT_EQ(boundary_loops(shuffled.mesh, again).size(), 2u);
}

// Three triangles on one edge make it non-manifold; their six outer edges are the boundary. Two
// holes that touch at a vertex are one loop.
TEST(MeshEdges, NonManifoldEdgesAndTouchingHoles) {
  TriangleMesh fin;
  fin.positions = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}, {0.5, 0, 1}};
  fin.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  const EdgeTally tally = tally_edges(fin);
  EXPECT_EQ(tally.edges, 7u);
  EXPECT_EQ(tally.non_manifold_edges, 1u);
  EXPECT_EQ(tally.boundary.size(), 6u);
  EXPECT_EQ(boundary_loops(fin, tally).size(), 1u);

  TriangleMesh bowtie;  // two triangles sharing only vertex 0
  bowtie.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
  bowtie.triangles = {{0, 1, 2}, {0, 3, 4}};
  const EdgeTally t2 = tally_edges(bowtie);
  EXPECT_EQ(t2.boundary.size(), 6u);
  EXPECT_EQ(boundary_loops(bowtie, t2).size(), 1u);
}

// The tally is counted in parallel: the same list on one thread and on all.
TEST(MeshEdges, SameOnAnyThreadCount) {
  const TriangleMesh mesh = test_meshes::split_at_midpoints(test_meshes::open_cylinder(0.2, 0.8, 200, 200));
  const EdgeTally all = tally_edges(mesh);
  EdgeTally one;
  {
    tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
    one = tally_edges(mesh);
  }
  EXPECT_EQ(one.edges, all.edges);
  EXPECT_EQ(one.boundary, all.boundary);
  EXPECT_EQ(boundary_loops(mesh, one), boundary_loops(mesh, all));
}

}  // namespace
}  // namespace meshtour
