#include "tour/captioned_video.h"

#include "core/error.h"

namespace meshtour {

CaptionedVideo::CaptionedVideo(VideoEncoder& encoder, const VideoOptions& video, const CaptionArgs& args)
    : encoder_(encoder), video_(video), args_(args) {
  // The caption and the title card are drawn on opaque RGB; they would need their own alpha.
  if (video.alpha && args_.any())
    throw InputError("--caption and --title-card are not drawn into video with alpha; leave them out, or leave out "
                     "--alpha (the frames then show over black)");
  if (args_.caption) caption_ = std::make_unique<CaptionBurner>(video.width, video.height, *args_.caption);
}

CaptionedVideo::~CaptionedVideo() = default;

void CaptionedVideo::start(std::span<const std::uint8_t> poster_rgb) {
  if (!needs_poster()) return;
  card_ = std::make_unique<TitleCard>(video_.width, video_.height, video_.fps, args_.title_card, poster_rgb,
                                      args_.caption.value_or(CaptionStyle{}));
}

void CaptionedVideo::add(std::span<const std::uint8_t> rgb) {
  if (needs_poster() && !card_) throw RuntimeFailure("CaptionedVideo: the title card needs the poster frame first");
  std::vector<std::uint8_t> captioned;
  if (caption_) {
    captioned = caption_->burn(rgb);
    rgb = captioned;
  }
  if (!card_) {
    encoder_.add_frame(rgb);
    return;
  }
  for (const auto& frame : card_->add(rgb)) encoder_.add_frame(frame);
}

void CaptionedVideo::finish() {
  if (card_)
    for (const auto& frame : card_->end()) encoder_.add_frame(frame);
  encoder_.finish();
}

}  // namespace meshtour
