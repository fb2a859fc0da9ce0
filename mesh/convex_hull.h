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

/// Indices (ascending) of the points of `points` that are vertices of their convex hull, plus
/// points that lie within rounding error of its boundary: a point is dropped only when it is
/// inside the hull by clearly more than the rounding error of the coordinates, so no vertex is
/// ever lost to rounding and the largest value of a linear function over the result equals its
/// largest value over all the points. Of several points with identical coordinates only the first
/// is kept. Degenerate sets are handled: all points in a plane (their hull in the plane), on a
/// line (its two ends), or at one place (one point). The same result for any thread count.
/// Checks for interrupts (core/interrupt.h) between blocks of work.
/// \throw InputError if a coordinate is not finite; RuntimeFailure if Qhull fails otherwise.
std::vector<std::size_t> convex_hull_vertex_indices(std::span<const Eigen::Vector3d> points);

/// The points of convex_hull_vertex_indices(), in input order.
std::vector<Eigen::Vector3d> convex_hull_vertices(std::span<const Eigen::Vector3d> points);

/// The hull vertices of the mesh's vertices that some triangle uses (unreferenced vertices do not
/// count, as in TriangleMesh::bounds()), in vertex order.
std::vector<Eigen::Vector3d> convex_hull_vertices(const TriangleMesh& mesh);

}  // namespace meshtour
