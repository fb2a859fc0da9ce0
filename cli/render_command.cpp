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
#include "tour/render_job.h"
#include "cli/scene_args.h"
#include "core/error.h"
#include "jobs/frame_dir.h"
#include "jobs/frame_range.h"

namespace meshtour::cli {

namespace {

struct RenderArgs {
  SceneArgs scene;
  RenderJob job;
};

}  // namespace

void add_render_command(CLI::App& app) {
  auto args = std::make_shared<RenderArgs>();
  RenderJob& job = args->job;
  CLI::App* cmd = app.add_subcommand("render", "Render frames of a tour into a directory (all, or a farm chunk); resumable.");
  cmd->description(
      "Render the frames of a tour (or the ones --frames names) into --out-dir as frame_000123.png/.exr,\n"
      "with the tour's manifest (meshtour-frames.json) beside them for 'meshtour encode'. Frames that\n"
      "already exist are skipped (each file appears only when complete), so a killed job is resumed by\n"
      "running it again. Any split of the frames over processes gives the same bytes as one run.\n"
      "SIGINT/SIGTERM stop after the current frame (exit 130).");
  add_scene_options(*cmd, args->scene, options::render,
                    {{"frame-selection", options::to(job.frames)},
                     {"format", options::to(job.format, parse_frame_formats)},
                     {"threads", options::to(job.threads)},
                     {"out-dir", options::to(job.out_dir)},
                     {"overwrite", options::to(job.overwrite)},
                     {"progress", options::to(job.progress, parse_progress_mode)},
                     {"max-memory", options::to(job.resources.max_memory)},
                     {"verbose", options::to(job.resources.verbose)},
                     {"quiet", options::to(job.quiet)}});
  cmd->callback([args] {
    args->job.scene = resolve_scene(args->scene);
    run_render(args->job);
  });
}

}  // namespace meshtour::cli
