#include "tour/render_job.h"

#include "tour/thread_limit.h"
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include "core/error.h"
#include "jobs/frame_dir.h"
#include "jobs/frame_range.h"
#include "core/interrupt.h"
#include "tour/mesh_warnings.h"
#include "tour/path_overview.h"
#include "tour/path_plot.h"
#include "tour/progress.h"

namespace meshtour {
namespace {

// A command that fails before its first output leaves no file: the frames directory and its
// manifest, when this run made them, are removed again unless a frame was written.
class NewFrameDirGuard {
public:
  explicit NewFrameDirGuard(const std::filesystem::path& dir) : dir_(dir), manifest_(dir / kFrameDirManifestName) {
    std::error_code ec;
    dir_existed_ = std::filesystem::exists(dir_, ec);
    manifest_existed_ = std::filesystem::exists(manifest_, ec);
  }
  NewFrameDirGuard(const NewFrameDirGuard&) = delete;
  NewFrameDirGuard& operator=(const NewFrameDirGuard&) = delete;
  ~NewFrameDirGuard() {
    if (kept_) return;
    std::error_code ec;
    if (!manifest_existed_) std::filesystem::remove(manifest_, ec);
    if (!dir_existed_) std::filesystem::remove(dir_, ec);  // only if empty
  }
  void keep() { kept_ = true; }

private:
  std::filesystem::path dir_, manifest_;
  bool dir_existed_ = false, manifest_existed_ = false, kept_ = false;
};

}  // namespace

void run_render(const RenderJob& args) {
  install_interrupt_handlers();
  const Scene& scene = args.scene;
  const std::filesystem::path dir = args.out_dir;
  const std::vector<int> selected = parse_frame_range(args.frames, scene.frames);
  const std::vector<std::string> formats = frame_extensions(args.format);

  const FrameDirInfo info = frame_dir_info(scene, formats);
  NewFrameDirGuard guard(dir);
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
  const ProgressMode mode = args.quiet ? ProgressMode::none : args.progress;
  if (todo.empty()) {  // nothing to do: not even the model is loaded
    guard.keep();
    Progress("frame", 0, mode).finish(skipped);
    return;
  }

  // A chunk that searches the path repeats what every other chunk does, and a near tie decided
  // differently on another machine would give another path: `farm slurm` searches once instead.
  if (!args.quiet && !scene.path_file && scene.path_mode != PathMode::turntable && static_cast<int>(selected.size()) < scene.frames)
    std::fprintf(stderr, "meshtour: note: this chunk searches the camera path itself; write it once with 'meshtour path --path %s -o "
                 "FILE' (same settings) and give every chunk --path-file FILE\n", std::string(path_mode_name(scene.path_mode)).c_str());
  const ThreadLimit thread_limit(args.threads, args.quiet);
  if (!args.quiet) std::fprintf(stderr, "rendering with %d threads\n", thread_limit.threads());
  StageLog log(args.resources.verbose, mode);
  log.start("check");
  const TourMemoryCheck memory = check_tour_memory(scene, args.resources);
  const PreparedTour tour = prepare_tour(scene, args.quiet, &log, &memory);
  // The path search's view scores (feature orbit) join the manifest, as `tour --frames-dir`
  // writes them: every chunk computes the same ones, so concurrent writers agree.
  if (!tour.view_scores.empty()) {
    FrameDirInfo scored = read_frame_dir_info(dir);
    if (scored.view_scores.empty()) {
      const FrameDirInfo with_scores = frame_dir_info(scene, formats, tour.view_scores);
      scored.view_scores = with_scores.view_scores;
      scored.best_view_frame = with_scores.best_view_frame;
      write_frame_dir_info(dir, scored);
    }
  }

  log.announce("render");
  Progress progress("frame", static_cast<int>(todo.size()), mode);  // from here: frames/s are rendering only

  int done = 0;
  render_frames(tour, todo, [&](int k, const Image& image, double seconds) {
    for (const auto& f : formats) write_image(image, frame_file(dir, k, f));
    guard.keep();
    progress.step_done(k, seconds, ++done);
  });
  progress.finish(skipped);
}

}  // namespace meshtour
