#pragma once
// The video's deliverables given as registry values (the command line, a batch manifest item):
// the poster (--poster, --poster-size) and the caption (--caption, --caption-position,
// --caption-size, --font, --title-card), parsed once, here at the edge, into the tour library's
// typed settings.
#include "options/option_registry.h"
#include "tour/captioned_video.h"
#include "tour/poster.h"

namespace meshtour::cli {

/// --poster and --poster-size among `values` (checked text). \throw InputError for a poster file
/// that is not a .png.
PosterJob poster_job(const options::Values& values);

/// --caption, --caption-position, --caption-size, --font and --title-card among `values`. A
/// position, size or font without a caption is an InputError (it would silently do nothing).
/// `title`, a scene document's title, is the caption when none is given (caption_by_default).
CaptionArgs caption_args(const options::Values& values, const std::string& title = "");

}  // namespace meshtour::cli
