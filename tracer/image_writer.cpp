#include "tracer/image_writer.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <string_view>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"

namespace meshtour {

void write_8bit_image(const std::filesystem::path& file, std::span<const std::uint8_t> pixels, int width, int height, int channels,
                      SrgbTag tag, const std::string& what) {
  if (pixels.size() != static_cast<std::size_t>(width) * height * channels)
    throw InputError(file.string() + ": the " + what + "'s pixels do not match its size " + std::to_string(width) + "x" +
                         std::to_string(height) + "x" + std::to_string(channels));
  OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::UINT8);
  if (tag == SrgbTag::tagged) spec.attribute("oiio:ColorSpace", "sRGB");
  // The pixels' alpha is straight, as PNG stores it: without this OpenImageIO's PNG writer takes
  // them as premultiplied and divides the colour by alpha once more (an edge pixel of grey 128 at
  // alpha 128 was stored as 255).
  if (channels == 2 || channels == 4) spec.attribute("oiio:UnassociatedAlpha", 1);
  write_encoded_image(file, spec, OIIO::TypeDesc::UINT8, pixels.data(), what);
}

void write_encoded_image(const std::filesystem::path& file, const OIIO::ImageSpec& spec, OIIO::TypeDesc type, const void* pixels,
                         const std::string& what) {
  // OpenImageIO picks the writer by the file's extension.
  auto out = OIIO::ImageOutput::create(file.string());
  if (!out)
    throw InputError(file.string() + ": cannot write the " + what + ": no image writer for '" + file.extension().string() +
                     "' files; use a .png name");
  if (!out->supports("ioproxy"))
    throw InputError(file.string() + ": cannot write the " + what + ": OpenImageIO's " + out->format_name() +
                     " writer cannot write to memory; use a .png or .exr name");
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput memory(bytes);
  OIIO::ImageSpec to_memory = spec;
  OIIO::Filesystem::IOProxy* proxy = &memory;
  to_memory.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  bool ok = out->open(file.string(), to_memory) && out->write_image(type, pixels);
  const std::string error = ok ? "" : out->geterror();
  ok = out->close() && ok;
  if (!ok) throw IoError(file.string() + ": cannot encode the " + what + ": " + (error.empty() ? "the image writer failed" : error));
  write_text_file_atomically(file, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), what);
}

}  // namespace meshtour
