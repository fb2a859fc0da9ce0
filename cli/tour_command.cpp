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
#include "cli/progress.h"
#include "cli/tour_setup.h"
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
  render_tour_video(scene, job);
}

}  // namespace

void render_tour_video(const Scene& scene, const TourVideoJob& job) {
  const std::filesystem::path& output = job.output;
  if (output.extension() != ".mp4") throw InputError(output.string() + ": the video is written as H.264 MP4; name it *.mp4");
  const bool keep_frames = !job.frames_dir.empty();
  const bool write_png = keep_frames && (job.format == "png" || job.format == "png+exr");
  const bool write_exr = keep_frames && (job.format == "exr" || job.format == "png+exr");

  const int threads = capped_threads(render_threads(job.threads), job.quiet);
  tbb::global_control thread_limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));

  // Refuse what would not fit before allocating anything.
  StageLog log(job.resources.verbose);
  log.start("check");
  check_tour_memory(scene, job.resources);

  // Fail on the output before the expensive work: the encoder opens its temporary file now.
  VideoOptions video;
  video.width = scene.render.width;
  video.height = scene.render.height;
  video.fps = scene.fps;
  video.crf = scene.crf;
  VideoEncoder encoder(output, video);

  const PreparedTour tour = prepare_tour(scene, job.quiet, &log);
  // The frames directory and its manifest only once the tour could be prepared: a bad model or
  // path file leaves nothing behind.
  if (keep_frames) {
    // The same frames directory `meshtour render` writes: `meshtour encode` can read it too.
    FrameDirInfo info;
    info.frame_count = scene.frames;
    info.fps = scene.fps;
    info.width = scene.render.width;
    info.height = scene.render.height;
    if (write_png) info.image_formats.push_back("png");
    if (write_exr) info.image_formats.push_back("exr");
    info.source = scene.source;
    if (scene.path_file) info.path_file = std::filesystem::absolute(*scene.path_file).string();
    prepare_frame_dir(job.frames_dir, info);
  }

  if (!job.gltf.empty() || !job.camera_frames.empty()) {
    const double aspect = static_cast<double>(scene.render.width) / scene.render.height;
    const TourCameras cameras = sample_tour(*tour.path, scene.frames, tour.fov, aspect, scene.fps);
    if (!job.gltf.empty()) write_camera_gltf(cameras, job.gltf);
    if (!job.camera_frames.empty()) write_camera_frames(cameras, job.camera_frames);
  }

  Progress progress("frame", scene.frames, job.progress);
  using Clock = std::chrono::steady_clock;
  double render_seconds = 0.0, encode_seconds = 0.0;
  for (int k = 0; k < scene.frames; ++k) {
    throw_if_interrupted();
    const auto start = Clock::now();
    const Image image = tour.render_frame(k);
    if (write_png) write_image(image, frame_file(job.frames_dir, k, "png"));
    if (write_exr) write_image(image, frame_file(job.frames_dir, k, "exr"));
    const auto rendered = Clock::now();
    encoder.add_frame(image.to_srgb8());
    encode_seconds += std::chrono::duration<double>(Clock::now() - rendered).count();
    render_seconds += std::chrono::duration<double>(rendered - start).count();
    progress.step_done(k, std::chrono::duration<double>(Clock::now() - start).count(), k + 1);
  }
  throw_if_interrupted();
  log.report("render", render_seconds);
  const auto finish_start = Clock::now();
  encoder.finish();
  log.report("encode", encode_seconds + std::chrono::duration<double>(Clock::now() - finish_start).count());
  progress.finish();
  if (!job.quiet) std::fprintf(stderr, "wrote %s (%d frames, %dx%d, %d fps)\n", output.string().c_str(), scene.frames,
                               scene.render.width, scene.render.height, scene.fps);
}

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
