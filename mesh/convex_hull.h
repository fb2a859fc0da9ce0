#pragma once
// The vertices of a point set's convex hull: an exact reduction for every "largest value over the
// model" question whose value is a linear function of the point, or a maximum of such functions,
// or a linear-fractional one with a positive denominator (camera framing: how far back, how wide
// a lens, whether every vertex is in frame). The largest value over the points is attained at a
// hull vertex, so asking the few thousand hull vertices gives the answer of the millions of points.
#include <Eigen/Core>
#include <cstddef>
#include <span>
#include <vector>

#include "mesh/mesh.h"

namespace meshtour {

/// Indices (ascending) of the points of `points` that are vertices of their convex hull. Exact up
/// to the rounding of the coordinates: a point is dropped only when it lies inside the hull of the
/// kept points, or on or near its boundary, within 1e-13 of the model's size (its extent or its
/// coordinates' magnitude, whichever is larger). So points on a facet or an edge (the midpoints of
/// a subdivided mesh, the flat sides of a CAD part) are dropped, and the largest value of a linear
/// function with a unit gradient over the kept points is its largest value over all points, or
/// within 1e-13 of the model's size of it (in practice the same number, see the tests). Of several
/// points with identical coordinates one is kept. Degenerate sets: all points in a plane give
/// their polygon's corners, on a line its two ends, at one place one point.
/// Deterministic: the same result for any thread count. Interruptible (core/interrupt.h) between
/// blocks of work; a Qhull run itself is not, but on a mesh it sees few points (mesh/convex_hull.cpp
/// says why), except when most points are hull vertices (points on a sphere).
/// \throw InputError if a coordinate is not finite; RuntimeFailure if Qhull fails otherwise.
std::vector<std::size_t> convex_hull_vertex_indices(std::span<const Eigen::Vector3d> points);

/// The points of convex_hull_vertex_indices(), in input order. Typical cost on 2 cores: 0.1 s for
/// 0.56M points, 0.6 s for 8.9M (bench/framing_bench.cpp).
std::vector<Eigen::Vector3d> convex_hull_vertices(std::span<const Eigen::Vector3d> points);

/// The hull vertices of the mesh's vertices that some triangle uses (unreferenced vertices do not
/// count, as in TriangleMesh::bounds()), in vertex order.
std::vector<Eigen::Vector3d> convex_hull_vertices(const TriangleMesh& mesh);

}  // namespace meshtour
