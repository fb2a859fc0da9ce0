// meshtour render: the frames of a tour (all, or a farm chunk of them) into a frames directory,
// resumable. Every process that renders part of a tour computes the same camera path and the same
// field of view (fitted over every frame of the tour), so frame k is the same bytes whichever
// process renders it; `meshtour encode` turns the directory into a video.
#include <tbb/global_control.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/scene_args.h"
#include "core/error.h"
#include "jobs/frame_dir.h"
#include "jobs/frame_range.h"

namespace meshtour::cli {
namespace {

struct RenderCommandArgs {
  SceneArgs scene;
  std::string out_dir;
  std::string progress = "auto";
  ResourceArgs resources;  // --max-memory, --verbose
  bool overwrite = false;
  bool quiet = false;
};

std::vector<std::string> formats_of(const std::string& format) {
  if (format == "png+exr") return {"png", "exr"};
  return {format};
}

void run_render(const RenderCommandArgs& args) {
  install_interrupt_handlers();
  const Scene scene = resolve_scene(args.scene);
  const std::filesystem::path dir = args.out_dir;
  const options::Values& values = args.scene.values;
  const std::vector<int> selected = parse_frame_range(value_or(values, "frame-selection", "all"), scene.frames);
  const std::vector<std::string> formats = formats_of(value_or(values, "format", "png"));

  const FrameDirInfo info = frame_dir_info(scene, formats);
  prepare_frame_dir(dir, info);

  // A frame is done when every format of it exists: files appear under a frame name only when
  // complete (written under a temporary name, then renamed), so existing means complete.
  std::vector<int> todo;
  for (const int k : selected) {
    bool done = !args.overwrite;
    for (const auto& f : formats) done = done && missing_frames(dir, {k}, f).empty();
    if (!done) todo.push_back(k);
  }
  const int skipped = static_cast<int>(selected.size() - todo.size());
  if (!args.quiet)
    std::fprintf(stderr, "frames %s of %d: %zu to render, %d already there\n",
                 selected.empty() ? "(none)" : format_frame_range(selected).c_str(), scene.frames, todo.size(), skipped);
  const ProgressMode mode = args.quiet ? ProgressMode::none : parse_progress_mode(args.progress);
  if (todo.empty()) {  // nothing to do: not even the model is loaded
    Progress("frame", 0, mode).finish(skipped);
    return;
  }

  const int threads = thread_count(int_value_or(values, "threads", 0), args.quiet);
  tbb::global_control thread_limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  if (!args.quiet) std::fprintf(stderr, "rendering with %d threads\n", threads);
  StageLog log(args.resources.verbose);
  log.start("check");
  check_tour_memory(scene, args.resources);
  const PreparedTour tour = prepare_tour(scene, args.quiet, &log);

  Progress progress("frame", static_cast<int>(todo.size()), mode);  // from here: frames/s are rendering only

  int done = 0;
  render_frames(tour, todo, [&](int k, const Image& image, double seconds) {
    for (const auto& f : formats) write_image(image, frame_file(dir, k, f));
    progress.step_done(k, seconds, ++done);
  });
  progress.finish(skipped);
}

}  // namespace

void add_render_command(CLI::App& app) {
  auto args = std::make_shared<RenderCommandArgs>();
  CLI::App* cmd = app.add_subcommand("render", "Render frames of a tour into a directory (all, or a farm chunk); resumable.");
  cmd->description(
      "Render the frames of a tour (or the ones --frames names) into --out-dir as frame_000123.png/.exr,\n"
      "with the tour's manifest (meshtour-frames.json) beside them for 'meshtour encode'. Frames that\n"
      "already exist are skipped (each file appears only when complete), so a killed job is resumed by\n"
      "running it again. Any split of the frames over processes gives the same bytes as one run.\n"
      "SIGINT/SIGTERM stop after the current frame (exit 130).");
  add_scene_options(*cmd, args->scene, options::render);
  cmd->add_option("--out-dir", args->out_dir, "Directory for the frames and the manifest (created if needed)")->required();
  cmd->add_flag("--overwrite", args->overwrite, "Render the selected frames again even if they exist");
  add_progress_option(*cmd, args->progress);
  add_resource_options(*cmd, args->resources);
  cmd->add_flag("-q,--quiet", args->quiet, "Print nothing but errors");
  cmd->callback([args] { run_render(*args); });
}

}  // namespace meshtour::cli
