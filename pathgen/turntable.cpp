#include <Eigen/Geometry>
#include "pathgen/turntable.h"

#include <cmath>
#include <numbers>

#include "core/error.h"

namespace meshtour {
namespace {

// The conventional "front" of a model for each up axis: +Z for Y-up (OpenGL, most scanners),
// -Y for Z-up (Blender and CAD), +Z for X-up.
Eigen::Vector3d front_direction(const Axis& up) {
  switch (up.index) {
    case 2: return -Eigen::Vector3d::UnitY();
    default: return Eigen::Vector3d::UnitZ();
  }
}

}  // namespace

TurntablePath::TurntablePath(std::span<const Eigen::Vector3d> points, const TurntableOptions& options)
    : options_(options) {
  if (points.empty()) throw InputError("turntable: the model has no vertices");
  Eigen::Vector3d lo = points.front(), hi = points.front();
  for (const auto& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  if (!(std::abs(options.elevation_deg) < 89.0))
    throw InputError("turntable: elevation must be between -89 and 89 degrees");
  if (!((hi - lo).norm() > 0.0)) throw InputError("turntable: all vertices coincide; nothing to frame");
  center_ = 0.5 * (lo + hi);
  up_ = options.up.vector();
  front_ = front_direction(options.up);
  side_ = up_.cross(front_);  // completes a right-handed frame; increasing angle turns CCW seen from +up

  // The orbit radius is the largest distance any orbit angle needs to keep every vertex in view.
  // Sampling 180 angles is exact enough: between samples the margin of the lens absorbs the rest.
  constexpr int kAngles = 180;
  double radius = 0.0;
  for (int k = 0; k < kAngles; ++k) {
    const double angle = 2.0 * std::numbers::pi * k / kAngles;
    // Put the eye (almost) at the centre and ask how far back it has to go.
    const double start = 1e-6 * (hi - lo).norm();
    const CameraPose near_center{center_ + direction(angle) * start, center_, up_};
    radius = std::max(radius, start + fit_pullback(points, near_center, options.lens));
  }
  radius_ = radius;
}

Eigen::Vector3d TurntablePath::direction(double angle) const {
  const double elevation = options_.elevation_deg * std::numbers::pi / 180.0;
  const Eigen::Vector3d horizontal = std::cos(angle) * front_ + std::sin(angle) * side_;
  return std::cos(elevation) * horizontal + std::sin(elevation) * up_;
}

CameraPose TurntablePath::pose(double t) const {
  const double angle = 2.0 * std::numbers::pi * options_.revolutions * (t - std::floor(t));
  return CameraPose{center_ + radius_ * direction(angle), center_, up_};
}

}  // namespace meshtour
