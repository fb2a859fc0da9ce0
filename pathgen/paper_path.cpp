// §12–§14 glue: the gaze and position paths, the camera path, the metrics and the whole pipeline.
#include "pathgen/paper_path.h"
#include "pathgen/stage_timer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <string>

#include "core/angles.h"
#include "core/error.h"

namespace meshtour {
namespace {

void require_finite_in(double value, double lo, double hi, const std::string& what) {
  if (!(value >= lo && value <= hi))
    throw InputError(what + " must be between " + std::to_string(lo) + " and " + std::to_string(hi) +
                     ", got " + std::to_string(value));
}

}  // namespace

std::string to_string(AxisPointMode mode) {
  return mode == AxisPointMode::surface_centroid ? "centroid" : "aabb-center";
}
std::string to_string(CellAveraging mode) { return mode == CellAveraging::mean ? "mean" : "area-weighted"; }
std::string to_string(EmptyColumnMode mode) {
  return mode == EmptyColumnMode::middle_row ? "middle-row" : "interpolate";
}
std::string to_string(HeightReference mode) {
  return mode == HeightReference::mid_height ? "mid-height" : "curve-mean";
}
std::string to_string(GazeRadiusMode mode) { return mode == GazeRadiusMode::cylinder ? "cylinder" : "scaled"; }

void PaperPathOptions::validate() const {
  if (rows < 1 || rows > 1000) throw InputError("--rows must be between 1 and 1000, got " + std::to_string(rows));
  if (columns < 3 || columns > 1000)
    throw InputError("--columns must be between 3 and 1000 (a closed curve needs 3 control points), got " +
                     std::to_string(columns));
  if (degree != 2 && degree != 3)
    throw InputError("--degree must be 2 (quadratic, C1) or 3 (cubic, C2), got " + std::to_string(degree));
  require_finite_in(gaze_scale, 0.0, 1.0, "--gaze-scale");
  require_finite_in(position_scale, 0.0, 1.0, "--position-scale");
  if (samples < 1 || samples > 1000000)
    throw InputError("--samples must be between 1 and 1000000, got " + std::to_string(samples));
  if (up.kind == UpDirection::Kind::vector && !(up.vector.norm() > 0.5))
    throw InputError("the up vector must be non-zero");
}

double PaperPathGeometry::gaze_height(double t) const {
  return height_reference + gaze_scale * (curve.value(t) - height_reference);
}

double PaperPathGeometry::position_height(double t) const {
  return height_reference + position_scale * (curve.value(t) - height_reference);
}

double PaperPathGeometry::angle(double t) const {
  // Reduce t first so that the angle keeps full precision for any t.
  double v = std::numbers::pi / curve.size() + kFullTurn * (t - std::floor(t));
  if (v >= kFullTurn) v -= kFullTurn;
  return v;
}

Eigen::Vector3d PaperPathGeometry::base_point(double t) const {
  return cylinder.point(base_height(t), angle(t), cylinder.radius);
}
Eigen::Vector3d PaperPathGeometry::gaze_point(double t) const {
  return cylinder.point(gaze_height(t), angle(t), gaze_radius);
}
Eigen::Vector3d PaperPathGeometry::position_point(double t) const {
  return cylinder.point(position_height(t), angle(t), position_radius);
}

CameraPose PaperCameraPath::normalized_pose(double t) const {
  const double curve_t = geometry_.start_parameter + t;
  CameraPose pose;
  pose.eye = geometry_.position_point(curve_t);
  pose.target = geometry_.gaze_point(curve_t);
  pose.up = geometry_.cylinder.up;
  return pose;
}

CameraPose PaperCameraPath::pose(double t) const {
  CameraPose pose = normalized_pose(t);
  // model = scale · normalized + offset (uniform scale: directions are unchanged).
  pose.eye = geometry_.scale * pose.eye + geometry_.offset;
  pose.target = geometry_.scale * pose.target + geometry_.offset;
  return pose;
}

double position_radius_factor(double height, double radius) { return height / radius > 2.0 ? 6.0 : 4.0; }

PaperPathResult compute_paper_path(const TriangleMesh& mesh, const PaperPathOptions& options) {
  options.validate();
  return compute_paper_path(analyze_surface(mesh, options.surface), options);
}

std::unique_ptr<CameraPath> make_paper_camera_path(const TriangleMesh& mesh, const PaperPathOptions& options) {
  return std::make_unique<PaperCameraPath>(compute_paper_path(mesh, options).camera_path());
}

PaperPathResult compute_paper_path(SurfaceAnalysis surface, const PaperPathOptions& options) {
  options.validate();
  if (surface.triangles.empty()) throw InputError("the mesh has no faces: nothing to build a camera path around");
  for (const auto& tri : surface.triangles)
    for (std::uint32_t v : tri)
      if (v >= surface.positions.size()) throw InputError("internal: a face refers to a missing vertex");

  PaperPathResult result;
  result.options = options;
  result.surface = std::move(surface);
  result.stage_seconds = result.surface.stage_seconds;
  const auto& positions = result.surface.positions;
  const auto& triangles = result.surface.triangles;
  StageTimer timer(result.stage_seconds);

  // §9
  result.up = resolve_up(options.up, positions, triangles);
  result.cylinder = fit_cylinder(positions, triangles, result.up, options.axis_point);
  timer.done("cylinder");

  // §10
  result.grid = build_grid(positions, triangles, result.surface.face_weight, result.cylinder, options.rows,
                           options.columns, options.cell_averaging);
  timer.done("grid");

  // §11, §13.2
  result.control = choose_control_points(result.grid, options.empty_columns);
  result.start = choose_start_cell(result.grid);
  timer.done("control_points");

  // §12, §13.1
  PaperPathGeometry& g = result.geometry;
  g.cylinder = result.cylinder;
  g.curve = PeriodicBSpline(result.control.heights, options.degree);
  if (options.height_reference == HeightReference::mid_height) {
    g.height_reference = 0.5;
  } else {
    // The mean of U over a loop equals the mean of the control heights (partition of unity).
    double sum = 0.0;
    for (double u : result.control.heights) sum += u;
    g.height_reference = sum / static_cast<double>(result.control.heights.size());
  }
  g.gaze_scale = options.gaze_scale;
  g.position_scale = options.position_scale;
  const double r = result.cylinder.radius;
  const double k_r = position_radius_factor(result.cylinder.height, r);
  g.gaze_radius = options.gaze_radius == GazeRadiusMode::cylinder ? r : options.gaze_scale * r;
  g.position_radius = k_r * r;
  g.start_parameter = result.start.parameter;
  g.scale = result.surface.scale;
  g.offset = result.surface.offset;
  timer.done("curve");

  // §14
  PathMetrics& mt = result.metrics;
  const auto [lo, hi] = g.curve.range();
  mt.amplitude_curve = hi - lo;
  mt.amplitude_gaze = options.gaze_scale * mt.amplitude_curve;
  mt.amplitude_position = options.position_scale * mt.amplitude_curve;
  mt.extreme_points = g.curve.extreme_points();
  mt.weight_max = *std::max_element(result.grid.weight.begin(), result.grid.weight.end());
  double sum = 0.0;
  for (double w : result.grid.weight) sum += w;  // empty cells hold 0
  mt.weight_avg = sum / static_cast<double>(result.grid.weight.size());
  mt.empty_cells = result.grid.empty_cells();
  const int nonempty = static_cast<int>(result.grid.weight.size()) - mt.empty_cells;
  mt.weight_avg_nonempty = nonempty > 0 ? sum / nonempty : 0.0;
  mt.height_over_radius = result.cylinder.height / r;
  mt.radius_factor = k_r;
  timer.done("metrics");
  return result;
}

}  // namespace meshtour
