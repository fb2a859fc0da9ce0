// Automatic field of view: the narrowest lens that keeps every vertex in every frame.
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.h"
#include "core/interrupt.h"
#include "tracer/tracer.h"

namespace meshtour {

double fit_vertical_fov(const std::vector<Camera>& cameras, std::span<const Eigen::Vector3d> positions, double aspect,
                        double margin) {
  return fit_vertical_fov(cameras, positions, {}, aspect, margin);
}

double fit_vertical_fov(const std::vector<Camera>& cameras, std::span<const Eigen::Vector3d> positions,
                        std::span<const Eigen::Vector3d> hull, double aspect, double margin) {
  if (!(aspect > 0.0)) throw InputError("the frame's aspect ratio must be positive");
  if (!(margin >= 0.0 && margin < 0.5)) throw InputError("the framing margin must be at least 0 and under half the frame");
  const FrameFill fill = frame_fill(aspect, margin);
  // The half-height tangent each vertex needs: |y|/z vertically, |x|/z / aspect horizontally.
  double needed = 0.0;
  bool any = false;
  for (const Camera& c : cameras) {
    throw_if_interrupted();  // every frame reads every vertex (or hull vertex)
    const LookAtFrame view = look_at(c);
    const Eigen::Vector3d &f = view.forward, &r = view.right, &u = view.up;
    // z is linear in the point: its smallest value over the vertices is its smallest over the hull.
    const bool hull_in_front = !hull.empty() && std::all_of(hull.begin(), hull.end(), [&](const Eigen::Vector3d& p) {
      return (p - c.eye).dot(f) > 0.0;
    });
    for (const auto& p : hull_in_front ? hull : positions) {
      const Eigen::Vector3d d = p - c.eye;
      const double z = d.dot(f);
      if (!(z > 0.0)) continue;
      any = true;
      needed = std::max({needed, std::abs(d.dot(u)) / z / fill.y, std::abs(d.dot(r)) / z / aspect / fill.x});
    }
  }
  if (!any) throw InputError("no vertex of the model is in front of the camera; check the camera path");
  const double fov = 2.0 * std::atan(needed) * 180.0 / std::numbers::pi;
  if (!(fov <= 170.0))
    throw InputError("the model cannot be kept in frame (it would need a " + std::to_string(fov) +
                     " degree field of view); move the camera further away or fix the field of view");
  return std::max(fov, 1e-3);
}

}  // namespace meshtour
