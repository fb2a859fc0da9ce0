#include "scenes/scene.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <fstream>
#include <set>
#include <sstream>

#include "core/error.h"
#include "core/json_reader.h"
#include "mesh/up_axis.h"
#include "default_scene.h"

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

// The look values that are also command-line options (registry rows "background", "exposure",
// "crease-angle").
void apply_look_value(Shading& sh, std::string_view id, const std::string& text) {
  if (id == "background") sh.background = text == "transparent" ? BackgroundKind::transparent : BackgroundKind::gradient;
  if (id == "exposure") sh.exposure = std::stof(text);
  if (id == "crease-angle") sh.material.crease_angle_deg = std::stof(text);
  if (id == "tone-mapping") sh.tone_mapping = text == "clamp" ? ToneMapping::clamp : ToneMapping::filmic;
}

// The "look" object: a preset, then any of its values overridden. `preset_override`, when not
// empty, replaces the file's preset (the command line's --preset).
void apply_look(const json& look_json, const std::string& source, Shading& sh, const std::string& preset_override) {
  JsonReader look(look_json, source, "look");
  std::string preset = read_registered(look, "preset", options::option("preset")).value_or(sh.preset);
  if (!preset_override.empty()) preset = preset_override;
  sh = look_preset(preset);
  Material& m = sh.material;
  read_color(look, "base_color", m.base_color);
  look.read("roughness", m.roughness, 0.0, 1.0);
  look.read("specular", m.specular, 0.0, 10.0);
  look.read("vertex_colors", m.use_vertex_colors);
  look.read("texture", m.use_texture);
  if (auto crease = read_registered(look, "crease_angle", options::option("crease-angle"))) apply_look_value(sh, "crease-angle", *crease);
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
  if (auto background = read_registered(look, "background", options::option("background"))) apply_look_value(sh, "background", *background);
  read_color(look, "background_top", sh.background_top);
  read_color(look, "background_bottom", sh.background_bottom);
  if (auto exposure = read_registered(look, "exposure", options::option("exposure"))) apply_look_value(sh, "exposure", *exposure);
  if (auto tone = read_registered(look, "tone_mapping", options::option("tone-mapping"))) apply_look_value(sh, "tone-mapping", *tone);
  look.finish();
}

}  // namespace

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
  if (top.has("look")) {
    scene.look_json = top.raw("look").dump();
    apply_look(top.raw("look"), source, scene.render.shading, "");
  }
  top.finish();
  return scene;
}

void apply_option(Scene& scene, const options::Option& o, const std::string& text) {
  using options::Target;
  if (options::target(o) == Target::path_search) {
    scene.path_search[std::string(o.id)] = text;
    return;
  }
  const std::string_view id = o.id;
  const auto integer = [&] { return static_cast<int>(std::stol(text)); };
  if (id == "width") scene.render.width = integer();
  else if (id == "height") scene.render.height = integer();
  else if (id == "fps") scene.fps = integer();
  else if (id == "frame-count") scene.frames = integer();
  else if (id == "seconds") {
    const double frames = std::stod(text) * scene.fps;
    if (!(frames >= 1.0 && frames <= 1e6)) throw InputError("--seconds gives " + std::to_string(frames) + " frames; it must give 1 to 1000000");
    scene.frames = static_cast<int>(std::lround(frames));
  } else if (id == "up") {
    scene.up_auto = is_auto_up(text);
    scene.up = scene.up_auto ? Axis{1, false} : Axis::parse(text);
  } else if (id == "missing-textures") {
    scene.missing_textures_grey = text == "grey";
  } else if (id == "path") {
    scene.path_mode = text;
  } else if (id == "path-file") {
    scene.path_file = std::filesystem::path(text);
  } else if (id == "fov") {
    scene.auto_fov = text == "auto";
    if (!scene.auto_fov) scene.vertical_fov_deg = std::stod(text);
  } else if (id == "elevation") {
    scene.elevation_deg = std::stod(text);
  } else if (id == "preset") {
    set_look_preset(scene, text);
  } else if (id == "spp") {
    scene.render.samples_per_pixel = integer();
  } else if (id == "denoise") {
    scene.render.denoise = text == "on";
  } else if (id == "background" || id == "exposure" || id == "crease-angle" || id == "tone-mapping") {
    apply_look_value(scene.render.shading, id, text);
  } else if (id == "exr-layers") {
    for (std::size_t begin = 0; begin <= text.size();) {
      const std::size_t end = std::min(text.find(',', begin), text.size());
      const std::string_view layer = std::string_view(text).substr(begin, end - begin);
      if (layer == "albedo") scene.render.layers.albedo = true;
      if (layer == "normal") scene.render.layers.normal = true;
      if (layer == "depth") scene.render.layers.depth = true;
      begin = end + 1;
    }
  } else if (id == "crf") {
    scene.crf = integer();  // checked for the codec by the reader (scene file: h264; command line: --codec)
  }
}

void apply_options(Scene& scene, const options::Values& values) {
  for (const options::Option& o : options::registry())
    if (const auto it = values.find(o.id); it != values.end()) apply_option(scene, o, it->second);
  // The ground lies under the model's up axis, whichever way the file or --up gave it.
  scene.render.world_up = scene.up.vector();
}

void set_look_preset(Scene& scene, const std::string& preset) {
  if (scene.look_json.empty()) {
    scene.render.shading = look_preset(preset);
    return;
  }
  apply_look(json::parse(scene.look_json), scene.source, scene.render.shading, preset);
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
  if (!quiet) std::fprintf(stderr, "--up auto: %s (%s)\n", scene.up.name().c_str(), choice.reason.c_str());
  // Overriding a glTF file's own up changes the picture: said even with -q.
  if (!choice.warning.empty()) std::fprintf(stderr, "meshtour: warning: --up auto: %s\n", choice.warning.c_str());
}

TriangleMesh load_scene_model(const Scene& scene, LoadReport* report) {
  if (scene.mesh_file) return load_mesh(*scene.mesh_file, report, LoadOptions{.missing_textures_grey = scene.missing_textures_grey});
  return make_sculpture(scene.procedural_detail);
}

}  // namespace meshtour
