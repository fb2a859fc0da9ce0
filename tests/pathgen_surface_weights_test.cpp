// §8 per-face weights: the exact items of §17.6 and a brute-force comparison with the definition.
#include <gtest/gtest.h>

#include <set>

#include "pathgen/surface.h"
#include "pathgen/surface_mesh.h"
#include "pathgen/weights.h"
#include "test_meshes.h"

namespace meshtour {
namespace {

using namespace test_meshes;

// Every face its own patch (see the hand-checked orphan test in the patch tests).
SurfaceOptions every_face_its_own_patch(WeightNeighbourhood n) {
  SurfaceOptions o;
  o.smoothing = SmoothingMethod::none;
  o.tolerance = 1e-300;
  o.keep_inaccurate_patches = true;
  o.weight_neighbourhood = n;
  return o;
}

// Interior faces of plane(n) that are at least `margin` quads away from the border.
bool interior(const TriangleMesh& m, const std::array<std::uint32_t, 3>& t, double margin) {
  for (std::uint32_t v : t)
    if (std::abs(m.positions[v].x()) > 0.5 - margin || std::abs(m.positions[v].y()) > 0.5 - margin) return false;
  return true;
}

TEST(PathgenSurfaceWeights, EveryFaceItsOwnPatchCountsTheNeighbourhood) {
  const TriangleMesh m = plane(16);
  const double q = 1.0 / 16;
  const struct {
    WeightNeighbourhood n;
    double expected;
  } cases[] = {{WeightNeighbourhood::vertex_3_ring, 73}, {WeightNeighbourhood::vertex_2_ring, 37}, {WeightNeighbourhood::edge_2_ring, 10}};
  for (const auto& c : cases) {
    const SurfaceAnalysis s = analyze_surface(m, every_face_its_own_patch(c.n));
    ASSERT_EQ(s.patch_count, static_cast<int>(m.triangles.size()));
    int checked = 0;
    for (std::size_t f = 0; f < s.triangles.size(); ++f) {
      if (!interior(m, m.triangles[s.input_face[f]], 3.5 * q)) continue;
      EXPECT_EQ(s.face_weight[f], c.expected) << to_string(c.n) << " face " << f;
      ++checked;
    }
    EXPECT_GT(checked, 100);
  }
}

TEST(PathgenSurfaceWeights, OnePatchEverywhereGivesWeightOne) {
  for (auto n : {WeightNeighbourhood::vertex_3_ring, WeightNeighbourhood::vertex_2_ring, WeightNeighbourhood::edge_2_ring}) {
    SurfaceOptions o;
    o.weight_neighbourhood = n;
    const SurfaceAnalysis s = analyze_surface(plane(16), o);
    ASSERT_EQ(s.patch_count, 1);
    for (double w : s.face_weight) ASSERT_EQ(w, 1.0);
  }
}

TEST(PathgenSurfaceWeights, MatchesTheDefinitionOnAnIrregularMesh) {
  // Random patch ids (with orphans) on a bumpy sphere; w(f) from N1/N2/N3 taken literally.
  const SurfaceAnalysis s = analyze_surface(bumpy_sphere(2, 0.01), SurfaceOptions{});
  const std::size_t F = s.triangles.size();
  std::mt19937_64 rng(3);
  std::vector<int> pid(F);
  for (auto& p : pid) p = static_cast<int>(rng() % 40) - 5;  // -5..-1 → orphan
  for (auto& p : pid) p = std::max(p, -1);

  std::vector<std::set<std::size_t>> faces_of_vertex(s.positions.size());
  for (std::size_t f = 0; f < F; ++f)
    for (std::uint32_t v : s.triangles[f]) faces_of_vertex[v].insert(f);
  const auto n1 = [&](const std::set<std::size_t>& faces) {
    std::set<std::size_t> out;
    for (std::size_t g : faces)
      for (std::uint32_t v : s.triangles[g]) out.insert(faces_of_vertex[v].begin(), faces_of_vertex[v].end());
    return out;
  };
  const auto count = [&](const std::set<std::size_t>& faces) {
    std::set<int> ids;
    for (std::size_t g : faces)
      if (pid[g] >= 0) ids.insert(pid[g]);
    return static_cast<double>(ids.size());
  };
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::size_t>> by_edge;
  for (std::size_t f = 0; f < F; ++f)
    for (int k = 0; k < 3; ++k) by_edge[std::minmax(s.triangles[f][k], s.triangles[f][(k + 1) % 3])].push_back(f);
  const auto edge_step = [&](const std::set<std::size_t>& faces) {
    std::set<std::size_t> out = faces;
    for (std::size_t g : faces)
      for (int k = 0; k < 3; ++k)
        for (std::size_t h : by_edge[std::minmax(s.triangles[g][k], s.triangles[g][(k + 1) % 3])]) out.insert(h);
    return out;
  };

  // The library's adjacency for the same cleaned mesh.
  TriangleMesh cleaned;
  cleaned.positions = s.positions;
  cleaned.triangles = s.triangles;
  CleanupCounts counts;
  std::vector<std::string> notes;
  const auto mesh = surface_detail::clean_and_build(cleaned, SurfaceOptions{}, counts, notes);
  ASSERT_EQ(mesh.face_count(), F);
  const auto w3 = surface_detail::face_weights(mesh, pid, 35, WeightNeighbourhood::vertex_3_ring);
  const auto w2 = surface_detail::face_weights(mesh, pid, 35, WeightNeighbourhood::vertex_2_ring);
  const auto we = surface_detail::face_weights(mesh, pid, 35, WeightNeighbourhood::edge_2_ring);
  for (std::size_t f = 0; f < F; ++f) {
    const std::set<std::size_t> N1 = n1({f}), N2 = n1(N1), N3 = n1(N2);
    ASSERT_EQ(w3[f], count(N3)) << "face " << f;
    ASSERT_EQ(w2[f], count(N2)) << "face " << f;
    ASSERT_EQ(we[f], count(edge_step(edge_step({f})))) << "face " << f;
  }
}

}  // namespace
}  // namespace meshtour
