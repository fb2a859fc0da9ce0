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
#include "cli/scene_args.h"
#include "core/error.h"
#include "encoder/video_encoder.h"
#include "jobs/frame_dir.h"
#include "pathgen/camera_export.h"
#include "cli/video_settings.h"
#include "tour/tour.h"
#include "scenes/scene.h"
#include "scenes/voyager.h"
#include "tracer/tracer.h"

namespace meshtour::cli {
namespace {

struct TourArgs {
  SceneArgs scene;  // model, size, timing, camera, look: shared with render, batch and farm
  TourVideoJob job;
  std::string output;
};

std::filesystem::path default_output(const TourArgs& a) {
  if (a.scene.input.empty()) return "meshtour-default.mp4";
  std::string stem = std::filesystem::path(a.scene.input).stem().string();
  if (is_voyager_document(a.scene.input)) stem.resize(stem.size() - 4);  // "bell.svx.json" -> bell.mp4
  return stem + ".mp4";
}

void run_tour(TourArgs& args) {
  install_interrupt_handlers();
  TourVideoJob& job = args.job;
  job.output = args.output.empty() ? default_output(args) : std::filesystem::path(args.output);
  const Scene scene = resolve_scene(args.scene, video_codec_info(tour_video_codec(job.output)).name);
  job.crf_given = args.scene.values.contains("crf");
  if (job.quiet) job.progress = ProgressMode::none;
  job.poster = poster_job(args.scene.values);
  job.caption = caption_args(args.scene.values, scene.title);
  if (job.caption.caption_by_default && !job.quiet)
    std::fprintf(stderr, "meshtour: caption: \"%s\" (the document's title; --caption replaces it)\n", job.caption.caption->text.c_str());
  render_tour_video(scene, job);
}

}  // namespace

void add_tour_command(CLI::App& app) {
  auto args = std::make_shared<TourArgs>();
  CLI::App* cmd = app.add_subcommand("tour", "Render a tour video of a mesh or a scene (the whole job on this machine).");
  cmd->description(
      "Render a tour video: load the model, compute the camera path, render every frame with the\n"
      "ray tracer and encode them to an H.264 MP4 (or the codec the output's name says: .mov ProRes, .mkv FFV1,\n"
      ".webm VP9, .gif; --alpha keeps a transparent background's alpha in .mov, .webm and .mkv). With no INPUT,\n"
      "renders the built-in default scene. The video loops: frame k of N is at k/N of the closed path.\n"
      "Options given here override the scene file; a mesh file gets the default scene's settings.\n\n"
      "Examples:\n"
      "  meshtour tour bunny.ply -o bunny.mp4                                 # H.264, 1280x720, 30 fps\n"
      "  meshtour tour bunny.ply --size vertical --fps 60 -o story.mp4        # 1080x1920 for phones\n"
      "  meshtour tour bunny.ply --background transparent --alpha -o bunny.mov  # ProRes 4444 with alpha\n"
      "  meshtour tour bunny.ply --background transparent --alpha -o bunny.webm # VP9 with alpha, for web pages");
  TourVideoJob& job = args->job;
  add_scene_options(*cmd, args->scene, options::tour,
                    {{"format", options::to(job.format, parse_frame_formats)},
                     {"threads", options::to(job.threads)},
                     {"alpha", options::to(job.alpha)},
                     {"gltf", options::to(job.gltf)},
                     {"camera-frames", options::to(job.camera_frames)},
                     {"output", options::to(args->output)},
                     {"frames-dir", options::to(job.frames_dir)},
                     {"progress", options::to(job.progress, parse_progress_mode)},
                     {"max-memory", options::to(job.resources.max_memory)},
                     {"verbose", options::to(job.resources.verbose)},
                     {"quiet", options::to(job.quiet)}});
  cmd->callback([args] { run_tour(*args); });
}

}  // namespace meshtour::cli
