#include "pathgen/path_file.h"

#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
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

// The keys every format-2 file starts with: version, mode, generator, source, made_for.
OrderedJson file_head(const char* mode, const char* generator, const PathRecord& record) {
  OrderedJson j;
  j["format_version"] = kPathFormatVersion;
  j["mode"] = mode;
  j["generator"] = generator;
  if (!record.source.empty()) j["source"] = record.source;
  OrderedJson made_for = OrderedJson::object();
  for (const auto& [key, value] : record.made_for) made_for[key] = value;
  j["made_for"] = made_for;
  return j;
}

void add_frame_scores(OrderedJson& j, const PathRecord& record) {
  if (record.frames <= 0 || static_cast<int>(record.frame_scores.size()) != record.frames) return;
  j["frames"] = record.frames;
  j["frame_scores"] = record.frame_scores;
}

// ---- reading ------------------------------------------------------------------------------

// A unit vector (the orbit frames' axes): a file that is not one would not give a camera frame.
Eigen::Vector3d unit_vector(JsonReader& rd, const std::string& key) {
  const Eigen::Vector3d v = rd.vector3(key);
  if (std::abs(v.norm() - 1.0) > 1e-9) rd.fail_key(key, "must be a unit vector");
  return v;
}

// Coordinates and lengths of a path in model units: finite, and far from overflowing when added.
constexpr double kLargestCoordinate = 1e15;
Eigen::Vector3d point(JsonReader& rd, const std::string& key) {
  const Eigen::Vector3d v = rd.vector3(key);
  if (!(v.cwiseAbs().maxCoeff() <= kLargestCoordinate)) rd.fail_key(key, "must hold numbers between -1e15 and 1e15");
  return v;
}

PaperCameraPath read_paper(JsonReader& rd) {
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

// The centre and the three axes every orbit of a path file has, under `key` ("orbit", "turntable").
template <typename Geometry>
void read_orbit_frame(JsonReader& rd, const std::string& key, Geometry& g) {
  g.center = point(rd, key + ".center");
  g.up = unit_vector(rd, key + ".up");
  g.front = unit_vector(rd, key + ".front");
  g.side = unit_vector(rd, key + ".side");
}

template <typename Geometry>
OrderedJson orbit_frame_json(const Geometry& g) {
  OrderedJson j;
  j["center"] = vec(g.center);
  j["up"] = vec(g.up);
  j["front"] = vec(g.front);
  j["side"] = vec(g.side);
  return j;
}

FeatureOrbitPath read_feature_orbit(JsonReader& rd) {
  FeatureOrbitGeometry g;
  read_orbit_frame(rd, "orbit", g);
  g.start = rd.number_in("orbit.start", -1e6, 1e6);
  const std::vector<double> d = rd.numbers("orbit.distance");
  if (d.size() != g.distance.size()) rd.fail_key("orbit.distance", "must hold 5 numbers (d0, c1, s1, c2, s2)");
  double swing = 0.0;
  for (std::size_t k = 0; k < d.size(); ++k) {
    if (!(std::abs(d[k]) <= kLargestCoordinate)) rd.fail_key("orbit.distance", "must hold numbers between -1e15 and 1e15");
    g.distance[k] = d[k];
    if (k > 0) swing += std::abs(d[k]);
  }
  if (!(d[0] > swing)) rd.fail_key("orbit.distance", "must keep the camera away from the centre (d0 > |c1| + |s1| + |c2| + |s2|)");
  ElevationCurve& e = g.elevation;
  constexpr double kRightAngle = 1.5707963267948966;
  e.base = rd.number_in("orbit.elevation.base", -kRightAngle, kRightAngle);
  e.swing = rd.number_in("orbit.elevation.swing", -kRightAngle, kRightAngle);
  e.swing_phase = rd.number_in("orbit.elevation.swing_phase", -1e6, 1e6);
  e.ripple = rd.number_in("orbit.elevation.ripple", -kRightAngle, kRightAngle);
  e.ripple_phase = rd.number_in("orbit.elevation.ripple_phase", -1e6, 1e6);
  return FeatureOrbitPath(std::move(g));
}

TurntablePath read_turntable(JsonReader& rd) {
  TurntableGeometry g;
  read_orbit_frame(rd, "turntable", g);
  g.radius = rd.positive("turntable.radius");
  if (!(g.radius <= kLargestCoordinate)) rd.fail_key("turntable.radius", "must be at most 1e15");
  g.elevation_deg = rd.number_in("turntable.elevation_deg", -89.0, 89.0);
  g.revolutions = rd.number_in("turntable.revolutions", -1e6, 1e6);
  return TurntablePath(g);
}

}  // namespace

std::string search_options_text(const PaperPathOptions& options) {
  OrderedJson j = options_json(options);
  j.erase("up");
  j.erase("samples");
  return j.dump();
}

std::string search_options_text(const SurfaceOptions& options) { return surface_options_json(options).dump(); }

std::string setting_text(double value) {
  // The shortest text that reads back as the same double: "18", "30", "1.7777777777777777".
  char text[64];
  if (value == std::trunc(value) && std::abs(value) < 1e15) {
    std::snprintf(text, sizeof text, "%.0f", value);
    return text;
  }
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(text, sizeof text, "%.*g", digits, value);
    if (std::strtod(text, nullptr) == value) break;
  }
  return text;
}

std::string path_file_text(const PaperPathResult& r, const std::string& source) {
  PathRecord record;
  record.source = source;
  return path_file_text(r, record);
}

std::string path_file_text(const PaperPathResult& r, const PathRecord& record) {
  const auto& s = r.surface;
  const int F = static_cast<int>(s.triangles.size());
  OrderedJson j = file_head("paper", "meshtour path (docs/METHOD.md, Choi et al. 2024 toroidal patches)", record);
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

PathFile load_path_file(const std::filesystem::path& file) {
  const std::string source = "path file " + file.string();
  const std::string hint = " (write the file again with 'meshtour path -o')";
  const nlohmann::json root = parse_json_document(read_json_file_text(file, "path file"), source, hint);
  // Its version first: a document of another kind is reported by what it lacks.
  if (!root.is_object()) throw InputError(source + ": 'format_version' is missing: the document must be a JSON object" + hint);
  JsonReader rd(root, source, "", hint);
  const auto& version = rd.raw("format_version");
  if (!version.is_number_integer() || version.get<long long>() < kOldestPathFormatVersion ||
      version.get<long long>() > kPathFormatVersion)
    rd.fail_key("format_version", "must be " + std::to_string(kOldestPathFormatVersion) + " or " +
                                      std::to_string(kPathFormatVersion) + " but is " + version.dump());
  PathFile out;
  out.format_version = static_cast<int>(version.get<long long>());
  out.mode = "paper";  // format 1 holds the paper path only
  if (out.format_version >= 2) {
    const auto& mode = rd.raw("mode");
    if (!mode.is_string()) rd.fail_key("mode", "must be a string");
    out.mode = mode.get<std::string>();
    const auto& made_for = rd.raw("made_for");
    if (!made_for.is_object()) rd.fail_key("made_for", "must be an object of settings");
    for (const auto& [key, value] : made_for.items()) {
      if (!value.is_string()) rd.fail_key("made_for." + key, "must be a string");
      out.record.made_for.emplace_back(key, value.get<std::string>());
    }
    if (rd.has("frames")) {
      out.record.frames = rd.integer("frames", 1, 1'000'000);
      out.record.frame_scores = rd.numbers("frame_scores");
      if (static_cast<int>(out.record.frame_scores.size()) != out.record.frames)
        rd.fail_key("frame_scores", "must hold one number per frame (" + std::to_string(out.record.frames) + ")");
    }
  }
  if (rd.has("source")) {
    const auto& name = rd.raw("source");
    if (name.is_string()) out.record.source = name.get<std::string>();
  }
  if (out.mode == "paper")
    out.path = std::make_unique<PaperCameraPath>(read_paper(rd));
  else if (out.mode == "feature-orbit")
    out.path = std::make_unique<FeatureOrbitPath>(read_feature_orbit(rd));
  else if (out.mode == "turntable")
    out.path = std::make_unique<TurntablePath>(read_turntable(rd));
  else
    rd.fail_key("mode", "must be paper, feature-orbit or turntable but is " + rd.raw("mode").dump());
  return out;
}

std::unique_ptr<CameraPath> read_path_file(const std::filesystem::path& file) { return load_path_file(file).path; }

PaperCameraPath read_paper_path_file(const std::filesystem::path& file) {
  PathFile f = load_path_file(file);
  if (f.mode != "paper")
    throw InputError("path file " + file.string() + ": holds a " + f.mode + " path, not the paper path (write it with 'meshtour path --path paper -o')");
  return *static_cast<const PaperCameraPath*>(f.path.get());
}

void check_path_settings(const PathFile& file, const PathSettings& current, const std::filesystem::path& name) {
  for (const auto& [key, made] : file.record.made_for)
    for (const auto& [current_key, value] : current)
      if (key == current_key && made != value)
        throw InputError("path file " + name.string() + ": its " + file.mode + " path was made for " + key + " " + made +
                         ", but this render has " + key + " " + value + ": give the same " + key +
                         ", or write the path file again with 'meshtour path -o' and this render's settings");
}

std::string path_file_text(const FeatureOrbitGeometry& g, const PathRecord& record) {
  OrderedJson j = file_head("feature-orbit", "meshtour path --path feature-orbit (pathgen/feature_orbit.h)", record);
  j["units"] = "model";
  OrderedJson orbit = orbit_frame_json(g);
  orbit["start"] = g.start;
  orbit["distance"] = g.distance;
  OrderedJson e;
  e["base"] = g.elevation.base;
  e["swing"] = g.elevation.swing;
  e["swing_phase"] = g.elevation.swing_phase;
  e["ripple"] = g.elevation.ripple;
  e["ripple_phase"] = g.elevation.ripple_phase;
  orbit["elevation"] = e;
  j["orbit"] = orbit;
  add_frame_scores(j, record);
  return j.dump(2) + "\n";
}

std::string path_file_text(const TurntableGeometry& g, const PathRecord& record) {
  OrderedJson j = file_head("turntable", "meshtour path --path turntable (pathgen/turntable.h)", record);
  j["units"] = "model";
  OrderedJson t = orbit_frame_json(g);
  t["radius"] = g.radius;
  t["elevation_deg"] = g.elevation_deg;
  t["revolutions"] = g.revolutions;
  j["turntable"] = t;
  add_frame_scores(j, record);
  return j.dump(2) + "\n";
}

}  // namespace meshtour
