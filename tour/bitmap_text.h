#pragma once
// Text on plots without any font file: a built-in 5×7 bitmap font (printable ASCII and a few
// symbols such as '°'), drawn at an integer scale. Self-contained and pixel-exact, so that plots
// are identical on every machine and tests can check them.
#include <array>
#include <cstdint>
#include <string_view>

#include "tour/plot_image.h"

namespace meshtour {

inline constexpr int kGlyphColumns = 5;  ///< ink columns of a glyph
inline constexpr int kGlyphRows = 9;     ///< 7 above the baseline, 2 of descenders
inline constexpr int kGlyphAdvance = 6;  ///< columns from one glyph to the next

/// True if the font has a glyph for the Unicode code point (others are drawn as a box).
bool has_glyph(char32_t code);

/// Width and height in pixels of `text` (UTF-8, one line) drawn at `scale`.
int text_width(std::string_view text, int scale = 1);
int text_height(int scale = 1);

/// Draws `text` (UTF-8, one line) with its top-left corner at (x, y), each font pixel a
/// scale × scale square; only the ink is drawn (the background shows through). Clipped to the image.
void draw_text(PlotImage& image, int x, int y, std::string_view text, std::array<std::uint8_t, 3> color, int scale = 1);

}  // namespace meshtour
