#pragma once
// Frame sizes by name (--size): the common video sizes and the shapes social channels crop to.
// One row each; the option registry shows and checks the names from here, the scene applies them.
#include <array>
#include <optional>
#include <string_view>

namespace meshtour {

struct NamedSize {
  std::string_view name;  ///< option value, lower case ("vertical")
  int width, height;      ///< pixels, even (every video codec's chroma subsampling takes them)
  std::string_view use;   ///< what it is for, for help texts
};

/// The sizes, in help-text order: landscape 16:9 from small to large, then the other shapes.
inline constexpr std::array<NamedSize, 8> kNamedSizes = {{
    {"720p", 1280, 720, "HD 16:9 (the default size)"},
    {"1080p", 1920, 1080, "Full HD 16:9"},
    {"1440p", 2560, 1440, "QHD 16:9"},
    {"4k", 3840, 2160, "UHD 4K 16:9"},
    {"vertical", 1080, 1920, "9:16 for phone stories, Reels, Shorts, TikTok"},
    {"vertical-720", 720, 1280, "9:16 at 720p, smaller files"},
    {"square", 1080, 1080, "1:1 for feeds"},
    {"portrait", 1080, 1350, "4:5 for feed posts"},
}};

/// The row named `name` (case-insensitive), or nullopt.
inline std::optional<NamedSize> named_size(std::string_view name) {
  for (const NamedSize& s : kNamedSizes) {
    if (s.name.size() != name.size()) continue;
    bool same = true;
    for (std::size_t i = 0; i < name.size() && same; ++i) {
      const char c = name[i] >= 'A' && name[i] <= 'Z' ? static_cast<char>(name[i] - 'A' + 'a') : name[i];
      same = c == s.name[i];
    }
    if (same) return s;
  }
  return std::nullopt;
}

}  // namespace meshtour
