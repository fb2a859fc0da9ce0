// Fuzz target: the WIDTHxHEIGHT parser of --poster-size (options::parse_pixel_size) and the
// registry's check of it. An accepted size must have both sides in range and even, and read back
// the same from its own text.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "options/option_registry.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  int w = -1, h = -1;
  if (meshtour::options::parse_pixel_size(text, w, h)) {
    if (w < 0 || h < 0) __builtin_trap();
    int w2 = -1, h2 = -1;
    if (!meshtour::options::parse_pixel_size(std::to_string(w) + "x" + std::to_string(h), w2, h2) || w2 != w || h2 != h)
      __builtin_trap();
  }
  const meshtour::options::Option& o = meshtour::options::option("poster-size");
  if (meshtour::options::check_value(o, text).empty()) {
    if (!meshtour::options::parse_pixel_size(text, w, h)) __builtin_trap();
    if (w < o.lo || w > o.hi || h < o.lo || h > o.hi || w % 2 || h % 2) __builtin_trap();
  }
  return 0;
}
