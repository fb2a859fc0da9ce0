// The caption's text as code points: the one UTF-8 decoder of captions (its own file, without the
// libav and FreeType dependencies of caption.cpp, so the fuzz target builds it alone).
#include <cstdio>
#include <string>

#include "core/error.h"
#include "encoder/caption.h"

namespace meshtour {
std::string code_point_name(char32_t c) {
  char text[16];
  std::snprintf(text, sizeof text, "U+%04X", static_cast<unsigned>(c));
  return text;
}

std::vector<char32_t> decode_caption_text(std::string_view s) {
  std::vector<char32_t> out;
  const auto bad = [&](std::size_t at, const char* what) {
    return InputError("caption text is not valid UTF-8: " + std::string(what) + " at byte " + std::to_string(at));
  };
  for (std::size_t i = 0; i < s.size();) {
    const auto b0 = static_cast<unsigned char>(s[i]);
    int extra = 0;
    char32_t c = 0;
    if (b0 < 0x80) c = b0;
    else if ((b0 & 0xE0) == 0xC0) extra = 1, c = b0 & 0x1F;
    else if ((b0 & 0xF0) == 0xE0) extra = 2, c = b0 & 0x0F;
    else if ((b0 & 0xF8) == 0xF0) extra = 3, c = b0 & 0x07;
    else throw bad(i, "a byte that starts no character");
    if (i + static_cast<std::size_t>(extra) >= s.size() && extra > 0) throw bad(i, "a character cut short");
    for (int k = 1; k <= extra; ++k) {
      const auto b = static_cast<unsigned char>(s[i + static_cast<std::size_t>(k)]);
      if ((b & 0xC0) != 0x80) throw bad(i, "a character cut short");
      c = (c << 6) | (b & 0x3F);
    }
    static constexpr char32_t kMin[] = {0, 0x80, 0x800, 0x10000};
    if (c < kMin[extra]) throw bad(i, "an overlong encoding");
    if (c > 0x10FFFF || (c >= 0xD800 && c <= 0xDFFF)) throw bad(i, "a code point that is not a character");
    if (c < 0x20 || c == 0x7F || (c >= 0x80 && c < 0xA0))
      throw InputError("caption text has a control character (" + code_point_name(c) + ") at byte " + std::to_string(i) +
                       "; a caption is one line of printable text");
    out.push_back(c);
    i += 1 + static_cast<std::size_t>(extra);
  }
  return out;
}

}  // namespace meshtour
