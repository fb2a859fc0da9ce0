// Fuzz target: the texture checks of mesh/textures.cpp (verify_texture: the header's bomb,
// size, channel and KTX2 checks, the PNG structure walk with its zlib inflate, the JPEG end
// marker, and every pixel decoded once through OpenImageIO) on an embedded texture holding the
// input. The first byte picks the name the image has (.png, .jpg, .exr, .tif), as a glTF's
// embedded image or an OBJ's map_Kd would. Anything wrong must end in meshtour::IoError.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/error.h"
#include "mesh/textures.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const char* const names[] = {"texture.png", "texture.jpg", "texture.exr", "texture.tif"};
  meshtour::MeshMaterial material;
  material.name = "fuzz";
  material.texture.file = names[data[0] % 4];
  material.texture.bytes = std::make_shared<const std::vector<unsigned char>>(data + 1, data + size);
  try {
    meshtour::verify_texture(material.texture, material.name);
  } catch (const meshtour::IoError&) {
  }
  return 0;
}
