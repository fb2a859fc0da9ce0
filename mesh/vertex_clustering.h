#pragma once
// A coarse stand-in of a mesh at a fixed resolution, in linear time: vertex clustering (Rossignac
// & Borrel 1993). Space is cut into cubic cells; the vertices in one cell merge into one vertex
// at their area-weighted mean, and triangles whose corners land in fewer than three cells vanish.
// The cell size follows from the surface area, not the face count, so a shape and any finer
// tessellation of it give nearly the same proxy: what the tessellation-independent feature
// measures are computed on (pathgen/feature_field.h).
#include <cstdint>
#include <vector>

#include "mesh/mesh.h"

namespace meshtour {

struct ClusteredMesh {
  TriangleMesh mesh;                          ///< the proxy (positions and triangles only)
  std::vector<std::uint32_t> vertex_cluster;  ///< proxy vertex of each input vertex (unused ones: 0)
  double cell_size = 0.0;                     ///< edge of the cubic cells, model units
  Eigen::Vector3d grid_origin = Eigen::Vector3d::Zero();
};

/// Clusters `mesh` into cells of the size that would give about `target_cells` cells if the
/// surface were flat (cell = sqrt(area / target_cells)). Deterministic; duplicate proxy triangles
/// (the same three proxy vertices) are kept once. \throw InputError if the mesh has no area.
ClusteredMesh cluster_vertices(const TriangleMesh& mesh, std::size_t target_cells);

}  // namespace meshtour
