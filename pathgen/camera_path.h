#pragma once
// Camera paths: where the camera is and what it looks at, as a function of the loop fraction.
// Every path mode (turntable, the paper's toroidal-patch path, a path file) implements CameraPath.
#include <Eigen/Core>
#include <memory>
#include <span>
#include <vector>

#include "core/camera.h"

namespace meshtour {

/// A camera placement in model units: eye position, the point looked at, and the up direction.

/// What the camera sees: the vertical field of view and the image aspect ratio (width / height).
struct Lens {
  double vertical_fov_deg = 40.0;
  double aspect = 16.0 / 9.0;
  /// Space kept free between the model and every edge of the frame, as a share of the frame's
  /// smaller side (core/camera.h frame_fill): the 5 % action-safe margin broadcast and social crops
  /// expect, plus 1 % for the soft edge the pixel filter draws around the model (1.5 pixels:
  /// 1.7 % of a 90-pixel-high test frame, 0.2 % at 720p) and the framing's sampling of the loop.
  double margin = 0.06;

  double horizontal_fov_deg() const;
};

/// A closed camera path. t is the loop fraction: t and t + 1 give the same pose.
class CameraPath {
public:
  virtual ~CameraPath() = default;
  /// Pose at loop fraction t (any real number; the path is periodic with period 1).
  virtual CameraPose pose(double t) const = 0;
};

/// Pose of frame k of a loop of `frame_count` frames: t = k / frame_count, so the last frame
/// stops one step short of the first and the video loops seamlessly. The step is the same in t
/// everywhere; a path whose view should turn evenly says so in its t (UniformTurnPath).
inline CameraPose frame_pose(const CameraPath& path, int frame, int frame_count) {
  return path.pose(static_cast<double>(frame) / static_cast<double>(frame_count));
}

/// Wraps a path so that the model stays in frame: every eye moves back along its view direction
/// by the largest distance any of `samples` poses around the loop needs (one constant distance,
/// so the framing does not pump). A path that already frames the model is left unchanged.
/// `points` may be the model's vertices or only their convex hull's vertices (mesh/convex_hull.h):
/// fit_pullback() is the largest of linear functions of a point, which a hull vertex attains, so
/// both give the same pull-back.
class FramedPath final : public CameraPath {
public:
  FramedPath(std::unique_ptr<CameraPath> path, std::span<const Eigen::Vector3d> points, const Lens& lens,
             int samples = 180);
  CameraPose pose(double t) const override;
  /// How far every eye was moved back (0 if the path already framed the model).
  double pullback() const { return pullback_; }

private:
  std::unique_ptr<CameraPath> path_;
  double pullback_ = 0.0;
};

/// Wraps a closed path so that its view direction (eye to target) turns at a constant rate: t is
/// the share of the loop's whole turn (the sum of the angles between view directions) made since
/// t = 0. Frames sampled evenly in t (frame_pose) are then equally many degrees apart, the last
/// to the first included, at any frame count, where the wrapped path may slow down and speed up
/// along its parameter (an orbit that climbs, a curve whose knots are not evenly spaced). t = 0
/// is the wrapped path's t = 0, so the first frame stays. The turn is tabulated at `samples`
/// points of the wrapped parameter and inverted piecewise linearly (tests/pathgen_uniform_turn_test
/// measures the steps). A path whose view does not turn is left as it is.
class UniformTurnPath final : public CameraPath {
public:
  explicit UniformTurnPath(std::unique_ptr<CameraPath> path, int samples = 8192);
  CameraPose pose(double t) const override;
  /// The wrapped path's parameter at loop fraction t (t + 1 gives the parameter + 1).
  double parameter(double t) const;
  /// The wrapped path's fastest turn over its mean (1 for a path that already turns evenly).
  double unevenness() const { return unevenness_; }

private:
  std::unique_ptr<CameraPath> path_;
  std::vector<double> turn_;  ///< share of the whole turn at wrapped parameter i / samples; [samples] = 1
  double unevenness_ = 1.0;
};

/// Signed distance by which the eye of `pose` must move back along its view direction so that
/// every point lies inside the view frustum of `lens` (with its margin). Negative when the camera
/// could move closer. Points behind the eye are handled: the result always brings them in front.
/// The result over a point set's convex hull vertices is the result over the set (see FramedPath).
/// \throw InputError if `pose` has eye == target or up parallel to the view direction.
double fit_pullback(std::span<const Eigen::Vector3d> points, const CameraPose& pose, const Lens& lens);

}  // namespace meshtour
