#pragma once
// Encoding a frames directory (written by `render`, `tour --frames-dir` or a farm) into a video.
#include <filesystem>
#include <optional>
#include <string>

#include "tour/captioned_video.h"
#include "tour/poster.h"

namespace meshtour {

/// What to encode; unset values come from the frames manifest, the EXR headers or the codec.
struct EncodeJob {
  std::string dir;     ///< the frames directory
  std::string output;  ///< the video; its extension must match the codec
  std::optional<int> fps, crf;
  std::optional<std::string> codec, frames, input_format, tone_mapping;  ///< frames: a selection (jobs/frame_range.h)
  std::optional<double> exposure;
  PosterJob poster;    ///< the best frame (the manifest's best_view_frame, else 0) as a PNG
  CaptionArgs caption;  ///< burned into the video; the frames stay as they are
  bool quiet = false;
};

/// Checks every selected frame, then encodes them. \throw InputError for missing, unreadable or
/// wrongly sized frames (all named) before any output exists; the video appears only when complete.
void encode_frames(const EncodeJob& job);

}  // namespace meshtour
