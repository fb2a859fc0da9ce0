#include <Eigen/Geometry>
#include "pathgen/camera_path.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

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
  const FrameFill fill = frame_fill(lens.aspect, std::clamp(lens.margin, 0.0, 0.45));
  const double ty = std::tan(radians(lens.vertical_fov_deg) / 2.0) * fill.y;
  const double tx = std::tan(radians(lens.vertical_fov_deg) / 2.0) * lens.aspect * fill.x;
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

UniformTurnPath::UniformTurnPath(std::unique_ptr<CameraPath> path, int samples) : path_(std::move(path)) {
  if (samples < 2) throw std::logic_error("UniformTurnPath: needs at least 2 samples");
  const auto view = [this](double s) {
    const CameraPose p = path_->pose(s);
    return Eigen::Vector3d(p.target - p.eye).normalized();
  };
  std::vector<double> turn(static_cast<std::size_t>(samples) + 1, 0.0);
  Eigen::Vector3d previous = view(0.0);
  double fastest = 0.0;
  for (int i = 1; i <= samples; ++i) {
    const Eigen::Vector3d next = view(static_cast<double>(i) / samples);
    // atan2 of the cross and dot products: accurate for the small angles between samples.
    const double step = std::atan2(previous.cross(next).norm(), previous.dot(next));
    turn[static_cast<std::size_t>(i)] = turn[static_cast<std::size_t>(i) - 1] + (std::isfinite(step) ? step : 0.0);
    fastest = std::max(fastest, step);
    previous = next;
  }
  const double total = turn.back();
  if (!(total > 1e-9)) return;  // a still view: nothing to even out
  for (double& v : turn) v /= total;
  turn.back() = 1.0;
  turn_ = std::move(turn);
  unevenness_ = fastest * samples / total;
}

double UniformTurnPath::parameter(double t) const {
  if (turn_.empty()) return t;
  const double whole = std::floor(t), share = t - whole;
  // The sample interval [i, i + 1] whose turn holds `share` (turn_ rises from 0 to 1).
  const auto above = std::upper_bound(turn_.begin() + 1, turn_.end() - 1, share);
  const std::size_t i = static_cast<std::size_t>(above - turn_.begin()) - 1;
  const double width = turn_[i + 1] - turn_[i];
  const double within = width > 0.0 ? std::clamp((share - turn_[i]) / width, 0.0, 1.0) : 0.0;
  const double samples = static_cast<double>(turn_.size() - 1);
  return whole + (static_cast<double>(i) + within) / samples;
}

CameraPose UniformTurnPath::pose(double t) const { return path_->pose(parameter(t)); }

}  // namespace meshtour
