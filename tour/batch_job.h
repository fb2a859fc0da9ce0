#pragma once
// The batch job of `meshtour batch`: a catalogue job. One video per manifest item, each made by the tour pipeline in
// this process; a bad item is reported and skipped without stopping the others, items whose video
// exists are skipped (so a re-run does only what is missing), and a summary table (stdout) and
// batch-summary.json say what succeeded and failed.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "tour/encode_frames.h"
#include "tour/resources.h"
#include "tour/tour.h"

namespace meshtour {

/// Exit code of `batch` when some items failed (the others were done): main() returns it.
inline constexpr int kSomeItemsFailedExitCode = 5;
/// Thrown by `batch` after all items ran, when some of them failed; main() exits with
/// kSomeItemsFailedExitCode.
struct SomeItemsFailed : std::exception {
  const char* what() const noexcept override { return "some batch items failed"; }
};


struct BatchJob {
  std::string manifest;
  std::string out_dir;
  SceneArgs defaults;  // scene options for every item; the manifest's columns override them
  std::optional<int> item;
  int threads = 0;  // 0 = thread_count()'s default
  bool web = false;        // per item also a VP9 WebM and a glTF camera, and index.html for the batch
  bool page_only = false;  // only index.html, from the summaries in out_dir
  ProgressMode progress = ProgressMode::automatic;
  bool quiet = false;
};

/// Runs the job: throws meshtour errors (InputError, IoError, ...) with one-line messages, and
/// Interrupted after SIGINT/SIGTERM, leaving no partial output behind.
/// Runs the job: throws meshtour errors (InputError, IoError, ...) with one-line messages, and
/// Interrupted after SIGINT/SIGTERM, leaving no partial output behind.
void run_batch(const BatchJob& args);

}  // namespace meshtour
