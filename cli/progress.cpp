#include "cli/progress.h"

#include <unistd.h>

#include <cstdio>

namespace meshtour::cli {

Progress::Progress(std::string what, int total, bool quiet)
    : what_(std::move(what)), total_(total), quiet_(quiet), terminal_(::isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()) {}

void Progress::update(int done) {
  if (quiet_) return;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double per_step = done > 0 ? elapsed / done : 0.0;
  const double left = per_step * (total_ - done);
  if (terminal_) {
    std::fprintf(stderr, "\r%s %d/%d  %.2f s each  %.0f s left   ", what_.c_str(), done, total_, per_step, left);
  } else {
    std::fprintf(stderr, "%s %d/%d (%.2f s each, %.0f s left)\n", what_.c_str(), done, total_, per_step, left);
  }
  std::fflush(stderr);
}

void Progress::finish() {
  if (quiet_) return;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (terminal_) std::fputc('\n', stderr);
  std::fprintf(stderr, "%s: %d done in %.1f s (%.3f s each)\n", what_.c_str(), total_, elapsed,
               total_ > 0 ? elapsed / total_ : 0.0);
}

}  // namespace meshtour::cli
