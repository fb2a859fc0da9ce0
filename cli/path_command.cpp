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
#include "scenes/scene.h"
#include "pathgen/camera_export.h"
#include "pathgen/debug_output.h"
#include "pathgen/path_file.h"

namespace meshtour::cli {

void add_path_command(CLI::App& app) {
  auto args = std::make_shared<PathJob>();
  CLI::App* cmd = app.add_subcommand(
      "path",
      "Computes the camera path of a mesh by the toroidal-patch method of Choi et al. 2024 "
      "(see docs/METHOD.md) and writes it as a JSON path file; no rendering. The mesh is "
      "normalized (bounding-box diagonal = 1) and smoothed, split into toroidal patches; faces "
      "where many small patches meet are 'interesting'. A cylinder around the up axis is cut "
      "into a grid, each column's most interesting cell becomes a control point, and a closed "
      "B-spline through them gives the height of the camera as it circles the model. Lengths "
      "in options are in units of the bounding-box diagonal; I-n refers to the interpretations "
      "in docs/METHOD.md §15.");
  add_mesh_argument(*cmd, args->mesh);
  options::add_command_options(*cmd, options::path, args->values,
                               {{"up", options::to(args->up)},
                                {"path", options::to(args->mode)},
                                {"threads", options::to(args->threads)},
                                {"gltf", options::to(args->gltf)},
                                {"camera-frames", options::to(args->camera_frames)},
                                {"output", options::to(args->output)},
                                {"plot", options::to(args->plot)},
                                {"debug-dir", options::to(args->debug_dir)},
                                {"overview", options::to(args->overview)},
                                {"overview-size", options::to(args->overview_size)},
                                {"path-samples", options::to(args->options.samples)},
                                {"max-memory", options::to(args->resources.max_memory)},
                                {"verbose", options::to(args->resources.verbose)},
                                {"quiet", options::to(args->quiet)}});
  cmd->callback([args] { run_path(*args); });
}

}  // namespace meshtour::cli
