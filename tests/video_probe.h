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
  std::string alpha_mode;          ///< WebM/Matroska: the track's AlphaMode ("1": players decode the alpha), else ""
  std::int64_t decoded_frames = 0; ///< frames actually decoded
  /// RGB24 pixels of the frames whose indices were requested, in request order.
  std::vector<std::vector<std::uint8_t>> rgb_frames;
  /// The same frames as RGBA (alpha 255 where the decoded frame has none).
  std::vector<std::vector<std::uint8_t>> rgba_frames;
  std::string decoded_pixel_format;  ///< what the decoder gave (e.g. "yuva420p" from libvpx-vp9)
};

/// Decodes every frame of `file`; keeps RGB and RGBA copies of the frames listed in `keep`.
/// `decoder`: a libavcodec decoder by name (e.g. "libvpx-vp9", which, unlike the native VP9
/// decoder, decodes WebM's alpha); "" = the default decoder of the stream's codec.
/// Throws std::runtime_error on failure.
VideoProbe probe_video(const std::filesystem::path& file, const std::vector<int>& keep = {},
                       const std::string& decoder = {});

}  // namespace meshtour::test
