#pragma once
// Scenes: the model and everything a tour needs besides the output name, as typed settings of
// the libraries (the tracer's RenderOptions, the path search's PaperPathOptions, the camera and
// the timing). Scene files (JSON) are read here; every key is optional except the model, and
// command-line options override what the file says (scenes/scene_options.h applies them). See
// scenes/README.md.
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "core/axis.h"
#include "mesh/mesh.h"
#include "pathgen/feature_orbit.h"
#include "pathgen/paper_path.h"
#include "tracer/tracer.h"

namespace meshtour {

/// How the camera goes round the model.
enum class PathMode {
  feature_orbit,  ///< an orbit that shows the most feature area smoothly (pathgen/feature_orbit.h)
  paper,          ///< the toroidal-patch method (docs/METHOD.md)
  turntable,      ///< a circle around the up axis (pathgen/turntable.h)
};
/// "feature-orbit", "paper" or "turntable": the --path value.
std::string_view path_mode_name(PathMode mode);
/// The inverse of path_mode_name. \throw InputError for anything else.
PathMode parse_path_mode(std::string_view text);
/// "preferred" or "best-covering": the --first-view value.
std::string_view orbit_start_name(OrbitStart start);
/// The inverse of orbit_start_name. \throw InputError for anything else.
OrbitStart parse_orbit_start(std::string_view text);

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
  /// Whether --up (or the scene file's "up") was given; if not, a mesh file's format decides
  /// (resolve_scene: by shape for every format meshtour reads, up_by_shape_by_default) and the
  /// built-in model is +y.
  bool up_given = false;
  bool missing_textures_grey = false;  ///< --missing-textures grey

  // A Smithsonian Voyager document (scenes/voyager.h): the tour's model is its derivative, posed
  // as the document says; resolve_voyager() fills the fields below from it.
  std::optional<std::filesystem::path> voyager_file;
  std::string quality;  ///< --quality: the derivative's quality ("" = the highest on disk)
  /// Applied to the model's vertices when it is loaded (load_scene_model): the document's node
  /// transforms, the model's neutral pose and units, into Voyager's Y-up world.
  std::optional<Eigen::Matrix4d> model_transform;
  /// Where frame 0 looks from: unit direction from the model to the eye (the opening view of the
  /// document's navigation setup), in the coordinates of the transformed model.
  std::optional<Eigen::Vector3d> opening_view;
  std::string title;  ///< the document's collection title: the default caption
  std::string voyager_summary;  ///< what resolve_voyager() chose, one line for the tour's summary

  // Camera and timing.
  PathMode path_mode = PathMode::feature_orbit;
  std::optional<std::filesystem::path> path_file;
  double vertical_fov_deg = 35.0;
  /// "fov": "auto": geometry-driven paths keep their camera distance and the field of view is
  /// fitted to the model over the whole tour; the turntable keeps vertical_fov_deg and fits its
  /// radius instead.
  bool auto_fov = true;
  double elevation_deg = 18.0;  ///< turntable only (the registry's --elevation default)
  OrbitStart orbit_start = FeatureOrbitOptions{}.start;  ///< feature orbit only: its first view (--first-view)
  int fps = 30;
  int frames = 120;

  // Output.
  RenderOptions render;
  int crf = 18;
  /// The scene file's own look values (its "look" object, checked when the file was read), put
  /// back over a preset chosen later (set_look_preset): --preset keeps what the file says.
  std::function<void(Shading&)> file_look;
  /// Settings of the path search (toroidal patches, cylinder, curve): registry rows with scene
  /// keys "patches.*" and "paper.*". The up direction is the scene's.
  PaperPathOptions path_search;
};

/// Switches the scene's look to another preset, keeping the values the scene file's "look" sets
/// explicitly.
void set_look_preset(Scene& scene, const std::string& preset);

/// The scene compiled into the program (scenes/default.json).
Scene default_scene();

/// Reads a scene file. \throw IoError if unreadable, InputError naming the file and the key for
/// malformed JSON, unknown keys, wrong types or values out of range.
Scene load_scene(const std::filesystem::path& file);

/// Parses scene JSON text; `source` names it in messages, relative paths resolve from `base_dir`.
Scene parse_scene(const std::string& json_text, const std::string& source, const std::filesystem::path& base_dir);

/// With a Voyager document (voyager_file), reads it: mesh_file becomes the chosen derivative
/// (scene.quality), and model_transform, opening_view and title are set; up is +y (Voyager's
/// world) unless up_given. voyager_summary says what it chose. Otherwise does nothing.
/// \throw InputError naming the document's key.
void resolve_voyager(Scene& scene);

/// The scene's model: loads mesh_file (transformed by model_transform), or builds the procedural model.
TriangleMesh load_scene_model(const Scene& scene, LoadReport* report = nullptr);

/// With --up auto, sets the scene's up axis (and the ground under it) to the one the model's shape
/// gives (mesh/up_axis.h) and, unless quiet, says which and why on stderr (as the default, only
/// when it is not +y). Otherwise does nothing.
void resolve_auto_up(Scene& scene, const TriangleMesh& mesh, bool quiet);

}  // namespace meshtour
