#pragma once
// The one writer of 8-bit images: the PNG frames (write_image, tracer/tracer.h), the posters
// (tour/poster.h) and the path plots (tour/path_plot.h) all go through it, so that they share the
// encoder's settings, the atomic write and the error messages.
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

#include <OpenImageIO/imageio.h>

namespace meshtour {

/// Whether the file records that its values are sRGB-encoded (a PNG's sRGB, gAMA and cHRM chunks).
/// Frames and posters do; path plots never have, and keep their bytes.
enum class SrgbTag { tagged, untagged };

/// Encodes an image with OpenImageIO into memory (the writer the extension of `file` names, with
/// `spec`; `pixels` of `type`, interleaved as the spec says) and writes the bytes as `file`,
/// atomically. In memory first because OpenImageIO's writers do not all report a failed write to
/// the file (a full disk left a truncated PNG under its final name); these writes are checked.
/// `what` names the output in messages. \throw InputError if no writer handles the extension or it
/// cannot write to memory, IoError if the image cannot be encoded or the file cannot be written.
void write_encoded_image(const std::filesystem::path& file, const OIIO::ImageSpec& spec, OIIO::TypeDesc type, const void* pixels,
                         const std::string& what);

/// Writes 8-bit display values (`channels` 3 = RGB or 4 = RGBA with straight alpha, interleaved,
/// rows top to bottom) as `file`, atomically (core/atomic_file.h), in the format its extension
/// names (PNG for .png; OpenImageIO chooses). `what` names the output in messages ("poster").
/// \throw InputError if no writer handles the extension, IoError if the file cannot be written.
void write_8bit_image(const std::filesystem::path& file, std::span<const std::uint8_t> pixels, int width, int height, int channels,
                      SrgbTag tag, const std::string& what);

}  // namespace meshtour
