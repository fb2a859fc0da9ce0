#pragma once
// Stages §9–§14 of docs/METHOD.md: the bounding cylinder, the m×n grid of cell weights, one control
// point per column, the periodic B-spline base curve, the gaze and position paths, the start
// point and the reported metrics. Built on the surface analysis of §3–§8 (pathgen/surface.h).
//
// Everything is computed in normalized units (AABB diagonal of the smoothed model = 1);
// PaperCameraPath maps its poses back to the input model's units.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/axis.h"
#include "mesh/mesh.h"
#include "pathgen/bspline.h"
#include "pathgen/camera_path.h"
#include "pathgen/cylinder.h"
#include "pathgen/grid.h"
#include "pathgen/surface.h"

namespace meshtour {

enum class HeightReference { mid_height, curve_mean };       ///< I-25: u_ref of the stabilization
enum class GazeRadiusMode { cylinder, scaled };              ///< I-26: r or s_g·r

std::string to_string(HeightReference mode);
std::string to_string(GazeRadiusMode mode);

/// Every option of the paper path (§2 defaults).
struct PaperPathOptions {
  SurfaceOptions surface;  ///< §3–§8
  UpDirection up;          ///< cylinder axis direction (I-18), default +Y
  AxisPointMode axis_point = AxisPointMode::surface_centroid;
  int rows = 11;     ///< m, grid rows along the height
  int columns = 20;  ///< n, grid columns around the axis (= number of control points)
  CellAveraging cell_averaging = CellAveraging::mean;
  EmptyColumnMode empty_columns = EmptyColumnMode::middle_row;
  int degree = 3;             ///< B-spline degree p (I-23)
  double gaze_scale = 0.5;    ///< s_g
  double position_scale = 0.25;  ///< s_p
  HeightReference height_reference = HeightReference::mid_height;
  GazeRadiusMode gaze_radius = GazeRadiusMode::cylinder;
  int samples = 360;  ///< K, samples per loop for the CSV and the plot

  /// \throw InputError naming the option when a value is out of range.
  void validate() const;
};

/// The gaze and position paths of §13 and the map back to model units: all read_path_file needs
/// to rebuild the camera path.
struct PaperPathGeometry {
  Cylinder cylinder;
  PeriodicBSpline curve;            ///< U(t), the base curve's normalized height
  double height_reference = 0.5;    ///< u_ref (resolved)
  double gaze_scale = 0.5;          ///< s_g
  double position_scale = 0.25;     ///< s_p
  double gaze_radius = 0.0;         ///< r or s_g·r (resolved)
  double position_radius = 0.0;     ///< k_r·r
  double start_parameter = 0.0;     ///< t0
  double scale = 1.0;               ///< model = scale · normalized + offset
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();

  // Curve functions of the curve parameter t (not shifted by t0), normalized units.
  double base_height(double t) const { return curve.value(t); }
  double gaze_height(double t) const;
  double position_height(double t) const;
  double angle(double t) const;  ///< V(t) = π/n + 2πt, in [0, 2π)
  Eigen::Vector3d base_point(double t) const;
  Eigen::Vector3d gaze_point(double t) const;
  Eigen::Vector3d position_point(double t) const;
};

/// The camera path of the paper: eye on the position path, target on the gaze path, up = û,
/// in model units. pose(t) samples the curves at t0 + t, so t = 0 is the start point (§13.2).
class PaperCameraPath final : public CameraPath {
public:
  explicit PaperCameraPath(PaperPathGeometry geometry) : geometry_(std::move(geometry)) {}
  CameraPose pose(double t) const override;
  /// The same pose in normalized units.
  CameraPose normalized_pose(double t) const;
  const PaperPathGeometry& geometry() const { return geometry_; }

private:
  PaperPathGeometry geometry_;
};

/// §14.
struct PathMetrics {
  double amplitude_curve = 0.0;     ///< max U − min U (fraction of h)
  double amplitude_gaze = 0.0;      ///< A: the same for U_g (I-28)
  double amplitude_position = 0.0;  ///< the same for U_p
  int extreme_points = 0;           ///< E
  double weight_max = 0.0;          ///< Wmax
  double weight_avg = 0.0;          ///< Wavg over all m·n cells (I-29)
  double weight_avg_nonempty = 0.0;
  int empty_cells = 0;
  double height_over_radius = 0.0;  ///< h/r
  double radius_factor = 4.0;       ///< k_r
};

/// k_r of §13.1: 6 if h/r > 2, else 4.
double position_radius_factor(double height, double radius);

/// Everything the path command reports and writes.
struct PaperPathResult {
  PaperPathOptions options;
  SurfaceAnalysis surface;
  Eigen::Vector3d up = Eigen::Vector3d::UnitY();  ///< the resolved û
  Cylinder cylinder;
  CellGrid grid;
  ControlPoints control;
  StartCell start;
  PaperPathGeometry geometry;
  PathMetrics metrics;
  /// Wall time of every stage, §3–§8 (from analyze_surface) then §9–§14, in order.
  std::vector<std::pair<std::string, double>> stage_seconds;

  PaperCameraPath camera_path() const { return PaperCameraPath(geometry); }
};

/// The whole method: analyze_surface (§3–§8), then §9–§14.
/// \throw InputError for unusable meshes or options.
PaperPathResult compute_paper_path(const TriangleMesh& mesh, const PaperPathOptions& options);

/// The camera path alone (for `meshtour tour`): compute_paper_path(mesh, options).camera_path().
std::unique_ptr<CameraPath> make_paper_camera_path(const TriangleMesh& mesh, const PaperPathOptions& options);

/// §9–§14 on an already analysed surface (positions, triangles, face weights; the patch data is
/// only copied to the result). Lets tests drive these stages with synthetic inputs.
PaperPathResult compute_paper_path(SurfaceAnalysis surface, const PaperPathOptions& options);

}  // namespace meshtour
