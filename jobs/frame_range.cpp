#include "jobs/frame_range.h"

#include <algorithm>
#include <charconv>
#include <string>

#include "core/error.h"

namespace meshtour {
namespace {

constexpr long long kMaxFrameNumber = 1'000'000'000;

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

[[noreturn]] void bad(std::string_view spec, std::string_view part, const std::string& why) {
  throw InputError("frame selection '" + std::string(spec) + "': '" + std::string(part) + "' " + why +
                   " (use A, A-B, A-B:STEP or a comma-separated list of these, e.g. 0-99 or 0-299:10,5)");
}

long long number(std::string_view spec, std::string_view part, std::string_view text) {
  text = trim(text);
  long long value = -1;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size())
    bad(spec, part, "is not a frame number or range");
  if (value < 0 || value > kMaxFrameNumber) bad(spec, part, "is out of range (frames are 0 to 1000000000)");
  return value;
}

}  // namespace

std::vector<int> parse_frame_range(std::string_view spec, int frame_count) {
  if (frame_count < 1) throw InputError("frame selection '" + std::string(spec) + "': the tour has no frames");
  std::vector<int> frames;
  const std::string_view whole = trim(spec);
  if (whole.empty() || whole == "all") {
    frames.resize(static_cast<std::size_t>(frame_count));
    for (int k = 0; k < frame_count; ++k) frames[static_cast<std::size_t>(k)] = k;
    return frames;
  }
  std::string_view rest = whole;
  while (true) {
    const std::size_t comma = rest.find(',');
    const std::string_view part = trim(rest.substr(0, comma));
    if (part.empty()) bad(spec, part, "is empty");
    long long first = 0, last = 0, step = 1;
    const std::size_t colon = part.find(':');
    const std::string_view range = part.substr(0, colon);
    if (colon != std::string_view::npos) {
      step = number(spec, part, part.substr(colon + 1));
      if (step < 1) bad(spec, part, "has a step below 1");
    }
    const std::size_t dash = range.find('-', 1);  // from 1: a leading '-' is a (refused) negative number
    if (dash == std::string_view::npos) {
      if (colon != std::string_view::npos) bad(spec, part, "has a step but no range");
      first = last = number(spec, part, range);
    } else {
      first = number(spec, part, range.substr(0, dash));
      last = number(spec, part, range.substr(dash + 1));
      if (last < first) bad(spec, part, "ends before it starts");
    }
    // Clamp to the tour; the step stays anchored at `first` so chunks stay aligned.
    for (long long k = first; k <= std::min<long long>(last, frame_count - 1); k += step)
      frames.push_back(static_cast<int>(k));
    if (comma == std::string_view::npos) break;
    rest = rest.substr(comma + 1);
  }
  std::sort(frames.begin(), frames.end());
  frames.erase(std::unique(frames.begin(), frames.end()), frames.end());
  return frames;
}

std::string format_frame_range(const std::vector<int>& sorted_frames) {
  std::string text;
  for (std::size_t i = 0; i < sorted_frames.size();) {
    std::size_t j = i;
    while (j + 1 < sorted_frames.size() && sorted_frames[j + 1] == sorted_frames[j] + 1) ++j;
    if (!text.empty()) text += ',';
    text += std::to_string(sorted_frames[i]);
    if (j > i) text += '-' + std::to_string(sorted_frames[j]);
    i = j + 1;
  }
  return text;
}

}  // namespace meshtour
