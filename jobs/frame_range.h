#pragma once
// Frame selections, as render farms name them: which frames of a tour one process renders.
#include <string>
#include <string_view>
#include <vector>

namespace meshtour {

/// Parses a frame selection against a tour of `frame_count` frames (numbered 0 .. frame_count-1):
///   "all" (or "")      every frame
///   "A"                one frame
///   "A-B"              A to B inclusive
///   "A-B:S"            A, A+S, ... up to B (S >= 1)
///   "0-9,20,30-40:2"   any comma-separated list of the above
/// Ranges are clamped to the tour (a chunk "100-199" of a 150-frame tour is 100..149; a chunk that
/// starts past the end selects nothing, so a farm's last array task may be empty).
/// \return the selected frames, sorted, each once.
/// \throw InputError naming the offending part for malformed text (letters, B < A, S < 1, negative
///        numbers, numbers beyond 10^9) or frame_count < 1.
std::vector<int> parse_frame_range(std::string_view spec, int frame_count);

/// The inverse for display and for scripts: consecutive runs written as "A-B", e.g. "0-9,20,30-31".
std::string format_frame_range(const std::vector<int>& sorted_frames);

}  // namespace meshtour
