#include "mesh/mesh_edges.h"

#include <algorithm>
#include <atomic>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/disjoint_sets.h"
#include "core/error.h"

namespace meshtour {

EdgeTally tally_edges(const TriangleMesh& mesh) {
  const std::size_t vertices = mesh.positions.size();
  // A half-edge is kept in its lower vertex's bucket as its higher vertex, shifted left by one,
  // with the low bit set when it runs from the higher vertex to the lower: 31 bits per vertex.
  if (vertices >= (std::size_t{1} << 31))
    throw InputError("the mesh has " + std::to_string(vertices) + " vertices; at most 2^31 - 1 are supported");
  // Counted and placed in parallel: the order within a bucket depends on the threads, which the
  // sort below undoes.
  const auto triangles = tbb::blocked_range<std::size_t>(0, mesh.triangles.size(), 1 << 14);
  std::vector<std::size_t> first(vertices + 1, 0);
  tbb::parallel_for(triangles, [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t f = range.begin(); f != range.end(); ++f)
      for (int c = 0; c < 3; ++c) {
        const auto& t = mesh.triangles[f];
        std::atomic_ref<std::size_t>(first[std::min(t[c], t[(c + 1) % 3]) + 1]).fetch_add(1, std::memory_order_relaxed);
      }
  });
  for (std::size_t v = 0; v < vertices; ++v) first[v + 1] += first[v];
  std::vector<std::uint32_t> bucket(first[vertices]);
  {
    std::vector<std::size_t> next(first.begin(), first.end() - 1);
    tbb::parallel_for(triangles, [&](const tbb::blocked_range<std::size_t>& range) {
      for (std::size_t f = range.begin(); f != range.end(); ++f)
        for (int c = 0; c < 3; ++c) {
          const auto& t = mesh.triangles[f];
          const std::uint32_t a = t[c], b = t[(c + 1) % 3];
          const std::size_t at = std::atomic_ref<std::size_t>(next[std::min(a, b)]).fetch_add(1, std::memory_order_relaxed);
          bucket[at] = std::max(a, b) << 1 | (a > b ? 1u : 0u);
        }
    });
  }
  // Sorting each bucket puts an edge's half-edges next to each other whatever order the
  // triangles came in, so the tally below is the same on any thread count.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, vertices, 4096), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t v = range.begin(); v != range.end(); ++v)
      std::sort(bucket.begin() + static_cast<std::ptrdiff_t>(first[v]), bucket.begin() + static_cast<std::ptrdiff_t>(first[v + 1]));
  });
  EdgeTally tally;
  for (std::size_t v = 0; v < vertices; ++v)
    for (std::size_t i = first[v], end = first[v + 1]; i < end;) {
      std::size_t j = i + 1;
      while (j < end && bucket[j] >> 1 == bucket[i] >> 1) ++j;
      ++tally.edges;
      if (j - i > 2) ++tally.non_manifold_edges;
      if (j - i == 1) {
        const auto low = static_cast<std::uint32_t>(v), high = bucket[i] >> 1;
        tally.boundary.push_back((bucket[i] & 1u) ? std::array<std::uint32_t, 2>{high, low} : std::array<std::uint32_t, 2>{low, high});
      }
      i = j;
    }
  return tally;
}

std::vector<std::vector<std::uint32_t>> boundary_loops(const TriangleMesh& mesh, const EdgeTally& tally) {
  if (tally.boundary.empty()) return {};  // a closed mesh: no per-vertex tables to fill
  DisjointSets sets(mesh.positions.size());
  for (const auto& [a, b] : tally.boundary) sets.join(a, b);
  // A loop's number is its root, the lowest vertex of its edges (DisjointSets keeps the lowest).
  std::vector<std::uint32_t> loop_of_root(mesh.positions.size(), std::numeric_limits<std::uint32_t>::max());
  std::vector<std::uint32_t> roots;
  for (const auto& edge : tally.boundary) {
    const std::uint32_t r = sets.root(edge[0]);
    if (loop_of_root[r] == std::numeric_limits<std::uint32_t>::max()) {
      loop_of_root[r] = 0;
      roots.push_back(r);
    }
  }
  std::sort(roots.begin(), roots.end());
  for (std::size_t i = 0; i < roots.size(); ++i) loop_of_root[roots[i]] = static_cast<std::uint32_t>(i);
  std::vector<std::vector<std::uint32_t>> loops(roots.size());
  for (std::size_t e = 0; e < tally.boundary.size(); ++e)
    loops[loop_of_root[sets.root(tally.boundary[e][0])]].push_back(static_cast<std::uint32_t>(e));
  return loops;
}

}  // namespace meshtour
