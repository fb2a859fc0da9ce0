#include "scenes/scene.h"

#include "scenes/scene_options.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "core/error.h"
#include "core/frame_sizes.h"
#include "core/json_reader.h"
#include "mesh/up_axis.h"
#include "scenes/voyager.h"
#include "default_scene.h"
#include "tracer/environment.h"

namespace meshtour {
namespace {

using nlohmann::json;

// A linear RGB colour.
void read_color(JsonReader& r, const std::string& key, Eigen::Vector3f& out) {
  r.read_vector(key, out, 0.0, 1000.0, "components must be between 0 and 1000 (linear RGB)");
}

// The value of `key` as the registry row `o` checks it (numbers, strings, booleans and string
// arrays become the row's text), or nullopt when the key is absent.
std::optional<std::string> read_registered(JsonReader& r, const std::string& key, const options::Option& o) {
  if (!r.has(key)) return std::nullopt;
  const json& v = r.raw(key);
  std::string text;
  if (v.is_string()) text = v.get<std::string>();
  else if (v.is_boolean()) text = v.get<bool>() ? "true" : "false";
  else if (v.is_number_integer()) text = std::to_string(v.get<long long>());
  else if (v.is_number()) text = options::number_text(v.get<double>());
  else if (v.is_array() && o.kind == options::Kind::choice_list) {
    for (const auto& item : v) {
      if (!item.is_string()) r.fail_key(key, "must be an array of names, e.g. [\"albedo\", \"normal\", \"depth\"]");
      text += (text.empty() ? "" : ",") + item.get<std::string>();
    }
  } else {
    r.fail_key(key, "must be " + std::string(o.kind == options::Kind::choice_list ? "an array of names" : "a number or a string"));
  }
  // Scene files describe tours, whose video is H.264: a codec-dependent value is checked for it.
  const std::string problem = !o.codec_dependent ? options::check_value(o, text) : options::check_value_for_codec(o, text, "h264");
  if (!problem.empty()) r.fail_key(key, problem);
  return options::normalize_value(o, text);
}

// The look values that are also options, each parsed once into the Shading's typed field.
void set_background(Shading& sh, const std::string& text) {
  sh.background = text == "transparent" ? BackgroundKind::transparent : BackgroundKind::gradient;
}
void set_exposure(Shading& sh, const std::string& text) { sh.exposure = std::stof(text); }
void set_crease_angle(Shading& sh, const std::string& text) { sh.material.crease_angle_deg = std::stof(text); }
void set_materials(Shading& sh, const std::string& text) { sh.material.use_file_material = text == "file"; }
void set_tone_mapping(Shading& sh, const std::string& text) { sh.tone_mapping = parse_tone_mapping(text); }
void set_environment(Shading& sh, const std::string& text) { sh.environment = text == "none" ? nullptr : environment_named(text); }
void set_environment_rotation(Shading& sh, const std::string& text) { sh.environment_rotation_deg = std::stof(text); }
void set_environment_intensity(Shading& sh, const std::string& text) { sh.environment_intensity = std::stof(text); }
void set_environment_background(Shading& sh, const std::string& text) { sh.environment_background = text == "shown"; }
void set_bounces(Shading& sh, const std::string& text) { sh.bounces = std::stoi(text); }

// One registered look key: checked by its row, then set.
void read_look_value(JsonReader& look, const std::string& key, std::string_view id, Shading& sh,
                     void (*set)(Shading&, const std::string&)) {
  if (const auto text = read_registered(look, key, options::option(id))) set(sh, *text);
}

// The values of a "look" object over `sh` (the preset is the caller's: apply_look). The object
// was checked when the file was read, so putting them back over another preset cannot fail.
void apply_look_values(JsonReader& look, const std::string& source, Shading& sh, const std::filesystem::path& base_dir) {
  Material& m = sh.material;
  read_color(look, "base_color", m.base_color);
  look.read("roughness", m.roughness, 0.0, 1.0);
  look.read("specular", m.specular, 0.0, 10.0);
  look.read("vertex_colors", m.use_vertex_colors);
  look.read("texture", m.use_texture);
  read_look_value(look, "crease_angle", "crease-angle", sh, set_crease_angle);
  read_look_value(look, "materials", "materials", sh, set_materials);
  if (look.has("lights")) {
    const json& lights = look.raw("lights");
    if (!lights.is_array() || lights.size() > 8)
      look.fail_key("lights", "must be an array of at most 8 lights, e.g. [{\"from\": [-0.5, 0.7, 0.6], \"intensity\": 2}]");
    sh.lights.clear();
    for (std::size_t i = 0; i < lights.size(); ++i) {
      JsonReader l(lights[i], source, "look.lights[" + std::to_string(i) + "]");
      Light light;
      l.read_vector("from", light.from_camera, -1000.0, 1000.0, "components must be between -1000 and 1000");
      if (!(light.from_camera.norm() > 0.0f)) l.fail_key("from", "must not be [0, 0, 0]: it is the direction the light comes from (camera space: x right, y up, z towards the viewer)");
      read_color(l, "color", light.color);
      l.read("intensity", light.intensity, 0.0, 1000.0);
      l.read("size", light.angular_diameter_deg, 0.0, 90.0);
      l.finish();
      sh.lights.push_back(light);
    }
  }
  look.read("shadows", sh.shadows);
  if (look.has("ambient")) {
    const json& a = look.raw("ambient");
    if (a.is_number()) {
      const double v = a.get<double>();
      if (!(v >= 0.0 && v <= 1000.0)) look.fail_key("ambient", "must be between 0 and 1000");
      sh.ambient = Eigen::Vector3f::Constant(static_cast<float>(v));
    } else {
      read_color(look, "ambient", sh.ambient);
    }
  }
  look.read("ambient_occlusion", sh.ambient_occlusion);
  look.read("ao_distance", sh.ao_distance, 0.0, 100.0);
  look.read("ground", sh.ground);
  look.read("ground_shadow", sh.ground_shadow, 0.0, 1.0);
  read_look_value(look, "background", "background", sh, set_background);
  read_color(look, "background_top", sh.background_top);
  read_color(look, "background_bottom", sh.background_bottom);
  read_look_value(look, "exposure", "exposure", sh, set_exposure);
  read_look_value(look, "tone_mapping", "tone-mapping", sh, set_tone_mapping);
  // An environment file is relative to the scene file, like the model.
  if (const auto text = read_registered(look, "environment", options::option("environment"))) {
    const std::filesystem::path p(*text);
    set_environment(sh, *text == "none" || *text == "neutral" || p.is_absolute() ? *text : (base_dir / p).string());
  }
  read_look_value(look, "environment_rotation", "environment-rotation", sh, set_environment_rotation);
  read_look_value(look, "environment_intensity", "environment-intensity", sh, set_environment_intensity);
  read_look_value(look, "environment_background", "environment-background", sh, set_environment_background);
  read_look_value(look, "bounces", "bounces", sh, set_bounces);
}

// The "look" object: its preset, then its values; kept as the scene's file_look, so that a preset
// chosen later (--preset) gets the file's values too.
void apply_look(const json& look_json, const std::string& source, Scene& scene, const std::filesystem::path& base_dir) {
  JsonReader look(look_json, source, "look");
  const std::string preset = read_registered(look, "preset", options::option("preset")).value_or(scene.render.shading.preset);
  scene.render.shading = look_preset(preset);
  apply_look_values(look, source, scene.render.shading, base_dir);
  look.finish();
  scene.file_look = [look_json, source, base_dir](Shading& sh) {
    JsonReader again(look_json, source, "look");
    apply_look_values(again, source, sh, base_dir);
  };
}

// Reads every registry row whose scene key lies directly in the object `section` ("" = the
// document's top level) and applies it.
void read_registered_keys(JsonReader& r, std::string_view section, Scene& scene, const std::filesystem::path& base_dir) {
  for (const options::Option& o : options::registry()) {
    const std::string_view key = o.scene_key;
    const auto dot = key.rfind('.');
    const std::string_view parent = dot == std::string_view::npos ? std::string_view() : key.substr(0, dot);
    if (key.empty() || parent != section) continue;
    const std::string leaf(dot == std::string_view::npos ? key : key.substr(dot + 1));
    std::optional<std::string> text = read_registered(r, leaf, o);
    if (!text) continue;
    if (o.kind == options::Kind::existing_file) {
      const std::filesystem::path p(*text);
      text = (p.is_absolute() ? p : base_dir / p).string();
    }
    apply_option(scene, o, *text);
  }
}

// The tour settings, each parsed once from its row's checked text into the Scene's typed field.
using SceneSetter = void (*)(Scene&, const std::string&);
int whole(const std::string& text) { return static_cast<int>(std::stol(text)); }
double real(const std::string& text) { return std::stod(text); }
bool given(const std::string& text) { return text == "true"; }

const std::map<std::string_view, SceneSetter>& scene_bindings() {
  using S = Scene&;
  using T = const std::string&;
  static const std::map<std::string_view, SceneSetter> table = {
      {"size",
       [](S s, T t) {
         const NamedSize size = *named_size(t);  // checked against the registry's choices
         s.render.width = size.width;
         s.render.height = size.height;
       }},
      {"width", [](S s, T t) { s.render.width = whole(t); }},
      {"height", [](S s, T t) { s.render.height = whole(t); }},
      {"fps", [](S s, T t) { s.fps = whole(t); }},
      {"frame-count", [](S s, T t) { s.frames = whole(t); }},
      {"seconds",
       [](S s, T t) {
         const double frames = real(t) * s.fps;  // after --fps: the registry applies fps first
         if (!(frames >= 1.0 && frames <= 1e6))
           throw InputError("--seconds gives " + std::to_string(frames) + " frames; it must give 1 to 1000000");
         s.frames = static_cast<int>(std::lround(frames));
       }},
      {"up",
       [](S s, T t) {
         s.up_auto = is_auto_up(t);
         s.up = s.up_auto ? Axis{1, false} : Axis::parse(t);
         s.up_given = true;
       }},
      {"missing-textures", [](S s, T t) { s.missing_textures_grey = t == "grey"; }},
      {"quality", [](S s, T t) { s.quality = t; }},
      {"path", [](S s, T t) { s.path_mode = parse_path_mode(t); }},
      {"path-file", [](S s, T t) { s.path_file = std::filesystem::path(t); }},
      {"fov",
       [](S s, T t) {
         s.auto_fov = t == "auto";
         if (!s.auto_fov) s.vertical_fov_deg = real(t);
       }},
      {"elevation", [](S s, T t) { s.elevation_deg = real(t); }},
      {"first-view", [](S s, T t) { s.orbit_start = parse_orbit_start(t); }},
      {"preset", [](S s, T t) { set_look_preset(s, t); }},
      {"crease-angle", [](S s, T t) { set_crease_angle(s.render.shading, t); }},
      {"materials", [](S s, T t) { set_materials(s.render.shading, t); }},
      {"spp", [](S s, T t) { s.render.samples_per_pixel = whole(t); }},
      {"denoise", [](S s, T t) { s.render.denoise = t == "on"; }},
      {"background", [](S s, T t) { set_background(s.render.shading, t); }},
      {"exposure", [](S s, T t) { set_exposure(s.render.shading, t); }},
      {"tone-mapping", [](S s, T t) { set_tone_mapping(s.render.shading, t); }},
      {"environment", [](S s, T t) { set_environment(s.render.shading, t); }},
      {"environment-rotation", [](S s, T t) { set_environment_rotation(s.render.shading, t); }},
      {"environment-intensity", [](S s, T t) { set_environment_intensity(s.render.shading, t); }},
      {"environment-background", [](S s, T t) { set_environment_background(s.render.shading, t); }},
      {"bounces", [](S s, T t) { set_bounces(s.render.shading, t); }},
      {"exr-layers",
       [](S s, T t) {
         ExtraLayers& layers = s.render.layers;
         for (std::size_t begin = 0; begin <= t.size();) {
           const std::size_t end = std::min(t.find(',', begin), t.size());
           const std::string_view layer = std::string_view(t).substr(begin, end - begin);
           layers.albedo = layers.albedo || layer == "albedo";
           layers.normal = layers.normal || layer == "normal";
           layers.depth = layers.depth || layer == "depth";
           begin = end + 1;
         }
       }},
      // Checked for the video's codec by the reader (scene file: h264; command line: --codec).
      {"crf", [](S s, T t) { s.crf = whole(t); }},
      // The path search (PaperPathOptions and its SurfaceOptions).
      {"tolerance", [](S s, T t) { s.path_search.surface.tolerance = real(t); }},
      {"tolerance-unit", [](S s, T t) { s.path_search.surface.tolerance_unit = parse_tolerance_unit(t); }},
      {"smoothing", [](S s, T t) { s.path_search.surface.smoothing = parse_smoothing_method(t); }},
      {"smoothing-strength", [](S s, T t) { s.path_search.surface.smoothing_strength = real(t); }},
      {"curvature-fit", [](S s, T t) { s.path_search.surface.curvature_fit = parse_curvature_fit(t); }},
      {"kappa-min", [](S s, T t) { s.path_search.surface.kappa_min = real(t); }},
      {"face-samples", [](S s, T t) { s.path_search.surface.face_samples = parse_face_samples(t); }},
      {"patch-measure", [](S s, T t) { s.path_search.surface.patch_measure = parse_patch_measure(t); }},
      {"patch-normal-angle", [](S s, T t) { s.path_search.surface.patch_normal_angle_deg = real(t); }},
      {"patches-on-unsmoothed", [](S s, T t) { s.path_search.surface.patches_on_unsmoothed = given(t); }},
      {"seed-order", [](S s, T t) { s.path_search.surface.seed_order = parse_seed_order(t); }},
      {"leftovers", [](S s, T t) { s.path_search.surface.leftovers = parse_leftover_mode(t); }},
      {"keep-inaccurate", [](S s, T t) { s.path_search.surface.keep_inaccurate_patches = given(t); }},
      {"weight-neighbourhood", [](S s, T t) { s.path_search.surface.weight_neighbourhood = parse_weight_neighbourhood(t); }},
      {"keep-duplicate-vertices", [](S s, T t) { s.path_search.surface.merge_duplicate_vertices = !given(t); }},
      {"axis-point",
       [](S s, T t) {
         s.path_search.axis_point = t == "aabb-center" ? AxisPointMode::aabb_center : AxisPointMode::surface_centroid;
       }},
      {"rows", [](S s, T t) { s.path_search.rows = whole(t); }},
      {"columns", [](S s, T t) { s.path_search.columns = whole(t); }},
      {"cell-averaging",
       [](S s, T t) { s.path_search.cell_averaging = t == "area-weighted" ? CellAveraging::area_weighted : CellAveraging::mean; }},
      {"empty-columns",
       [](S s, T t) {
         s.path_search.empty_columns = t == "interpolate" ? EmptyColumnMode::interpolate : EmptyColumnMode::middle_row;
       }},
      {"degree", [](S s, T t) { s.path_search.degree = whole(t); }},
      {"gaze-scale", [](S s, T t) { s.path_search.gaze_scale = real(t); }},
      {"position-scale", [](S s, T t) { s.path_search.position_scale = real(t); }},
      {"height-reference",
       [](S s, T t) {
         s.path_search.height_reference = t == "curve-mean" ? HeightReference::curve_mean : HeightReference::mid_height;
       }},
      {"gaze-radius",
       [](S s, T t) { s.path_search.gaze_radius = t == "scaled" ? GazeRadiusMode::scaled : GazeRadiusMode::cylinder; }},
  };
  return table;
}

}  // namespace

std::string_view path_mode_name(PathMode mode) {
  switch (mode) {
    case PathMode::feature_orbit: return "feature-orbit";
    case PathMode::paper: return "paper";
    case PathMode::turntable: return "turntable";
  }
  return "feature-orbit";
}

PathMode parse_path_mode(std::string_view text) {
  for (const PathMode m : {PathMode::feature_orbit, PathMode::paper, PathMode::turntable})
    if (path_mode_name(m) == text) return m;
  throw InputError("unknown path mode '" + std::string(text) + "'; use feature-orbit, paper or turntable");
}

std::string_view orbit_start_name(OrbitStart start) {
  return start == OrbitStart::best_covering ? "best-covering" : "preferred";
}

OrbitStart parse_orbit_start(std::string_view text) {
  for (const OrbitStart s : {OrbitStart::preferred, OrbitStart::best_covering})
    if (orbit_start_name(s) == text) return s;
  throw InputError("unknown first view '" + std::string(text) + "'; use preferred or best-covering");
}

bool is_scene_setting(const options::Option& o) { return scene_bindings().contains(o.id); }

ToneMapping parse_tone_mapping(const std::string& text) {
  // The row has checked the text against tone_mapping_names().
  return tone_mapping_from_name(text).value_or(ToneMapping::filmic);
}

Scene parse_scene(const std::string& json_text, const std::string& source, const std::filesystem::path& base_dir) {
  const json doc = parse_json_document(json_text, source);
  Scene scene;
  scene.source = source;
  JsonReader top(doc, source, "");
  std::string format = "meshtour-scene/1";
  top.read("format", format);
  if (format != "meshtour-scene/1")
    top.fail_key("format", "is '" + format + "'; this meshtour reads 'meshtour-scene/1'");
  std::string description;
  top.read("description", description);

  if (!top.has("model")) top.fail("has no 'model': name a mesh file ({\"file\": \"bunny.ply\"}) or {\"procedural\": \"sculpture\"}");
  {
    JsonReader model = top.child("model");
    std::string file;
    model.read("file", file);
    model.read("procedural", scene.procedural);
    model.read("detail", scene.procedural_detail, 0.05, 16.0);
    if (!file.empty()) {
      std::filesystem::path p(file);
      scene.mesh_file = p.is_absolute() ? p : base_dir / p;
      if (is_voyager_document(*scene.mesh_file)) scene.voyager_file = scene.mesh_file;
    } else if (scene.procedural != "sculpture") {
      model.fail_key("procedural", "is '" + scene.procedural + "'; the procedural models are: sculpture");
    }
    model.finish();
  }
  read_registered_keys(top, "", scene, base_dir);  // "up"
  for (const char* section : {"camera", "timing", "output", "patches", "paper"}) {
    if (!top.has(section)) continue;
    JsonReader object = top.child(section);
    read_registered_keys(object, section, scene, base_dir);
    if (std::string_view(section) == "output") object.read("filter_radius", scene.render.filter_radius, 0.5, 2.0);
    object.finish();
  }
  if (top.has("look")) apply_look(top.raw("look"), source, scene, base_dir);
  top.finish();
  return scene;
}

void apply_option(Scene& scene, const options::Option& o, const std::string& text) {
  if (const auto it = scene_bindings().find(o.id); it != scene_bindings().end()) it->second(scene, text);
}

void apply_options(Scene& scene, const options::Values& values) {
  for (const options::Option& o : options::registry())
    if (const auto it = values.find(o.id); it != values.end()) apply_option(scene, o, it->second);
  // The ground lies under the model's up axis, whichever way the file or --up gave it.
  scene.render.world_up = scene.up.vector();
}

Scene resolve_scene(const std::string& input, const options::Values& values, std::string_view codec) {
  Scene scene;
  if (input.empty()) {
    scene = default_scene();
  } else if (is_voyager_document(input)) {
    scene = default_scene();  // defaults for everything but the model, which the document gives
    scene.source = input;
    scene.mesh_file = input;
    scene.voyager_file = input;
  } else if (std::filesystem::path(input).extension() == ".json") {
    scene = load_scene(input);
  } else {
    scene = default_scene();  // defaults for everything but the model
    scene.source = input;
    scene.mesh_file = input;
  }
  if (const auto crf = values.find("crf"); crf != values.end())
    if (const std::string problem = options::check_value_for_codec(options::option("crf"), crf->second, codec); !problem.empty())
      throw InputError("--crf " + problem);
  apply_options(scene, values);
  resolve_voyager(scene);
  // Where neither the command line nor the scene says, the format decides (mesh/up_axis.h).
  if (!scene.up_given && !scene.voyager_file && scene.mesh_file && up_by_shape_by_default(*scene.mesh_file)) scene.up_auto = true;
  return scene;
}

void resolve_voyager(Scene& scene) {
  if (!scene.voyager_file) return;
  const VoyagerDocument doc = load_voyager_document(*scene.voyager_file, scene.quality);
  scene.mesh_file = doc.model_file;
  scene.model_transform = doc.transform;
  // Voyager's world is Y-up: the document's rotation has already stood the model up.
  if (!scene.up_given) {
    scene.up = Axis{1, false};
    scene.up_auto = false;
    scene.render.world_up = scene.up.vector();
  }
  scene.opening_view = doc.view_direction();
  scene.title = doc.title;
  char line[160];
  std::snprintf(line, sizeof line, " (units %s in a %s scene); frame 0 at its opening view, orbit %g, %g, %g%s",
                doc.model_units.c_str(), doc.scene_units.c_str(), doc.orbit_deg.x(), doc.orbit_deg.y(), doc.orbit_deg.z(),
                doc.orbit_given ? "" : " (Voyager's default: the document gives none)");
  scene.voyager_summary = scene.voyager_file->string() + ": the " + doc.quality + " Web3D derivative, " + doc.model_file.string() + line;
}

void set_look_preset(Scene& scene, const std::string& preset) {
  scene.render.shading = look_preset(preset);
  if (scene.file_look) scene.file_look(scene.render.shading);
}

Scene default_scene() {
  return parse_scene(generated::default_scene_json, "<built-in default scene>", std::filesystem::current_path());
}

Scene load_scene(const std::filesystem::path& file) {
  return parse_scene(read_json_file_text(file, "scene file"), file.string(), file.parent_path());
}

void resolve_auto_up(Scene& scene, const TriangleMesh& mesh, bool quiet) {
  if (!scene.up_auto) return;
  const UpChoice choice = scene.mesh_file ? choose_up_axis(mesh, *scene.mesh_file) : choose_up_axis(mesh);
  scene.up = choice.up;
  scene.up_auto = false;  // decided: a second call (or a copy of the scene) keeps it
  scene.render.world_up = scene.up.vector();
  // Asked for, the choice is said; as the default, only where it is not the +y it used to be.
  if (!quiet && (scene.up_given || scene.up != Axis{1, false}))
    std::fprintf(stderr, "--up auto: %s (%s)\n", scene.up.name().c_str(), choice.reason.c_str());
  // Overriding a glTF file's own up changes the picture: said even with -q.
  if (!choice.warning.empty()) std::fprintf(stderr, "meshtour: warning: --up auto: %s\n", choice.warning.c_str());
}

TriangleMesh load_scene_model(const Scene& scene, LoadReport* report) {
  if (!scene.mesh_file) return make_sculpture(scene.procedural_detail);
  TriangleMesh mesh = load_mesh(*scene.mesh_file, report, LoadOptions{.missing_textures_grey = scene.missing_textures_grey});
  if (scene.model_transform) transform_mesh(mesh, *scene.model_transform);
  return mesh;
}

}  // namespace meshtour
