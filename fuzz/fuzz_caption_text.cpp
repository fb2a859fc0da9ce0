// Fuzz target: the UTF-8 decoder of --caption (decode_caption_text). Malformed text must end in
// meshtour::InputError; accepted text must decode to printable code points that encode back to
// exactly the input bytes (no overlong forms, no surrogates, nothing past U+10FFFF).
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "core/error.h"
#include "encoder/caption.h"

namespace {
std::string encode(char32_t c) {
  std::string s;
  if (c < 0x80) {
    s += static_cast<char>(c);
  } else if (c < 0x800) {
    s += static_cast<char>(0xC0 | (c >> 6));
    s += static_cast<char>(0x80 | (c & 0x3F));
  } else if (c < 0x10000) {
    s += static_cast<char>(0xE0 | (c >> 12));
    s += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
    s += static_cast<char>(0x80 | (c & 0x3F));
  } else {
    s += static_cast<char>(0xF0 | (c >> 18));
    s += static_cast<char>(0x80 | ((c >> 12) & 0x3F));
    s += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
    s += static_cast<char>(0x80 | (c & 0x3F));
  }
  return s;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    std::string back;
    for (const char32_t c : meshtour::decode_caption_text(text)) {
      if (c < 0x20 || c > 0x10FFFF || (c >= 0xD800 && c <= 0xDFFF)) __builtin_trap();
      back += encode(c);
    }
    if (back != text) __builtin_trap();
  } catch (const meshtour::InputError&) {
  }
  return 0;
}
