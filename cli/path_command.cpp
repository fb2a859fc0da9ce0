// meshtour path: the camera path of a mesh by the toroidal-patch method (docs/METHOD.md), written
// as a JSON path file, with an optional plot and debug outputs. No rendering.
#include <tbb/global_control.h>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include "cli/commands.h"
#include "tour/path_job.h"
#include "tour/mesh_warnings.h"
#include "tour/path_overview.h"
#include "tour/path_plot.h"
#include "cli/scene_args.h"
#include "core/error.h"
#include "mesh/mesh.h"
#include "mesh/up_axis.h"
#include "scenes/scene_options.h"
#include "scenes/voyager.h"
#include "pathgen/camera_export.h"
#include "pathgen/debug_output.h"
#include "pathgen/path_file.h"

namespace meshtour::cli {
namespace {

struct PathArgs {
  PathJob job;
  options::Values values;       // the tour's settings path takes: frames, size, lens, path search
  std::string up;               // checked by the row; parsed once the path mode is known ("" = not given)
  int samples = PaperPathOptions{}.samples;
};

void run_path_command(PathArgs& args) {
  PathJob& job = args.job;
  // The cameras exactly as `meshtour tour MESH --path MODE --frames N` renders them (default frame
  // size and field of view "auto"): the tour's settings applied as `tour` applies them.
  job.scene = default_scene();
  job.scene.source = job.mesh;
  job.scene.mesh_file = job.mesh;
  apply_options(job.scene, args.values);
  job.scene.up_given = !args.up.empty();
  if (is_voyager_document(job.mesh)) {
    // The document's derivative, posed as it says (loaded by run_path with the scene's transform).
    job.scene.voyager_file = job.mesh;
    resolve_voyager(job.scene);
    job.mesh = job.scene.mesh_file->string();
  }
  // Without --up the format decides, as for tour (mesh/up_axis.h); a Voyager model is +y.
  job.up_auto = args.up.empty() ? !job.scene.voyager_file && up_by_shape_by_default(job.mesh) : is_auto_up(args.up);
  if (!job.up_auto) {
    const std::string up = args.up.empty() ? "y" : args.up;
    job.up = UpDirection::parse(up);
    if (job.mode != PathMode::paper) (void)Axis::parse(up);  // the other modes take a coordinate axis
  }
  job.options = job.scene.path_search;
  job.options.samples = args.samples;
  run_path(job);
}

}  // namespace

void add_path_command(CLI::App& app) {
  auto args = std::make_shared<PathArgs>();
  PathJob& job = args->job;
  CLI::App* cmd = app.add_subcommand(
      "path",
      "Computes the camera path of a mesh by the toroidal-patch method of Choi et al. 2024 "
      "(see docs/METHOD.md) and writes it as a JSON path file; no rendering. The mesh is "
      "normalized (bounding-box diagonal = 1) and smoothed, split into toroidal patches; faces "
      "where many small patches meet are 'interesting'. A cylinder around the up axis is cut "
      "into a grid, each column's most interesting cell becomes a control point, and a closed "
      "B-spline through them gives the height of the camera as it circles the model. Lengths "
      "in options are in units of the bounding-box diagonal, but --tolerance, whose unit is "
      "--tolerance-unit (half the box's largest side by default); I-n refers to the interpretations "
      "in docs/METHOD.md §15. With --path feature-orbit or turntable, -o writes that mode's path "
      "file instead (as 'tour' would compute it with the same size, --fov, --frames and --up), "
      "for 'tour --path-file' and the farm.");
  add_mesh_argument(*cmd, job.mesh);
  const auto overview_size = [&job](const std::string& text) {
    (void)options::parse_pixel_size(text, job.overview_width, job.overview_height);  // checked by the row
  };
  options::add_command_options(*cmd, options::path, args->values,
                               {{"up", options::to(args->up)},
                                {"path", options::to(job.mode, parse_path_mode)},
                                {"threads", options::to(job.threads)},
                                {"gltf", options::to(job.gltf)},
                                {"camera-frames", options::to(job.camera_frames)},
                                {"output", options::to(job.output)},
                                {"plot", options::to(job.plot)},
                                {"debug-dir", options::to(job.debug_dir)},
                                {"overview", options::to(job.overview)},
                                {"overview-size", overview_size},
                                {"path-samples", options::to(args->samples)},
                                {"max-memory", options::to(job.resources.max_memory)},
                                {"verbose", options::to(job.resources.verbose)},
                                {"quiet", options::to(job.quiet)}});
  cmd->callback([args] { run_path_command(*args); });
}

}  // namespace meshtour::cli
