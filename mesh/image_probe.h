#pragma once
// The header checks every texture gets (mesh/textures.cpp), for any image file: an environment
// map is read with them too (OpenEXR allocates what a header announces before it reads a pixel).
#include <filesystem>
#include <string>

#include "mesh/mesh.h"

namespace meshtour {

/// Opens `file` and reads its header after the checks of probe_texture() (damaged PNG chunks,
/// OpenEXR attributes larger than the file, KTX2, a header claiming more pixels than the file can
/// hold, more than 65536 a side or 1 gigapixel, 1-4 channels). `what` begins each message, e.g.
/// "sky.hdr: the environment image". \throw IoError naming it and what is wrong.
TextureSize probe_image(const std::filesystem::path& file, const std::string& what);

}  // namespace meshtour
