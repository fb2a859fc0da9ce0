#include "mesh/stl_reader.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <memory>
#include <string_view>

#include "core/error.h"
#include "mesh/mesh_text.h"
#include "mesh/vertex_weld.h"

namespace meshtour::stl_detail {
namespace {

// Merges bit-identical corners into one vertex as they are read (mesh/vertex_weld.h): the memory
// is the distinct corners' (a closed surface has a sixth as many vertices as corners), never all
// of them (a 17.8M-facet scan has 53M).
class CornerWelder {
public:
  explicit CornerWelder(std::size_t corners) : welder_(corners / 6 + 16) {}

  std::uint32_t vertex(const float* corner) {
    return welder_.vertex({weld_detail::key_bits(corner[0]), weld_detail::key_bits(corner[1]), weld_detail::key_bits(corner[2])});
  }

  std::vector<Eigen::Vector3d> positions() const {
    const auto& keys = welder_.keys();
    std::vector<Eigen::Vector3d> out(keys.size());
    for (std::size_t i = 0; i < keys.size(); ++i)
      out[i] = Eigen::Vector3d(std::bit_cast<float>(keys[i][0]), std::bit_cast<float>(keys[i][1]), std::bit_cast<float>(keys[i][2]));
    return out;
  }

private:
  weld_detail::VertexWelder<3> welder_;
};

bool all_finite(const float* values, int n) {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(values[i])) return false;
  return true;
}

// Binary STL: an 80-byte header, a little-endian triangle count, 50 bytes per facet (normal, three
// corners as little-endian floats, an attribute word), read through a buffer of whole facets.
void read_binary(const std::filesystem::path& file, const std::string& name, std::uint32_t facets, StlContents& out) {
  std::ifstream in(file, std::ios::binary);
  in.seekg(84);
  CornerWelder welder(3ull * facets);
  out.triangles.reserve(facets);
  constexpr std::size_t kRecord = 50, kBatch = 20000;  // 1 MB of facets at a time
  std::vector<char> buffer(kRecord * std::min<std::size_t>(kBatch, facets));
  for (std::size_t done = 0; done < facets;) {
    const std::size_t batch = std::min<std::size_t>(kBatch, facets - done);
    in.read(buffer.data(), static_cast<std::streamsize>(batch * kRecord));
    if (static_cast<std::size_t>(in.gcount()) != batch * kRecord)  // the size was checked; the file changed since
      throw InputError(name + ": truncated binary STL: the file ends inside facet " + std::to_string(done + static_cast<std::size_t>(in.gcount()) / kRecord));
    for (std::size_t r = 0; r < batch; ++r) {
      float corners[9];
      std::memcpy(corners, buffer.data() + r * kRecord + 12, sizeof corners);
      if constexpr (std::endian::native == std::endian::big)
        for (float& c : corners) c = std::bit_cast<float>(__builtin_bswap32(std::bit_cast<std::uint32_t>(c)));
      if (!all_finite(corners, 9))
        throw InputError(name + ": facet " + std::to_string(done + r) + " has a NaN or infinite corner coordinate");
      out.triangles.push_back({welder.vertex(corners), welder.vertex(corners + 3), welder.vertex(corners + 6)});
    }
    done += batch;
  }
  out.positions = welder.positions();
}

bool keyword_is(std::string_view word, std::string_view keyword) {
  return word.size() == keyword.size() &&
         std::equal(word.begin(), word.end(), keyword.begin(), [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) == b; });
}

// ASCII STL: "solid NAME", then per facet "facet normal NX NY NZ", "outer loop", a "vertex X Y Z"
// per corner, "endloop", "endfacet"; "endsolid NAME". Read as a stream of words, so a writer's line
// breaks do not matter; several solids in one file are read as one model.
void read_ascii(const std::filesystem::path& file, const std::string& name, bool read, StlContents& out) {
  mesh_text::LineReader lines(file);
  std::vector<std::string_view> words;
  std::size_t at = 0, number = 0;
  const auto fail = [&](const std::string& what) -> void { throw InputError(name + ": line " + std::to_string(number) + ": " + what); };
  // The next word; false at the end of the file. A view into the reader's buffer, valid until
  // the next call.
  const auto next = [&](std::string_view& word) {
    while (at == words.size()) {
      std::string_view line;
      if (!lines.next(line)) return false;
      ++number;
      for (const char c : line)
        if (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\v' && c != '\f')
          fail("binary data in an ASCII STL (control character " + std::to_string(static_cast<unsigned char>(c)) +
               "); a binary STL must be exactly 84 bytes plus 50 per facet its header announces");
      mesh_text::split_words(line, words);
      at = 0;
    }
    word = words[at++];
    return true;
  };
  const auto quoted = [](std::string_view word) {
    std::string text(1, '\'');
    text.append(word.substr(0, 40)).append(word.size() > 40 ? "...'" : "'");
    return text;
  };
  const auto skip_rest_of_line = [&] { at = words.size(); };

  std::unique_ptr<CornerWelder> welder;
  if (read) welder = std::make_unique<CornerWelder>(std::filesystem::file_size(file) / 40);  // ~130 bytes per facet
  std::string_view word;
  bool in_solid = false;
  std::vector<std::uint32_t> loop;
  std::size_t facet = 0;
  for (;;) {
    if (!next(word)) break;
    if (!in_solid) {
      if (!keyword_is(word, "solid"))
        fail("expected 'solid' (an ASCII STL begins each solid with it), found " + quoted(word));
      in_solid = true;
      skip_rest_of_line();  // the solid's name
      continue;
    }
    if (keyword_is(word, "endsolid")) {
      in_solid = false;
      skip_rest_of_line();
      continue;
    }
    if (!keyword_is(word, "facet")) fail("expected 'facet' or 'endsolid', found " + quoted(word));
    const auto expect = [&](std::string_view keyword) {
      if (!next(word)) fail("truncated: the file ends inside facet " + std::to_string(facet));
      if (!keyword_is(word, keyword)) fail("expected '" + std::string(keyword) + "' in facet " + std::to_string(facet) + ", found " + quoted(word));
    };
    const auto number_word = [&](const char* what) {
      if (!next(word)) fail("truncated: the file ends inside facet " + std::to_string(facet));
      double value = 0.0;
      if (!mesh_text::parse_double(word, value)) fail(std::string(what) + " of facet " + std::to_string(facet) + " is not a number: " + quoted(word));
      return value;
    };
    if (!next(word)) fail("truncated: the file ends inside facet " + std::to_string(facet));
    if (keyword_is(word, "normal")) {
      for (int k = 0; k < 3; ++k) number_word("the normal");  // recomputed from the corners
      expect("outer");
    } else if (!keyword_is(word, "outer")) {
      fail("expected 'normal' or 'outer' in facet " + std::to_string(facet) + ", found " + quoted(word));
    }
    expect("loop");
    loop.clear();
    std::size_t corners = 0;
    for (;;) {
      if (!next(word)) fail("truncated: the file ends inside facet " + std::to_string(facet));
      if (keyword_is(word, "endloop")) break;
      if (!keyword_is(word, "vertex")) fail("expected 'vertex' or 'endloop' in facet " + std::to_string(facet) + ", found " + quoted(word));
      float corner[3];
      for (float& c : corner) {
        const double value = number_word("a corner");
        c = static_cast<float>(value);
        if (!std::isfinite(c)) fail("a corner of facet " + std::to_string(facet) + " is NaN, infinite or beyond float range");
      }
      ++corners;
      if (welder) loop.push_back(welder->vertex(corner));
    }
    if (corners < 3) fail("facet " + std::to_string(facet) + " has " + std::to_string(corners) + " corners; a facet needs 3");
    expect("endfacet");
    if (corners > 3) ++out.polygons;
    for (std::size_t k = 1; welder && k + 1 < loop.size(); ++k) out.triangles.push_back({loop[0], loop[k], loop[k + 1]});
    out.summary.corners += corners;
    ++facet;
  }
  if (in_solid && facet > 0)
    out.warnings.push_back("the file ends without 'endsolid' after " + std::to_string(facet) + " facets (truncated?); they are read");
  out.summary.faces = facet;
  out.summary.vertices = out.summary.corners;
  if (welder) out.positions = welder->positions();
}

}  // namespace

StlContents read_stl(const std::filesystem::path& file, bool read) {
  const std::string name = file.string();
  const unsigned long long size = std::filesystem::file_size(file);
  StlContents out;
  char header[512] = {};  // the binary header (84 bytes) and enough of the facets to tell text
  {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw IoError(name + ": cannot open for reading (check permissions)");
    in.read(header, sizeof header);
  }
  const std::size_t got = static_cast<std::size_t>(std::min<unsigned long long>(size, sizeof header));
  std::string start(header, std::min<std::size_t>(got, 80));
  start.erase(0, start.find_first_not_of(" \t\r\n"));
  const bool says_solid = start.size() >= 5 && keyword_is(std::string_view(start).substr(0, 5), "solid");
  // Text has no control characters but line ends and blanks; a binary count and floats soon do.
  const bool binary_bytes = std::any_of(header, header + got, [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return (u < 0x20 && c != '\t' && c != '\n' && c != '\r' && c != '\v' && c != '\f') || u == 0x7f;
  });
  if (got >= 84) {
    std::uint32_t facets = 0;
    std::memcpy(&facets, header + 80, 4);
    if constexpr (std::endian::native == std::endian::big) facets = __builtin_bswap32(facets);
    const unsigned long long binary_size = 84ull + 50ull * facets;
    // Binary STL files may also begin with "solid" (many writers put the part name there): the
    // exact size tells them apart, or, where bytes follow the facets, bytes no text holds.
    const bool trailing = says_solid && binary_size < size && binary_bytes;
    if (binary_size == size || !says_solid || trailing) {
      if (binary_size > size)
        throw InputError(name + ": truncated or corrupt binary STL: the header announces " + std::to_string(facets) +
                         " triangles (" + std::to_string(binary_size) + " bytes) but the file holds " + std::to_string(size) + " bytes");
      out.binary = true;
      out.summary = MeshFileSummary{3ull * facets, facets, 3ull * facets};
      if (binary_size < size)
        out.warnings.push_back(std::to_string(size - binary_size) + " bytes after the " + std::to_string(facets) +
                               " facets its header announces are ignored");
      if (read) read_binary(file, name, facets, out);
      return out;
    }
  } else if (!says_solid) {
    throw InputError(name + ": truncated or corrupt STL: " + std::to_string(size) + " bytes, shorter than a binary STL header");
  }
  read_ascii(file, name, read, out);
  return out;
}

}  // namespace meshtour::stl_detail
