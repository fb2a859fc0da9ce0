#pragma once
// The turntable path: a circular orbit around the model's up axis, framed so the whole model
// stays in view at every angle. The baseline every geometry-driven path is compared with.
#include <span>

#include "core/axis.h"
#include "pathgen/camera_path.h"

namespace meshtour {

struct TurntableOptions {
  Axis up{1, false};             ///< the model's up axis (the orbit's axis)
  double elevation_deg = 15.0;   ///< camera height above the model's centre, as an angle
  double revolutions = 1.0;      ///< turns per loop (an integer keeps the loop seamless)
  Lens lens;
};

/// What a turntable orbit is once fitted to a model: enough to rebuild it without the model
/// (the path file of pathgen/path_file.h).
struct TurntableGeometry {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d up = Eigen::Vector3d::UnitY(), front = Eigen::Vector3d::UnitZ(), side = Eigen::Vector3d::UnitX();
  double radius = 1.0;
  double elevation_deg = 15.0;
  double revolutions = 1.0;
};

/// Circular orbit around the vertical line through the centre of the bounding box, counter-
/// clockwise seen from +up, starting in front of the model (+Z for a Y-up model, -Y for Z-up,
/// +Z for X-up). The orbit's height is adjusted so the model looks vertically centred, and its
/// radius is the smallest that keeps every vertex in frame at every angle.
class TurntablePath final : public CameraPath {
public:
  /// `points`: the model's vertices, or only the vertices of their convex hull
  /// (convex_hull_vertices() of mesh/convex_hull.h), which gives the same orbit far faster on a
  /// big mesh: every fit is the largest of linear functions of a point (the bounding box, the
  /// pull-back) or of a ratio of them with a positive denominator (the vertical balance), which a
  /// hull vertex attains.
  /// \throw InputError if there are no points or they all coincide.
  TurntablePath(std::span<const Eigen::Vector3d> points, const TurntableOptions& options);
  /// The orbit of a fitted geometry (the same poses, bit for bit, as the path it was taken from).
  explicit TurntablePath(const TurntableGeometry& geometry);
  CameraPose pose(double t) const override;

  double radius() const { return radius_; }
  const Eigen::Vector3d& center() const { return center_; }
  TurntableGeometry geometry() const;

private:
  Eigen::Vector3d direction(double angle) const;  // unit vector from centre to eye
  double fit_radius(std::span<const Eigen::Vector3d> points, double size) const;
  double vertical_imbalance(std::span<const Eigen::Vector3d> points) const;
  static constexpr int kFramingAngles = 180;

  TurntableOptions options_;
  Eigen::Vector3d center_, up_, front_, side_;
  double radius_ = 0.0;
};

}  // namespace meshtour
