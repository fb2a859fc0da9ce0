#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <system_error>

#include "core/error.h"
#include "tracer/color.h"
#include "tracer/tracer.h"

namespace meshtour {

std::vector<std::uint8_t> Image::to_srgb8() const {
  std::vector<std::uint8_t> out(static_cast<std::size_t>(width) * height * 3);
  for (std::size_t p = 0, n = static_cast<std::size_t>(width) * height; p < n; ++p)
    for (int k = 0; k < 3; ++k) {
      const float c = linear_to_srgb(std::clamp(rgba[p * 4 + k], 0.0f, 1.0f));
      out[p * 3 + k] = static_cast<std::uint8_t>(std::lround(c * 255.0f));
    }
  return out;
}

void write_image(const Image& image, const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  const bool png = ext == ".png", exr = ext == ".exr";
  if (!png && !exr) throw InputError(file.string() + ": frames can be written as .png or .exr, not '" + ext + "'");

  // Same directory, same extension (OpenImageIO picks the format from it), hidden temporary name.
  const auto temp = file.parent_path() /
                    ("." + file.stem().string() + ".partial-" + std::to_string(::getpid()) + ext);
  auto out = OIIO::ImageOutput::create(temp.string());
  if (!out) throw IoError(file.string() + ": no image writer for '" + ext + "': " + OIIO::geterror());

  bool ok = false;
  if (png) {
    OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:ColorSpace", "sRGB");
    const auto pixels = image.to_srgb8();
    ok = out->open(temp.string(), spec) && out->write_image(OIIO::TypeDesc::UINT8, pixels.data());
  } else {
    OIIO::ImageSpec spec(image.width, image.height, 4, OIIO::TypeDesc::HALF);
    spec.attribute("oiio:ColorSpace", "linear");
    spec.attribute("compression", "zip");
    ok = out->open(temp.string(), spec) && out->write_image(OIIO::TypeDesc::FLOAT, image.rgba.data());
  }
  const std::string error = ok ? "" : out->geterror();
  ok = out->close() && ok;
  std::error_code ec;
  if (!ok) {
    std::filesystem::remove(temp, ec);
    throw IoError(file.string() + ": cannot write image: " + (error.empty() ? "write failed" : error));
  }
  std::filesystem::rename(temp, file, ec);
  if (ec) {
    std::filesystem::remove(temp, ec);
    throw IoError(file.string() + ": cannot write image: " + ec.message());
  }
}

}  // namespace meshtour
