#pragma once
// Reads an embedded image (a glTF buffer view, a data: URI) through OpenImageIO from memory.
#include <OpenImageIO/filesystem.h>

#include <algorithm>
#include <cstdint>
#include <cstring>

namespace meshtour {

/// OpenImageIO's IOMemReader with its offsets checked. OpenImageIO 2.4's reader copies from any
/// offset it is given, and a damaged EXR's line-offset table sends OpenEXR to offsets before the
/// buffer (found by fuzz_texture: a heap read out of bounds). Here a seek outside the image fails
/// and a read there returns nothing, which the decoders report as a truncated file.
class ImageBytesReader final : public OIIO::Filesystem::IOMemReader {
 public:
  ImageBytesReader(const unsigned char* data, std::size_t size) : IOMemReader(data, size) {}

  bool seek(std::int64_t offset) override {
    if (offset < 0 || static_cast<std::uint64_t>(offset) > size()) return false;
    m_pos = offset;
    return true;
  }
  std::size_t pread(void* out, std::size_t count, std::int64_t offset) override {
    const auto bytes = buffer();
    const std::int64_t end = static_cast<std::int64_t>(bytes.size());
    if (offset < 0 || offset >= end) return 0;
    const std::size_t n = std::min(count, static_cast<std::size_t>(end - offset));
    std::memcpy(out, bytes.data() + offset, n);
    return n;
  }
  std::size_t read(void* out, std::size_t count) override {
    const std::size_t n = pread(out, count, m_pos);
    m_pos += static_cast<std::int64_t>(n);
    return n;
  }
};

}  // namespace meshtour
