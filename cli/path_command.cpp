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
#include "cli/path_options.h"
#include "tour/path_overview.h"
#include "tour/path_plot.h"
#include "cli/common_options.h"
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
  cmd->option_defaults()->always_capture_default();
  cmd->add_option("mesh", args->mesh, "Mesh file (" + supported_mesh_formats() + ")")
      ->required()
      ->type_name("MESH");
  cmd->add_option("--up", args->up, kPaperUpHelp)
      ->check(up_direction_validator())
      ->type_name("AXIS")
      ->capture_default_str();
  cmd->add_option("-o,--output", args->output,
                  "Path file to write (JSON, normalized units plus the transform back to model "
                  "units). Default: <mesh name>.path.json in the current folder")
      ->type_name("FILE");
  cmd->add_option("--plot", args->plot,
                  "Also draw a PNG of the grid weights over the (angle, height) domain with the "
                  "control points (white discs), the base (white), gaze (cyan) and position "
                  "(magenta) curves and the start cell (red)")
      ->type_name("PNG");
  cmd->add_option("--debug-dir", args->debug_dir,
                  "Also write the debug outputs of §14 into this folder: patches.ply, "
                  "face_weights.ply, cell_weights.ply (the smoothed mesh in model units, faces "
                  "coloured by patch / by w(f) / by the weight of their cell, green = low, red = "
                  "high) and samples.csv (the sampled curves and camera poses)")
      ->type_name("DIR");
  cmd->add_option("--path", args->mode,
                  "Path mode: paper (this method; the path file, --plot and --debug-dir describe it), turntable or "
                  "feature-orbit (see 'meshtour evaluate --help'); the other modes need a coordinate --up axis")
      ->check(CLI::IsMember({"paper", "turntable", "feature-orbit"}))
      ->capture_default_str();
  cmd->add_option("--overview", args->overview,
                  "Also render a picture of the path (PNG): the model, its bounding cylinder (blue-grey), the camera "
                  "positions (magenta), the points looked at (cyan), sight lines (yellow) and the start (red)")
      ->type_name("PNG");
  cmd->add_option("--overview-size", args->overview_size, "Size of the --overview picture, WIDTHxHEIGHT")
      ->type_name("WxH")
      ->capture_default_str();
  cmd->add_option("--samples", args->options.samples,
                  "Samples per loop K in samples.csv (§13.3)")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  cmd->add_flag("-q,--quiet", args->quiet, "Print nothing on success");
  options::add_registered_options(*cmd, options::path, args->values);
  add_resource_options(*cmd, args->resources);
  cmd->callback([args] { run_path(*args); });
}

}  // namespace meshtour::cli
