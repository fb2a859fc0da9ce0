// Fuzz target: the frame-selection parser (parse_frame_range), as `render --frames` and the farm's
// array tasks call it. Every malformed selection must end in meshtour::InputError; an accepted
// one must be sorted, unique, inside the tour, and survive format_frame_range() unchanged.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/error.h"
#include "jobs/frame_range.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  // The first two bytes choose the tour's length (1 .. 65536 frames), the rest is the selection.
  const int frame_count = 1 + (data[0] | (data[1] << 8));
  const std::string_view spec(reinterpret_cast<const char*>(data + 2), size - 2);
  try {
    const std::vector<int> frames = meshtour::parse_frame_range(spec, frame_count);
    for (std::size_t i = 0; i < frames.size(); ++i) {
      if (frames[i] < 0 || frames[i] >= frame_count) __builtin_trap();
      if (i > 0 && frames[i] <= frames[i - 1]) __builtin_trap();
    }
    if (!frames.empty() && meshtour::parse_frame_range(meshtour::format_frame_range(frames), frame_count) != frames)
      __builtin_trap();
  } catch (const meshtour::InputError&) {
  }
  return 0;
}
