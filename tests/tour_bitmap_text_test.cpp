// The built-in bitmap font of the plots (tour/bitmap_text.h): text measures, glyphs drawn pixel
// for pixel as their art says, at any scale, clipped, and the same bytes every time.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "tour/bitmap_text.h"

namespace {

using namespace meshtour;

constexpr std::array<std::uint8_t, 3> kInk{10, 20, 30};
constexpr std::uint8_t kPaper = 200;

PlotImage blank(int width, int height) {
  return PlotImage{width, height, std::vector<std::uint8_t>(static_cast<std::size_t>(width) * height * 3, kPaper)};
}

// The image as rows of '#' (ink) and '.' (untouched paper); anything else is '?'.
std::vector<std::string> ink_rows(const PlotImage& image) {
  std::vector<std::string> rows;
  for (int y = 0; y < image.height; ++y) {
    std::string row;
    for (int x = 0; x < image.width; ++x) {
      const std::uint8_t* p = &image.rgb[(static_cast<std::size_t>(y) * image.width + x) * 3];
      const bool ink = p[0] == kInk[0] && p[1] == kInk[1] && p[2] == kInk[2];
      const bool paper = p[0] == kPaper && p[1] == kPaper && p[2] == kPaper;
      row += ink ? '#' : paper ? '.' : '?';
    }
    rows.push_back(row);
  }
  return rows;
}

TEST(TourBitmapText, WidthsAndHeights) {
  EXPECT_EQ(text_width(""), 0);
  EXPECT_EQ(text_width("A"), kGlyphColumns);
  // Glyphs advance by 6 columns; the last one has no gap after it.
  EXPECT_EQ(text_width("AB"), kGlyphAdvance + kGlyphColumns);
  EXPECT_EQ(text_width("Wmax"), 3 * kGlyphAdvance + kGlyphColumns);
  EXPECT_EQ(text_width("Wmax", 3), 3 * text_width("Wmax"));
  // A scale below 1 draws at 1.
  EXPECT_EQ(text_width("Wmax", 0), text_width("Wmax"));
  // UTF-8: '°' is two bytes and one glyph.
  EXPECT_EQ(text_width("90°"), text_width("900"));
  // A malformed byte stands for itself: one glyph.
  EXPECT_EQ(text_width("\xC3"), kGlyphColumns);
  EXPECT_EQ(text_height(), kGlyphRows);
  EXPECT_EQ(text_height(2), 2 * kGlyphRows);
}

TEST(TourBitmapText, GlyphsTheFontHas) {
  for (const char32_t c : {U'A', U'z', U'0', U'9', U' ', U'°', U'σ', U'π', U'×'}) EXPECT_TRUE(has_glyph(c)) << static_cast<int>(c);
  for (const char32_t c : {U'€', U'\t', char32_t{0}}) EXPECT_FALSE(has_glyph(c)) << static_cast<int>(c);
}

TEST(TourBitmapText, GlyphsAreDrawnAsTheirArtAtAnyScale) {
  PlotImage image = blank(12, 10);
  draw_text(image, 1, 0, "Lg", kInk);
  // 'L' at columns 1-5, 'g' (with its descender) at columns 7-11; only ink is drawn.
  const std::vector<std::string> expected = {
      ".#..........",  //
      ".#..........",  //
      ".#......####",  //
      ".#.....#...#",  //
      ".#.....#...#",  //
      ".#......####",  //
      ".#####.....#",  //
      ".......#...#",  //
      "........###.",  //
      "............",  //
  };
  EXPECT_EQ(ink_rows(image), expected);

  // At scale 2 every font pixel is a 2x2 square.
  PlotImage big = blank(10, 18);
  draw_text(big, 0, 0, "L", kInk, 2);
  const std::vector<std::string> rows = ink_rows(big);
  for (int y = 0; y < 18; ++y)
    for (int x = 0; x < 10; ++x) {
      const bool ink = (x < 2 && y < 14) || (y >= 12 && y < 14);
      EXPECT_EQ(rows[y][x], ink ? '#' : '.') << x << "," << y;
    }
}

TEST(TourBitmapText, AGlyphTheFontLacksIsABox) {
  PlotImage image = blank(5, 9);
  draw_text(image, 0, 0, "€", kInk);
  const std::vector<std::string> rows = ink_rows(image);
  EXPECT_EQ(rows[0], "#####");
  for (int y = 1; y < 6; ++y) EXPECT_EQ(rows[y], "#...#");
  EXPECT_EQ(rows[6], "#####");
}

TEST(TourBitmapText, ClippedAtTheEdgesAndTheSameBytesEveryTime) {
  // Text running off every edge draws only its part inside the image.
  PlotImage clipped = blank(20, 6);
  draw_text(clipped, -3, -2, "HELLO, WORLD", kInk, 2);
  PlotImage again = blank(20, 6);
  draw_text(again, -3, -2, "HELLO, WORLD", kInk, 2);
  EXPECT_EQ(clipped.rgb, again.rgb);
  const std::vector<std::string> rows = ink_rows(clipped);
  int ink = 0;
  for (const auto& row : rows) ink += static_cast<int>(std::count(row.begin(), row.end(), '#'));
  EXPECT_GT(ink, 0);
  // 'H' at scale 2 from x = -3: its left stem (columns -3, -2) is cut off, its right stem is at
  // columns 5 and 6, and its bar (font row 3) on image rows 4 and 5.
  EXPECT_EQ(rows[0].substr(0, 8), ".....##.");
  EXPECT_EQ(rows[4].substr(0, 8), "#######.");

  // Entirely outside: nothing changes.
  PlotImage outside = blank(8, 8);
  draw_text(outside, 100, 100, "A", kInk);
  draw_text(outside, -100, 0, "A", kInk);
  EXPECT_EQ(outside.rgb, blank(8, 8).rgb);
}

}  // namespace
