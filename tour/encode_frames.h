#pragma once
// Encoding a frames directory (written by `render`, `tour --frames-dir` or a farm) into a video.
#include <filesystem>
#include <optional>
#include <string>

#include "tour/captioned_video.h"
#include "tour/poster.h"
#include "encoder/video_codecs.h"
#include "tracer/tracer.h"

namespace meshtour {

/// What to encode; unset values come from the frames manifest, the EXR headers or the codec.
struct EncodeJob {
  std::string dir;     ///< the frames directory
  std::string output;  ///< the video; its extension must match the codec
  std::optional<int> fps, crf;
  std::optional<VideoCodec> codec;         ///< unset: the one the output's extension names
  std::optional<std::string> frames;       ///< a selection (jobs/frame_range.h)
  std::optional<std::string> input_format;  ///< "png" or "exr": the frame files to read
  std::optional<ToneMapping> tone_mapping;  ///< EXR frames; unset: from their header
  std::optional<double> exposure;
  PosterJob poster;    ///< frame 0 (the loop's first view, --first-view) as a PNG
  CaptionArgs caption;  ///< burned into the video; the frames stay as they are
  /// Keep the frames' alpha (straight) in the video: prores, vp9 or ffv1; the frames must have
  /// alpha. Unset: frames with alpha are shown over black.
  bool alpha = false;
  bool quiet = false;
};

/// Checks every selected frame, then encodes them. \throw InputError for missing, unreadable or
/// wrongly sized frames (all named) before any output exists; the video appears only when complete.
void encode_frames(const EncodeJob& job);

}  // namespace meshtour
