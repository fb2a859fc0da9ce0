#include "mesh/off_reader.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <string_view>

#include "core/error.h"
#include "mesh/mesh_text.h"

namespace meshtour::off_detail {
namespace {

using mesh_text::parse_double;
using mesh_text::parse_integer;

// What the keyword's prefixes say follows each vertex's coordinates: [ST][C][N][4]OFF.
struct OffLayout {
  int dimensions = 3;      // 4OFF: x y z w (w is dropped, as Geomview's 3D viewers do)
  bool normals = false;    // NOFF: a normal after the coordinates (as many numbers)
  bool colours = false;    // COFF: a colour after the coordinates (and the normal)
  bool texcoords = false;  // STOFF: a texture coordinate pair last (not used)

  std::size_t colour_at() const { return static_cast<std::size_t>(dimensions) * (normals ? 2 : 1); }  // the colour's first number
};

OffLayout layout_of(std::string_view keyword, const std::string& where) {
  if (keyword.size() < 3 || keyword.substr(keyword.size() - 3) != "OFF")
    throw InputError(where + "not an OFF file: the first word is '" + std::string(keyword) + "', not OFF (or COFF, NOFF, STOFF, ...)");
  OffLayout layout;
  const std::string_view prefix = keyword.substr(0, keyword.size() - 3);
  for (std::size_t i = 0; i < prefix.size(); ++i) {
    const char c = prefix[i];
    if (c == 'n') throw InputError(where + "nOFF (vertices of any dimension) is not supported");
    if (c == '4') layout.dimensions = 4;
    else if (c == 'N') layout.normals = true;
    else if (c == 'C') layout.colours = true;
    else if (c == 'S' && i + 1 < prefix.size() && prefix[i + 1] == 'T') layout.texcoords = true, ++i;
    else throw InputError(where + "unknown OFF keyword '" + std::string(keyword) + "' (its prefixes may be ST, C, N and 4)");
  }
  return layout;
}

// The counts announced against the file's size: each vertex needs at least three numbers and
// separators, each face a count and three indices (text); binary sizes are exact minimums.
void check_counts(long long vertices, long long faces, long double needed, unsigned long long size, const std::string& name, const char* kind) {
  if (needed > static_cast<long double>(size))
    throw InputError(name + ": truncated or corrupt " + kind + ": the header announces " + std::to_string(vertices) + " vertices and " +
                     std::to_string(faces) + " faces but the file holds only " + std::to_string(size) + " bytes");
}

// Checks the counts against the file's size (`needed`: the least they take), then records them
// and, when reading, makes room for what they announce.
void start_lists(long long nv, long long nf, long double needed, unsigned long long size, const std::string& name, const char* kind,
                 const OffLayout& layout, bool read, OffContents& out) {
  check_counts(nv, nf, needed, size, name, kind);
  out.summary.vertices = static_cast<std::size_t>(nv);
  out.summary.faces = static_cast<std::size_t>(nf);
  if (!read) return;
  out.positions.reserve(static_cast<std::size_t>(nv));
  if (layout.colours) out.colors.reserve(static_cast<std::size_t>(nv));
  out.triangles.reserve(static_cast<std::size_t>(nf));
}

// Fans a polygon's corners into triangles (a triangle stays as it is).
void add_polygon(const std::uint32_t* corners, std::size_t count, OffContents& out) {
  for (std::size_t k = 1; k + 1 < count; ++k) out.triangles.push_back({corners[0], corners[k], corners[k + 1]});
  if (count > 3) ++out.polygons;
}

// ---- text OFF -------------------------------------------------------------------------------

class TextOff {
public:
  TextOff(const std::filesystem::path& file, std::string name) : lines_(file), name_(std::move(name)) {}

  // The next line that holds anything but a comment, as words; false at the end of the file.
  bool next() {
    std::string_view line;
    while (lines_.next(line)) {
      ++number_;
      for (const char c : line)
        if (static_cast<unsigned char>(c) < 0x20 && c != '\t')
          fail("binary data in a text OFF file (control character " + std::to_string(static_cast<unsigned char>(c)) + ")");
      if (const auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
      mesh_text::split_words(line, words_);
      if (!words_.empty()) return true;
    }
    return false;
  }
  const std::vector<std::string_view>& words() const { return words_; }
  [[noreturn]] void fail(const std::string& what) const { throw InputError(where() + what); }
  std::string where() const { return name_ + ": line " + std::to_string(number_) + ": "; }

private:
  mesh_text::LineReader lines_;
  std::string name_;
  std::size_t number_ = 0;
  std::vector<std::string_view> words_;
};

void read_text(const std::filesystem::path& file, const std::string& name, unsigned long long size, bool read, OffContents& out) {
  TextOff text(file, name);
  if (!text.next()) throw InputError(name + ": not an OFF file (no header)");
  const OffLayout layout = layout_of(text.words()[0], text.where());
  // The counts: on the keyword's line, or on the next line that holds anything.
  std::vector<std::string_view> counts(text.words().begin() + 1, text.words().end());
  if (counts.empty()) {
    if (!text.next()) text.fail("the file ends before the vertex and face counts");
    counts = text.words();
  }
  long long nv = -1, nf = -1, ne = 0;
  if (counts.size() < 2 || counts.size() > 3 || !parse_integer(counts[0], nv) || !parse_integer(counts[1], nf) ||
      (counts.size() == 3 && !parse_integer(counts[2], ne)) || nv < 0 || nf < 0 || ne < 0)
    text.fail("the header's counts must be two or three non-negative numbers: vertices, faces (and edges)");
  if (nv > static_cast<long long>(std::numeric_limits<std::uint32_t>::max()))
    text.fail("the header announces " + std::to_string(nv) + " vertices, more than meshtour can index (2^32 - 1)");
  start_lists(nv, nf, 6.0L * nv + 8.0L * nf, size, name, "OFF", layout, read, out);
  const std::size_t colour_at = layout.colour_at();
  for (long long v = 0; v < nv; ++v) {
    if (!text.next()) text.fail("truncated: the file ends after " + std::to_string(v) + " of its " + std::to_string(nv) + " vertices");
    const auto& words = text.words();
    if (words.size() < static_cast<std::size_t>(layout.dimensions))
      text.fail("vertex " + std::to_string(v) + " has fewer than " + std::to_string(layout.dimensions) + " coordinates");
    double p[3];
    for (int k = 0; k < 3; ++k) {
      if (!parse_double(words[static_cast<std::size_t>(k)], p[k]))
        text.fail("vertex " + std::to_string(v) + " has a coordinate that is not a number: '" + std::string(words[static_cast<std::size_t>(k)]) + "'");
      if (!std::isfinite(p[k]))
        text.fail("vertex " + std::to_string(v) + " has a NaN or infinite coordinate ('" + std::string(words[static_cast<std::size_t>(k)]) + "')");
    }
    if (read) out.positions.emplace_back(p[0], p[1], p[2]);
    if (!layout.colours) continue;
    // A colour is three or four numbers: integers 0..255 or decimals 0..1 (a decimal point or an
    // exponent in any of them says which: '0.5 0.25 1' is decimal); the first three are its red,
    // green and blue.
    if (words.size() < colour_at + 3)
      text.fail("vertex " + std::to_string(v) + " has no colour: a COFF vertex is its coordinates, then red, green and blue");
    const bool decimal = std::any_of(words.begin() + static_cast<std::ptrdiff_t>(colour_at), words.begin() + static_cast<std::ptrdiff_t>(colour_at + 3),
                                     [](std::string_view w) { return w.find_first_of(".eE") != std::string_view::npos; });
    float rgb[3];
    for (std::size_t k = 0; k < 3; ++k) {
      const std::string_view word = words[colour_at + k];
      double c = 0.0;
      if (!parse_double(word, c)) text.fail("vertex " + std::to_string(v) + " has a colour component that is not a number: '" + std::string(word) + "'");
      if (!(c >= 0.0 && c <= (decimal ? 1.0 : 255.0)))
        text.fail("vertex " + std::to_string(v) + " has a colour component '" + std::string(word) + "' outside " + (decimal ? "0 to 1" : "0 to 255"));
      rgb[k] = static_cast<float>(decimal ? c : c / 255.0);
    }
    if (read) out.colors.emplace_back(rgb[0], rgb[1], rgb[2]);
  }

  std::vector<std::uint32_t> corners;
  for (long long f = 0; f < nf; ++f) {
    if (!text.next()) text.fail("truncated: the file ends after " + std::to_string(f) + " of its " + std::to_string(nf) + " faces");
    const auto& words = text.words();
    long long count = 0;
    if (!parse_integer(words[0], count) || count < 3 || static_cast<long long>(words.size()) < count + 1)
      text.fail("face " + std::to_string(f) + " is not a corner count (3 or more) followed by that many vertex indices");
    out.summary.corners += static_cast<std::size_t>(count);
    corners.clear();
    for (long long k = 1; k <= count; ++k) {
      long long index = 0;
      if (!parse_integer(words[static_cast<std::size_t>(k)], index))
        text.fail("face " + std::to_string(f) + " has an index that is not a number: '" + std::string(words[static_cast<std::size_t>(k)]) + "'");
      if (index < 0 || index >= nv)
        text.fail("face " + std::to_string(f) + " refers to vertex " + std::to_string(index) + " but the file has " + std::to_string(nv) +
                  " vertices (0 to " + std::to_string(nv - 1) + ")");
      corners.push_back(static_cast<std::uint32_t>(index));
    }
    if (read) add_polygon(corners.data(), corners.size(), out);  // a face colour after the indices is not used
  }
}

// ---- binary OFF -----------------------------------------------------------------------------
// After the line 'OFF BINARY': 32-bit integers and floats. The counts; per vertex its coordinates,
// normal (N), colour (C: four floats, RGBA) and texture coordinates (ST); per face its corner count
// and indices. Two dialects are in use: Geomview's (big-endian, each face followed by a colour's
// component count and its components) and the one PMP and OpenMesh write (the machine's
// little-endian order, no face colours; pmp-data's beetle and amo). The byte order is the one
// whose counts fit the file; the face layout the one that reads the faces to the file's end.

std::uint32_t big_endian_word(const unsigned char* b) {
  return static_cast<std::uint32_t>(b[0]) << 24 | static_cast<std::uint32_t>(b[1]) << 16 | static_cast<std::uint32_t>(b[2]) << 8 | b[3];
}
std::uint32_t little_endian_word(const unsigned char* b) {
  return static_cast<std::uint32_t>(b[3]) << 24 | static_cast<std::uint32_t>(b[2]) << 16 | static_cast<std::uint32_t>(b[1]) << 8 | b[0];
}

class BinaryOff {
public:
  BinaryOff(std::ifstream& in, std::string name, bool big_endian) : in_(in), name_(std::move(name)), big_endian_(big_endian) {}

  std::uint32_t word(const std::string& what) {
    unsigned char b[4];
    in_.read(reinterpret_cast<char*>(b), 4);
    if (in_.gcount() != 4) throw InputError(name_ + ": truncated binary OFF: the file ends inside " + what);
    return big_endian_ ? big_endian_word(b) : little_endian_word(b);
  }
  float number(const std::string& what) { return std::bit_cast<float>(word(what)); }

private:
  std::ifstream& in_;
  std::string name_;
  bool big_endian_;
};

// The faces from the stream's position, with or without a colour after each; out's triangles and
// corner count are this layout's.
void read_binary_faces(BinaryOff& data, long long nv, long long nf, unsigned long long size, bool face_colours, const std::string& name,
                       bool read, OffContents& out) {
  out.triangles.clear();
  out.polygons = 0;
  out.summary.corners = 0;
  std::vector<std::uint32_t> corners;
  for (long long f = 0; f < nf; ++f) {
    const std::string what = "face " + std::to_string(f);
    const std::uint32_t count = data.word(what);
    if (count < 3 || count > size / 4)
      throw InputError(name + ": face " + std::to_string(f) + " has " + std::to_string(count) + " corners (3 or more, each an index)");
    out.summary.corners += count;
    corners.resize(count);
    for (std::uint32_t& index : corners) {
      index = data.word(what);
      if (index >= static_cast<unsigned long long>(nv))
        throw InputError(name + ": face " + std::to_string(f) + " refers to vertex " + std::to_string(index) + " but the file has " +
                         std::to_string(nv) + " vertices");
    }
    if (face_colours) {
      const std::uint32_t colour = data.word(what);
      if (colour > 4) throw InputError(name + ": face " + std::to_string(f) + " has a colour of " + std::to_string(colour) + " components (0 to 4)");
      for (std::uint32_t k = 0; k < colour; ++k) data.number(what);  // face colours are not used
    }
    if (read) add_polygon(corners.data(), corners.size(), out);
  }
}

void read_binary(std::ifstream& in, const std::string& name, unsigned long long size, const OffLayout& layout, bool read, OffContents& out) {
  const auto header_end = static_cast<unsigned long long>(std::max<std::streamoff>(0, in.tellg()));
  unsigned char head[12] = {};
  in.read(reinterpret_cast<char*>(head), 12);
  if (in.gcount() != 12) throw InputError(name + ": truncated binary OFF: the header has no vertex and face counts");
  const int per_vertex = layout.dimensions * (layout.normals ? 2 : 1) + (layout.colours ? 4 : 0) + (layout.texcoords ? 2 : 0);
  // The least a file of these counts holds: the vertices, and a triangle per face.
  const auto needed = [&](long long nv, long long nf) { return static_cast<long double>(header_end) + 12.0L + 4.0L * per_vertex * nv + 16.0L * nf; };
  long long nv = big_endian_word(head), nf = big_endian_word(head + 4);
  bool big_endian = true;
  if (needed(nv, nf) > static_cast<long double>(size) && needed(little_endian_word(head), little_endian_word(head + 4)) <= static_cast<long double>(size)) {
    nv = little_endian_word(head);
    nf = little_endian_word(head + 4);
    big_endian = false;
  }
  start_lists(nv, nf, needed(nv, nf), size, name, "binary OFF", layout, read, out);
  BinaryOff data(in, name, big_endian);
  std::vector<float> values(static_cast<std::size_t>(per_vertex));
  const std::size_t colour_at = layout.colour_at();
  for (long long v = 0; v < nv; ++v) {
    const std::string what = "vertex " + std::to_string(v);
    for (float& x : values) x = data.number(what);
    if (!std::isfinite(values[0]) || !std::isfinite(values[1]) || !std::isfinite(values[2]))
      throw InputError(name + ": vertex " + std::to_string(v) + " has a NaN or infinite coordinate");
    if (layout.colours)
      for (std::size_t k = colour_at; k < colour_at + 3; ++k)
        if (!(values[k] >= 0.0f && values[k] <= 1.0f))
          throw InputError(name + ": vertex " + std::to_string(v) + " has a colour component outside 0 to 1 (" + std::to_string(values[k]) + ")");
    if (!read) continue;
    out.positions.emplace_back(values[0], values[1], values[2]);
    if (layout.colours) out.colors.emplace_back(values[colour_at], values[colour_at + 1], values[colour_at + 2]);
  }
  // The dialect's face layout first (Geomview's colours when big-endian), then the other: the first
  // that reads the faces to the file's end. Where neither does, the dialect's own layout decides:
  // its error, or its faces with data after them.
  const std::streampos faces = in.tellg();
  const auto read_faces = [&](bool face_colours) {
    in.clear();
    in.seekg(faces);
    read_binary_faces(data, nv, nf, size, face_colours, name, read, out);
  };
  const auto reads_to_end = [&](bool face_colours) {
    try {
      read_faces(face_colours);
      return in.peek() == std::ifstream::traits_type::eof();
    } catch (const InputError&) {
      return false;
    }
  };
  if (reads_to_end(big_endian) || reads_to_end(!big_endian)) return;
  read_faces(big_endian);
}

}  // namespace

OffContents read_off(const std::filesystem::path& file, bool read) {
  const std::string name = file.string();
  const unsigned long long size = std::filesystem::file_size(file);
  OffContents out;
  {
    // Binary OFF says so on its header line; its data starts after that line's end.
    std::ifstream in(file, std::ios::binary);
    if (!in) throw IoError(name + ": cannot open for reading (check permissions)");
    std::string line;
    while (std::getline(in, line)) {
      std::vector<std::string_view> words;
      mesh_text::split_words(std::string_view(line).substr(0, line.find('#')), words);
      if (words.empty()) continue;
      if (words.size() >= 2 && words[1] == "BINARY") {
        read_binary(in, name, size, layout_of(words[0], name + ": "), read, out);
        return out;
      }
      break;
    }
  }
  read_text(file, name, size, read, out);
  return out;
}

}  // namespace meshtour::off_detail
