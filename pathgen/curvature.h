#pragma once
// §5: angle-weighted vertex normals and Goldfeather–Interrante principal curvatures.
#include <span>
#include <vector>

#include "pathgen/surface_mesh.h"

namespace meshtour::surface_detail {

/// §5.1: angle-weighted vertex normals (with the area-weighted and single-face fallbacks).
std::vector<Eigen::Vector3d> vertex_normals(const SurfaceMesh& mesh);

/// §5.2: the right-handed frame (X, Y, N) of a unit normal, independent of any neighbour order.
std::pair<Eigen::Vector3d, Eigen::Vector3d> tangent_frame(const Eigen::Vector3d& normal);

/// §5.3–§5.4 at every vertex from the given unit normals.
std::vector<VertexDifferential> principal_curvatures(const SurfaceMesh& mesh, const std::vector<Eigen::Vector3d>& normals,
                                                     CurvatureFit fit);

/// The fit of §5.3–§5.4 at one point from explicit neighbour sets (used by the mesh loop and by
/// tests). `ring1` and `ring2` hold neighbour positions and their unit normals; ring2 is the
/// fallback set (vertex-based 2-ring) and may be empty.
struct FitNeighbour {
  Eigen::Vector3d position;
  Eigen::Vector3d normal;
};
VertexDifferential fit_vertex(const Eigen::Vector3d& p, const Eigen::Vector3d& normal, std::span<const FitNeighbour> ring1,
                              std::span<const FitNeighbour> ring2, CurvatureFit fit);

}  // namespace meshtour::surface_detail
