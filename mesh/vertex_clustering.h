#pragma once
// A coarse stand-in of a mesh's surface at a fixed resolution, in linear time, that depends on the
// surface and not on how it is tessellated: clustering into cubic cells (after Rossignac & Borrel
// 1993), with two changes that take the input's vertices out of the answer.
//
//  - Vertices: one per cell the surface passes through, at the point of the cell that best fits
//    the surface inside it (the triangles are clipped to the cells, so the area, its centroid and
//    its area-weighted plane quadric are exact; the point starts at the centroid and moves onto the
//    surface along the directions the quadric pins down, as in dual contouring). Plain
//    vertex clustering put it at the mean of the input vertices in the cell and made a vertex only
//    where an input vertex lay: a finer tessellation of the same shape filled cells the surface
//    merely clips (the bunny's proxy grew from 9,466 to 10,994 vertices over two 1-to-4 splits)
//    and moved every representative, and the toroidal patches on the proxy reshuffled (the top
//    quartile by patch density kept only a third of its samples).
//  - Faces: the dual of the grid, as in dual contouring: where the surface crosses a cell edge, the
//    four cells around that edge make a quad (two triangles, along the shorter diagonal), oriented
//    by the side the surface faces. Which cells are connected then depends on where the surface
//    crosses the grid, not on which input triangles happen to span three cells.
//
// The cell size follows from the surface area, not the face count. A shape and any finer
// tessellation of it (a split of its faces) give the same proxy up to rounding. What the
// tessellation-independent feature measures are computed on (pathgen/coverage.h).
#include <cstdint>
#include <vector>

#include "mesh/mesh.h"

namespace meshtour {

struct ClusteredMesh {
  TriangleMesh mesh;                          ///< the proxy (positions and triangles only)
  double cell_size = 0.0;                     ///< edge of the cubic cells, model units
  Eigen::Vector3d grid_origin = Eigen::Vector3d::Zero();
  std::vector<std::uint64_t> cell_keys;       ///< cell of each proxy vertex, ascending

  /// The proxy vertex of the cell holding `p`, or the nearest of the neighbouring cells' when the
  /// surface has no area in it (0 if none has). On demand, not for every input vertex: a lookup
  /// per vertex of a 4.5M-face mesh cost a third of a second and is rarely needed.
  std::uint32_t vertex_near(const Eigen::Vector3d& p) const;
};

/// Clusters the surface of `mesh` into cells of the size that would give about `target_cells` cells
/// if the surface were flat (cell = sqrt(area / target_cells)). Deterministic: the same bits for any
/// thread count. \throw InputError if the mesh has no area.
///
/// The grid starts half a cell below the mesh's bounds. With `centred_grid`, it is placed
/// symmetrically about the centre of the bounds instead (a cell boundary or a cell centre on each
/// of its mid-planes), so a mesh turned by a quarter turn or mirrored about an axis gets the same
/// cells, turned: for measures that must not depend on which way the model is stored.
ClusteredMesh cluster_surface(const TriangleMesh& mesh, std::size_t target_cells, bool centred_grid = false);

}  // namespace meshtour
