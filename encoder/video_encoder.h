#pragma once
// Video writer on libavcodec/libavformat/libswscale/libavfilter (no ffmpeg subprocess): H.264
// MP4, ProRes MOV, FFV1 MKV, VP9 WebM or animated GIF. Frames go in as 8-bit sRGB RGB (or RGBA
// with straight alpha, for the codecs that keep it); the file
// appears under its final name only when finish() succeeds, so a crash or an error never leaves a
// half-written video behind. Every encoder setting, its thread count included, follows from
// VideoOptions alone: the same frames and options give the same file bytes on any machine with
// the same libraries (for H.264, any x86-64 CPU with SSSE3: x264's SIMD is capped at AVX2, since
// its output differs below SSSE3 and its AVX-512 code reads uninitialised memory).
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "encoder/video_codecs.h"

namespace meshtour {

struct VideoOptions {
  int width = 0;               ///< pixels; even for h264, prores, vp9 (chroma subsampling)
  int height = 0;              ///< pixels; even for h264, prores, vp9
  int fps = 30;                ///< constant frame rate, frames per second
  VideoCodec codec = VideoCodec::h264;
  /// Constant rate factor, lower is better: h264 0..51 (default 18, visually lossless), vp9
  /// 0..63 (default 31). Unset: the codec's default. Setting it for prores, ffv1 or gif is an
  /// InputError (ProRes has a fixed profile, FFV1 is lossless, GIF is palette-limited).
  std::optional<int> crf;
  std::string preset = "medium";  ///< x264 speed preset (ultrafast .. veryslow); h264 only
  /// Frames carry straight (not premultiplied) alpha and the file keeps it: ProRes 4444, VP9 with
  /// its alpha plane, FFV1 RGBA. An InputError for h264 and gif, which cannot carry alpha.
  bool alpha = false;
};

/// Writes one video file. Not copyable; the destructor discards an unfinished file.
class VideoEncoder {
public:
  /// Opens the encoder and a temporary file next to `output`.
  /// \throw InputError for bad options (odd size where the codec needs even sizes, fps or crf out
  ///        of range, unknown preset, an output extension that does not match the codec),
  ///        IoError if the output directory is not writable, RuntimeFailure if libav fails.
  VideoEncoder(const std::filesystem::path& output, const VideoOptions& options);
  ~VideoEncoder();
  VideoEncoder(const VideoEncoder&) = delete;
  VideoEncoder& operator=(const VideoEncoder&) = delete;

  /// Appends one frame: width*height*3 bytes, rows top to bottom, RGB order, sRGB-encoded; with
  /// VideoOptions::alpha width*height*4 bytes, RGBA with straight alpha (as PNG stores it).
  /// \throw InputError if the size is wrong, RuntimeFailure if encoding fails, IoError if writing
  ///        fails. After a RuntimeFailure/IoError the file is discarded and the encoder is unusable.
  /// GIF keeps every frame until finish() (its palette is computed over the whole clip).
  void add_frame(std::span<const std::uint8_t> rgb);

  /// Flushes the encoder, writes the trailer and moves the file to its final name.
  /// \throw RuntimeFailure / IoError on failure (the temporary file is removed);
  ///        InputError if no frame was added (an empty video is never written).
  void finish();

  std::int64_t frames_written() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace meshtour
