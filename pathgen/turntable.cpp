#include <Eigen/Geometry>
#include "pathgen/turntable.h"

#include <cmath>
#include <limits>
#include <numbers>

#include "core/error.h"
#include "core/interrupt.h"

namespace meshtour {
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
  radius_ = fit_radius(points, (hi - lo).norm());
  // An elevated camera sees the near bottom edge low in the frame and the top high, so the bounding
  // box centre is not where the model looks centred. Move the orbit along the up axis until the
  // model's vertical extent is balanced in the frame (averaged over the orbit), then refit.
  const double ty = std::tan(options.lens.vertical_fov_deg * std::numbers::pi / 360.0);
  for (int iteration = 0; iteration < 3; ++iteration) {
    center_ += vertical_imbalance(points) * ty * radius_ * up_;
    radius_ = fit_radius(points, (hi - lo).norm());
  }
}

TurntablePath::TurntablePath(const TurntableGeometry& g)
    : center_(g.center), up_(g.up), front_(g.front), side_(g.side), radius_(g.radius) {
  options_.elevation_deg = g.elevation_deg;
  options_.revolutions = g.revolutions;
}

TurntableGeometry TurntablePath::geometry() const {
  return TurntableGeometry{center_, up_, front_, side_, radius_, options_.elevation_deg, options_.revolutions};
}

double TurntablePath::fit_radius(std::span<const Eigen::Vector3d> points, double size) const {
  double radius = 0.0;
  const double start = 1e-6 * size;
  for (int k = 0; k < kFramingAngles; ++k) {
    throw_if_interrupted();  // each angle reads every vertex: seconds in all on a big scan
    const double angle = 2.0 * std::numbers::pi * k / kFramingAngles;
    // Put the eye (almost) at the centre and ask how far back it has to go.
    const CameraPose near_center{center_ + direction(angle) * start, center_, up_};
    radius = std::max(radius, start + fit_pullback(points, near_center, options_.lens));
  }
  return radius;
}

double TurntablePath::vertical_imbalance(std::span<const Eigen::Vector3d> points) const {
  // Mean over the orbit of the middle of the model's vertical extent, in units of the half-frame
  // (tan of half the field of view): positive when the model sits high in the frame.
  constexpr int kAngles = 24;
  const double ty = std::tan(options_.lens.vertical_fov_deg * std::numbers::pi / 360.0);
  double sum = 0.0;
  for (int k = 0; k < kAngles; ++k) {
    const CameraPose p = pose(static_cast<double>(k) / kAngles);
    const LookAtFrame frame = look_at(p);
    const Eigen::Vector3d &forward = frame.forward, &up = frame.up;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const auto& q : points) {
      const Eigen::Vector3d d = q - p.eye;
      const double y = d.dot(up) / (d.dot(forward) * ty);
      lo = std::min(lo, y);
      hi = std::max(hi, y);
    }
    sum += 0.5 * (lo + hi);
  }
  return sum / kAngles;
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
