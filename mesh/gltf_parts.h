#pragma once
// The parts of the glTF reader that its files share (private to mesh/gltf*.cpp): the file and
// JSON side reads the model (gltf_container.cpp: GLB container, JSON pre-pass, read_model,
// gltf_summary), the extensions' decoders fill buffers and primitives (gltf_decoders.cpp: Draco,
// meshoptimizer), the materials are read from the model (gltf_materials.cpp), and gltf.cpp walks
// the scene and assembles the mesh. Split by concern so that each file includes only the heavy
// headers it needs (nlohmann::json, libdraco, Eigen's geometry module).
#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "mesh/mesh.h"
#include "mesh/tinygltf_config.h"

namespace meshtour::gltf_detail {

// EXT_meshopt_compression (gltfpack, glTF-Transform): a buffer view's bytes are stored
// compressed in another buffer, and the view's own buffer is a "fallback" that has no data when
// the extension is required. One compressed view, read from the JSON before the reader sees it.
struct MeshoptView {
  std::size_t view = 0;          // the buffer view it fills
  std::size_t source = 0;        // the buffer holding the compressed bytes
  std::size_t offset = 0, length = 0;
  std::size_t stride = 0, count = 0;
  std::string mode, filter;      // ATTRIBUTES | TRIANGLES | INDICES; NONE | OCTAHEDRAL | QUATERNION | EXPONENTIAL
};

// What the JSON needs before tinygltf 2.7 reads it, and what must be done after.
struct Prepared {
  std::string json;                                         // the text to hand to the reader
  std::vector<std::pair<std::size_t, std::size_t>> fallbacks;  // (buffer, byteLength) standing in for decoded data
  std::vector<MeshoptView> meshopt;
};

// The default scene's node graph, depth first (one walk for the loader's instances and the
// check's counts): `visit(node, parent)` gets each node with its parent's value and returns the
// node's own (the loader's: its world matrix). The roots are the default scene's nodes, else (no
// scenes) every node that is no node's child. A node that is its own ancestor is refused.
template <class Value, class Children, class Visit>
void walk_default_scene(int node_count, const std::vector<int>* scene_roots, const Children& children, const Value& root,
                        const Visit& visit, const std::string& name) {
  std::vector<int> path;
  const auto walk = [&](auto&& self, int index, const Value& parent) -> void {
    if (index < 0 || index >= node_count) throw InputError(name + ": a scene or node names node " + std::to_string(index) + ", which does not exist");
    if (std::find(path.begin(), path.end(), index) != path.end() || path.size() > 256)
      throw InputError(name + ": node " + std::to_string(index) + " is its own ancestor (the node hierarchy has a cycle)");
    const Value value = visit(index, parent);
    path.push_back(index);
    for (const int child : children(index)) self(self, child, value);
    path.pop_back();
  };
  if (scene_roots) {
    for (const int r : *scene_roots) walk(walk, r, root);
    return;
  }
  std::vector<bool> child(static_cast<std::size_t>(node_count), false);
  for (int i = 0; i < node_count; ++i)
    for (const int c : children(i))
      if (c >= 0 && c < node_count) child[static_cast<std::size_t>(c)] = true;
  for (int i = 0; i < node_count; ++i)
    if (!child[static_cast<std::size_t>(i)]) walk(walk, i, root);
}

// One primitive's data before it joins the mesh.
struct PrimitiveData {
  std::vector<std::array<double, 4>> positions, colors, uvs;
  std::vector<std::array<double, 4>> normals, tangents;  // NORMAL, TANGENT (xyz, w), or empty
  std::vector<std::uint32_t> indices;  // as the primitive lists them (mode applies), or empty
  // A skinned primitive's JOINTS_n and WEIGHTS_n, one pair per set n.
  std::vector<std::pair<std::vector<std::array<double, 4>>, std::vector<std::array<double, 4>>>> skin_sets;
};

// A glTF material as meshtour uses it, with the texture coordinate set and UV transform its
// maps read (the base colour's, which the normal texture shares).
struct MaterialUse {
  MeshMaterial material;
  int uv_set = -1;  // -1: untextured
  Eigen::Matrix<double, 2, 3> uv_transform = Eigen::Matrix<double, 2, 3>::Identity();
};

// gltf_container.cpp
/// The model of a .gltf or .glb file, read by tinygltf after the JSON pre-pass, its
/// EXT_meshopt_compression views decoded. \throw InputError naming the file and what is wrong.
tinygltf::Model read_model(const std::filesystem::path& file, const std::string& name);

// gltf_decoders.cpp
void decode_meshopt(tinygltf::Model& model, const Prepared& prepared, const std::string& name);
PrimitiveData decode_draco(const tinygltf::Model& model, const tinygltf::Value& ext, int uv_set, bool want_colors, bool want_skin,
                           const std::string& where);

// gltf_materials.cpp
std::string percent_decoded(const std::string& uri);
/// Its base colour and normal texture, with the one coordinate set and UV transform the triangles
/// get; a normal texture on other coordinates is not used, and `warnings` says so.
MaterialUse material_use(const tinygltf::Model& model, int index, const std::filesystem::path& file, const std::string& name,
                         std::vector<std::string>& warnings);

}  // namespace meshtour::gltf_detail
