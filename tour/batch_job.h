#pragma once
// The batch job of `meshtour batch`: a catalogue job. One video per manifest item, each made by the tour pipeline in
// this process; a bad item is reported and skipped without stopping the others, items whose video
// exists are skipped (so a re-run does only what is missing), and a summary table (stdout) and
// batch-summary.json say what succeeded and failed.
#include <exception>
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


/// One item of the manifest, its settings resolved at the edge (cli/: the batch's options with the
/// item's columns on top): the scene and the video's deliverables, or why they could not be.
struct BatchEntry {
  int index = 0;               ///< 0-based position in the manifest (a farm's array task id)
  int line = 0;                ///< CSV line or JSON array position (1-based), for messages
  std::filesystem::path mesh;  ///< resolved against the manifest's folder
  std::string output;          ///< video file name inside the output directory
  std::string error;           ///< the manifest's complaint about the item ("" if it is fine): it fails
  std::string poster;          ///< poster file name inside the output directory
  std::string caption;         ///< the caption's text, for the summary ("" = none)
  std::optional<Scene> scene;  ///< unset when the settings could not be resolved (or the item is not run)
  std::exception_ptr settings_failure;  ///< why not: the item fails with it when it runs
  PosterJob poster_job;        ///< its size (the file is `poster` in the output directory)
  CaptionArgs caption_args;
};

struct BatchJob {
  std::string manifest;            // for the summary
  std::string out_dir;
  std::vector<BatchEntry> items;   // every item of the manifest, in its order (empty with page_only)
  std::optional<int> item;
  int threads = 0;  // 0 = thread_count()'s default
  ResourceArgs resources;  // --max-memory, for each item
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
