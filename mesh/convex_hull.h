#pragma once
// The vertices of a point set's convex hull: an exact reduction for every "largest value over the
// model" question whose value is a linear function of the point, or a maximum of such functions,
// or a linear-fractional one with a positive denominator (camera framing: how far back, how wide
// a lens, whether every vertex is in frame). The largest value over the points is attained at a
// hull vertex, so asking the few thousand hull vertices gives the answer of the millions of points.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstddef>
#include <span>
#include <vector>

#include "core/triangle_geometry.h"
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

/// One triangle of a convex hull's boundary.
struct HullTriangle {
  Eigen::Vector3d normal;                ///< outward unit normal
  std::array<Eigen::Vector3d, 3> corner;  ///< its corners (hull vertices)
  double area() const { return triangle_area(corner[0], corner[1], corner[2]); }
};

/// The boundary of the convex hull of `hull_vertices` (the output of convex_hull_vertices(), so a
/// few thousand points), triangulated: what "on which face does the model rest" questions need
/// (mesh/up_axis.h). Empty when the points have no volume (flat, on a line, one point).
/// \throw RuntimeFailure if Qhull fails on a set with volume.
std::vector<HullTriangle> convex_hull_triangles(std::span<const Eigen::Vector3d> hull_vertices);

/// The convex hull of points in a plane, counter-clockwise from the lowest-then-leftmost point,
/// without collinear points (Andrew's monotone chain: exact orientation tests are not needed for
/// the areas and distances its users measure). Fewer than 3 points when they are collinear.
std::vector<Eigen::Vector2d> convex_polygon(std::vector<Eigen::Vector2d> points);

}  // namespace meshtour
