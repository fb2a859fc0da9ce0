#include "tour/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include "core/error.h"

namespace meshtour {

ProgressMode parse_progress_mode(const std::string& text) {
  if (text == "auto") return ProgressMode::automatic;
  if (text == "bar") return ProgressMode::bar;
  if (text == "json") return ProgressMode::json;
  if (text == "none") return ProgressMode::none;
  throw InputError("--progress must be auto, bar, json or none, not '" + text + "'");
}


namespace {
ProgressMode resolve(ProgressMode mode) {
  if (mode != ProgressMode::automatic) return mode;
  return ::isatty(STDERR_FILENO) != 0 ? ProgressMode::bar : ProgressMode::json;
}
}  // namespace

void report_stage(ProgressMode mode, const std::string& stage) {
  if (resolve(mode) != ProgressMode::json) return;
  std::fprintf(stderr, "{\"event\":\"stage\",\"stage\":\"%s\"}\n", stage.c_str());
  std::fflush(stderr);
}

Progress::Progress(std::string what, int total, ProgressMode mode)
    : what_(std::move(what)), total_(total), mode_(resolve(mode)), start_(std::chrono::steady_clock::now()) {}

Progress::Progress(std::string what, int total, bool quiet)
    : Progress(std::move(what), total, quiet ? ProgressMode::none : ProgressMode::automatic) {}

double Progress::elapsed() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void Progress::draw_bar(int done) {
  constexpr int kWidth = 30;
  const double t = elapsed();
  const double rate = t > 0 ? done / t : 0.0;
  const double left = rate > 0 ? (total_ - done) / rate : 0.0;
  const int filled = total_ > 0 ? std::clamp(kWidth * done / total_, 0, kWidth) : kWidth;
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.append(static_cast<std::size_t>(kWidth - filled), '.');
  std::fprintf(stderr, "\r[%s] %d/%d %ss  %.2f/s  %.0f s left   ", bar.c_str(), done, total_, what_.c_str(), rate, left);
  std::fflush(stderr);
}

void Progress::update(int done) {
  done_ = done;
  if (mode_ == ProgressMode::bar) draw_bar(done);
  if (mode_ == ProgressMode::json) {
    std::fprintf(stderr, "{\"event\":\"%s\",\"done\":%d,\"total\":%d,\"elapsed\":%.3f}\n", what_.c_str(), done, total_, elapsed());
    std::fflush(stderr);
  }
}

void Progress::step_done(int index, double seconds, int done) {
  done_ = done;
  if (mode_ == ProgressMode::bar) draw_bar(done);
  if (mode_ == ProgressMode::json) {
    std::fprintf(stderr, "{\"event\":\"%s\",\"%s\":%d,\"seconds\":%.3f,\"done\":%d,\"total\":%d}\n", what_.c_str(),
                 what_.c_str(), index, seconds, done, total_);
    std::fflush(stderr);
  }
}

void Progress::finish(int skipped) {
  const double t = elapsed();
  const double rate = t > 0 ? done_ / t : 0.0;
  if (mode_ == ProgressMode::bar) {
    std::fputc('\n', stderr);
    std::fprintf(stderr, "%ss: %d done in %.1f s (%.3f s each)%s\n", what_.c_str(), done_, t, done_ > 0 ? t / done_ : 0.0,
                 skipped > 0 ? (", " + std::to_string(skipped) + " already there").c_str() : "");
  }
  if (mode_ == ProgressMode::json)
    std::fprintf(stderr, "{\"event\":\"summary\",\"what\":\"%s\",\"done\":%d,\"total\":%d,\"skipped\":%d,\"seconds\":%.3f,\"per_second\":%.4f}\n",
                 what_.c_str(), done_, total_, skipped, t, rate);
  std::fflush(stderr);
}

}  // namespace meshtour
