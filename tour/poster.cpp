#include "tour/poster.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "tracer/image_writer.h"

namespace meshtour {
namespace {

namespace fs = std::filesystem;

}  // namespace

void check_poster_name(const fs::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext != ".png") throw InputError("--poster " + file.string() + ": the poster is written as PNG; name it *.png");
}

namespace {

// The frame, cropped (centred) to the poster's aspect and resampled to its size, written atomically.
void write_resampled(const OIIO::ImageBuf& frame, const PosterSize& size, const fs::path& file) {
  const OIIO::ImageSpec& spec = frame.spec();
  const double frame_aspect = static_cast<double>(spec.width) / spec.height;
  const double poster_aspect = static_cast<double>(size.width) / size.height;
  OIIO::ROI roi = frame.roi();
  if (poster_aspect > frame_aspect) {  // wider poster: keep the width, crop rows
    const int rows = std::max(1, static_cast<int>(std::lround(spec.width / poster_aspect)));
    roi.ybegin = (spec.height - rows) / 2;
    roi.yend = roi.ybegin + rows;
  } else {
    const int cols = std::max(1, static_cast<int>(std::lround(spec.height * poster_aspect)));
    roi.xbegin = (spec.width - cols) / 2;
    roi.xend = roi.xbegin + cols;
  }
  const OIIO::ImageBuf cropped = OIIO::ImageBufAlgo::cut(frame, roi, /*nthreads=*/1);
  OIIO::ImageSpec out_spec(size.width, size.height, spec.nchannels, OIIO::TypeDesc::UINT8);
  OIIO::ImageBuf poster(out_spec);
  if (!OIIO::ImageBufAlgo::resize(poster, cropped, "lanczos3", 0.0f, {}, /*nthreads=*/1))
    throw RuntimeFailure(file.string() + ": resampling the poster failed: " + poster.geterror());
  // The frame was read premultiplied (OpenImageIO's default), which is how it must be resampled;
  // the poster is written with straight alpha, as PNG stores it.
  if (spec.alpha_channel >= 0 && !OIIO::ImageBufAlgo::unpremult(poster, poster, {}, /*nthreads=*/1))
    throw RuntimeFailure(file.string() + ": resampling the poster failed: " + poster.geterror());
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(size.width) * size.height * spec.nchannels);
  if (!poster.get_pixels(poster.roi(), OIIO::TypeDesc::UINT8, pixels.data()))
    throw RuntimeFailure(file.string() + ": resampling the poster failed: " + poster.geterror());
  write_8bit_image(file, pixels, size.width, size.height, spec.nchannels, SrgbTag::tagged, "poster");
}

}  // namespace

void check_poster_output(const PosterJob& job) {
  if (job.file.empty()) return;
  check_poster_name(job.file);
  const fs::path dir = job.file.parent_path().empty() ? fs::path(".") : job.file.parent_path();
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw IoError("--poster " + job.file.string() + ": the folder " + dir.string() + " does not exist; create it first");
}

void write_poster(const Image& image, const PosterJob& job) {
  if (job.file.empty()) return;
  if (!job.size || (job.size->width == image.width && job.size->height == image.height)) {
    write_image(image, job.file);  // the frame's own PNG, byte for byte
    return;
  }
  const auto pixels = image.transparent ? image.to_srgba8() : image.to_srgb8();
  write_poster_pixels(pixels, image.width, image.height, image.transparent ? 4 : 3, job);
}

void write_poster_from_png(const fs::path& frame_png, const PosterJob& job) {
  if (job.file.empty()) return;
  OIIO::ImageBuf frame(frame_png.string());
  if (!frame.read(0, 0, true, OIIO::TypeDesc::UINT8))
    throw InputError(frame_png.string() + ": cannot read the poster frame: " + frame.geterror());
  const OIIO::ImageSpec& spec = frame.spec();
  if (job.size && (job.size->width != spec.width || job.size->height != spec.height)) {
    write_resampled(frame, *job.size, job.file);
    return;
  }
  // At the frames' size the poster is the frame's file itself.
  std::ifstream in(frame_png, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof()) throw IoError(frame_png.string() + ": cannot read the poster frame");
  write_text_file_atomically(job.file, bytes, "poster");
}

void write_poster_pixels(std::span<const std::uint8_t> pixels, int width, int height, int channels, const PosterJob& job) {
  if (job.file.empty()) return;
  OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::UINT8);
  OIIO::ImageBuf frame(spec);
  frame.set_pixels(frame.roi(), OIIO::TypeDesc::UINT8, pixels.data());
  write_resampled(frame, job.size.value_or(PosterSize{width, height}), job.file);
}

}  // namespace meshtour
