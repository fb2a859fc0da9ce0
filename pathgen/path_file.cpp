#include "pathgen/path_file.h"

#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numeric>
#include <sstream>

#include "core/error.h"
#include "core/json_reader.h"

namespace meshtour {
namespace {

using OrderedJson = nlohmann::ordered_json;  // keys in the order written: easier to read

OrderedJson vec(const Eigen::Vector3d& v) { return OrderedJson::array({v.x(), v.y(), v.z()}); }

OrderedJson surface_options_json(const SurfaceOptions& s) {
  OrderedJson j;
  // JSON has no infinity (nlohmann would write null): an unlimited tolerance is written as "inf".
  if (std::isfinite(s.tolerance))
    j["tolerance"] = s.tolerance;
  else
    j["tolerance"] = "inf";
  j["smoothing"] = to_string(s.smoothing);
  j["smoothing_strength"] = s.smoothing_strength;
  j["curvature_fit"] = to_string(s.curvature_fit);
  j["kappa_min"] = s.kappa_min;
  j["face_samples"] = to_string(s.face_samples);
  j["tolerance_unit"] = to_string(s.tolerance_unit);
  j["patch_measure"] = to_string(s.patch_measure);
  j["patch_normal_angle"] = s.patch_normal_angle_deg;
  j["patches_on_unsmoothed"] = s.patches_on_unsmoothed;
  j["seed_order"] = to_string(s.seed_order);
  j["leftovers"] = to_string(s.leftovers);
  j["keep_inaccurate_patches"] = s.keep_inaccurate_patches;
  j["weight_neighbourhood"] = to_string(s.weight_neighbourhood);
  j["merge_duplicate_vertices"] = s.merge_duplicate_vertices;
  // Test hooks replace estimated data by exact data: record that they were in force.
  j["exact_normals"] = !s.exact_normals.empty();
  j["exact_differential"] = !s.exact_differential.empty();
  j["explicit_seeds"] = !s.seed_vertices.empty();
  return j;
}

OrderedJson options_json(const PaperPathOptions& o) {
  OrderedJson j;
  j["surface"] = surface_options_json(o.surface);
  j["up"] = o.up.name();
  j["axis_point"] = to_string(o.axis_point);
  j["rows"] = o.rows;
  j["columns"] = o.columns;
  j["cell_averaging"] = to_string(o.cell_averaging);
  j["empty_columns"] = to_string(o.empty_columns);
  j["degree"] = o.degree;
  j["gaze_scale"] = o.gaze_scale;
  j["position_scale"] = o.position_scale;
  j["height_reference"] = to_string(o.height_reference);
  j["gaze_radius"] = to_string(o.gaze_radius);
  j["samples"] = o.samples;
  return j;
}

// ---- reading ------------------------------------------------------------------------------


}  // namespace

std::string path_file_text(const PaperPathResult& r, const std::string& source) {
  const auto& s = r.surface;
  const int F = static_cast<int>(s.triangles.size());
  OrderedJson j;
  j["format_version"] = kPathFormatVersion;
  j["generator"] = "meshtour path (docs/METHOD.md, Choi et al. 2024 toroidal patches)";
  if (!source.empty()) j["source"] = source;
  j["units"] = "normalized: AABB diagonal of the smoothed model = 1; model = transform.scale * p + transform.offset";
  j["faces"] = F;
  j["vertices"] = s.positions.size();
  j["cleanup_notes"] = s.cleanup_notes;

  OrderedJson patches;
  patches["count"] = s.patch_count;
  patches["ratio"] = F > 0 ? static_cast<double>(s.patch_count) / F : 0.0;
  patches["grown"] = s.grown_patches;
  patches["single_face"] = s.single_face_patches;
  patches["orphans"] = s.orphans;
  patches["largest"] = s.largest_patch;
  j["patches"] = patches;

  OrderedJson transform;
  transform["scale"] = r.geometry.scale;
  transform["offset"] = vec(r.geometry.offset);
  j["transform"] = transform;

  const Cylinder& c = r.cylinder;
  OrderedJson cyl;
  cyl["up"] = vec(c.up);
  cyl["e_x"] = vec(c.e_x);
  cyl["e_y"] = vec(c.e_y);
  cyl["axis_point"] = vec(c.axis_point);
  cyl["base"] = c.base;
  cyl["height"] = c.height;
  cyl["radius"] = c.radius;
  cyl["height_over_radius"] = r.metrics.height_over_radius;
  j["cylinder"] = cyl;

  const CellGrid& g = r.grid;
  OrderedJson grid;
  grid["rows"] = g.rows;
  grid["columns"] = g.columns;
  OrderedJson weights = OrderedJson::array(), counts = OrderedJson::array();
  for (int i = 0; i < g.rows; ++i) {
    OrderedJson wr = OrderedJson::array(), cr = OrderedJson::array();
    for (int jj = 0; jj < g.columns; ++jj) {
      wr.push_back(g.at(i, jj));
      cr.push_back(g.face_count[static_cast<std::size_t>(i) * g.columns + jj]);
    }
    weights.push_back(wr);
    counts.push_back(cr);
  }
  grid["weights"] = weights;
  grid["face_counts"] = counts;
  grid["empty_cells"] = r.metrics.empty_cells;
  grid["control_rows"] = r.control.rows;
  grid["start_cell"] = OrderedJson::array({r.start.row, r.start.column});
  j["grid"] = grid;

  const PaperPathGeometry& geo = r.geometry;
  OrderedJson curve;
  curve["degree"] = geo.curve.degree();
  curve["control_heights"] = geo.curve.control();
  curve["control_angles"] = r.control.angles;
  OrderedJson points = OrderedJson::array();
  for (std::size_t k = 0; k < r.control.heights.size(); ++k)
    points.push_back(vec(c.point(r.control.heights[k], r.control.angles[k], c.radius)));
  curve["control_points"] = points;
  curve["knots"] = geo.curve.knots();
  curve["start_parameter"] = geo.start_parameter;
  j["curve"] = curve;

  OrderedJson paths;
  paths["height_reference"] = geo.height_reference;
  paths["gaze_scale"] = geo.gaze_scale;
  paths["position_scale"] = geo.position_scale;
  paths["gaze_radius"] = geo.gaze_radius;
  paths["radius_factor"] = r.metrics.radius_factor;
  paths["position_radius"] = geo.position_radius;
  j["paths"] = paths;

  const PathMetrics& m = r.metrics;
  OrderedJson metrics;
  metrics["amplitude_ratio"] = m.amplitude_gaze;
  metrics["amplitude_ratio_curve"] = m.amplitude_curve;
  metrics["amplitude_ratio_position"] = m.amplitude_position;
  metrics["extreme_points"] = m.extreme_points;
  metrics["weight_max"] = m.weight_max;
  metrics["weight_avg"] = m.weight_avg;
  metrics["weight_avg_nonempty"] = m.weight_avg_nonempty;
  metrics["empty_cells"] = m.empty_cells;
  metrics["height_over_radius"] = m.height_over_radius;
  metrics["radius_factor"] = m.radius_factor;
  j["metrics"] = metrics;

  j["options"] = options_json(r.options);

  OrderedJson timings;
  double total = 0.0;
  for (const auto& [stage, seconds] : r.stage_seconds) {
    timings[stage] = seconds;
    total += seconds;
  }
  timings["total"] = total;
  j["timings_s"] = timings;
  return j.dump(2) + "\n";
}

void write_path_file(const PaperPathResult& result, const std::filesystem::path& file, const std::string& source) {
  const std::string text = path_file_text(result, source);
  write_text_file_atomically(file, text, "path file");
}

PaperCameraPath read_paper_path_file(const std::filesystem::path& file) {
  const std::string source = "path file " + file.string();
  const std::string hint = " (write the file again with 'meshtour path')";
  const nlohmann::json root = parse_json_document(read_json_file_text(file, "path file"), source, hint);
  // Its version first: a document of another kind is reported by what it lacks.
  if (!root.is_object()) throw InputError(source + ": 'format_version' is missing: the document must be a JSON object" + hint);
  JsonReader rd(root, source, "", hint);
  const auto& version = rd.raw("format_version");
  if (!version.is_number_integer() || version.get<long long>() != kPathFormatVersion)
    rd.fail_key("format_version", "must be " + std::to_string(kPathFormatVersion) + " but is " + version.dump());

  PaperPathGeometry g;
  g.cylinder.up = rd.vector3("cylinder.up");
  if (std::abs(g.cylinder.up.norm() - 1.0) > 1e-9) rd.fail_key("cylinder.up", "must be a unit vector");
  // The angular frame is a function of û (§9.1); recomputing it keeps the file free of
  // redundant data that could disagree with it.
  std::tie(g.cylinder.e_x, g.cylinder.e_y) = angular_frame(g.cylinder.up);
  g.cylinder.axis_point = rd.vector3("cylinder.axis_point");
  g.cylinder.base = rd.number("cylinder.base");
  g.cylinder.height = rd.positive("cylinder.height");
  g.cylinder.radius = rd.positive("cylinder.radius");

  const double degree = rd.number("curve.degree");
  if (degree != 2.0 && degree != 3.0) rd.fail_key("curve.degree", "must be 2 or 3");
  const std::vector<double> heights = rd.numbers("curve.control_heights");
  if (heights.size() < 3) rd.fail_key("curve.control_heights", "must hold at least 3 heights");
  g.curve = PeriodicBSpline(heights, static_cast<int>(degree));
  g.start_parameter = rd.number("curve.start_parameter");

  g.height_reference = rd.number("paths.height_reference");
  g.gaze_scale = rd.number("paths.gaze_scale");
  g.position_scale = rd.number("paths.position_scale");
  g.gaze_radius = rd.number("paths.gaze_radius");
  if (g.gaze_radius < 0.0) rd.fail_key("paths.gaze_radius", "must not be negative");
  g.position_radius = rd.positive("paths.position_radius");

  g.scale = rd.positive("transform.scale");
  g.offset = rd.vector3("transform.offset");
  return PaperCameraPath(std::move(g));
}

std::unique_ptr<CameraPath> read_path_file(const std::filesystem::path& file) {
  return std::make_unique<PaperCameraPath>(read_paper_path_file(file));
}

}  // namespace meshtour
