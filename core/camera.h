#pragma once
// The camera, one definition for every stage: where it stands and looks (CameraPose, what a
// camera path yields), the same with a field of view (Camera, what the tracer renders), and the
// one look-at that turns either into a right-handed frame.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace meshtour {

/// A camera placement in model units: eye position, the point looked at, and the up direction.
struct CameraPose {
  Eigen::Vector3d eye = Eigen::Vector3d::Zero();
  Eigen::Vector3d target = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d up = Eigen::Vector3d::UnitY();
};

/// A pinhole camera: a pose and its vertical field of view.
struct Camera {
  Eigen::Vector3d eye = Eigen::Vector3d(0, 0, 5);
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  Eigen::Vector3d up = Eigen::Vector3d::UnitY();
  double vertical_fov_deg = 40.0;

  static Camera at(const CameraPose& pose, double vertical_fov_deg) { return {pose.eye, pose.target, pose.up, vertical_fov_deg}; }
  CameraPose pose() const { return {eye, target, up}; }
};

/// The camera's frame: forward towards the target, right and up completing it (right-handed,
/// orthonormal; the image's x is right, its y is up).
struct LookAtFrame {
  Eigen::Vector3d forward, right, up;
  /// The up direction was parallel to the view: right is an arbitrary perpendicular instead.
  bool up_along_view = false;
};

/// The look-at. Every stage that places a camera uses this one, so that the tracer's image, the
/// framing, the path search, the evaluation and the glTF export agree to the last bit.
inline LookAtFrame look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target, const Eigen::Vector3d& up) {
  LookAtFrame f;
  f.forward = (target - eye).normalized();
  f.right = f.forward.cross(up);
  if (!(f.right.norm() > 1e-9)) {
    f.right = f.forward.unitOrthogonal();
    f.up_along_view = true;
  }
  f.right.normalize();
  f.up = f.right.cross(f.forward);
  return f;
}
inline LookAtFrame look_at(const CameraPose& pose) { return look_at(pose.eye, pose.target, pose.up); }
inline LookAtFrame look_at(const Camera& camera) { return look_at(camera.eye, camera.target, camera.up); }

/// How much of the half-frame the model may fill across (x) and up (y) when `margin` of the
/// frame's smaller side stays free between the model and every edge (broadcast and social crops
/// ask for 5 %: the action-safe area). In tangent units a point at (x, y, z) in camera space is
/// inside when |x| <= x·tan(fov_x / 2)·z and |y| <= y·tan(fov_y / 2)·z.
struct FrameFill {
  double x = 1.0, y = 1.0;
};
/// `aspect` = width / height; `margin` in [0, 0.5).
inline FrameFill frame_fill(double aspect, double margin) {
  const double smaller_over_height = aspect < 1.0 ? aspect : 1.0, smaller_over_width = aspect > 1.0 ? 1.0 / aspect : 1.0;
  return {1.0 - 2.0 * margin * smaller_over_width, 1.0 - 2.0 * margin * smaller_over_height};
}

}  // namespace meshtour
