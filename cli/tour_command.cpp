// meshtour tour: the whole job on one machine. Model -> camera path -> frames -> video, with the
// encoder fed as frames finish, so memory stays flat however long the tour is.
#include <tbb/global_control.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/scene_args.h"
#include "core/error.h"
#include "encoder/video_encoder.h"
#include "jobs/frame_dir.h"
#include "pathgen/camera_export.h"
#include "scenes/scene.h"
#include "tracer/tracer.h"

namespace meshtour::cli {
namespace {

struct TourArgs {
  SceneArgs scene;  // model, size, timing, camera, look: shared with render, batch and farm
  std::string output;
  std::string frames_dir;
  std::string progress = "auto";
  ResourceArgs resources;  // --max-memory, --verbose
  bool quiet = false;
};

std::filesystem::path default_output(const TourArgs& a) {
  if (a.scene.input.empty()) return "meshtour-default.mp4";
  return std::filesystem::path(a.scene.input).stem().string() + ".mp4";
}

void run_tour(const TourArgs& args) {
  install_interrupt_handlers();
  const Scene scene = resolve_scene(args.scene);
  TourVideoJob job;
  job.output = args.output.empty() ? default_output(args) : std::filesystem::path(args.output);
  job.frames_dir = args.frames_dir;
  const options::Values& values = args.scene.values;
  job.format = value_or(values, "format", "png");
  job.threads = int_value_or(values, "threads", 0);
  job.progress = args.quiet ? ProgressMode::none : parse_progress_mode(args.progress);
  job.quiet = args.quiet;
  job.resources = args.resources;
  job.gltf = value_or(values, "gltf", "");
  job.camera_frames = value_or(values, "camera-frames", "");
  job.poster = poster_job(values);
  job.caption = caption_args(values);
  render_tour_video(scene, job);
}

}  // namespace

void add_tour_command(CLI::App& app) {
  auto args = std::make_shared<TourArgs>();
  CLI::App* cmd = app.add_subcommand("tour", "Render a tour video of a mesh or a scene (the whole job on this machine).");
  cmd->description(
      "Render a tour video: load the model, compute the camera path, render every frame with the\n"
      "ray tracer and encode them to an H.264 MP4. With no INPUT, renders the built-in default scene.\n"
      "Options given here override the scene file; a mesh file gets the default scene's settings.");
  add_scene_options(*cmd, args->scene, options::tour);
  cmd->add_option("-o,--output", args->output, "Video file to write (.mp4); default: <input name>.mp4 in the current directory");
  cmd->add_option("--frames-dir", args->frames_dir, "Also write every frame as an image into this directory (frame_000000.png, ...)");
  add_progress_option(*cmd, args->progress);
  add_resource_options(*cmd, args->resources);
  cmd->add_flag("-q,--quiet", args->quiet, "Print nothing but errors");
  cmd->callback([args] { run_tour(*args); });
}

}  // namespace meshtour::cli
