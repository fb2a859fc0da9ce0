#include "pathgen/motion.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace meshtour {
namespace {

// Columns: right, up, -direction (the tracer's camera frame).
Eigen::Matrix3d frame(const Eigen::Vector3d& direction, const Eigen::Vector3d& up) {
  const Eigen::Vector3d d = direction.normalized();
  Eigen::Vector3d right = d.cross(up);
  if (!(right.norm() > 1e-9)) right = d.unitOrthogonal();
  right.normalize();
  Eigen::Matrix3d m;
  m.col(0) = right;
  m.col(1) = right.cross(d);
  m.col(2) = -d;
  return m;
}

}  // namespace

std::pair<double, double> angular_motion(const std::vector<Eigen::Vector3d>& directions, const std::vector<Eigen::Vector3d>& ups) {
  const std::size_t n = directions.size();
  if (n < 2) return {0.0, 0.0};
  std::vector<Eigen::Matrix3d> frames(n);
  for (std::size_t k = 0; k < n; ++k) frames[k] = frame(directions[k], ups[k]);
  std::vector<Eigen::Vector3d> omega(n);
  double speed = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t next = (k + 1) % n;
    const Eigen::Vector3d a = directions[k].normalized(), b = directions[next].normalized();
    speed = std::max(speed, std::atan2(a.cross(b).norm(), a.dot(b)));
    const Eigen::AngleAxisd step(Eigen::Matrix3d(frames[next] * frames[k].transpose()));
    omega[k] = step.angle() * step.axis();
  }
  double acceleration = 0.0;
  if (n >= 3)
    for (std::size_t k = 0; k < n; ++k) acceleration = std::max(acceleration, (omega[(k + 1) % n] - omega[k]).norm());
  return {speed, acceleration};
}

}  // namespace meshtour
