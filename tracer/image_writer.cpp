#include "tracer/image_writer.h"

#include <OpenImageIO/imageio.h>

#include "core/atomic_file.h"
#include "core/error.h"

namespace meshtour {

void write_8bit_image(const std::filesystem::path& file, std::span<const std::uint8_t> pixels, int width, int height, int channels,
                      SrgbTag tag, const std::string& what) {
  if (pixels.size() != static_cast<std::size_t>(width) * height * channels)
    throw InputError(file.string() + ": the " + what + "'s pixels do not match its size " + std::to_string(width) + "x" +
                         std::to_string(height) + "x" + std::to_string(channels));
  // The temporary keeps the extension: OpenImageIO picks the format from it.
  PendingFile pending(file);
  const std::string temporary = pending.temporary().string();
  auto out = OIIO::ImageOutput::create(temporary);
  if (!out)
    throw InputError(file.string() + ": cannot write the " + what + ": no image writer for '" + file.extension().string() +
                     "' files; use a .png name");
  OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::UINT8);
  if (tag == SrgbTag::tagged) spec.attribute("oiio:ColorSpace", "sRGB");
  bool ok = out->open(temporary, spec) && out->write_image(OIIO::TypeDesc::UINT8, pixels.data());
  const std::string error = ok ? "" : out->geterror();
  ok = out->close() && ok;
  if (!ok) throw IoError(file.string() + ": cannot write the " + what + ": " + (error.empty() ? "write failed" : error));
  pending.commit();
}

}  // namespace meshtour
