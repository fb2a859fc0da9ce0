#pragma once
// The folder a fuzz target writes its input files into: one per fuzzing process (libFuzzer's
// -jobs run several), removed at exit.
#include <unistd.h>

#include <filesystem>
#include <string>

namespace meshtour::fuzz {

struct ScratchDir {
  std::filesystem::path dir;
  explicit ScratchDir(const std::string& target)
      : dir(std::filesystem::temp_directory_path() / ("meshtour-" + target + "-" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(dir);
  }
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(dir, ignored);
  }
};

}  // namespace meshtour::fuzz
