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

}  // namespace meshtour
