#pragma once
// Captions burned into a video: libavfilter's drawtext draws the text with a font found through
// fontconfig (DejaVu Sans by default, or a given file); FreeType measures it first, because drawtext
// neither reports nor refuses text wider than the frame: a caption that does not fit is an error
// naming the limit, never cut. The text reaches drawtext through the filter's options API (no filter
// string, so no escaping) with expansion off, so '%', ':' and quotes are drawn as written.
// The title card (the clip opening on the poster with the caption large, cross-fading into the tour)
// uses libavfilter's xfade. Deterministic: the same frames, text and font give the same pixels.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace meshtour {

enum class CaptionPosition { bottom_left, bottom, bottom_right, top_left, top, top_right };

/// \throw InputError for a name that is not a position (the registry checks it first).
CaptionPosition parse_caption_position(std::string_view name);

struct CaptionStyle {
  std::string text;  ///< UTF-8
  CaptionPosition position = CaptionPosition::bottom_left;
  int size = 0;                ///< font size in pixels; 0 = default_caption_size(frame height)
  std::filesystem::path font;  ///< "" = default_caption_font()
};

/// The default font size for a frame `height` pixels high (1/18 of it, at least 10).
int default_caption_size(int height);

/// Decodes UTF-8 into code points. \throw InputError naming the byte offset of invalid UTF-8 (a
/// truncated or overlong sequence, a surrogate) or of a control character (a caption is one line).
std::vector<char32_t> decode_caption_text(std::string_view utf8);

/// "U+00C4": a code point as messages name it.
std::string code_point_name(char32_t c);

/// DejaVu Sans as fontconfig finds it. \throw InputError when it is not installed (naming the
/// Debian package fonts-dejavu-core and --font).
std::filesystem::path default_caption_font();

/// Width in pixels of `text` set in `font` at `size` pixels (advances and kerning, as drawtext lays
/// it out). \throw InputError for an unreadable font or a character the font has no glyph for.
int caption_text_width(const std::filesystem::path& font, int size, std::string_view text);

/// Draws a caption on frames of one size. Not copyable; owns its filter graph.
class CaptionBurner {
public:
  /// Measures the text and builds the filter graph. \throw InputError when the caption is empty,
  /// is not valid UTF-8, has a character the font lacks, or is wider than the frame allows (the
  /// message names the width available and the largest size that fits).
  CaptionBurner(int width, int height, const CaptionStyle& style);
  ~CaptionBurner();
  CaptionBurner(const CaptionBurner&) = delete;
  CaptionBurner& operator=(const CaptionBurner&) = delete;

  /// One frame (width*height*3 bytes, RGB, rows top to bottom) with the caption drawn on it.
  std::vector<std::uint8_t> burn(std::span<const std::uint8_t> rgb);

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The title card in front of a tour: `seconds` of the poster frame with the caption large and
/// centred, then an xfade (fade, 1/3 of the card, at most 1 s) into the tour's frames. Feed the
/// tour's frames to add(); each call returns the frames ready for the encoder (possibly none); end()
/// returns the rest.
class TitleCard {
public:
  /// \throw InputError as CaptionBurner for the large caption (an empty caption shows the poster alone).
  TitleCard(int width, int height, int fps, double seconds, std::span<const std::uint8_t> poster_rgb,
            const CaptionStyle& style);
  ~TitleCard();
  TitleCard(const TitleCard&) = delete;
  TitleCard& operator=(const TitleCard&) = delete;

  std::vector<std::vector<std::uint8_t>> add(std::span<const std::uint8_t> tour_rgb);
  std::vector<std::vector<std::uint8_t>> end();

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace meshtour
