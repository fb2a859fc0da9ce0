#include "tour/captioned_video.h"

#include "core/error.h"

namespace meshtour {

CaptionArgs caption_args(const options::Values& values) {
  CaptionArgs a;
  const auto text = values.find("caption");
  if (text != values.end()) {
    CaptionStyle style;
    style.text = text->second;
    if (const auto it = values.find("caption-position"); it != values.end()) style.position = parse_caption_position(it->second);
    if (const auto it = values.find("caption-size"); it != values.end()) style.size = std::stoi(it->second);
    if (const auto it = values.find("font"); it != values.end()) style.font = it->second;
    a.caption = style;
  } else {
    for (const char* id : {"caption-position", "caption-size", "font"})
      if (values.contains(id))
        throw InputError(std::string(options::option(id).flag) + " has no effect without --caption; give the caption's text");
  }
  if (const auto it = values.find("title-card"); it != values.end()) a.title_card = std::stod(it->second);
  return a;
}

CaptionedVideo::CaptionedVideo(VideoEncoder& encoder, const VideoOptions& video, const CaptionArgs& args)
    : encoder_(encoder), video_(video), args_(args) {
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
