#pragma once
// Progress of long work on stderr: a self-updating line on a terminal, one line per step in logs.
#include <chrono>
#include <string>

namespace meshtour::cli {

class Progress {
public:
  Progress(std::string what, int total, bool quiet);
  /// Reports that `done` of the total steps are complete.
  void update(int done);
  /// Ends the progress display with a summary line.
  void finish();

private:
  std::string what_;
  int total_;
  bool quiet_, terminal_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace meshtour::cli
