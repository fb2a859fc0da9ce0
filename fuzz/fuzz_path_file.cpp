// Fuzz target: the path-file reader (load_path_file: every mode, formats 1 and 2) on a file holding
// the input, the comparison of its made_for with a render's settings, then the camera path it
// rebuilt, sampled as the renderer samples it. Malformed files must end in meshtour::InputError;
// an accepted file must give finite camera poses.
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.h"
#include "pathgen/path_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("meshtour-fuzz-path-" + std::to_string(::getpid()) + ".json");
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    const meshtour::PathFile read = meshtour::load_path_file(file);
    const auto& path = read.path;
    try {
      meshtour::check_path_settings(read, {{"up", "y"}, {"aspect", "1.7777777777777777"}, {"fov", "auto"}, {"frames", "4"}}, file);
    } catch (const meshtour::InputError&) {
    }
    for (int k = 0; k < 4; ++k) {
      const meshtour::CameraPose pose = meshtour::frame_pose(*path, k, 4);
      if (!pose.eye.allFinite() || !pose.target.allFinite() || !pose.up.allFinite()) __builtin_trap();
    }
  } catch (const meshtour::Error&) {
  }
  return 0;
}
