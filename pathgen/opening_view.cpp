#include "pathgen/opening_view.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.h"

namespace meshtour {
namespace {

// The part of v across the up axis.
Eigen::Vector3d horizontal(const Eigen::Vector3d& v, const Eigen::Vector3d& up) { return v - v.dot(up) * up; }

}  // namespace

OpeningViewPath::OpeningViewPath(std::unique_ptr<CameraPath> path, const Eigen::Vector3d& center, const Axis& up,
                                 const Eigen::Vector3d& direction, double lowest_deg)
    : path_(std::move(path)), center_(center), up_(up.vector()) {
  if (!(direction.norm() > 0.0) || !direction.allFinite()) throw InputError("the opening view has no direction");
  const Eigen::Vector3d d = direction.normalized();
  constexpr double kDeg = std::numbers::pi / 180.0;
  const double asked = std::asin(std::clamp(d.dot(up_), -1.0, 1.0));
  elevation_ = std::clamp(asked, lowest_deg * kDeg, 85.0 * kDeg);
  raised_ = asked < lowest_deg * kDeg - 1e-12;
  // Straight down or up, the direction names no azimuth: the path keeps its own.
  const CameraPose first = path_->pose(0.0);
  const Eigen::Vector3d from = horizontal(first.eye - first.target, up_), to = horizontal(d, up_);
  if (from.norm() > 1e-12 * (first.eye - first.target).norm() && to.norm() > 1e-9) {
    const double angle = std::atan2(up_.dot(from.cross(to)), from.dot(to));
    turn_ = Eigen::AngleAxisd(angle, up_).toRotationMatrix();
  }
}

CameraPose OpeningViewPath::pose(double t) const {
  CameraPose p = path_->pose(t);
  p.eye = center_ + turn_ * (p.eye - center_);
  p.target = center_ + turn_ * (p.target - center_);
  p.up = turn_ * p.up;
  const Eigen::Vector3d v = p.eye - p.target;
  const double distance = v.norm();
  const Eigen::Vector3d across = horizontal(v, up_);
  if (!(distance > 0.0) || !(across.norm() > 1e-12 * distance)) return p;
  const double own = std::asin(std::clamp(v.dot(up_) / distance, -1.0, 1.0));
  const double c = 0.5 * (1.0 + std::cos(2.0 * std::numbers::pi * (t - std::floor(t))));
  const double w = c * c;
  // A blend of two elevations at or above the floor's is at or above it too.
  const double e = (1.0 - w) * own + w * elevation_;
  p.eye = p.target + distance * (std::cos(e) * across.normalized() + std::sin(e) * up_);
  return p;
}

}  // namespace meshtour
