#pragma once
// Wall time of consecutive pipeline stages, appended to a result's stage_seconds (internal).
#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace meshtour {

class StageTimer {
public:
  explicit StageTimer(std::vector<std::pair<std::string, double>>& log) : log_(log) {}
  /// Records the time since construction or the previous call under `stage`.
  void done(const std::string& stage) {
    const auto now = std::chrono::steady_clock::now();
    log_.emplace_back(stage, std::chrono::duration<double>(now - start_).count());
    start_ = now;
  }

private:
  std::vector<std::pair<std::string, double>>& log_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace meshtour
