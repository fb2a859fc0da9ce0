#pragma once
// Topology figures of a loaded mesh, for `meshtour info` (what a file holds before it is toured).
#include <cstddef>

#include "mesh/mesh.h"

namespace meshtour {

struct MeshStatistics {
  std::size_t edges = 0;               ///< undirected edges
  std::size_t boundary_edges = 0;      ///< edges of exactly one triangle (holes, open scans)
  std::size_t non_manifold_edges = 0;  ///< edges of more than two triangles
  std::size_t components = 0;          ///< triangles sharing a vertex are connected
  std::size_t unreferenced_vertices = 0;
  double surface_area = 0.0;
};

/// Counts edges by their triangles and the connected components (union-find, deterministic).
MeshStatistics mesh_statistics(const TriangleMesh& mesh);

/// A guess of the model's length unit from its size (bounding-box diagonal `diagonal`): scans in
/// millimetres measure hundreds to thousands, in metres about 0.1 to 10. Returns e.g.
/// "millimetres (diagonal 412)" — a guess, stated as one.
std::string guess_units(double diagonal);

}  // namespace meshtour
