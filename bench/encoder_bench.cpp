// encoder_bench: time per frame and file size of every codec on real frames. Reads the PNG frames
// of a directory into memory first (so only the encoder is timed), then encodes them with each
// codec at its default settings and prints one line per codec.
//   build-test/bench/encoder_bench FRAMES_DIR [OUT_DIR]     (e.g. frames of `meshtour tour --frames-dir`)
#include <OpenImageIO/imageio.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <string>
#include <vector>

#include "core/error.h"
#include "encoder/video_encoder.h"

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s FRAMES_DIR [OUT_DIR]\n", argv[0]);
    return 2;
  }
  const fs::path dir = argv[1];
  const fs::path out_dir = argc > 2 ? fs::path(argv[2]) : fs::temp_directory_path();
  std::vector<std::vector<std::uint8_t>> frames;
  int width = 0, height = 0;
  for (int k = 0;; ++k) {
    char name[64];
    std::snprintf(name, sizeof name, "frame_%06d.png", k);
    auto in = OIIO::ImageInput::open((dir / name).string());
    if (!in) break;
    width = in->spec().width, height = in->spec().height;
    std::vector<std::uint8_t> rgb(static_cast<std::size_t>(width) * height * 3);
    if (!in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, rgb.data())) break;
    frames.push_back(std::move(rgb));
  }
  if (frames.empty()) {
    std::fprintf(stderr, "%s: no frame_000000.png\n", dir.c_str());
    return 2;
  }
  std::printf("%zu frames %dx%d\n%-7s %12s %12s %12s\n", frames.size(), width, height, "codec", "wall ms/frm",
              "cpu ms/frm", "bytes");
  try {
    for (const auto& codec : meshtour::video_codecs()) {
      meshtour::VideoOptions options;
      options.width = width;
      options.height = height;
      options.codec = codec.codec;
      const fs::path file = out_dir / ("encoder_bench" + std::string(codec.extension));
      const auto wall0 = std::chrono::steady_clock::now();
      const std::clock_t cpu0 = std::clock();
      meshtour::VideoEncoder encoder(file, options);
      for (const auto& f : frames) encoder.add_frame(f);
      encoder.finish();
      const double wall = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall0).count();
      const double cpu = 1000.0 * static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
      const double n = static_cast<double>(frames.size());
      std::printf("%-7s %12.1f %12.1f %12ju\n", std::string(codec.name).c_str(), wall / n, cpu / n,
                  static_cast<std::uintmax_t>(fs::file_size(file)));
      fs::remove(file);
    }
  } catch (const meshtour::Error& e) {
    std::fprintf(stderr, "encoder_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
