// Fuzz target: the glTF/GLB reader (tinygltf, the accessor and Draco checks, libdraco). The first
// byte picks .glb or .gltf, the rest is the file; its references (buffers, images) resolve in an
// empty folder, so external files are missing. Any meshtour::Error is a correct answer.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.h"
#include "fuzz_scratch.h"
#include "mesh/mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const meshtour::fuzz::ScratchDir scratch("fuzz-gltf");
  const auto file = scratch.dir / (data[0] % 2 ? "input.gltf" : "input.glb");
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  }
  // The check (the JSON's counts and the buffers' sizes, nothing read) and the reader, each on its
  // own: a file the check refuses still goes through the reader.
  try {
    meshtour::check_mesh_file(file);
  } catch (const meshtour::Error&) {
  }
  try {
    const meshtour::TriangleMesh mesh = meshtour::load_mesh(file, nullptr, meshtour::LoadOptions{.missing_textures_grey = true});
    for (const auto& t : mesh.triangles)
      for (auto v : t)
        if (v >= mesh.positions.size()) __builtin_trap();
    if (!mesh.corner_uvs.empty() && mesh.corner_uvs.size() != 3 * mesh.triangles.size()) __builtin_trap();
    if (!mesh.corner_normals.empty() && mesh.corner_normals.size() != 3 * mesh.triangles.size()) __builtin_trap();
    if (!mesh.corner_tangents.empty() && mesh.corner_tangents.size() != 3 * mesh.triangles.size()) __builtin_trap();
    if (!mesh.triangle_materials.empty() && mesh.triangle_materials.size() != mesh.triangles.size()) __builtin_trap();
    for (auto m : mesh.triangle_materials)
      if (m >= mesh.materials.size()) __builtin_trap();
    // Material parameters stay in their ranges whatever the file says.
    for (const auto& m : mesh.materials) {
      if (m.metallic_roughness && !(m.metallic_roughness->metallic >= 0.0f && m.metallic_roughness->metallic <= 1.0f &&
                                    m.metallic_roughness->roughness >= 0.0f && m.metallic_roughness->roughness <= 1.0f))
        __builtin_trap();
      if (!(m.emissive.minCoeff() >= 0.0f) || !(m.alpha >= 0.0f && m.alpha <= 1.0f) || !(m.alpha_cutoff >= 0.0f)) __builtin_trap();
    }
  } catch (const meshtour::Error&) {
  }
  return 0;
}
