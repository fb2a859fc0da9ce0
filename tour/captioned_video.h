#pragma once
// The video side of a tour, shared by `tour`, `batch` and `encode`: frames go through the caption
// (encoder/caption.h) and the title card, then into the encoder. The frames themselves (a frames
// directory, the poster) stay clean: captions exist only in the video.
#include <cstdint>
#include <memory>
#include <optional>
#include <span>

#include "encoder/caption.h"
#include "encoder/video_encoder.h"

namespace meshtour {

/// --caption, --caption-position, --caption-size, --font and --title-card.
struct CaptionArgs {
  std::optional<CaptionStyle> caption;  ///< unset: no caption
  double title_card = 0.0;              ///< seconds; 0 = none
  /// The caption is a scene document's title, not the user's (--caption): where it cannot be
  /// drawn (video with alpha, a frame too narrow for it) the video goes without it, saying so.
  bool caption_by_default = false;

  bool any() const { return caption || title_card > 0.0; }
};

/// An encoder with the caption and the title card in front of it.
class CaptionedVideo {
public:
  /// Builds the caption filter now, so a caption that does not fit fails before any rendering.
  /// \throw InputError for a caption or title card on video with alpha (VideoOptions::alpha).
  CaptionedVideo(VideoEncoder& encoder, const VideoOptions& video, const CaptionArgs& args);
  ~CaptionedVideo();
  CaptionedVideo(const CaptionedVideo&) = delete;
  CaptionedVideo& operator=(const CaptionedVideo&) = delete;

  /// True when start() must be given the poster frame before the first add().
  bool needs_poster() const { return args_.title_card > 0.0; }
  /// The poster frame (8-bit sRGB RGB), for the title card.
  void start(std::span<const std::uint8_t> poster_rgb);
  /// One tour frame (8-bit sRGB RGB; RGBA with straight alpha for video with alpha).
  void add(std::span<const std::uint8_t> rgb);
  /// Flushes the title card and finishes the encoder.
  void finish();

private:
  VideoEncoder& encoder_;
  VideoOptions video_;
  CaptionArgs args_;
  std::unique_ptr<CaptionBurner> caption_;
  std::unique_ptr<TitleCard> card_;
};

}  // namespace meshtour
