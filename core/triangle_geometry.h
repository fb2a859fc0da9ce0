#pragma once
// A triangle's cross product, area and unit normal, written once for every stage (in the spirit
// of pmp's differential_geometry.h). Each is one fixed sequence of floating-point operations, so
// every caller gets bit-identical results for the same corners: outputs are hashed, and a
// rewritten copy (another corner as origin, the 0.5 elsewhere) changes them in the last bit.
// float and double corners both work; the result has the corners' precision.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <vector>

namespace meshtour {

template <class Scalar>
using Point3 = Eigen::Matrix<Scalar, 3, 1>;

/// (b − a) × (c − a): normal to the triangle a, b, c (pointing to where the corners turn
/// counter-clockwise), twice its area long; zero when the triangle is degenerate.
template <class Scalar>
Point3<Scalar> triangle_cross(const Point3<Scalar>& a, const Point3<Scalar>& b, const Point3<Scalar>& c) {
  return (b - a).cross(c - a);
}

/// The triangle's area, ½ |(b − a) × (c − a)|.
template <class Scalar>
Scalar triangle_area(const Point3<Scalar>& a, const Point3<Scalar>& b, const Point3<Scalar>& c) {
  return Scalar(0.5) * triangle_cross(a, b, c).norm();
}

/// The triangle's unit normal (counter-clockwise corners seen from where it points); zero when
/// the triangle is degenerate (Eigen's normalized() of a zero vector).
template <class Scalar>
Point3<Scalar> triangle_normal(const Point3<Scalar>& a, const Point3<Scalar>& b, const Point3<Scalar>& c) {
  return triangle_cross(a, b, c).normalized();
}

/// The same for a mesh's triangle `t` (vertex indices into `positions`).
template <class Scalar>
Point3<Scalar> triangle_cross(const std::vector<Point3<Scalar>>& positions, const std::array<std::uint32_t, 3>& t) {
  return triangle_cross(positions[t[0]], positions[t[1]], positions[t[2]]);
}
template <class Scalar>
Scalar triangle_area(const std::vector<Point3<Scalar>>& positions, const std::array<std::uint32_t, 3>& t) {
  return triangle_area(positions[t[0]], positions[t[1]], positions[t[2]]);
}
template <class Scalar>
Point3<Scalar> triangle_normal(const std::vector<Point3<Scalar>>& positions, const std::array<std::uint32_t, 3>& t) {
  return triangle_normal(positions[t[0]], positions[t[1]], positions[t[2]]);
}

}  // namespace meshtour
