#include "mesh/textures.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include "core/error.h"

namespace meshtour {

TextureSize probe_texture(const MeshMaterial& material) {
  const std::string file = material.texture_file.string();
  const std::string what = file + ": the texture of material '" + material.name + "'";
  std::unique_ptr<OIIO::ImageInput> in;
  if (material.texture_bytes) {
    OIIO::Filesystem::IOMemReader memory(material.texture_bytes->data(), material.texture_bytes->size());
    in = OIIO::ImageInput::open(file, nullptr, &memory);
    if (!in) throw IoError(what + " (embedded) is not a readable image: " + OIIO::geterror());
    TextureSize size{in->spec().width, in->spec().height, in->spec().nchannels};
    in->close();
    return size;
  }
  std::error_code ec;
  if (!std::filesystem::is_regular_file(material.texture_file, ec)) throw IoError(what + " does not exist");
  in = OIIO::ImageInput::open(file);
  if (!in) throw IoError(what + " is not a readable image: " + OIIO::geterror());
  TextureSize size{in->spec().width, in->spec().height, in->spec().nchannels};
  in->close();
  if (size.width <= 0 || size.height <= 0) throw IoError(what + " has no pixels");
  return size;
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
    if (!used[m] || !material.has_texture() || !options.check_textures) continue;
    try {
      probe_texture(material);
    } catch (const IoError& e) {
      if (!options.missing_textures_grey)
        throw IoError(name + ": " + e.what() + " (fix the path, or pass --missing-textures grey to render its faces untextured)");
      warnings.push_back(std::string(e.what()) + "; its faces are rendered untextured (--missing-textures grey)");
      material.texture_file.clear();
      material.texture_bytes.reset();
    }
  }
}

}  // namespace meshtour
