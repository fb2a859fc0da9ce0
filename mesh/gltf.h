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
/// accessors' counts without decoding Draco data. \throw InputError for a file tinygltf refuses.
MeshFileSummary gltf_summary(const std::filesystem::path& file);

}  // namespace meshtour::gltf_detail
