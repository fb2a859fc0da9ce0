#include <Eigen/Geometry>
#include "pathgen/camera_path.h"

#include <cmath>
#include <limits>
#include <numbers>

#include "core/error.h"

namespace meshtour {
namespace {
double radians(double deg) { return deg * std::numbers::pi / 180.0; }
}  // namespace

double Lens::horizontal_fov_deg() const {
  return 2.0 * std::atan(std::tan(radians(vertical_fov_deg) / 2.0) * aspect) * 180.0 / std::numbers::pi;
}

double fit_pullback(std::span<const Eigen::Vector3d> points, const CameraPose& pose, const Lens& lens) {
  const Eigen::Vector3d view = pose.target - pose.eye;
  if (!(view.norm() > 0.0)) throw InputError("camera eye and target coincide; cannot frame the model");
  const LookAtFrame frame = look_at(pose);
  if (frame.up_along_view) throw InputError("camera looks along its up axis; cannot frame the model");
  const Eigen::Vector3d &forward = frame.forward, &r = frame.right, &u = frame.up;
  // A point (x, y, z) in camera coordinates is in frame when |x| <= tx*z and |y| <= ty*z. Moving
  // the eye back by s adds s to every z, so each point needs s >= max(|x|/tx, |y|/ty) - z.
  const double keep = std::clamp(1.0 - lens.margin, 0.05, 1.0);
  const double ty = std::tan(radians(lens.vertical_fov_deg) / 2.0) * keep;
  const double tx = std::tan(radians(lens.vertical_fov_deg) / 2.0) * lens.aspect * keep;
  double needed = -std::numeric_limits<double>::infinity();
  for (const auto& p : points) {
    const Eigen::Vector3d q = p - pose.eye;
    const double z = q.dot(forward);
    const double s = std::max(std::abs(q.dot(r)) / tx, std::abs(q.dot(u)) / ty) - z;
    needed = std::max(needed, s);
  }
  return needed;
}

FramedPath::FramedPath(std::unique_ptr<CameraPath> path, std::span<const Eigen::Vector3d> points, const Lens& lens,
                       int samples)
    : path_(std::move(path)) {
  for (int k = 0; k < samples; ++k)
    pullback_ = std::max(pullback_, fit_pullback(points, path_->pose(static_cast<double>(k) / samples), lens));
}

CameraPose FramedPath::pose(double t) const {
  CameraPose p = path_->pose(t);
  if (pullback_ > 0.0) p.eye -= pullback_ * (p.target - p.eye).normalized();
  return p;
}

}  // namespace meshtour
