#pragma once
// A video reader for tests (MP4, MOV, MKV, WebM, GIF), written directly on libavformat/libavcodec, independent of the encoder.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace meshtour::test {

struct VideoProbe {
  std::string codec;          ///< e.g. "h264"
  std::string pixel_format;   ///< e.g. "yuv420p"
  int width = 0, height = 0;
  double fps = 0;             ///< average frame rate of the stream
  double duration_seconds = 0;
  std::int64_t stream_frames = 0;  ///< nb_frames from the container
  std::int64_t decoded_frames = 0; ///< frames actually decoded
  /// RGB24 pixels of the frames whose indices were requested, in request order.
  std::vector<std::vector<std::uint8_t>> rgb_frames;
};

/// Decodes every frame of `file`; keeps RGB copies of the frames listed in `keep`.
/// Throws std::runtime_error on failure.
VideoProbe probe_video(const std::filesystem::path& file, const std::vector<int>& keep = {});

}  // namespace meshtour::test
