#pragma once
// Scene files: a JSON document naming the model and how to tour it. Every key is optional except
// the model; command-line options override what the file says. See scenes/README.md.
#include <filesystem>
#include <optional>
#include <string>

#include "core/axis.h"
#include "mesh/mesh.h"
#include "options/option_registry.h"
#include "tracer/tracer.h"

namespace meshtour {

/// Everything a tour needs besides the output name.
struct Scene {
  std::string source = "<built-in default scene>";  ///< where the scene came from, for messages
  // Model: a file, or a procedural model made by meshtour itself.
  std::optional<std::filesystem::path> mesh_file;  ///< resolved relative to the scene file
  std::string procedural = "sculpture";             ///< used when mesh_file is empty
  double procedural_detail = 1.0;
  Axis up{1, false};
  /// --up auto: `up` is decided by the model's shape once it is loaded (resolve_auto_up()); until
  /// then it is +y.
  bool up_auto = false;
  bool missing_textures_grey = false;  ///< --missing-textures grey

  // Camera and timing.
  std::string path_mode = "feature-orbit";  ///< "feature-orbit" (pathgen/feature_orbit.h), "paper" (toroidal patches, docs/METHOD.md) or "turntable"
  std::optional<std::filesystem::path> path_file;
  double vertical_fov_deg = 35.0;
  /// "fov": "auto": geometry-driven paths keep their camera distance and the field of view is
  /// fitted to the model over the whole tour; the turntable keeps vertical_fov_deg and fits its
  /// radius instead.
  bool auto_fov = true;
  double elevation_deg = 15.0;  ///< turntable only
  int fps = 30;
  int frames = 120;

  // Output.
  RenderOptions render;
  int crf = 18;
  /// The file's "look" object as JSON text ("" if none), kept so that a preset chosen on the
  /// command line can be applied under the file's own overrides (set_look_preset).
  std::string look_json;
  /// Settings of the path search (registry rows with scene keys "patches.*" and "paper.*"), as
  /// checked text; turned into the path stage's options by cli/path_options.h.
  options::Values path_search;
};

/// Applies one registry value (checked text, see options::check_value) to the scene: the one
/// place where a tour setting given on the command line, in a scene file or in a batch manifest
/// takes effect. Rows of the path search are kept in scene.path_search; rows only a command reads
/// are ignored. \throw InputError when the value is valid alone but not for this scene.
void apply_option(Scene& scene, const options::Option& option, const std::string& text);
/// Applies every value of `values` in registry order, then points the ground under the up axis.
void apply_options(Scene& scene, const options::Values& values);

/// Switches the scene's look to another preset, keeping the values the scene file's "look" sets
/// explicitly. \throw InputError for an unknown preset.
void set_look_preset(Scene& scene, const std::string& preset);

/// The scene compiled into the program (scenes/default.json).
Scene default_scene();

/// Reads a scene file. \throw IoError if unreadable, InputError naming the file and the key for
/// malformed JSON, unknown keys, wrong types or values out of range.
Scene load_scene(const std::filesystem::path& file);

/// Parses scene JSON text; `source` names it in messages, relative paths resolve from `base_dir`.
Scene parse_scene(const std::string& json_text, const std::string& source, const std::filesystem::path& base_dir);

/// The scene's model: loads mesh_file, or builds the procedural model.
TriangleMesh load_scene_model(const Scene& scene, LoadReport* report = nullptr);

/// With --up auto, sets the scene's up axis (and the ground under it) to the one the model's shape
/// gives (mesh/up_axis.h) and, unless quiet, says which and why on stderr. Otherwise does nothing.
void resolve_auto_up(Scene& scene, const TriangleMesh& mesh, bool quiet);

}  // namespace meshtour
