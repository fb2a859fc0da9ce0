#pragma once
// Checks of the textures a model's materials name (private to mesh/; probe_texture is public in
// mesh/mesh.h). Every loader calls check_material_textures() once its materials are known.
#include <string>
#include <vector>

#include "mesh/mesh.h"

namespace meshtour {

/// Checks one texture fully (probe_texture's header checks, then the file's structure and every
/// pixel decoded once; see docs/FORMATS.md, "Hostile textures"): an IoError naming the file and
/// what is wrong with it.
void verify_texture(const MeshTexture& map, const std::string& material_name, const char* kind = "texture");

/// Whether the image of `map` is a tangent-space normal map rather than a height map: three or
/// more channels, blue the largest of the three in at least 90 % of the pixels, mean blue at least
/// 0.6 and not grey (a height map saved as RGB has R = G = B). Looks at up to 256 x 256 pixels
/// spread over the image. Call after verify_texture(). \throw IoError when the image cannot be read.
bool reads_as_normal_map(const MeshTexture& map, const std::string& material_name);

/// verify_texture(), and where it fails the --missing-textures policy: an IoError naming the model
/// `name` and how to go on, or with options.missing_textures_grey a warning that its faces are
/// rendered `without` it ("untextured", "without their normal map", ...) and false.
bool verify_or_warn(const MeshTexture& map, const std::string& material_name, const char* kind, const std::string& without,
                    const std::string& name, const LoadOptions& options, std::vector<std::string>& warnings);

/// Opens the texture of every material some triangle uses. A missing or unreadable one is an
/// IoError naming the texture, the material and the model `name`, or, with
/// options.missing_textures_grey, a warning appended to `warnings` and a material without texture.
/// Also refuses triangle material indices outside the material list (InputError).
void check_material_textures(TriangleMesh& mesh, const std::string& name, const LoadOptions& options,
                             std::vector<std::string>& warnings);

}  // namespace meshtour
