// Fuzz target: the mesh loaders as meshtour calls them. The first byte picks the format (the
// loader chooses its reader by extension), the rest is written to a file that load_mesh() reads.
// Any meshtour::Error is a correct answer to garbage; a crash, a hang, a leak or an allocation
// beyond -rss_limit_mb/-malloc_limit_mb is a bug.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.h"
#include "fuzz_scratch.h"
#include "mesh/mesh.h"

namespace {

const std::filesystem::path& scratch_dir() {
  static const meshtour::fuzz::ScratchDir scratch("fuzz-mesh");
  return scratch.dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const char* const extensions[] = {".ply", ".obj", ".off", ".stl"};
  const auto file = scratch_dir() / (std::string("input") + extensions[data[0] % 4]);
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  }
  try {
    meshtour::LoadReport report;
    const meshtour::TriangleMesh mesh = meshtour::load_mesh(file, &report);
    // What the later stages rely on: every index is a vertex, every coordinate is finite.
    for (const auto& t : mesh.triangles)
      for (auto v : t)
        if (v >= mesh.positions.size()) __builtin_trap();
    for (const auto& p : mesh.positions)
      if (!p.allFinite()) __builtin_trap();
    if (!mesh.corner_uvs.empty() && mesh.corner_uvs.size() != 3 * mesh.triangles.size()) __builtin_trap();
    if (!mesh.corner_normals.empty() && mesh.corner_normals.size() != 3 * mesh.triangles.size()) __builtin_trap();
    if (!mesh.corner_tangents.empty() && mesh.corner_tangents.size() != 3 * mesh.triangles.size()) __builtin_trap();
  } catch (const meshtour::Error&) {
  }
  return 0;
}
