// The PLY reader (mesh/ply_reader.h): the header's grammar, then one walk of the body, bounded by
// the file's size, that checks every value and, when asked, keeps the model's.
#include "mesh/ply_reader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "mesh/mesh_text.h"

namespace meshtour::ply_detail {
namespace {

void strip_cr(std::string& line) {
  if (!line.empty() && line.back() == '\r') line.pop_back();
}

using mesh_text::parse_double;
using mesh_text::parse_integer;

std::vector<std::string> words_of(const std::string& line) {
  std::vector<std::string> words;
  std::istringstream in(line);
  for (std::string w; in >> w;) words.push_back(w);
  return words;
}

bool is_colour_property(const std::string& name) {
  for (const char* colour : {"red", "green", "blue", "alpha", "diffuse_red", "diffuse_green", "diffuse_blue", "diffuse_alpha"})
    if (name == colour) return true;
  return false;
}

// What a property means to the reader, decided once from the header (comparing its name per value
// was a third of the time of reading a big PLY).
enum class PlyRole : unsigned char { skip, x, y, z, red, green, blue, u, v, face_indices, face_texcoords, strip };

struct PlyProperty {
  std::string name;
  int size = 0;        // bytes of a scalar, or of a list's items
  int count_size = 0;  // bytes of a list's count, 0 for scalars
  bool is_float = false, is_signed = false;
  bool count_signed = false;
  PlyRole role = PlyRole::skip;
  bool colour = false;  // a vertex colour component (alpha too): floats must lie in [0, 1]
};
struct PlyElement {
  std::string name;
  unsigned long long count = 0;
  std::vector<PlyProperty> properties;
};

// Size and kind of a PLY scalar type; false for an unknown type.
bool ply_type(const std::string& type, int& size, bool& is_float, bool& is_signed) {
  struct T {
    const char* name;
    int size;
    bool is_float, is_signed;
  };
  static const T types[] = {{"char", 1, false, true},    {"int8", 1, false, true},   {"uchar", 1, false, false},
                            {"uint8", 1, false, false},  {"short", 2, false, true},  {"int16", 2, false, true},
                            {"ushort", 2, false, false}, {"uint16", 2, false, false}, {"int", 4, false, true},
                            {"int32", 4, false, true},   {"uint", 4, false, false},  {"uint32", 4, false, false},
                            {"float", 4, true, true},    {"float32", 4, true, true}, {"double", 8, true, true},
                            {"float64", 8, true, true}};
  for (const auto& t : types)
    if (type == t.name) {
      size = t.size;
      is_float = t.is_float;
      is_signed = t.is_signed;
      return true;
    }
  return false;
}

// Where a value lies, for a message: built only when one is thrown.
struct PlyWhere {
  const std::string& element;
  unsigned long long index;
  std::string text() const { return element + " " + std::to_string(index); }
};

// The body's values, read through a buffer of its own (an ifstream read per value cost as much as
// the rest of the walk).
class PlyBody {
public:
  PlyBody(std::ifstream& in, const std::string& name, bool ascii, bool big_endian)
      : in_(in), name_(name), ascii_(ascii), big_endian_(big_endian), buffer_(buffer_size(in)) {}

  // The next value, as a double (integers up to 2^53 are exact, enough for any index).
  double value(int size, bool is_float, bool is_signed, const PlyWhere& where) {
    const auto n = static_cast<std::size_t>(size);
    if (ascii_ || big_endian_ || end_ - at_ < n) return slow_value(size, is_float, is_signed, where);
    const char* b = buffer_.data() + at_;
    at_ += n;
    // Fixed-size copies per type (the common case of a little-endian file, buffered): a copy of
    // variable size was a library call per value.
    switch (size * 4 + (is_float ? 2 : 0) + (is_signed ? 1 : 0)) {
      case 4: return load<std::uint8_t>(b);
      case 5: return load<std::int8_t>(b);
      case 8: return load<std::uint16_t>(b);
      case 9: return load<std::int16_t>(b);
      case 16: return load<std::uint32_t>(b);
      case 17: return load<std::int32_t>(b);
      case 18:
      case 19: return load<float>(b);
      case 34:
      case 35: return load<double>(b);
      default: return decode(reinterpret_cast<const unsigned char*>(b), size, is_float, is_signed);
    }
  }

private:
  // 1 MiB, or what is left of the file where that is less: zeroing 1 MiB for a small file was most
  // of the cost of reading it.
  static std::size_t buffer_size(std::ifstream& in) {
    constexpr std::size_t kLargest = std::size_t{1} << 20, kSmallest = 4096;
    const std::streampos at = in.tellg();
    in.seekg(0, std::ios::end);
    const std::streampos end = in.tellg();
    in.seekg(at);
    if (at < 0 || end < at || static_cast<std::size_t>(end - at) >= kLargest) return kLargest;
    return std::max(kSmallest, static_cast<std::size_t>(end - at));
  }

  template <class T>
  static double load(const char* b) {
    T v;
    std::memcpy(&v, b, sizeof v);
    return static_cast<double>(v);
  }
  // Little-endian bytes of any scalar type (the host is little-endian).
  static double decode(const unsigned char* bytes, int size, bool is_float, bool is_signed) {
    if (is_float) {
      if (size == 4) {
        float f;
        std::memcpy(&f, bytes, 4);
        return f;
      }
      double d;
      std::memcpy(&d, bytes, 8);
      return d;
    }
    std::uint64_t u = 0;
    std::memcpy(&u, bytes, static_cast<std::size_t>(size));
    if (is_signed && size < 8 && (u >> (8 * size - 1)) & 1) return static_cast<double>(static_cast<std::int64_t>(u | (~0ull << (8 * size))));
    return static_cast<double>(u);
  }
  // ASCII, big-endian, or at the buffer's end.
  double slow_value(int size, bool is_float, bool is_signed, const PlyWhere& where) {
    if (ascii_) return ascii_value(where);
    const auto n = static_cast<std::size_t>(size);
    if (end_ - at_ < n && !fill(n)) throw InputError(name_ + ": truncated PLY: the file ends in " + where.text());
    unsigned char bytes[8] = {};
    std::memcpy(bytes, buffer_.data() + at_, n);
    at_ += n;
    if (big_endian_) std::reverse(bytes, bytes + size);
    return decode(bytes, size, is_float, is_signed);
  }

  // At least `n` bytes buffered after at_, unless the file ends first.
  bool fill(std::size_t n) {
    std::memmove(buffer_.data(), buffer_.data() + at_, end_ - at_);
    end_ -= at_;
    at_ = 0;
    while (end_ < n && in_) {
      in_.read(buffer_.data() + end_, static_cast<std::streamsize>(buffer_.size() - end_));
      end_ += static_cast<std::size_t>(in_.gcount());
    }
    return end_ >= n;
  }
  bool next_byte(char& c) {
    if (at_ == end_ && !fill(1)) return false;
    c = buffer_[at_++];
    return true;
  }
  // A whitespace-separated word, as strtod reads it (so "+1", "1e3" and "inf" mean what they did).
  double ascii_value(const PlyWhere& where) {
    char c = 0;
    do {
      if (!next_byte(c)) throw InputError(name_ + ": truncated PLY: the file ends in " + where.text());
    } while (std::isspace(static_cast<unsigned char>(c)));
    word_.clear();
    do word_ += c;
    while (next_byte(c) && !std::isspace(static_cast<unsigned char>(c)));
    double d = 0.0;
    if (!parse_double(word_, d)) throw InputError(name_ + ": " + where.text() + ": '" + word_ + "' is not a number");
    return d;
  }

  std::ifstream& in_;
  const std::string& name_;
  bool ascii_, big_endian_;
  std::vector<char> buffer_;
  std::size_t at_ = 0, end_ = 0;
  std::string word_;
};

// A vertex index read from the file, for a message: as an integer where it is one that fits, else
// as written (a float list may hold 1e30, whose conversion to an integer is undefined).
std::string index_text(double v) {
  if (v == std::floor(v) && std::abs(v) < 9e15) return std::to_string(static_cast<long long>(v));
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

bool is_u_property(const std::string& n) { return n == "texture_u" || n == "s" || n == "u"; }
bool is_v_property(const std::string& n) { return n == "texture_v" || n == "t" || n == "v"; }

MeshFileSummary check_ply(const std::filesystem::path& file, const std::string& name, PlyContents* out) {
  std::ifstream in(file, std::ios::binary);
  std::string line;
  if (!std::getline(in, line) || (strip_cr(line), line != "ply"))
    throw InputError(name + ": not a PLY file (it does not start with 'ply')");
  std::string format;
  std::vector<PlyElement> elements;
  bool header_complete = false;
  for (std::size_t number = 2; std::getline(in, line); ++number) {
    strip_cr(line);
    const auto words = words_of(line);
    if (words.empty()) continue;
    auto fail = [&](const std::string& what) -> void {
      throw InputError(name + ": PLY header line " + std::to_string(number) + ": " + what);
    };
    // The strict grammar of the header: OpenMesh's own header parser loops forever on some
    // malformed lines (a 'format' line with extra words was found by fuzzing).
    const std::string& keyword = words[0];
    if (keyword == "comment" && words.size() >= 3 && words[1] == "TextureFile" && out && out->texture_file.empty()) {
      // The name is the rest of the line (it may hold spaces).
      const std::string rest = line.substr(line.find("TextureFile") + 11);
      const auto first = rest.find_first_not_of(" \t");
      out->texture_file = rest.substr(first);
      while (!out->texture_file.empty() && std::isspace(static_cast<unsigned char>(out->texture_file.back())))
        out->texture_file.pop_back();
      continue;
    }
    if (keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "format") {
      double version = 0.0;
      if (words.size() != 3 || !parse_double(words[2], version))
        fail("'format' must be followed by a format and a version, e.g. 'format binary_little_endian 1.0'");
      format = words[1];
      if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
        fail("unknown format '" + format + "' (ascii, binary_little_endian or binary_big_endian)");
    } else if (keyword == "element") {
      PlyElement e;
      if (words.size() != 3) fail("an element needs a name and a count, e.g. 'element vertex 8'");
      e.name = words[1];
      long long count = -1;
      if (!parse_integer(words[2], count) || count < 0)
        throw InputError(name + ": PLY header: element '" + e.name + "' has an invalid count '" + words[2] + "'");
      e.count = static_cast<unsigned long long>(count);
      // One vertex list: faces index it, and the reader sizes the model by it (a second one, found
      // by fuzzing, wrote past the first's vertices).
      if (e.name == "vertex" && std::any_of(elements.begin(), elements.end(), [](const PlyElement& x) { return x.name == "vertex"; }))
        fail("a second 'element vertex' (a PLY has one vertex list)");
      elements.push_back(e);
    } else if (keyword == "property") {
      if (elements.empty()) fail("a property before any element");
      PlyProperty p;
      if (words.size() == 5 && words[1] == "list") {
        bool count_float = false, count_signed = false;
        if (!ply_type(words[2], p.count_size, count_float, count_signed) || count_float)
          fail("list count type '" + words[2] + "' is not an integer type");
        p.count_signed = count_signed;
        if (!ply_type(words[3], p.size, p.is_float, p.is_signed)) fail("unknown type '" + words[3] + "'");
        p.name = words[4];
      } else {
        if (words.size() != 3 || !ply_type(words[1], p.size, p.is_float, p.is_signed))
          fail("'" + line + "' is not 'property TYPE NAME' or 'property list COUNT_TYPE TYPE NAME' with a PLY type");
        p.name = words[2];
      }
      elements.back().properties.push_back(p);
    } else if (keyword == "end_header") {
      if (words.size() != 1) fail("'end_header' must stand alone on its line");
      header_complete = true;
      break;
    } else {
      fail("unexpected '" + keyword + "' (a header has format, element, property, comment and end_header lines)");
    }
  }
  if (!header_complete) throw InputError(name + ": truncated or corrupt PLY: the header has no 'end_header' line");
  if (format.empty()) throw InputError(name + ": corrupt PLY: the header has no 'format' line");
  const bool ascii = format == "ascii";

  // Refuse from the header alone what the body cannot hold (OpenMesh reserves the counts first).
  const auto body_start = in.tellg();
  const unsigned long long size = std::filesystem::file_size(file);
  const unsigned long long body = body_start < 0 ? 0 : size - static_cast<unsigned long long>(body_start);
  long double needed = 0;
  for (const auto& e : elements) {
    unsigned long long min_bytes = 0;  // smallest possible size of one element in the body
    for (const auto& p : e.properties) min_bytes += ascii ? 2 : (p.count_size ? p.count_size : p.size);
    needed += static_cast<long double>(e.count) * std::max(1ull, min_bytes);
  }
  if (needed > static_cast<long double>(body)) {
    std::string counts;
    for (const auto& e : elements) counts += (counts.empty() ? "" : ", ") + std::to_string(e.count) + " " + e.name;
    throw InputError(name + ": truncated or corrupt PLY: the header announces " + counts + " but the file holds only " +
                     std::to_string(body) + " bytes after the header");
  }

  // Walk the body: coordinates must be finite, face indices must name vertices of the file.
  MeshFileSummary s;
  unsigned long long vertex_count = 0;
  for (const auto& e : elements)
    if (e.name == "vertex") vertex_count = e.count;
  bool has_colour = false;
  for (auto& e : elements)
    for (auto& p : e.properties) {
      const std::string& n = p.name;
      if (e.name == "vertex" && !p.count_size) {
        p.role = n == "x" ? PlyRole::x : n == "y" ? PlyRole::y : n == "z" ? PlyRole::z
               : n == "red" || n == "diffuse_red" ? PlyRole::red : n == "green" || n == "diffuse_green" ? PlyRole::green
               : n == "blue" || n == "diffuse_blue" ? PlyRole::blue : is_u_property(n) ? PlyRole::u : is_v_property(n) ? PlyRole::v
               : PlyRole::skip;
        p.colour = is_colour_property(n);
        has_colour = has_colour || p.colour;
      }
      if (e.name == "face" && p.count_size && (n == "vertex_indices" || n == "vertex_index")) p.role = PlyRole::face_indices;
      if (e.name == "face" && p.count_size && n == "texcoord") p.role = PlyRole::face_texcoords;
      if (e.name == "tristrips" && p.count_size && (n == "vertex_indices" || n == "vertex_index")) p.role = PlyRole::strip;
    }
  // Texture coordinates count only in a file that names its texture.
  if (out && !out->texture_file.empty())
    for (const auto& e : elements)
      for (const auto& p : e.properties) {
        out->per_vertex = out->per_vertex || p.role == PlyRole::u;
        out->per_corner = out->per_corner || p.role == PlyRole::face_texcoords;
      }
  if (out) {
    // The header's counts fit the body (checked above), so these allocations are bounded by the file.
    out->positions.assign(static_cast<std::size_t>(vertex_count), Eigen::Vector3d::Zero());
    if (has_colour) out->colors.assign(static_cast<std::size_t>(vertex_count), Eigen::Vector3f::Ones());
    if (out->per_vertex) out->vertex_uvs.assign(static_cast<std::size_t>(vertex_count), Eigen::Vector2f::Zero());
  }
  PlyBody reader(in, name, ascii, format == "binary_big_endian");
  std::vector<std::uint32_t> corners;  // the face being read
  std::vector<Eigen::Vector2f> corner_uvs;
  const Eigen::Vector2f no_uv = Eigen::Vector2f::Constant(std::numeric_limits<float>::quiet_NaN());
  for (const auto& e : elements) {
    if (e.name == "vertex") s.vertices = e.count;
    if (e.name == "face") s.faces = e.count;
    for (unsigned long long i = 0; i < e.count; ++i) {
      const PlyWhere where{e.name, i};
      const auto at = static_cast<std::size_t>(i);
      bool face = false;
      corners.clear();
      corner_uvs.clear();
      for (const auto& p : e.properties) {
        if (!p.count_size) {
          const double v = reader.value(p.size, p.is_float, p.is_signed, where);
          if (p.role == PlyRole::x || p.role == PlyRole::y || p.role == PlyRole::z) {
            if (!std::isfinite(v))
              throw InputError(name + ": vertex " + std::to_string(i) + " has a NaN or infinite coordinate (" + p.name + ")");
            if (out) out->positions[at][static_cast<int>(p.role) - static_cast<int>(PlyRole::x)] = v;
          }
          // Float colours became bytes in OpenMesh without a range check (undefined behaviour).
          if (p.colour && p.is_float && !(v >= 0.0 && v <= 1.0))
            throw InputError(name + ": vertex " + std::to_string(i) + " has a colour component (" + p.name + ") outside 0 to 1");
          if (out && (p.role == PlyRole::red || p.role == PlyRole::green || p.role == PlyRole::blue)) {
            const double full = p.is_float ? 1.0 : p.size == 1 ? 255.0 : p.size == 2 ? 65535.0 : 4294967295.0;
            out->colors[at][static_cast<int>(p.role) - static_cast<int>(PlyRole::red)] = static_cast<float>(std::clamp(v / full, 0.0, 1.0));
          }
          if (out && out->per_vertex && p.role == PlyRole::u) out->vertex_uvs[at].x() = static_cast<float>(v);
          if (out && out->per_vertex && p.role == PlyRole::v) out->vertex_uvs[at].y() = static_cast<float>(v);
          continue;
        }
        const double n = reader.value(p.count_size, false, p.count_signed, where);
        if (!(n >= 0) || n > static_cast<double>(body))
          throw InputError(name + ": " + where.text() + ": the list '" + p.name + "' has an invalid length " + std::to_string(n));
        if (p.role == PlyRole::strip) {
          // One strip: vertex indices, -1 between strips; every index after the first two makes a triangle.
          std::uint32_t window[2] = {0, 0};
          long long in_strip = 0;
          for (double k = 0; k < n; ++k) {
            const double v = reader.value(p.size, p.is_float, p.is_signed, where);
            if (v == -1) {
              in_strip = 0;
              continue;
            }
            if (!(v >= 0 && v < static_cast<double>(vertex_count)))
              throw InputError(name + ": triangle strip " + std::to_string(i) + " refers to vertex " + index_text(v) +
                               " but the file has " + std::to_string(vertex_count) + " vertices (-1 ends a strip)");
            const auto index = static_cast<std::uint32_t>(v);
            if (in_strip >= 2) {
              std::array<std::uint32_t, 3> t = in_strip % 2 == 0 ? std::array<std::uint32_t, 3>{window[0], window[1], index}
                                                                 : std::array<std::uint32_t, 3>{window[1], window[0], index};
              if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) {
                ++s.faces;
                s.corners += 3;
                if (out) out->strip_triangles.push_back(t);
              }
            }
            window[0] = window[1];
            window[1] = index;
            ++in_strip;
          }
          continue;
        }
        if (p.role == PlyRole::face_indices) {
          if (n < 3) throw InputError(name + ": face " + std::to_string(i) + " has " + std::to_string(static_cast<long long>(n)) + " corners; a face needs 3 or more");
          s.corners += static_cast<std::size_t>(n);
          face = true;
        }
        for (double k = 0; k < n; ++k) {
          const double v = reader.value(p.size, p.is_float, p.is_signed, where);
          if (p.role == PlyRole::face_indices) {
            if (!(v >= 0 && v < static_cast<double>(vertex_count)))
              throw InputError(name + ": face " + std::to_string(i) + " refers to vertex " + index_text(v) +
                               " but the file has " + std::to_string(vertex_count) + " vertices");
            if (out) corners.push_back(static_cast<std::uint32_t>(v));
          }
          if (out && out->per_corner && p.role == PlyRole::face_texcoords) {
            if (static_cast<long long>(k) % 2 == 0) corner_uvs.emplace_back(static_cast<float>(v), 0.0f);
            else corner_uvs.back().y() = static_cast<float>(v);
          }
        }
      }
      // The face, fan-triangulated once all its properties are read (texcoord may come first).
      if (out && face) {
        const bool own_uvs = corner_uvs.size() == corners.size();
        out->polygons += corners.size() > 3 ? 1 : 0;
        for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
          out->face_triangles.push_back({corners[0], corners[k], corners[k + 1]});
          if (out->per_corner)
            for (const std::size_t c : {std::size_t{0}, k, k + 1}) out->face_corner_uvs.push_back(own_uvs ? corner_uvs[c] : no_uv);
        }
      }
    }
  }
  return s;
}

}  // namespace

PlyContents read_ply(const std::filesystem::path& file, bool read) {
  PlyContents contents;
  contents.summary = check_ply(file, file.string(), read ? &contents : nullptr);
  return contents;
}

}  // namespace meshtour::ply_detail
