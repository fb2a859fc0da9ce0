#pragma once
// Progress of long work on stderr. On a terminal: a bar with steps done, steps per second and
// time left, redrawn in place. Elsewhere (farm and batch logs): one JSON line per finished step
// and a summary line, so that log collectors can parse them:
//   {"event":"frame","frame":12,"seconds":0.84,"done":3,"total":12}
//   {"event":"summary","what":"frame","done":12,"total":12,"skipped":0,"seconds":9.6,"per_second":1.25}
//   {"event":"stage","stage":"render"}

#include <chrono>
#include <string>

namespace meshtour {

enum class ProgressMode { automatic, bar, json, none };

/// Parses "auto", "bar", "json" or "none".
ProgressMode parse_progress_mode(const std::string& text);

/// Where the progress is JSON lines (json, or automatic off a terminal): the line
/// {"event":"stage","stage":"path"} as a stage starts, so that a farm or batch log says which stage
/// a task was in when it stopped (load, bvh, path, shading, render, encode, poster, page, ...).
void report_stage(ProgressMode mode, const std::string& stage);

class Progress {
public:
  /// `total` steps of `what` ("frame"); automatic = bar on a terminal, JSON lines otherwise.
  Progress(std::string what, int total, ProgressMode mode);
  /// Old form: automatic, or none when `quiet`.
  Progress(std::string what, int total, bool quiet);

  /// Reports that `done` of the total steps are complete.
  void update(int done);
  /// Reports that step `index` (e.g. the frame number) finished after `seconds`, `done` in all.
  void step_done(int index, double seconds, int done);
  /// Ends the display with a summary line; `skipped` steps were already done before.
  void finish(int skipped = 0);

private:
  double elapsed() const;
  void draw_bar(int done);

  std::string what_;
  int total_;
  int done_ = 0;
  ProgressMode mode_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace meshtour
