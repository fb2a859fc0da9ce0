// The Film (film.h): the frame's tile sums and layers, allocated, cleared tile by tile, gathered
// and written out.
#include "tracer/film.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>

namespace meshtour {

Film::Film(int width, int height, int samples_per_pixel, const ReconstructionFilter& filter, const ExtraLayers& layers,
           bool denoiser_guides, FilmMemory& memory)
    : width_(width),
      height_(height),
      tiles_x_((width + kTileSize - 1) / kTileSize),
      tiles_y_((height + kTileSize - 1) / kTileSize),
      apron_(filter.apron()),
      stride_(kTileSize + 2 * apron_),
      // Per pixel: RGBA and the weight, plus the unshadowed light's RGB for the denoiser.
      sum_floats_(denoiser_guides ? 8 : 5),
      tile_floats_(static_cast<std::size_t>(stride_) * stride_ * sum_floats_),
      memory_(memory) {
  const std::size_t npix = static_cast<std::size_t>(width) * height;
  rgba_.assign(npix * 4, 0.0f);
  if (layers.albedo) albedo_.assign(npix * 3, 0.0f);
  if (layers.normal) normal_.assign(npix * 3, 0.0f);
  if (layers.depth) depth_.assign(npix, std::numeric_limits<float>::infinity());
  // One allocation for the frame's tile sums; each tile clears its own part (tile(), in
  // parallel, while it is hot).
  tile_sums_ = memory_.tile_sums.take();
  tile_sums_.resize(tile_floats_ * static_cast<std::size_t>(tile_count()));
  if (denoiser_guides) {
    guides_ = memory_.guides.take();
    guides_->resize(width, height, samples_per_pixel);  // each tile clears its own pixels
  }
}

Film::~Film() {
  if (!tile_sums_.empty()) memory_.tile_sums.give_back(std::move(tile_sums_));
  if (guides_) memory_.guides.give_back(std::move(*guides_));
}

FilmTile Film::tile(int index) {
  FilmTile t;
  t.x0 = index % tiles_x_ * kTileSize;
  t.y0 = index / tiles_x_ * kTileSize;
  t.x1 = std::min(width_, t.x0 + kTileSize);
  t.y1 = std::min(height_, t.y0 + kTileSize);
  t.frame_width = width_;
  t.apron = apron_;
  t.stride = stride_;
  t.sums = tile_sums_.data() + tile_floats_ * static_cast<std::size_t>(index);
  std::fill(t.sums, t.sums + tile_floats_, 0.0f);
  if (guides_) {  // the tile's pixels of the guides, which only this tile's samples add to
    DenoiseGuides& g = *guides_;
    t.guides = &g;
    for (int y = t.y0; y < t.y1; ++y) {
      const std::size_t row = static_cast<std::size_t>(y) * width_;
      std::fill(g.normal.begin() + static_cast<std::ptrdiff_t>((row + t.x0) * 3), g.normal.begin() + static_cast<std::ptrdiff_t>((row + t.x1) * 3), 0.0f);
      std::fill(g.moments.begin() + static_cast<std::ptrdiff_t>((row + t.x0) * 2), g.moments.begin() + static_cast<std::ptrdiff_t>((row + t.x1) * 2), 0.0f);
      std::fill(g.depth.begin() + static_cast<std::ptrdiff_t>(row + t.x0), g.depth.begin() + static_cast<std::ptrdiff_t>(row + t.x1),
                std::numeric_limits<float>::infinity());
    }
  }
  if (!albedo_.empty()) t.albedo = albedo_.data();
  if (!normal_.empty()) t.normal = normal_.data();
  if (!depth_.empty()) t.depth = depth_.data();
  return t;
}

void Film::finish_tile(const FilmTile& t) {
  if (!t.normal) return;
  for (int y = t.y0; y < t.y1; ++y)
    for (int x = t.x0; x < t.x1; ++x) {
      float* n = &t.normal[(static_cast<std::size_t>(y) * width_ + x) * 3];
      const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      if (len > 0.0f)
        for (int c = 0; c < 3; ++c) n[c] /= len;
    }
}

void Film::gather() {
  const int width = width_, tiles_x = tiles_x_, tiles_y = tiles_y_, apron = apron_, stride = stride_, sum_floats = sum_floats_;
  const std::size_t tile_floats = tile_floats_;
  const float* sums = tile_sums_.data();
  float* rgba = rgba_.data();
  float* unshadowed = guides_ ? guides_->unshadowed.data() : nullptr;
  tbb::parallel_for(tbb::blocked_range<int>(0, height_), [&](const tbb::blocked_range<int>& range) {
    for (int y = range.begin(); y != range.end(); ++y)
      for (int x = 0; x < width; ++x) {
        float acc[8] = {0, 0, 0, 0, 0, 0, 0, 0};
        for (int ty = std::max(0, (y - apron) / kTileSize); ty <= std::min(tiles_y - 1, (y + apron) / kTileSize); ++ty)
          for (int tx = std::max(0, (x - apron) / kTileSize); tx <= std::min(tiles_x - 1, (x + apron) / kTileSize); ++tx) {
            const int bx = x - (tx * kTileSize - apron), by = y - (ty * kTileSize - apron);
            if (bx < 0 || by < 0 || bx >= stride || by >= stride) continue;
            const float* src = sums + tile_floats * static_cast<std::size_t>(ty * tiles_x + tx) +
                               (static_cast<std::size_t>(by) * stride + bx) * sum_floats;
            for (int c = 0; c < sum_floats; ++c) acc[c] += src[c];
          }
        const std::size_t p = static_cast<std::size_t>(y) * width + x;
        const float weight = acc[sum_floats - 1];
        float* dst = &rgba[p * 4];
        for (int c = 0; c < 4; ++c) dst[c] = weight > 0.0f ? acc[c] / weight : 0.0f;
        if (unshadowed)
          for (int c = 0; c < 3; ++c) unshadowed[p * 3 + c] = weight > 0.0f ? acc[4 + c] / weight : 0.0f;
      }
  });
  memory_.tile_sums.give_back(std::move(tile_sums_));
  tile_sums_ = {};
}

void Film::write_to(Image& image) {
  image.width = width_;
  image.height = height_;
  image.rgba = std::move(rgba_);
  image.albedo = std::move(albedo_);
  image.normal = std::move(normal_);
  image.depth = std::move(depth_);
}

}  // namespace meshtour
