// The bad-input corpus (issue 6): hostile, broken and odd files run through the real `meshtour`
// executable. Each case is generated here into a scratch folder and lists the exit code and the
// words its one-line message must hold; every message must name the file at fault. After a
// failure the case's output folder must be empty: never a partial output file.
#include <gtest/gtest.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "helpers.h"
#include "textured_cube.h"

namespace {

namespace fs = std::filesystem;
using meshtour::test::run_meshtour;


fs::path write(const fs::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary) << bytes;
  return file;
}

std::string binary_floats(const std::vector<float>& values) {
  std::string out(values.size() * 4, '\0');
  std::memcpy(out.data(), values.data(), out.size());
  return out;
}

// ---- generated meshes ---------------------------------------------------------------------

// A closed UV sphere as OBJ text (`rings` x `segments` quads, triangle fans at the poles).
std::string sphere_obj(int rings = 8, int segments = 16, const std::string& eol = "\n") {
  std::ostringstream s;
  s << "v 0 1 0" << eol;
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double th = std::numbers::pi * i / rings, ph = 2 * std::numbers::pi * j / segments;
      s << "v " << std::sin(th) * std::cos(ph) << ' ' << std::cos(th) << ' ' << std::sin(th) * std::sin(ph) << eol;
    }
  s << "v 0 -1 0" << eol;
  auto ring_vertex = [&](int i, int j) { return 2 + (i - 1) * segments + (j % segments); };
  for (int j = 0; j < segments; ++j) s << "f 1 " << ring_vertex(1, j + 1) << ' ' << ring_vertex(1, j) << eol;
  for (int i = 1; i + 1 < rings; ++i)
    for (int j = 0; j < segments; ++j)
      s << "f " << ring_vertex(i, j) << ' ' << ring_vertex(i, j + 1) << ' ' << ring_vertex(i + 1, j + 1) << ' '
        << ring_vertex(i + 1, j) << eol;
  const int south = 2 + (rings - 1) * segments;
  for (int j = 0; j < segments; ++j) s << "f " << south << ' ' << ring_vertex(rings - 1, j) << ' ' << ring_vertex(rings - 1, j + 1) << eol;
  return s.str();
}

// A flat n x n grid of quads; `plane` picks the two axes it spans ("xy" contains the y axis,
// "xz" is perpendicular to it).
std::string plane_obj(const std::string& plane, int n = 12) {
  std::ostringstream s;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double a = double(i) / n, b = double(j) / n;
      if (plane == "xy") s << "v " << a << ' ' << b << " 0\n";
      else s << "v " << a << " 0 " << b << "\n";
    }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const int v = 1 + i * (n + 1) + j;
      s << "f " << v << ' ' << v + n + 1 << ' ' << v + n + 2 << ' ' << v + 1 << "\n";
    }
  return s.str();
}

// A prism over a regular `sides`-gon: two polygons of `sides` corners (top and bottom) and quads.
std::string prism_obj(int sides) {
  std::ostringstream s;
  for (int k = 0; k < sides; ++k) {
    const double a = 2 * std::numbers::pi * k / sides;
    s << "v " << std::cos(a) << " 0 " << std::sin(a) << "\n" << "v " << std::cos(a) << " 1.5 " << std::sin(a) << "\n";
  }
  s << "f";
  for (int k = sides - 1; k >= 0; --k) s << ' ' << 1 + 2 * k;
  s << "\nf";
  for (int k = 0; k < sides; ++k) s << ' ' << 2 + 2 * k;
  s << "\n";
  for (int k = 0; k < sides; ++k) {
    const int a = 1 + 2 * k, b = 1 + 2 * ((k + 1) % sides);
    s << "f " << a << ' ' << a + 1 << ' ' << b + 1 << ' ' << b << "\n";
  }
  return s.str();
}

// Every other line ends in CR LF instead of LF.
std::string mixed_line_endings(const std::string& text) {
  std::string out;
  int line = 0;
  for (char c : text) {
    if (c == '\n' && line++ % 2 == 0) out += '\r';
    out += c;
  }
  return out;
}

// A binary OFF: Geomview's 'OFF BINARY' (big-endian counts, float coordinates, per face its
// corner count, indices and a colour of no components), or with `pmp` the dialect PMP and
// OpenMesh write (little-endian, no face colours).
std::string binary_off(const std::vector<std::array<float, 3>>& vertices, const std::vector<std::array<std::uint32_t, 3>>& faces,
                       bool pmp = false) {
  std::string out = "OFF BINARY\n";
  const auto put = [&out, pmp](std::uint32_t w) {
    for (int k = 0; k < 4; ++k) out += static_cast<char>((w >> (pmp ? 8 * k : 24 - 8 * k)) & 0xFF);
  };
  put(static_cast<std::uint32_t>(vertices.size()));
  put(static_cast<std::uint32_t>(faces.size()));
  put(0);
  for (const auto& v : vertices)
    for (const float c : v) {
      std::uint32_t bits = 0;
      std::memcpy(&bits, &c, 4);
      put(bits);
    }
  for (const auto& f : faces) {
    put(3);
    for (const std::uint32_t i : f) put(i);
    if (!pmp) put(0);
  }
  return out;
}

const std::string kPlyTetHeader =
    "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
    "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n";

std::string ply_tetrahedron_body() {
  std::string body = binary_floats({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1});
  const int faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  for (const auto& f : faces) {
    body += char(3);
    body.append(reinterpret_cast<const char*>(f), 12);
  }
  return body;
}

// The textured cube of the golden tests with its checker replaced by a 4096 x 4096 one.
fs::path big_texture_cube(const fs::path& dir) {
  fs::create_directories(dir);
  const fs::path obj = meshtour::test::write_textured_cube(dir);
  OIIO::ImageBuf big(OIIO::ImageSpec(4096, 4096, 3, OIIO::TypeDesc::UINT8));
  const float grey[3] = {0.5f, 0.5f, 0.5f};
  OIIO::ImageBufAlgo::fill(big, grey);
  if (!big.write((dir / "checker.png").string())) throw std::runtime_error("cannot write the big texture");
  return obj;
}

// ---- hostile textures ---------------------------------------------------------------------

// The textured cube with its material's map_Kd replaced by `texture` (file name) holding `bytes`,
// or with `as_bump` that texture as a map_Bump beside its own colour map: a bump image is opened
// to see whether it is a normal map (mesh/obj_reader.h), so it gets every texture check first.
fs::path cube_with_texture(const fs::path& dir, const std::string& texture, const std::string& bytes, bool as_bump = false) {
  fs::create_directories(dir);
  const fs::path obj = meshtour::test::write_textured_cube(dir);
  std::ofstream(dir / "cube.mtl") << "newmtl checker\n"
                                  << (as_bump ? "map_Kd checker.png\nmap_Bump -bm 1 " : "Kd 0.8 0.5 0.2\nmap_Kd ") << texture << "\n";
  write(dir / texture, bytes);
  return obj;
}

std::uint32_t png_crc(const std::string& bytes) {
  std::uint32_t c = 0xFFFFFFFFu;
  for (const char ch : bytes) {
    c ^= static_cast<unsigned char>(ch);
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return c ^ 0xFFFFFFFFu;
}

std::string png_chunk(const std::string& type, const std::string& body) {
  const auto be = [](std::uint32_t v) {
    return std::string{static_cast<char>(v >> 24), static_cast<char>(v >> 16), static_cast<char>(v >> 8), static_cast<char>(v)};
  };
  return be(static_cast<std::uint32_t>(body.size())) + type + body + be(png_crc(type + body));
}

// A 65-byte PNG whose header claims 100,000 x 100,000 RGB pixels (30 GB decoded); its image data
// is an empty zlib stream.
std::string png_bomb() {
  const std::string ihdr("\x00\x01\x86\xa0\x00\x01\x86\xa0\x08\x02\x00\x00\x00", 13);
  return std::string("\x89PNG\r\n\x1a\n", 8) + png_chunk("IHDR", ihdr) + png_chunk("IDAT", std::string("\x78\x9c\x03\x00\x00\x00\x00\x01", 8)) +
         png_chunk("IEND", "");
}

// `exr` with its first header attribute's size set to 2 GiB - 256 bytes (OpenEXR 3.1 allocates
// that much before it finds the file too short).
std::string huge_exr_attribute(std::string exr) {
  const std::size_t name_end = exr.find('\0', 8), type_end = exr.find('\0', name_end + 1);
  const std::uint32_t size = 0x7fffff00u;
  std::memcpy(exr.data() + type_end + 1, &size, 4);  // little-endian, as the file
  return exr;
}

// A 64 x 64 noise image (so that it does not compress to a few bytes) with `channels`, in the
// format the extension names; its first `keep` bytes only when keep > 0.
std::string image_bytes(const fs::path& scratch, const std::string& extension, int channels, std::size_t keep = 0) {
  OIIO::ImageBuf image(OIIO::ImageSpec(64, 64, channels, extension == ".exr" ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::UINT8));
  OIIO::ImageBufAlgo::noise(image, "uniform", 0.0f, 1.0f, false, 7);
  const fs::path file = scratch / ("image" + extension);
  if (!image.write(file.string())) throw std::runtime_error("cannot write " + file.string() + ": " + image.geterror());
  std::ifstream in(file, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return keep > 0 ? bytes.substr(0, std::min(keep, bytes.size())) : bytes;
}

// ---- the corpus -----------------------------------------------------------------------------

struct Case {
  std::string name;
  std::string command;        // "path" or "tour"
  fs::path input;             // the file at fault, named in the message
  std::string extra;          // further arguments
  int exit_code;
  std::vector<std::string> words;  // must all appear in the output
  bool names_file = true;     // the message must name `input` (by its file name)
};

class BadInputCorpus : public ::testing::Test {
protected:
  void run(const Case& c) {
    SCOPED_TRACE(c.name);
    const fs::path out = dir_ / ("out-" + std::to_string(index_++));
    fs::create_directories(out);
    std::string args = c.command + " " + meshtour::test::shell_quoted(c.input) + " " + c.extra;
    const std::string threads = c.extra.find("--threads") == std::string::npos ? " --threads 1" : "";
    if (c.command == "path") args += " -o " + meshtour::test::shell_quoted(out / "p.path.json") + threads;
    else args += " -o " + meshtour::test::shell_quoted(out / "v.mp4") + " --frames-dir " + meshtour::test::shell_quoted(out / "frames") + threads;
    const auto start = std::chrono::steady_clock::now();
    const auto r = run_meshtour(args);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(r.exit_code, c.exit_code) << r.output;
    for (const char* raw : {"libpng", "libjpeg", "Premature end"}) EXPECT_EQ(r.output.find(raw), std::string::npos) << r.output;
    for (const auto& w : c.words) EXPECT_NE(r.output.find(w), std::string::npos) << "'" << w << "' not in: " << r.output;
    if (c.names_file) {
      EXPECT_NE(r.output.find(c.input.filename().string()), std::string::npos) << r.output;
    }
    // Every failure is refused quickly: no case needs more than a few seconds (the billion-face
    // header must not make the loader allocate or read for long).
    EXPECT_LT(seconds, 20.0) << r.output;
    std::size_t outputs = 0;
    for (const auto& e : fs::recursive_directory_iterator(out)) outputs += e.is_regular_file();
    if (c.exit_code != 0) {
      // One line, no partial outputs (the frames folder may exist, but empty).
      EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
      EXPECT_EQ(outputs, 0u) << "partial output left in " << out;
    } else {
      EXPECT_TRUE(fs::exists(out / (c.command == "path" ? "p.path.json" : "v.mp4"))) << r.output;
    }
    std::printf("  %-40s exit %d  %s", c.name.c_str(), r.exit_code, r.output.empty() ? "\n" : "");
    // The message, as documentation of the corpus in the test log.
    std::string first = r.output.substr(0, r.output.find('\n'));
    if (!r.output.empty()) std::printf("%s\n", first.c_str());
  }

  void SetUp() override { dir_ = meshtour::test::scratch_dir(); }
  fs::path dir_;
  int index_ = 0;
};

constexpr const char* kSmall = "--width 64 --height 48 --frames 2 --spp 1 -q";

TEST_F(BadInputCorpus, Meshes) {
  const fs::path d = dir_;
  const std::string tet_body = ply_tetrahedron_body();
  std::string garbage(tet_body.size(), '\0');
  std::uint32_t x = 12345;
  for (char& c : garbage) c = static_cast<char>((x = x * 1664525u + 1013904223u) >> 24);
  std::string past_end = tet_body;
  const int bad_index = 99;
  std::memcpy(past_end.data() + 48 + 13 * 3 + 1 + 8, &bad_index, 4);  // last face's third corner

  std::string stl(80, ' ');
  const std::uint32_t ten = 10;
  stl.append(reinterpret_cast<const char*>(&ten), 4);
  stl += std::string(50 * 2, '\0');  // 2 of the 10 announced triangles

  const std::vector<Case> cases = {
      {"empty file", "path", write(d / "empty.ply", ""), "", 2, {"empty"}},
      {"empty OBJ (only a comment)", "path", write(d / "comment.obj", "# nothing\n"), "", 2, {"no faces"}},
      {"truncated binary PLY", "path", write(d / "truncated.ply", kPlyTetHeader + tet_body.substr(0, 40)), "", 2, {"truncated"}},
      {"truncated binary STL", "path", write(d / "truncated.stl", stl), "", 2, {"truncated"}},
      {"ASCII STL facet with two corners", "path",
       write(d / "two_corners.stl", "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid s\n"), "", 2,
       {"two_corners.stl", "line 6", "facet 0 has 2 corners"}},
      {"ASCII STL cut inside a facet", "path", write(d / "cut.stl", "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"), "", 2,
       {"cut.stl", "truncated: the file ends inside facet 0"}},
      {"garbage body, valid PLY header", "path", write(d / "garbage.ply", kPlyTetHeader + garbage), "", 2, {}},
      {"PLY announces more vertices than it has", "path",
       write(d / "counts.ply", "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
                               "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
       "", 2, {}},
      {"PLY face past the vertex list", "path", write(d / "past.ply", kPlyTetHeader + past_end), "", 2, {"face", "99"}},
      // The PLY reader's own buffer: a big-endian body cut inside a face's list, and an ASCII body
      // cut in the middle of its last face.
      {"big-endian PLY truncated inside a face", "path",
       write(d / "big_endian.ply", std::string("ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                               "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n") +
                                       std::string(36, '\0') + std::string("\x03\0\0\0\0\0\0\0", 8)),
       "", 2, {"truncated", "face 0"}},
      {"PLY with two vertex lists (found by fuzzing)", "path",
       write(d / "two_lists.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                                  "element vertex 2\nproperty float x\nproperty float y\nproperty float z\nelement face 1\n"
                                  "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n0 0 0\n1 1 1\n3 0 1 2\n"),
       "", 2, {"line 7", "second 'element vertex'"}},
      {"ASCII PLY truncated inside its last face", "path",
       write(d / "ascii_cut.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                                  "element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1"),
       "", 2, {"truncated", "face 1"}},
      {"OBJ face past the vertex list", "path", write(d / "past.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 7\n"), "", 2,
       {"line 5", "7"}},
      {"OFF face past the vertex list", "path", write(d / "past.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n"), "", 2, {"face", "5"}},
      // Float colours outside 0..1 are undefined behaviour in OpenMesh's conversion to bytes.
      {"PLY float colour outside 0..1", "path",
       write(d / "colour.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                               "property float red\nproperty float green\nproperty float blue\nelement face 4\n"
                               "property list uchar int vertex_indices\nend_header\n0 0 0 0 0 0\n1 0 0 0 0 1e30\n0 1 0 0 0 0\n"
                               "0 0 1 0 0 0\n3 0 1 2\n3 0 1 3\n3 0 2 3\n3 1 2 3\n"),
       "", 2, {"vertex 1", "blue", "outside 0 to 1"}},
      {"COFF float colour outside 0..1", "path",
       write(d / "colour.off", "COFF\n4 4 0\n0 0 0 0 0 0\n1 0 0 -3.5 0 0\n0 1 0 0 0 0\n0 0 1 0 0 0\n3 0 1 2\n3 0 1 3\n3 0 2 3\n3 1 2 3\n"),
       "", 2, {"line 4", "'-3.5'", "outside 0 to 1"}},
      {"OFF face with two corners", "path", write(d / "two.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n"), "", 2,
       {"line 6", "face 0", "corner count"}},
      {"OFF counts that are not numbers", "path", write(d / "counts.off", "OFF\nfour 4 0\n"), "", 2, {"line 2", "counts"}},
      {"OFF unknown keyword prefix", "path", write(d / "xoff.off", "XOFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), "", 2,
       {"XOFF", "ST, C, N and 4"}},
      {"COFF vertex without a colour", "path",
       write(d / "nocolour.off", "COFF\n3 1 0\n0 0 0 255 0 0\n1 0 0\n0 1 0 0 0 255\n3 0 1 2\n"), "", 2, {"line 4", "vertex 1", "no colour"}},
      {"binary OFF with a face past the vertex list", "path",
       write(d / "past_binary.off", binary_off({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 7}})), "", 2, {"face 0", "vertex 7"}},
      {"binary OFF cut short", "path",
       write(d / "short_binary.off", binary_off({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}).substr(0, 40)), "", 2, {"binary OFF"}},
      {"NaN coordinate", "path", write(d / "nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n"), "", 2,
       {"NaN", "vertex 3"}},
      {"infinite coordinate", "path", write(d / "inf.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1e999 0\n0 0 1\n3 0 1 2\n3 0 1 3\n"), "", 2,
       {"infinite"}},
      {"all faces degenerate", "path", write(d / "degenerate.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 0 2 0\nf 1 2 3\nf 1 4 5\n"), "", 2,
       {"degenerate"}},
      {"points without faces", "path",
       write(d / "points.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                               "end_header\n0 0 0\n1 0 0\n0 1 0\n"),
       "", 2, {"no faces"}},
      {"billion-face PLY header on a tiny file", "path",
       write(d / "billion.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                "property float z\nelement face 1000000000\nproperty list uchar int vertex_indices\nend_header\n" +
                                    tet_body.substr(0, 36)),
       "", 2, {"1000000000 face"}},
      {"billion-face OFF header", "path", write(d / "billion.off", "OFF\n3 1000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), "", 2,
       {"1000000000"}},
      {"billion-triangle binary STL header", "path",
       write(d / "billion.stl", std::string(80, ' ') + std::string("\x00\xca\x9a\x3b", 4) + std::string(50, '\0')), "", 2,
       {"1000000000"}},
      {"mesh across the up axis (flat, y up)", "path", write(d / "floor.obj", plane_obj("xz")), "--up y", 2, {"flat", "--up"}},
      {"scene with unknown key", "tour", write(d / "unknown.json", R"({"model": {"procedural": "sculpture"}, "colour": "red"})"),
       kSmall, 2, {"'colour' unknown key"}},
      {"scene with a wrong type", "tour", write(d / "type.json", R"({"model": {"procedural": "sculpture"}, "timing": {"frames": "ten"}})"),
       "-q", 2, {"'timing.frames' must be a whole number"}},
      {"scene without a model", "tour", write(d / "nomodel.json", R"({"up": "y"})"), kSmall, 2, {"has no 'model'"}},
      {"scene naming a missing mesh", "tour", write(d / "missing.json", R"({"model": {"file": "nowhere.ply"}})"), kSmall, 3,
       {"nowhere.ply", "no such file"}, false},
      {"scene with a negative size", "tour",
       write(d / "negative.json", R"({"model": {"procedural": "sculpture"}, "output": {"width": -64, "height": 48}})"), "-q", 2,
       {"'output.width' must be between 2 and 16384, got -64"}},
      {"scene with zero frames", "tour", write(d / "zero.json", R"({"model": {"procedural": "sculpture"}, "timing": {"frames": 0}})"),
       "-q", 2, {"'timing.frames' must be between 1 and 1000000, got 0"}},
      {"scene at 100000 x 100000", "tour",
       write(d / "absurd.json", R"({"model": {"procedural": "sculpture"}, "output": {"width": 100000, "height": 100000}})"), "-q", 2,
       {"'output.width' must be between 2 and 16384"}},
      {"16384 x 16384 over a 1 GiB memory budget", "tour", write(d / "big.json", R"({"model": {"procedural": "sculpture"}, "output": {"width": 16384, "height": 16384}})"),
       "-q --max-memory 1G", 2, {"needs an estimated", "frame buffers", "memory budget is 1.0 GiB", "--max-memory"}, false},
      {"mesh over a 2 MiB memory budget", "path", write(d / "budget.obj", sphere_obj()), "--max-memory 2M", 2,
       {"budget.obj", "needs an estimated", "--max-memory 2M"}, false},
      {"--max-memory that is not a size", "path", write(d / "size.obj", sphere_obj()), "--max-memory lots", 2,
       {"--max-memory", "not a size"}, false},
      // The model fits the budget, its 4096 x 4096 atlas (64 MiB decoded) does not: refused once
      // the model is loaded and its textures' headers are read, before the texture cache exists.
      {"textures over a 140 MiB memory budget", "tour", big_texture_cube(d / "big-texture"),
       "-q --max-memory 140M --width 64 --height 48 --frames 2 --path turntable", 2,
       {"needs an estimated", "texture cache 64.0 MiB", "memory budget is 140.0 MiB"}, false},
      {"scene not JSON", "tour", write(d / "broken.json", "{\"model\": {\"procedural\": \"sculpture\"},\n  \"up\": }"), "-q", 2,
       {"not valid JSON", "line 2"}},
  };
  for (const auto& c : cases) run(c);
}

TEST_F(BadInputCorpus, OddButValidMeshes) {
  const fs::path d = dir_;
  const std::vector<Case> cases = {
      {"single triangle", "path", write(d / "triangle.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"), "", 0, {}, false},
      {"flat plane along the up axis", "path", write(d / "wall.obj", plane_obj("xy")), "", 0, {"warning", "flat"}},
      {"300-gon polygons", "path", write(d / "prism300.obj", prism_obj(300)), "", 0, {}, false},
      {"OFF with blank lines and comments after the numbers", "path",
       write(d / "commented.off", "OFF # a tetrahedron\n4 4 0\n0 0 0 # origin\n\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 3 # side\n3 0 2 3\n3 1 2 3\n"),
       "", 0, {}, false},
      {"OFF with comment lines inside its lists and the counts on the keyword's line", "path",
       write(d / "comment.off", "OFF 4 4 0\n# vertices\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n# faces\n3 0 1 2\n3 0 1 3\n3 0 2 3\n3 1 2 3\n"), "", 0,
       {"4 faces"}, false},
      {"binary OFF", "path", write(d / "binary.off", binary_off({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}})),
       "", 0, {"4 faces"}, false},
      {"binary OFF as PMP and OpenMesh write it", "path",
       write(d / "binary_pmp.off", binary_off({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}}, true)),
       "", 0, {"4 faces"}, false},
      {"mixed CRLF and LF line endings", "path", write(d / "mixed.obj", mixed_line_endings(sphere_obj())),
       "", 0, {}, false},
      {"non-ASCII file and folder names", "path",
       [&] {
         fs::create_directories(d / "données 3D");
         return write(d / "données 3D" / "modèle_球体.obj", sphere_obj());
       }(),
       "", 0, {}, false},
      {"non-ASCII names, tour", "tour", write(d / "vidéo_ß.obj", sphere_obj()), kSmall, 0, {}, false},
      {"more threads than cores are capped", "path", write(d / "threads.obj", sphere_obj()), "--threads 100000", 0,
       {"capped to the"}, false},
      {"--verbose reports every stage", "tour", write(d / "verbose.obj", sphere_obj()), "--width 64 --height 48 --frames 2 --spp 1 --verbose",
       0, {"stage load", "stage path", "stage bvh", "stage render", "stage encode", "peak"}, false},
  };
  for (const auto& c : cases) run(c);
}

// Hostile and broken textures (docs/FORMATS.md, "Hostile textures"): each is refused at load time
// with one line naming the texture and the way out, quickly and in little memory (the bomb made
// a 2-frame tour run 173 s and peak at 2 GB before), and never with the image libraries' own
// error text on stderr.
TEST_F(BadInputCorpus, HostileTextures) {
  const fs::path d = dir_;
  fs::create_directories(d / "scratch");
  const std::string png = image_bytes(d / "scratch", ".png", 3), jpeg = image_bytes(d / "scratch", ".jpg", 3),
                    exr = image_bytes(d / "scratch", ".exr", 3);
  const std::string extra = std::string(kSmall) + " --path turntable";
  const std::vector<Case> cases = {
      {"PNG bomb: 100000 x 100000 in 65 bytes", "tour", cube_with_texture(d / "bomb", "bomb.png", png_bomb()), extra, 3,
       {"bomb.png", "100000 x 100000", "65 bytes", "decompression bomb", "--missing-textures grey"}},
      {"PNG cut in half", "tour", cube_with_texture(d / "png", "cut.png", png.substr(0, png.size() / 2)), extra, 3,
       {"cut.png", "truncated", "--missing-textures grey"}},
      // (cut inside the text chunks before the image data: libpng fails while the header is read)
      {"PNG cut in its header chunks", "tour", cube_with_texture(d / "png-head", "head.png", png.substr(0, 60)), extra, 3,
       {"head.png", "truncated"}},
      {"PNG without its IEND chunk", "tour", cube_with_texture(d / "iend", "noend.png", png.substr(0, png.size() - 12)), extra, 3,
       {"noend.png", "truncated"}},
      {"JPEG cut in half", "tour", cube_with_texture(d / "jpeg", "cut.jpg", jpeg.substr(0, jpeg.size() / 2)), extra, 3,
       {"cut.jpg", "truncated", "end-of-image"}},
      {"EXR cut in half", "tour", cube_with_texture(d / "exr", "cut.exr", exr.substr(0, exr.size() / 2)), extra, 3,
       {"cut.exr", "cannot be decoded"}},
      {"EXR header attribute claiming 2 GiB", "tour", cube_with_texture(d / "exr-attribute", "attribute.exr", huge_exr_attribute(exr)), extra, 3,
       {"attribute.exr", "header attribute claims 2147483392 bytes"}},
      {"KTX2 texture", "tour", cube_with_texture(d / "ktx2", "atlas.ktx2", std::string("\xabKTX 20\xbb\r\n\x1a\n", 12) + std::string(68, '\0')),
       extra, 3, {"atlas.ktx2", "KTX2 / Basis Universal", "PNG or JPEG"}},
      {"KTX2 bytes behind a .png name", "tour",
       cube_with_texture(d / "ktx2-named-png", "atlas.png", std::string("\xabKTX 20\xbb\r\n\x1a\n", 12) + std::string(68, '\0')), extra, 3,
       {"atlas.png", "KTX2 / Basis Universal"}},
      {"PNG bomb as an OBJ's map_Bump", "tour", cube_with_texture(d / "bump-bomb", "bump.png", png_bomb(), true), extra, 3,
       {"bump.png", "bump map", "decompression bomb", "--missing-textures grey"}},
      {"EXR with 5 channels", "tour", cube_with_texture(d / "five", "five.exr", image_bytes(d / "scratch", ".exr", 5)), extra, 3,
       {"five.exr", "5 channels", "save it as RGB"}},
  };
  for (const auto& c : cases) run(c);

  // The documented fallback: with --missing-textures grey the bomb's faces take the material's
  // colour, with one warning line, and the tour is made.
  const fs::path out = d / "grey";
  fs::create_directories(out);
  const auto r = run_meshtour("tour " + meshtour::test::shell_quoted(d / "bomb" / "cube.obj") + " --width 64 --height 48 --frames 2 --spp 1 --path turntable --threads 1 "
                              "--missing-textures grey -o " + meshtour::test::shell_quoted(out / "v.mp4"));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(out / "v.mp4")) << r.output;
  std::size_t warnings = 0;
  for (std::size_t at = r.output.find("rendered untextured"); at != std::string::npos; at = r.output.find("rendered untextured", at + 1)) ++warnings;
  EXPECT_EQ(warnings, 1u) << r.output;
  EXPECT_EQ(r.output.find("libpng"), std::string::npos) << r.output;
}

// Voyager scene documents (.svx.json; scenes/voyager.h): partial and bad documents, each refused
// naming the document and the key.
TEST_F(BadInputCorpus, VoyagerDocuments) {
  const fs::path d = dir_;
  write(d / "shell.obj", sphere_obj());
  const auto svx = [](const std::string& setup, const std::string& model) {
    return R"({"asset": {"type": "application/si-dpo-3d.document+json", "version": "1.0"}, "scene": 0,
      "scenes": [{"nodes": [0], "setup": 0}], "nodes": [{"model": 0}],
      "setups": [)" + setup + R"(], "models": [)" + model + "]}";
  };
  const std::string setup = R"({"units": "cm", "navigation": {"orbit": {"orbit": [-20, 30, 0], "offset": [0, 0, 100]}}})";
  const std::string model = R"({"units": "cm", "derivatives": [{"usage": "Web3D", "quality": "High", "assets": [{"uri": "shell.obj", "type": "Model"}]}]})";
  const std::vector<Case> cases = {
      {"Voyager orbit of two angles", "tour", write(d / "orbit.svx.json", svx(R"({"navigation": {"orbit": {"orbit": [-20, 30]}}})", model)), kSmall, 2,
       {"'setups[0].navigation.orbit.orbit' must be an array of 3 numbers"}},
      {"Voyager model without units", "path", write(d / "units.svx.json", svx(setup, R"({"derivatives": []})")), "", 2, {"'models[0].units' is missing"}},
      {"Voyager derivative not on disk", "tour", write(d / "gone.svx.json", svx(setup, R"({"units": "cm", "derivatives": [{"usage": "Web3D",
          "quality": "Highest", "assets": [{"uri": "gone.glb", "type": "Model"}]}]})")), kSmall, 2, {"no Web3D derivative's model is on disk", "gone.glb"}},
      {"Voyager quality not listed", "tour", write(d / "quality.svx.json", svx(setup, model)), std::string(kSmall) + " --quality Thumb", 2,
       {"no Web3D derivative of quality Thumb"}},
      {"Voyager document with no scenes", "tour", write(d / "partial.svx.json", R"({"asset": {"type": "application/si-dpo-3d.document+json"}})"), kSmall,
       2, {"'scenes' is missing"}},
      {"glTF named as a Voyager document", "tour", write(d / "gltf.svx.json", R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}]})"), kSmall,
       2, {"'asset.type' must be"}},
      {"Voyager document that is not JSON", "path", write(d / "torn.svx.json", R"({"asset": {"type": )"), "", 2, {"not valid JSON"}},
  };
  for (const Case& c : cases) run(c);
}

TEST_F(BadInputCorpus, PathFiles) {
  const fs::path d = dir_;
  const fs::path mesh = write(d / "sphere.obj", sphere_obj());
  const fs::path good = d / "good.path.json";
  const auto made = run_meshtour("path " + meshtour::test::shell_quoted(mesh) + " -q -o " + meshtour::test::shell_quoted(good));
  ASSERT_EQ(made.exit_code, 0) << made.output;
  std::ifstream in(good);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto edited = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    const auto at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) t.replace(at, from.size(), to);
    return t;
  };
  const std::string tour = "--path-file ";
  auto path_case = [&](const std::string& name, const std::string& file, const std::string& content, int code,
                       std::vector<std::string> words) {
    const fs::path f = write(d / file, content);
    return Case{name, "tour", mesh, std::string(kSmall) + " --path-file " + meshtour::test::shell_quoted(f), code, std::move(words), false};
  };
  const std::vector<Case> cases = {
      path_case("path file from a newer version", "newer.path.json", edited("\"format_version\": 2", "\"format_version\": 3"), 2,
                {"newer.path.json", "format_version", "must be 1 or 2"}),
      path_case("path file of an unknown mode", "mode.path.json", edited("\"mode\": \"paper\"", "\"mode\": \"spiral\""), 2,
                {"mode.path.json", "'mode'", "paper, feature-orbit or turntable"}),
      path_case("path file made for another up axis", "up.path.json", edited("\"up\": \"+y\"", "\"up\": \"+z\""), 2,
                {"up.path.json", "made for up +z", "this render has up +y"}),
      path_case("path file made for another mesh", "faces.path.json", edited("\"faces\": \"", "\"faces\": \"1"), 2,
                {"faces.path.json", "made for faces 1"}),
      path_case("path file with a negative radius", "radius.path.json", edited("\"radius\": ", "\"radius\": -"), 2,
                {"radius.path.json", "cylinder.radius", "positive"}),
      path_case("path file with a missing key", "nokey.path.json", edited("\"start_parameter\"", "\"start_parametre\""), 2,
                {"nokey.path.json", "curve.start_parameter", "missing"}),
      path_case("path file hand-edited into nonsense", "nonsense.path.json", "{\"format_version\": 1, \"curve\": [1, 2}", 2,
                {"nonsense.path.json", "not valid JSON"}),
      path_case("path file that is a JSON array", "array.path.json", "[1, 2, 3]", 2, {"array.path.json", "format_version"}),
      path_case("path file with a huge degree", "degree.path.json", edited("\"degree\": 3", "\"degree\": 1e300"), 2,
                {"degree.path.json", "curve.degree"}),
  };
  for (const auto& c : cases) run(c);
}

// A render that fails before its first frame (here: the model cannot be loaded) leaves no
// frames directory and no meshtour-frames.json behind.
TEST(RenderCommand, FailingBeforeTheFirstFrameLeavesNoFile) {
  const fs::path dir = meshtour::test::scratch_dir();
  const fs::path model = write(dir / "broken.glb", "glTF this is not");
  std::string command = "render '";
  command.append(model.string()).append("' --out-dir '").append((dir / "frames").string()).append("' --frame-count 2 --progress none");
  const auto r = run_meshtour(command);
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("broken.glb"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "frames")) << r.output;
}

}  // namespace
