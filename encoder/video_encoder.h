#pragma once
// H.264/MP4 video writer on libavcodec/libavformat/libswscale (no ffmpeg subprocess).
// Frames go in as 8-bit sRGB RGB; the file appears under its final name only when finish()
// succeeds, so a crash or an error never leaves a half-written video behind.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>

namespace meshtour {

struct VideoOptions {
  int width = 0;               ///< pixels; must be even (yuv420p)
  int height = 0;              ///< pixels; must be even (yuv420p)
  int fps = 30;                ///< constant frame rate, frames per second
  int crf = 18;                ///< x264 constant rate factor: 0 lossless .. 51 worst; 18 is visually lossless
  std::string preset = "medium";  ///< x264 speed preset (ultrafast .. veryslow)
};

/// Writes one MP4 file. Not copyable; the destructor discards an unfinished file.
class VideoEncoder {
public:
  /// Opens the encoder and a temporary file next to `output`.
  /// \throw InputError for bad options (odd size, fps or crf out of range, unknown preset),
  ///        IoError if the output directory is not writable, RuntimeFailure if libav fails.
  VideoEncoder(const std::filesystem::path& output, const VideoOptions& options);
  ~VideoEncoder();
  VideoEncoder(const VideoEncoder&) = delete;
  VideoEncoder& operator=(const VideoEncoder&) = delete;

  /// Appends one frame: width*height*3 bytes, rows top to bottom, RGB order, sRGB-encoded.
  /// \throw InputError if the size is wrong, RuntimeFailure if encoding fails, IoError if writing
  ///        fails. After a RuntimeFailure/IoError the file is discarded and the encoder is unusable.
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
