#pragma once
// What the benchmarks share: the bunny split 1-to-4 at edge midpoints (the same shape at 70k, 1.1M,
// 4.5M, 17.8M faces; the split is tests/test_meshes.h's) and the hand-over of the command line
// to Google Benchmark once a benchmark has taken its own flags.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/atomic_file.h"
#include "core/triangle_geometry.h"
#include "mesh/mesh.h"
#include "test_meshes.h"

namespace meshtour::bench {

/// `source` split `levels` times, built once per level on first use (sizes a filter leaves out
/// cost nothing). `written(mesh, levels)`, when given, runs once for each new split level (to keep
/// the meshes as files). Exits with 2 and a message if `source` does not exist.
inline const TriangleMesh& split_mesh(const std::filesystem::path& source, int levels,
                                      const std::function<void(const TriangleMesh&, int)>& written = {}) {
  static std::map<int, TriangleMesh> cache;
  if (const auto it = cache.find(levels); it != cache.end()) return it->second;
  TriangleMesh mesh;
  if (levels == 0) {
    if (!std::filesystem::exists(source)) {
      std::cerr << source << " not found; pass --mesh=FILE\n";
      std::exit(2);
    }
    mesh = load_mesh(source);
  } else {
    mesh = test_meshes::split_at_midpoints(split_mesh(source, levels - 1, written));
    if (written) written(mesh, levels);
  }
  return cache.emplace(levels, std::move(mesh)).first->second;
}

// Writes `file` whole or not at all, as every output of meshtour (core/atomic_file.h): `body`
// fills a temporary beside it, flushed to the disk and renamed when complete (an interrupted
// bench, or a crashed machine, leaves no half mesh for the next run to read).
template <class Body>
void write_whole(const std::filesystem::path& file, Body body) {
  std::filesystem::create_directories(file.parent_path());
  meshtour::write_file_atomically(file, [&](const std::filesystem::path& temporary) {
    std::ofstream out(temporary, std::ios::binary);
    body(out);
    out.close();
    if (!out) throw meshtour::IoError("could not write " + file.string() + " (disk full?)");
  });
}

// A text mesh's lines: `vertex` and three float coordinates (9 significant digits, as the PLY's
// floats) per vertex, then `face` and three indices counted from `first` per triangle.
inline void write_text_lines(std::ofstream& out, const meshtour::TriangleMesh& mesh, const char* vertex, const char* face, unsigned first) {
  char line[128];
  for (const auto& p : mesh.positions) {
    const int n = std::snprintf(line, sizeof line, "%s%.9g %.9g %.9g\n", vertex, static_cast<float>(p.x()), static_cast<float>(p.y()),
                                static_cast<float>(p.z()));
    out.write(line, n);
  }
  for (const auto& t : mesh.triangles) {
    const int n = std::snprintf(line, sizeof line, "%s%u %u %u\n", face, t[0] + first, t[1] + first, t[2] + first);
    out.write(line, n);
  }
}

// Binary little-endian PLY, float coordinates (what scanners write).
inline void write_ply(const meshtour::TriangleMesh& mesh, const std::filesystem::path& file) {
  write_whole(file, [&](std::ofstream& out) {
    out << "ply\nformat binary_little_endian 1.0\nelement vertex " << mesh.positions.size()
        << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << mesh.triangles.size()
        << "\nproperty list uchar int vertex_indices\nend_header\n";
    for (const auto& p : mesh.positions) {
      const float xyz[3] = {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())};
      out.write(reinterpret_cast<const char*>(xyz), sizeof xyz);
    }
    for (const auto& t : mesh.triangles) {
      char face[13];
      face[0] = 3;
      std::memcpy(face + 1, t.data(), 12);
      out.write(face, sizeof face);
    }
  });
}

// OBJ text: "v x y z" with float precision (9 significant digits, as the PLY's floats) and
// "f a b c", as scanning software writes them.
inline void write_obj(const meshtour::TriangleMesh& mesh, const std::filesystem::path& file) {
  write_whole(file, [&](std::ofstream& out) { write_text_lines(out, mesh, "v ", "f ", 1); });
}

// Text OFF: the keyword, the counts, a line per vertex and per triangle (0-based indices).
inline void write_off(const meshtour::TriangleMesh& mesh, const std::filesystem::path& file) {
  write_whole(file, [&](std::ofstream& out) {
    out << "OFF\n" << mesh.positions.size() << ' ' << mesh.triangles.size() << " 0\n";
    write_text_lines(out, mesh, "", "3 ", 0);
  });
}

// Binary STL: an 80-byte header, the triangle count, then per triangle a float normal, three
// float corners and a 2-byte attribute (every corner written out: STL shares no vertices).
inline void write_stl(const meshtour::TriangleMesh& mesh, const std::filesystem::path& file) {
  write_whole(file, [&](std::ofstream& out) {
    char header[80] = "meshtour bench";
    out.write(header, sizeof header);
    const auto count = static_cast<std::uint32_t>(mesh.triangles.size());
    out.write(reinterpret_cast<const char*>(&count), 4);
    for (const auto& t : mesh.triangles) {
      const Eigen::Vector3d& a = mesh.positions[t[0]];
      const Eigen::Vector3d& b = mesh.positions[t[1]];
      const Eigen::Vector3d& c = mesh.positions[t[2]];
      const Eigen::Vector3d n = triangle_normal(a, b, c);
      float record[12];
      for (int k = 0; k < 3; ++k) {
        record[k] = static_cast<float>(n[k]);
        record[3 + k] = static_cast<float>(a[k]);
        record[6 + k] = static_cast<float>(b[k]);
        record[9 + k] = static_cast<float>(c[k]);
      }
      char bytes[50] = {};
      std::memcpy(bytes, record, sizeof record);
      out.write(bytes, sizeof bytes);
    }
  });
}

// GLB (glTF 2.0 binary): float positions and uint32 indices in one buffer, one mesh, one node.
/// `instances` > 1: the mesh drawn by that many nodes, side by side along +x (one mesh, shared).
inline void write_glb(const meshtour::TriangleMesh& mesh, const std::filesystem::path& file, int instances = 1) {
  std::vector<char> bin(12 * mesh.positions.size() + 12 * mesh.triangles.size());
  std::array<float, 3> lo{1e30f, 1e30f, 1e30f}, hi{-1e30f, -1e30f, -1e30f};
  char* at = bin.data();
  for (const auto& p : mesh.positions) {
    const float xyz[3] = {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())};
    for (std::size_t k = 0; k < 3; ++k) lo[k] = std::min(lo[k], xyz[k]), hi[k] = std::max(hi[k], xyz[k]);
    std::memcpy(at, xyz, 12);
    at += 12;
  }
  for (const auto& t : mesh.triangles) std::memcpy(at, t.data(), 12), at += 12;
  const std::size_t positions = 12 * mesh.positions.size();
  std::ostringstream json;
  json << std::setprecision(9);  // min and max exact in float
  json << R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":)" << bin.size() << R"(}],"bufferViews":[{"buffer":0,"byteLength":)"
       << positions << R"(},{"buffer":0,"byteOffset":)" << positions << R"(,"byteLength":)" << bin.size() - positions
       << R"(}],"accessors":[{"bufferView":0,"componentType":5126,"count":)" << mesh.positions.size() << R"(,"type":"VEC3","min":[)"
       << lo[0] << "," << lo[1] << "," << lo[2] << "],\"max\":[" << hi[0] << "," << hi[1] << "," << hi[2]
       << R"(]},{"bufferView":1,"componentType":5125,"count":)" << 3 * mesh.triangles.size()
       << R"(,"type":"SCALAR"}],"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],"nodes":[)";
  for (int i = 0; i < instances; ++i)
    json << (i ? "," : "") << R"({"mesh":0,"translation":[)" << 1.5 * (hi[0] - lo[0]) * i << ",0,0]}";
  json << R"(],"scenes":[{"nodes":[)";
  for (int i = 0; i < instances; ++i) json << (i ? "," : "") << i;
  json << R"(]}],"scene":0})";
  std::string text = json.str();
  while (text.size() % 4) text += ' ';
  const auto u32 = [](std::ofstream& out, std::size_t v) {
    const std::uint32_t w = static_cast<std::uint32_t>(v);
    out.write(reinterpret_cast<const char*>(&w), 4);
  };
  write_whole(file, [&](std::ofstream& out) {
    u32(out, 0x46546C67);  // "glTF"
    u32(out, 2);
    u32(out, 12 + 8 + text.size() + 8 + bin.size());
    u32(out, text.size());
    u32(out, 0x4E4F534A);  // "JSON"
    out << text;
    u32(out, bin.size());
    u32(out, 0x004E4942);  // "BIN"
    out.write(bin.data(), static_cast<std::streamsize>(bin.size()));
  });
}

/// argv without the flags of `flags` ("--mesh=" -> what to do with its value), for run_benchmarks():
/// each benchmark's own flags first, everything else goes to Google Benchmark.
inline std::vector<char*> take_flags(int argc, char** argv,
                                     const std::vector<std::pair<std::string, std::function<void(const char*)>>>& flags) {
  std::vector<char*> rest = {argv[0]};
  for (int i = 1; i < argc; ++i) {
    const auto flag = std::find_if(flags.begin(), flags.end(), [&](const auto& f) { return std::strncmp(argv[i], f.first.c_str(), f.first.size()) == 0; });
    if (flag != flags.end()) flag->second(argv[i] + flag->first.size());
    else rest.push_back(argv[i]);
  }
  return rest;
}

/// The source mesh and the folder the split meshes are written to: --mesh=FILE (default
/// ../shared/meshes/bunny.ply next to the source tree) and --mesh-dir=DIR (default bench-meshes/ in
/// the build folder). Returns argv without these flags, for run_benchmarks().
inline std::vector<char*> take_mesh_flags(int argc, char** argv, std::filesystem::path& source_mesh, std::filesystem::path& mesh_dir,
                                          const std::filesystem::path& source_dir, const std::filesystem::path& binary_dir) {
  source_mesh = source_dir.parent_path() / "shared" / "meshes" / "bunny.ply";
  mesh_dir = binary_dir / "bench-meshes";
  return take_flags(argc, argv, {{"--mesh=", [&](const char* v) { source_mesh = v; }}, {"--mesh-dir=", [&](const char* v) { mesh_dir = v; }}});
}

/// Runs the benchmarks selected by `args` (argv[0] first, then the flags the benchmark did not take).
inline int run_benchmarks(std::vector<char*> args) {
  int count = static_cast<int>(args.size());
  benchmark::Initialize(&count, args.data());
  if (benchmark::ReportUnrecognizedArguments(count, args.data())) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

}  // namespace meshtour::bench
