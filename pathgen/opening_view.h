#pragma once
// A path that starts at a given view: a scene document's opening view (a Voyager document's
// navigation setup, scenes/voyager.h) as frame 0 of a tour whose path was chosen for the model.
#include <Eigen/Core>
#include <memory>

#include "core/axis.h"
#include "pathgen/camera_path.h"

namespace meshtour {

/// Wraps a closed path so that t = 0 looks from `direction` (unit, from the model to the eye):
///  * azimuth: the whole path turns about the up axis through `center` until its first view's
///    azimuth is the direction's, so the path keeps its shape (and what its search chose it for);
///  * elevation: each view's elevation is blended towards the direction's, fully at t = 0 and
///    fading smoothly (weight ((1 + cos 2πt) / 2)², periodic, so the loop stays seamless) to the
///    path's own half-way round.
/// The floor rule holds: the opening elevation is raised to `lowest_deg` (0: level with the
/// centre, which no eye goes below, so none is below the floor the model stands on) and capped at
/// 85 degrees, where the azimuth is still defined. Distances and targets are the path's own.
class OpeningViewPath final : public CameraPath {
public:
  OpeningViewPath(std::unique_ptr<CameraPath> path, const Eigen::Vector3d& center, const Axis& up,
                  const Eigen::Vector3d& direction, double lowest_deg = 0.0);
  CameraPose pose(double t) const override;
  /// The elevation frame 0 looks from, degrees (the direction's, after the floor and the cap).
  double opening_elevation_deg() const { return elevation_ * 57.29577951308232; }
  /// Whether the floor raised the opening view (it looked from below the model's centre).
  bool raised() const { return raised_; }

private:
  std::unique_ptr<CameraPath> path_;
  Eigen::Vector3d center_, up_;
  Eigen::Matrix3d turn_ = Eigen::Matrix3d::Identity();  ///< about up_, first azimuth onto the direction's
  double elevation_ = 0.0;  ///< radians
  bool raised_ = false;
};

}  // namespace meshtour
