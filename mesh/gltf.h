#pragma once
// glTF 2.0 / GLB input (private to mesh/; load_mesh() and check_mesh_file() dispatch here).
#include <filesystem>
#include <string>
#include <vector>

#include "mesh/mesh.h"

namespace meshtour::gltf_detail {

/// Every triangle primitive of the default scene, with node transforms, materials (base colour
/// factor and texture, sampler wrap, texture coordinate set, KHR_texture_transform), COLOR_0 and
/// Draco-compressed primitives (KHR_draco_mesh_compression). Warnings (skipped points and lines)
/// go to `warnings`. \throw InputError naming the file and what is wrong with it.
TriangleMesh load_gltf(const std::filesystem::path& file, std::vector<std::string>& warnings);

/// Counts as check_mesh_file() reports them (vertices and triangles of every instance), from the
/// JSON alone: the accessors' counts, nothing decoded, no buffer read (only the GLB's chunks and
/// the buffer files' sizes checked against what the JSON says they hold).
/// \throw InputError for a truncated file or buffer, a missing buffer file, invalid JSON, an
/// unsupported required extension, or a reference to nothing.
MeshFileSummary gltf_summary(const std::filesystem::path& file);

}  // namespace meshtour::gltf_detail
