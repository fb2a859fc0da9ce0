#pragma once
// What every command that renders a tour shares (tour, render, batch, farm): the scene options,
// how they resolve into a Scene, the camera path, the field of view, the thread count. One
// implementation, so that a frame rendered by `render` in a farm chunk is the frame `tour` renders.
#include <CLI/CLI.hpp>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli/progress.h"
#include "options/cli_options.h"
#include "cli/resource_options.h"
#include "pathgen/camera_path.h"
#include "pathgen/paper_path.h"
#include "scenes/scene.h"
#include "tracer/tracer.h"

namespace meshtour::cli {

/// The options that say which tour to render: the input and every registry value the command
/// line gave (model, size, timing, camera, look, path search, and the command's own rows).
struct SceneArgs {
  std::string input;  // mesh or .json scene; empty = built-in default scene
  options::Values values;
};

/// Adds the INPUT positional (when `with_input`) and every registry row `command` takes to `cmd`.
void add_scene_options(CLI::App& cmd, SceneArgs& args, options::Command command, bool with_input = true);

/// The scene file (or default scene, or mesh with the default scene's settings) with the command
/// line's values applied; a --crf is checked for `codec` (the video the command makes).
Scene resolve_scene(const SceneArgs& args, std::string_view codec = "h264");

/// A registry value of the command line, or `fallback` when it was not given.
std::string value_or(const options::Values& values, std::string_view id, std::string fallback);
int int_value_or(const options::Values& values, std::string_view id, int fallback);

/// The toroidal-patch path of the scene's model (deterministic: the same for any thread count).
PaperPathResult compute_scene_paper_path(const Scene& scene, const TriangleMesh& mesh);

/// The camera path of the scene. Geometry-driven paths are wrapped in FramedPath when the fov is
/// fixed: the paper's 4r/6r distance rule frames typical models, but every vertex is checked.
std::unique_ptr<CameraPath> make_path(const Scene& scene, const TriangleMesh& mesh, const Lens& lens, bool quiet);

/// The field of view to render with. With "auto", a geometry-driven path keeps its distances and
/// the lens is fitted to the model over EVERY frame of the tour (one fov for the whole tour, so
/// the image does not pump, and every farm chunk of the tour gets the same one).
double choose_fov(const Scene& scene, const CameraPath& path, const TriangleMesh& mesh, const Lens& lens, bool quiet);

/// A tour ready to render frames: model, path, fov and renderer (its BVH built).
struct PreparedTour {
  Scene scene;
  TriangleMesh mesh;
  std::unique_ptr<CameraPath> path;
  double fov = 0.0;
  std::unique_ptr<Renderer> renderer;

  /// Frame `k` of the tour (k in 0 .. scene.frames-1); the same pixels in any process.
  Image render_frame(int k) const;
};

/// Loads the model (printing a summary unless `quiet`), computes the path and the fov and builds
/// the renderer; each of these is a stage of `log` (--verbose) when given.
PreparedTour prepare_tour(const Scene& scene, bool quiet, StageLog* log = nullptr);

/// Refuses (InputError) a tour of `scene` whose estimated memory exceeds the budget, before
/// anything big is allocated: the model's counts come from its file's structure (or the
/// procedural model's size), the rest from the options.
void check_tour_memory(const Scene& scene, const ResourceArgs& resources);

/// Threads to render with: `requested` when > 0, else SLURM_CPUS_PER_TASK when set (a farm task
/// must not take the whole node), else every core of the machine.
int render_threads(int requested);

/// The tour pipeline on one machine (defined in tour_command.cpp): path, frames, and the video
/// encoded as frames finish; also used by `batch` for every item.
struct TourVideoJob {
  std::filesystem::path output;      // .mp4
  std::filesystem::path frames_dir;  // also write the frames here ("" = no)
  std::string format = "png";        // png, exr or png+exr, for frames_dir
  std::filesystem::path gltf;           // also export the camera path as glTF 2.0 ("" = no)
  std::filesystem::path camera_frames;  // also write every frame's camera as .csv or .json ("" = no)
  int threads = 0;                   // 0 = render_threads' default
  ProgressMode progress = ProgressMode::automatic;
  ResourceArgs resources;  // --max-memory, --verbose
  bool quiet = false;
};
void render_tour_video(const Scene& scene, const TourVideoJob& job);

}  // namespace meshtour::cli
