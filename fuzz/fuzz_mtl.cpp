// Fuzz target: the MTL reader (mesh/obj_reader.cpp) as load_mesh() meets it: the input is the
// material library of a fixed textured quad whose faces use its materials by the names the seeds
// use. Textures are not opened (their checks are fuzz_texture's), so every statement's parsing and
// the material it makes are what is exercised. Any meshtour::Error is a correct answer to garbage.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "fuzz_scratch.h"
#include "mesh/mesh.h"

namespace {

const std::filesystem::path& scratch_dir() {
  static const meshtour::fuzz::ScratchDir scratch("fuzz-mtl");
  static const bool written = [] {
    std::ofstream(scratch.dir / "quad.obj", std::ios::binary)
        << "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
           "usemtl m\nf 1/1 2/2 3/3\nusemtl skin\nf 1/1 3/3 4/4\n";
    return true;
  }();
  (void)written;
  return scratch.dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto& dir = scratch_dir();
  {
    std::ofstream out(dir / "m.mtl", std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    const meshtour::TriangleMesh mesh = meshtour::load_mesh(dir / "quad.obj", nullptr, meshtour::LoadOptions{.check_textures = false});
    for (const auto& m : mesh.materials) {
      // What the renderer relies on: colours and factors finite and within their ranges.
      if (m.base_color && !(m.base_color->allFinite() && m.base_color->minCoeff() >= 0.0f && m.base_color->maxCoeff() <= 1.0f))
        __builtin_trap();
      if (!(m.alpha >= 0.0f && m.alpha <= 1.0f) || !m.emissive.allFinite() || !(m.emissive.minCoeff() >= 0.0f)) __builtin_trap();
      if (m.metallic_roughness && !(m.metallic_roughness->roughness >= 0.0f && m.metallic_roughness->roughness <= 1.0f &&
                                    m.metallic_roughness->metallic >= 0.0f && m.metallic_roughness->metallic <= 1.0f))
        __builtin_trap();
    }
  } catch (const meshtour::Error&) {
  }
  return 0;
}
