#pragma once
// Encoding a frames directory (written by `render`, `tour --frames-dir` or a farm) into a video.
#include <filesystem>
#include <optional>
#include <string>

namespace meshtour {

/// What to encode; unset values come from the frames manifest, the EXR headers or the codec.
struct EncodeJob {
  std::string dir;     ///< the frames directory
  std::string output;  ///< the video; its extension must match the codec
  std::optional<int> fps, crf;
  std::optional<std::string> codec, frames, input_format, tone_mapping;  ///< frames: a selection (jobs/frame_range.h)
  std::optional<double> exposure;
  bool quiet = false;
};

/// Checks every selected frame, then encodes them. \throw InputError for missing, unreadable or
/// wrongly sized frames (all named) before any output exists; the video appears only when complete.
void encode_frames(const EncodeJob& job);

}  // namespace meshtour
