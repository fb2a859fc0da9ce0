#pragma once
// The edges of a triangle mesh by how many triangles use them: the counts `meshtour info` reports
// and the boundary loops (holes) that `--up auto` reads an open scan's missing base from.
#include <array>
#include <cstdint>
#include <vector>

#include "mesh/mesh.h"

namespace meshtour {

struct EdgeTally {
  std::size_t edges = 0;               ///< undirected edges
  std::size_t non_manifold_edges = 0;  ///< edges of more than two triangles
  /// Edges of exactly one triangle, directed as they run in it (u -> v), ordered by their lower
  /// vertex, then their higher one: the same list on any thread count.
  std::vector<std::array<std::uint32_t, 2>> boundary;
};

/// Tallies every edge by the triangles using it. Linear in the triangles (each vertex's edges
/// are gathered in its own bucket and sorted there), with a temporary of 4 bytes per half-edge.
/// \throw InputError if the mesh has 2^31 vertices or more.
EdgeTally tally_edges(const TriangleMesh& mesh);

/// The boundary edges joined into loops: the edges of one hole, or of holes that touch at a
/// vertex. Each loop lists indices into `tally.boundary`; loops are ordered by their lowest vertex.
std::vector<std::vector<std::uint32_t>> boundary_loops(const TriangleMesh& mesh, const EdgeTally& tally);

}  // namespace meshtour
