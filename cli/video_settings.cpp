#include "cli/video_settings.h"

#include "core/error.h"

namespace meshtour::cli {

PosterJob poster_job(const options::Values& values) {
  PosterJob job;
  if (const auto it = values.find("poster"); it != values.end()) job.file = it->second;
  if (const auto it = values.find("poster-size"); it != values.end()) {
    PosterSize s;
    if (!options::parse_pixel_size(it->second, s.width, s.height)) throw InputError("--poster-size " + it->second + ": not WIDTHxHEIGHT");
    job.size = s;
  }
  if (!job.file.empty()) check_poster_name(job.file);
  return job;
}

CaptionArgs caption_args(const options::Values& values, const std::string& title) {
  CaptionArgs a;
  const auto text = values.find("caption");
  // A Voyager document's collection title captions its tour unless the user gave a caption.
  const bool by_default = text == values.end() && !title.empty() && options::check_value(options::option("caption"), title).empty();
  if (text != values.end() || by_default) {
    CaptionStyle style;
    style.text = by_default ? title : text->second;
    a.caption_by_default = by_default;
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

}  // namespace meshtour::cli
