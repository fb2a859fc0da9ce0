#include "mesh/textures.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>

#include "core/error.h"
#include "mesh/image_probe.h"
#include "mesh/file_extension.h"
#include "mesh/image_bytes_reader.h"

namespace meshtour {
namespace {

// Limits of a texture meshtour decodes (docs/FORMATS.md, "Hostile textures"). No image codec
// meshtour reads packs more than about 33,000 decoded bytes into one file byte (deflate's 1032:1
// times a 1-bit palette's 32-fold expansion), so a header claiming more than kMaxExpansion is
// damaged or a decompression bomb; and no atlas needs more than kMaxSide a side or kMaxPixels.
constexpr double kMaxExpansion = 65536.0;
constexpr long long kMaxSide = 65536;
constexpr double kMaxPixels = 1024.0 * 1024 * 1024;

std::string file_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Calls `check` with the image's bytes: the embedded ones, or the file's, read whole.
template <typename Check>
std::string with_bytes(const std::string& file, const std::vector<unsigned char>* bytes, Check check) {
  if (bytes) return check(bytes->data(), bytes->size());
  const std::string read = file_bytes(file);
  return check(reinterpret_cast<const std::uint8_t*>(read.data()), read.size());
}

bool is_ktx_or_basis(const std::string& file, const std::uint8_t* head, std::size_t size) {
  static const std::uint8_t ktx[] = {0xAB, 'K', 'T', 'X', ' '};
  const std::string ext = lower_extension(std::filesystem::path(file));
  return ext == ".ktx2" || ext == ".ktx" || ext == ".basis" || (size >= sizeof ktx && std::memcmp(head, ktx, sizeof ktx) == 0);
}

std::uint32_t big_endian(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | p[3];
}

// Checks a PNG's structure before OpenImageIO opens it: libpng reports a damaged file (even a
// text chunk cut short, while the header is read) by printing "libpng error" lines on stderr, so
// the file must be known whole first. Walks the chunks (lengths, CRCs, IHDR first, IEND last);
// with `image_data`, also inflates the IDAT stream in constant memory and checks that it holds
// exactly the rows the header announces, each with a valid filter byte. Returns what is wrong,
// or "" for a whole file.
std::string png_fault(const std::uint8_t* data, std::size_t size, bool image_data) {
  static const std::uint8_t signature[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  if (size < 8 || std::memcmp(data, signature, 8) != 0) return "it is not a PNG file";
  std::size_t at = 8;
  std::uint32_t width = 0, height = 0;
  int bits_per_pixel = 0, interlace = 0;
  bool ended = false;
  std::vector<std::pair<std::size_t, std::size_t>> rows;  // (bytes a row with its filter byte, count) per pass
  z_stream z{};
  if (inflateInit(&z) != Z_OK) return "zlib cannot start";
  struct End {
    z_stream& z;
    ~End() { inflateEnd(&z); }
  } end{z};
  std::array<std::uint8_t, 1 << 16> out{};
  std::size_t pass = 0, row = 0, in_row = 0;  // where the next inflated byte lands
  bool stream_done = false;
  const auto take = [&](const std::uint8_t* bytes, std::size_t n) -> std::string {
    for (std::size_t i = 0; i < n;) {
      while (pass < rows.size() && row == rows[pass].second) ++pass, row = 0;
      if (pass == rows.size()) return "its image data holds more than its " + std::to_string(width) + " x " + std::to_string(height) + " pixels";
      if (in_row == 0 && bytes[i] > 4) return "row " + std::to_string(row) + " has an invalid filter type";
      const std::size_t step = std::min(n - i, rows[pass].first - in_row);
      i += step;
      in_row += step;
      if (in_row == rows[pass].first) in_row = 0, ++row;
    }
    return "";
  };
  while (!ended) {
    if (size - at < 12) return "it is truncated (it ends inside a chunk, before IEND)";
    const std::uint32_t length = big_endian(data + at);
    if (length > size - at - 12) return "it is truncated (a chunk runs past the end of the file)";
    const std::uint8_t* type = data + at + 4;
    const std::uint8_t* body = type + 4;
    if (crc32(crc32(0, nullptr, 0), type, length + 4) != big_endian(body + length)) return "a chunk's checksum is wrong";
    const std::string name(reinterpret_cast<const char*>(type), 4);
    if (at == 8 && name != "IHDR") return "it does not start with an IHDR chunk";
    if (name == "IHDR") {
      if (length != 13) return "its IHDR chunk is malformed";
      width = big_endian(body);
      height = big_endian(body + 4);
      const int depth = body[8], colour = body[9];
      const int samples = colour == 0 || colour == 3 ? 1 : colour == 2 ? 3 : colour == 4 ? 2 : colour == 6 ? 4 : 0;
      if (samples == 0 || width == 0 || height == 0) return "its IHDR chunk is malformed";
      bits_per_pixel = samples * depth;
      interlace = body[12];
      // The passes of Adam7 (or the one pass of a plain image): origin and step in x and y.
      const int plain[1][4] = {{0, 0, 1, 1}};
      const int adam7[7][4] = {{0, 0, 8, 8}, {4, 0, 8, 8}, {0, 4, 4, 8}, {2, 0, 4, 4}, {0, 2, 2, 4}, {1, 0, 2, 2}, {0, 1, 1, 2}};
      for (int p = 0; p < (interlace ? 7 : 1); ++p) {
        const int* g = interlace ? adam7[p] : plain[0];
        const std::uint64_t w = width > static_cast<std::uint32_t>(g[0]) ? (width - g[0] + g[2] - 1) / g[2] : 0;
        const std::uint64_t h = height > static_cast<std::uint32_t>(g[1]) ? (height - g[1] + g[3] - 1) / g[3] : 0;
        if (w > 0 && h > 0) rows.emplace_back(1 + (w * bits_per_pixel + 7) / 8, h);
      }
    } else if (name == "IDAT" && image_data && !stream_done) {
      z.next_in = const_cast<std::uint8_t*>(body);
      z.avail_in = length;
      while (z.avail_in > 0 && !stream_done) {
        z.next_out = out.data();
        z.avail_out = out.size();
        const int r = inflate(&z, Z_NO_FLUSH);
        if (r != Z_OK && r != Z_STREAM_END && r != Z_BUF_ERROR) return "its image data is corrupt (" + std::string(z.msg ? z.msg : "deflate error") + ")";
        if (const std::string fault = take(out.data(), out.size() - z.avail_out); !fault.empty()) return fault;
        stream_done = r == Z_STREAM_END;
        if (r == Z_BUF_ERROR && z.avail_out != 0) break;
      }
    } else if (name == "IEND") {
      ended = true;
    }
    at += 12 + length;
  }
  if (!image_data) return "";
  if (!stream_done) return "it is truncated (its image data stops early)";
  while (pass < rows.size() && row == rows[pass].second) ++pass, row = 0;
  if (pass != rows.size()) return "it is truncated (its image data holds fewer rows than its header announces)";
  return "";
}

// Checks an OpenEXR file's headers before OpenEXR reads them: each attribute's size must lie
// inside the file (OpenEXR 3.1 allocates what a string attribute's size announces, up to 2 GiB,
// before it finds the file too short). Returns what is wrong, or "" when the headers fit.
std::string exr_header_fault(const std::uint8_t* data, std::size_t size) {
  if (size < 8) return "it is truncated (it ends inside its header)";
  const bool multipart = (data[5] & 0x10) != 0;  // version flags, bit 12
  std::size_t at = 8;
  const auto text = [&]() -> std::ptrdiff_t {  // length of the NUL-terminated string at `at`, -1 if none
    const auto* end = static_cast<const std::uint8_t*>(std::memchr(data + at, 0, size - at));
    return end ? end - (data + at) : -1;
  };
  for (int header = 0; header < 1 << 16; ++header) {
    for (;;) {
      if (at >= size) return "it is truncated (it ends inside its header)";
      const std::ptrdiff_t name = text();
      if (name < 0) return "it is truncated (it ends inside its header)";
      at += static_cast<std::size_t>(name) + 1;
      if (name == 0) break;  // the end of this header
      const std::ptrdiff_t type = at < size ? text() : -1;
      if (type < 0) return "it is truncated (it ends inside its header)";
      at += static_cast<std::size_t>(type) + 1;
      if (size - at < 4) return "it is truncated (it ends inside its header)";
      const std::uint32_t length = std::uint32_t{data[at]} | std::uint32_t{data[at + 1]} << 8 | std::uint32_t{data[at + 2]} << 16 |
                                   std::uint32_t{data[at + 3]} << 24;
      at += 4;
      if (length > size - at) return "a header attribute claims " + std::to_string(length) + " bytes, more than the file holds";
      at += length;
    }
    if (!multipart) return "";
    if (at < size && data[at] == 0) return "";  // an empty header ends the list of parts
  }
  return "it has too many parts";
}

// A JPEG ends with the EOI marker (some writers add a few padding bytes); libjpeg decodes a
// truncated one without an error, filling the missing part with grey.
bool jpeg_ends(const std::uint8_t* data, std::size_t size) {
  std::size_t end = size;
  for (int pad = 0; end > 2 && pad < 64 && (data[end - 1] == 0 || data[end - 1] == '\n' || data[end - 1] == '\r'); ++pad) --end;
  return end >= 4 && data[end - 2] == 0xFF && data[end - 1] == 0xD9;
}

// Decodes every pixel once, a band of rows (or a row of tiles) at a time, so that a truncated or
// damaged file is found at load time, as an error naming it, and not as a grey or black patch in
// the video. OpenImageIO reports the decoders' errors through geterror(), not on stderr.
std::string decode_fault(OIIO::ImageInput& in) {
  const OIIO::ImageSpec& spec = in.spec();
  if (spec.tile_width > 0 && static_cast<double>(spec.width + spec.tile_width) * spec.tile_height * spec.nchannels > 256.0 * 1024 * 1024)
    return "its tiles (" + std::to_string(spec.tile_width) + " x " + std::to_string(spec.tile_height) + " pixels) are too large to decode";
  // Rows of about 4 MiB at a time, no more than the image has (a small image's band is all of it).
  const int band = spec.tile_height > 0 ? spec.tile_height
                                        : std::clamp(static_cast<int>((4 << 20) / (std::max(1, spec.width) * std::max(1, spec.nchannels))), 1,
                                                     std::max(1, spec.height));
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(spec.width + std::max(0, spec.tile_width)) * band * spec.nchannels);
  for (int y = spec.y; y < spec.y + spec.height; y += band) {
    const int y_end = std::min(y + band, spec.y + spec.height);
    const bool ok = spec.tile_width > 0
                        ? in.read_tiles(0, 0, spec.x, spec.x + spec.width, y, y_end, spec.z, spec.z + 1, 0, spec.nchannels, OIIO::TypeDesc::UINT8, pixels.data())
                        : in.read_scanlines(0, 0, y, y_end, spec.z, 0, spec.nchannels, OIIO::TypeDesc::UINT8, pixels.data());
    if (!ok) {
      std::string message = in.geterror();
      std::replace(message.begin(), message.end(), '\n', ' ');
      return "it cannot be decoded (" + (message.empty() ? std::string("damaged or truncated") : message) + ")";
    }
  }
  return "";
}

// Opens the image (from `bytes` when given, else from `file`) and checks its header: the checks
// that need no decoding. Returns the reader, positioned at the first subimage.
std::unique_ptr<OIIO::ImageInput> open_checked(const std::string& file, const std::string& what, const std::vector<unsigned char>* bytes,
                                               std::unique_ptr<ImageBytesReader>& memory, double& file_size) {
  const std::string head = bytes ? std::string(bytes->begin(), bytes->begin() + std::min<std::size_t>(16, bytes->size())) : [&] {
    std::ifstream f(file, std::ios::binary);
    std::string h(16, '\0');
    f.read(h.data(), 16);
    h.resize(static_cast<std::size_t>(f.gcount()));
    return h;
  }();
  if (is_ktx_or_basis(file, reinterpret_cast<const std::uint8_t*>(head.data()), head.size()))
    throw IoError(what + " is a KTX2 / Basis Universal texture, which meshtour does not decode; convert it to PNG or JPEG");
  if (head.rfind("\x89PNG", 0) == 0)
    if (const std::string fault = with_bytes(file, bytes, [](const std::uint8_t* data, std::size_t size) { return png_fault(data, size, false); });
        !fault.empty())
      throw IoError(what + " is damaged: " + fault);
  if (head.rfind("\x76\x2f\x31\x01", 0) == 0)
    if (const std::string fault = with_bytes(file, bytes, exr_header_fault); !fault.empty()) throw IoError(what + " is damaged: " + fault);
  std::unique_ptr<OIIO::ImageInput> in;
  if (bytes) {
    memory = std::make_unique<ImageBytesReader>(bytes->data(), bytes->size());
    in = OIIO::ImageInput::open(file, nullptr, memory.get());
    file_size = static_cast<double>(bytes->size());
  } else {
    in = OIIO::ImageInput::open(file);
    std::error_code ec;
    file_size = static_cast<double>(std::filesystem::file_size(file, ec));
  }
  if (!in) {
    std::string message = OIIO::geterror();
    std::replace(message.begin(), message.end(), '\n', ' ');
    throw IoError(what + " is not a readable image: " + message);
  }
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0) throw IoError(what + " has no pixels");
  const double pixels = static_cast<double>(spec.width) * spec.height * std::max(1, spec.depth);
  const double decoded = pixels * std::max(1, spec.nchannels);
  const std::string claims = std::to_string(spec.width) + " x " + std::to_string(spec.height) + " pixels";
  if (decoded > kMaxExpansion * std::max(1.0, file_size))
    throw IoError(what + " claims " + claims + " but the file holds only " + std::to_string(static_cast<long long>(file_size)) +
                  " bytes, more than any image codec can pack (a damaged file or a decompression bomb)");
  if (spec.width > kMaxSide || spec.height > kMaxSide || pixels > kMaxPixels)
    throw IoError(what + " claims " + claims + ", more than meshtour decodes (at most 65536 a side and 1 gigapixel); scale it down");
  if (spec.nchannels < 1 || spec.nchannels > 4)
    throw IoError(what + " has " + std::to_string(spec.nchannels) +
                  " channels; a colour map needs 1 (grey), 2 (grey, alpha), 3 (RGB) or 4 (RGBA): save it as RGB");
  return in;
}

}  // namespace

namespace {

// What a message calls a map: "FILE: the texture of material 'NAME'" (+ " (embedded)").
std::string map_description(const MeshTexture& map, const std::string& material_name, const char* kind) {
  return map.file.string() + ": the " + kind + " of material '" + material_name + "'" + (map.bytes ? " (embedded)" : "");
}

}  // namespace

namespace {

// The header of an image from `bytes` when given, else from `file`, after open_checked's checks.
TextureSize probe(const std::filesystem::path& file, const std::string& what, const std::vector<unsigned char>* bytes) {
  std::error_code ec;
  if (!bytes && !std::filesystem::is_regular_file(file, ec)) throw IoError(what + " does not exist");
  std::unique_ptr<ImageBytesReader> memory;
  double file_size = 0;
  const auto in = open_checked(file.string(), what, bytes, memory, file_size);
  TextureSize size{in->spec().width, in->spec().height, in->spec().nchannels};
  in->close();
  return size;
}

}  // namespace

TextureSize probe_image(const std::filesystem::path& image, const std::string& what) { return probe(image, what, nullptr); }

TextureSize probe_texture(const MeshTexture& map, const std::string& material_name) {
  return probe(map.file, map_description(map, material_name, "texture"), map.bytes.get());
}

void verify_texture(const MeshTexture& map, const std::string& material_name, const char* kind) {
  const std::string file = map.file.string();
  const std::string what = map_description(map, material_name, kind);
  std::error_code ec;
  if (!map.bytes && !std::filesystem::is_regular_file(map.file, ec)) throw IoError(what + " does not exist");
  std::unique_ptr<ImageBytesReader> memory;
  double file_size = 0;
  const auto in = open_checked(file, what, map.bytes.get(), memory, file_size);
  const std::string format = in->format_name();
  std::string fault;
  if (format == "png" || format == "jpeg")
    fault = with_bytes(file, map.bytes.get(), [&](const std::uint8_t* data, std::size_t size) -> std::string {
      if (format == "png") return png_fault(data, size, true);
      return jpeg_ends(data, size) ? "" : "it is truncated (it does not end with the JPEG end-of-image marker)";
    });
  if (fault.empty()) fault = decode_fault(*in);
  in->close();
  if (!fault.empty()) throw IoError(what + " is damaged: " + fault);
}

bool reads_as_normal_map(const MeshTexture& map, const std::string& material_name) {
  const std::string what = map_description(map, material_name, "bump map");
  std::unique_ptr<ImageBytesReader> memory;
  double file_size = 0;
  const auto in = open_checked(map.file.string(), what, map.bytes.get(), memory, file_size);
  const OIIO::ImageSpec spec = in->spec();
  if (spec.nchannels < 3) return false;
  // Every step-th row and column: rows are decoded in order anyway (PNG, JPEG), one at a time.
  const int step = std::max(1, std::max(spec.width, spec.height) / 256);
  std::vector<float> row(static_cast<std::size_t>(spec.width) * spec.nchannels);
  std::size_t pixels = 0, blue_largest = 0;
  double blue = 0.0, off_grey = 0.0;
  // A tiled image (EXR, TIFF) is read whole, a byte per channel: no scanline access there.
  std::vector<std::uint8_t> whole;
  if (spec.tile_width > 0) {
    whole.resize(static_cast<std::size_t>(spec.width) * spec.height * spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, whole.data()))
      throw IoError(what + " could not be read: " + in->geterror());
  }
  for (int y = 0; y < spec.height; ++y) {
    // Scanlines are decoded in order: every row is read, every step-th looked at.
    if (whole.empty() && !in->read_scanline(y, 0, OIIO::TypeDesc::FLOAT, row.data()))
      throw IoError(what + " could not be read: " + in->geterror());
    if (y % step != 0) continue;
    if (!whole.empty())
      for (std::size_t i = 0; i < row.size(); ++i) row[i] = whole[static_cast<std::size_t>(y) * row.size() + i] / 255.0f;
    for (int x = 0; x < spec.width; x += step) {
      const float* p = &row[static_cast<std::size_t>(x) * spec.nchannels];
      ++pixels;
      blue += p[2];
      off_grey += std::abs(p[2] - p[0]) + std::abs(p[2] - p[1]);
      blue_largest += p[2] >= p[0] && p[2] >= p[1];
    }
  }
  in->close();
  if (pixels == 0) return false;
  const double n = static_cast<double>(pixels);
  return blue_largest >= 0.9 * n && blue / n >= 0.6 && off_grey / n >= 0.1;
}

bool verify_or_warn(const MeshTexture& map, const std::string& material_name, const char* kind, const std::string& without,
                    const std::string& name, const LoadOptions& options, std::vector<std::string>& warnings) {
  try {
    verify_texture(map, material_name, kind);
    return true;
  } catch (const IoError& e) {
    if (!options.missing_textures_grey)
      throw IoError(name + ": " + e.what() + " (fix the path or the file, or pass --missing-textures grey to render its faces " +
                    without + ")");
    warnings.push_back(std::string(e.what()) + "; its faces are rendered " + without + " (--missing-textures grey)");
    return false;
  }
}

void check_material_textures(TriangleMesh& mesh, const std::string& name, const LoadOptions& options,
                             std::vector<std::string>& warnings) {
  if (mesh.materials.empty()) {
    mesh.triangle_materials.clear();
    return;
  }
  std::vector<bool> used(mesh.materials.size(), false);
  if (mesh.triangle_materials.empty()) used[0] = true;
  for (std::size_t t = 0; t < mesh.triangle_materials.size(); ++t) {
    const std::uint32_t m = mesh.triangle_materials[t];
    if (m >= mesh.materials.size())
      throw InputError(name + ": triangle " + std::to_string(t) + " uses material " + std::to_string(m) + ", but the file has " +
                       std::to_string(mesh.materials.size()));
    used[m] = true;
  }
  for (std::size_t m = 0; m < mesh.materials.size(); ++m) {
    MeshMaterial& material = mesh.materials[m];
    if (!used[m] || !options.check_textures) continue;
    for (const auto& [map, kind] : material.named_maps()) {
      // What the faces are rendered without: "untextured", "without their normal map", ...
      std::string without = "untextured";
      if (map != &material.texture) {
        const std::string name = kind;
        without = "without their " + name.substr(0, name.rfind(" texture")) + " map";
      }
      if (!verify_or_warn(*map, material.name, kind, without, name, options, warnings)) *map = MeshTexture{};
    }
  }
}

}  // namespace meshtour
