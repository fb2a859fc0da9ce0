#pragma once
// The one writer of 8-bit images: the PNG frames (write_image, tracer/tracer.h), the posters
// (tour/poster.h) and the path plots (tour/path_plot.h) all go through it, so that they share the
// encoder's settings, the atomic write and the error messages.
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

namespace meshtour {

/// Whether the file records that its values are sRGB-encoded (a PNG's sRGB, gAMA and cHRM chunks).
/// Frames and posters do; path plots never have, and keep their bytes.
enum class SrgbTag { tagged, untagged };

/// Writes 8-bit display values (`channels` 3 = RGB or 4 = RGBA with straight alpha, interleaved,
/// rows top to bottom) as `file`, atomically (core/atomic_file.h), in the format its extension
/// names (PNG for .png; OpenImageIO chooses). `what` names the output in messages ("poster").
/// \throw InputError if no writer handles the extension, IoError if the file cannot be written.
void write_8bit_image(const std::filesystem::path& file, std::span<const std::uint8_t> pixels, int width, int height, int channels,
                      SrgbTag tag, const std::string& what);

}  // namespace meshtour
