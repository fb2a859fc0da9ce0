// §9: up direction, angular frame and the bounding cylinder.
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <sstream>
#include <tuple>

#include "core/error.h"
#include "core/triangle_geometry.h"
#include "pathgen/cylinder.h"

namespace meshtour {
namespace {

std::string format_vector(const Eigen::Vector3d& v) {
  std::ostringstream out;
  out << '(' << v.x() << ", " << v.y() << ", " << v.z() << ')';
  return out.str();
}

std::string lower(std::string_view text) {
  std::string s(text);
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

const char* const kUpForms = "use x, y, z, -x, -y, -z, a vector such as 0,1,0.2, longest-aabb or pca";

// "a,b,c" → vector; nullopt-like false when the text is not three numbers.
bool parse_vector(const std::string& text, Eigen::Vector3d& out) {
  std::istringstream in(text);
  for (int k = 0; k < 3; ++k) {
    if (!(in >> out[k])) return false;
    if (k < 2) {
      char comma = 0;
      if (!(in >> comma) || comma != ',') return false;
    }
  }
  in >> std::ws;
  return in.eof();
}

}  // namespace

UpDirection UpDirection::parse(std::string_view text) {
  const std::string t = lower(text);
  UpDirection up;
  if (t == "longest-aabb") {
    up.kind = Kind::longest_aabb;
    return up;
  }
  if (t == "pca") {
    up.kind = Kind::pca;
    return up;
  }
  if (t.find(',') != std::string::npos) {
    Eigen::Vector3d v;
    if (!parse_vector(t, v))
      throw InputError("invalid up direction '" + std::string(text) + "': a vector is three numbers separated by commas, e.g. 0,1,0.2");
    const double norm = v.norm();
    if (!(norm > 1e-12) || !std::isfinite(norm))
      throw InputError("invalid up direction '" + std::string(text) + "': the vector must be finite and non-zero");
    up.kind = Kind::vector;
    up.vector = v / norm;
    return up;
  }
  try {
    up.axis = Axis::parse(t);
  } catch (const InputError&) {
    throw InputError("invalid up direction '" + std::string(text) + "': " + kUpForms);
  }
  up.kind = Kind::axis;
  return up;
}

std::string UpDirection::name() const {
  switch (kind) {
    case Kind::axis: return axis.name();
    case Kind::longest_aabb: return "longest-aabb";
    case Kind::pca: return "pca";
    case Kind::vector: {
      std::ostringstream out;
      out.precision(17);
      out << vector.x() << ',' << vector.y() << ',' << vector.z();
      return out.str();
    }
  }
  return "?";
}

std::pair<Eigen::Vector3d, Eigen::Vector3d> angular_frame(const Eigen::Vector3d& up) {
  // The coordinate axes get the fixed frames of the table in §9.1 (so +Y up starts at +Z, the
  // front of a Stanford-style model); the negative axes keep e_x and flip e_y to stay right-handed.
  for (int k = 0; k < 3; ++k) {
    for (double sign : {1.0, -1.0}) {
      Eigen::Vector3d axis = Eigen::Vector3d::Zero();
      axis[k] = sign;
      if (up != axis) continue;
      Eigen::Vector3d e_x = Eigen::Vector3d::Zero();
      e_x[(k + 1) % 3] = 1.0;  // +Y → +Z, +Z → +X, +X → +Y
      return {e_x, up.cross(e_x)};
    }
  }
  // Any other direction: project the world axis most orthogonal to û (ties: X, then Y, then Z).
  int best = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(up[k]) < std::abs(up[best])) best = k;
  const Eigen::Vector3d e_c = Eigen::Vector3d::Unit(best);
  const Eigen::Vector3d e_x = (e_c - e_c.dot(up) * up).normalized();
  return {e_x, up.cross(e_x)};
}

Eigen::Vector3d Cylinder::point(double u, double theta, double rho) const {
  return axis_foot(base + u * height) + rho * (std::cos(theta) * e_x + std::sin(theta) * e_y);
}

double Cylinder::axis_distance(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d d = p - axis_point;
  return (d - d.dot(up) * up).norm();
}

Eigen::Vector3d resolve_up(const UpDirection& up, const std::vector<Eigen::Vector3d>& positions,
                           const std::vector<std::array<std::uint32_t, 3>>& triangles) {
  switch (up.kind) {
    case UpDirection::Kind::axis: return up.axis.vector();
    case UpDirection::Kind::vector: return up.vector.normalized();
    case UpDirection::Kind::longest_aabb: {
      if (positions.empty()) throw InputError("cannot choose the longest bounding-box axis of an empty mesh");
      Eigen::Vector3d lo = positions.front(), hi = positions.front();
      for (const auto& p : positions) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
      const Eigen::Vector3d extent = hi - lo;
      int best = 0;  // ties: the first of X, Y, Z
      for (int k = 1; k < 3; ++k)
        if (extent[k] > extent[best]) best = k;
      return Eigen::Vector3d::Unit(best);
    }
    case UpDirection::Kind::pca: {
      // Exact second moments of the surface as a uniform area distribution: for a triangle
      // (a, b, c) of area A, ∫ x xᵀ dA = A/12 (a aᵀ + b bᵀ + c cᵀ + s sᵀ) with s = a + b + c.
      double area = 0.0;
      Eigen::Vector3d first = Eigen::Vector3d::Zero();
      Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
      for (const auto& tri : triangles) {
        const Eigen::Vector3d& a = positions[tri[0]];
        const Eigen::Vector3d& b = positions[tri[1]];
        const Eigen::Vector3d& c = positions[tri[2]];
        const double A = triangle_area(a, b, c);
        const Eigen::Vector3d s = a + b + c;
        area += A;
        first += A * s / 3.0;
        second += A / 12.0 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
      }
      if (!(area > 0.0)) throw InputError("cannot compute the principal axis (--up pca) of a mesh without area");
      const Eigen::Vector3d mean = first / area;
      const Eigen::Matrix3d covariance = second / area - mean * mean.transpose();
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
      Eigen::Vector3d v = solver.eigenvectors().col(2).normalized();  // eigenvalues ascend
      // An eigenvector's sign is arbitrary: make its largest component positive so that the
      // result is reproducible (a Y-elongated model gets +Y, not −Y).
      int big = 0;
      for (int k = 1; k < 3; ++k)
        if (std::abs(v[k]) > std::abs(v[big])) big = k;
      if (v[big] < 0.0) v = -v;
      return v;
    }
  }
  return Eigen::Vector3d::UnitY();
}

Cylinder fit_cylinder(const std::vector<Eigen::Vector3d>& positions,
                      const std::vector<std::array<std::uint32_t, 3>>& triangles, const Eigen::Vector3d& up,
                      AxisPointMode axis_point) {
  if (positions.empty() || triangles.empty())
    throw InputError("cannot fit the bounding cylinder: the mesh has no faces");
  Cylinder cyl;
  cyl.up = up.normalized();
  std::tie(cyl.e_x, cyl.e_y) = angular_frame(cyl.up);

  Eigen::Vector3d lo = positions.front(), hi = positions.front();
  for (const auto& p : positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Eigen::Vector3d aabb_center = 0.5 * (lo + hi);
  if (axis_point == AxisPointMode::aabb_center) {
    cyl.axis_point = aabb_center;
  } else {
    // Area-weighted centroid, summed in face order so the result is bitwise reproducible.
    double area = 0.0;
    Eigen::Vector3d moment = Eigen::Vector3d::Zero();
    for (const auto& tri : triangles) {
      const Eigen::Vector3d& a = positions[tri[0]];
      const Eigen::Vector3d& b = positions[tri[1]];
      const Eigen::Vector3d& c = positions[tri[2]];
      const double A = triangle_area(a, b, c);
      area += A;
      moment += A * ((a + b + c) / 3.0);
    }
    // A mesh without area has no centroid; its bounding-box centre is the only sensible axis.
    cyl.axis_point = area > 0.0 ? Eigen::Vector3d(moment / area) : aabb_center;
  }

  double eta_min = std::numeric_limits<double>::infinity();
  double eta_max = -eta_min;
  double radius = 0.0;
  for (const auto& p : positions) {
    const double eta = p.dot(cyl.up);
    eta_min = std::min(eta_min, eta);
    eta_max = std::max(eta_max, eta);
    radius = std::max(radius, cyl.axis_distance(p));
  }
  cyl.base = eta_min;
  cyl.height = eta_max - eta_min;
  cyl.radius = radius;
  if (!(cyl.height >= 1e-9))
    throw InputError("the model is flat across the up direction " + format_vector(cyl.up) +
                     " (bounding-cylinder height 0): choose another --up");
  if (!(cyl.radius >= 1e-9))
    throw InputError("the model is a line along the up direction " + format_vector(cyl.up) +
                     " (bounding-cylinder radius 0): choose another --up");
  return cyl;
}

}  // namespace meshtour
