#pragma once
// The poster still of a tour: its first frame, which is the view people would prefer (the feature
// orbit turns its loop to start at it: pathgen/coverage.h, ViewPreferenceModel; the turntable
// starts at its front, the paper's path at its start), written as a PNG. At the frames' size it is the
// frame's own PNG, byte for byte, whether `tour` writes it from the rendered image or `encode`
// from a frames directory; at another --poster-size the frame is cropped to that aspect (centred)
// and resampled (Lanczos, one thread: the same bytes everywhere). Written atomically.
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "tracer/tracer.h"

namespace meshtour {

struct PosterSize {
  int width = 0, height = 0;
};

/// What a tour's poster needs: the file and the size (unset = the frames' size).
struct PosterJob {
  std::filesystem::path file;  ///< "" = no poster
  std::optional<PosterSize> size;
};

/// Refuses (InputError) a poster file whose name does not end in .png.
void check_poster_name(const std::filesystem::path& file);

/// Refuses (before any work) a poster whose folder does not exist or is not writable.
void check_poster_output(const PosterJob& job);

/// The frame the poster (and the title card) shows: the first, the view the path starts at (the
/// feature orbit's --first-view, a Voyager scene's opening view), so the poster is what a player's
/// thumbnail shows. The manifest's best_view_frame (the best-covering frame of all) is information.
constexpr int kPosterFrame = 0;

/// Writes the rendered frame `image` as the poster (write_image at the frames' size).
void write_poster(const Image& image, const PosterJob& job);

/// Writes the frame PNG `frame_png` (a frames directory's) as the poster: a copy of the file at
/// its own size. \throw InputError / IoError naming the file when it cannot be read or written.
void write_poster_from_png(const std::filesystem::path& frame_png, const PosterJob& job);

/// Writes a display image (8-bit sRGB, `channels` 3 or 4, rows top to bottom) as the poster.
void write_poster_pixels(std::span<const std::uint8_t> pixels, int width, int height, int channels, const PosterJob& job);

}  // namespace meshtour
