#include "mesh/gltf.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <tuple>

#include "core/error.h"
#include "mesh/gltf_parts.h"
#include "mesh/vertex_weld.h"

// The scene walk (nodes, instances, skins), the accessors, and the mesh assembled from the
// primitives; the file, the decoders and the materials are in gltf_container.cpp,
// gltf_decoders.cpp and gltf_materials.cpp (mesh/gltf_parts.h).
namespace meshtour::gltf_detail {
namespace {

using Matrix = Eigen::Matrix4d;

Matrix node_matrix(const tinygltf::Node& node) {
  Matrix m = Matrix::Identity();
  if (node.matrix.size() == 16) {
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) m(r, c) = node.matrix[static_cast<std::size_t>(4 * c + r)];  // column-major
    return m;
  }
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  if (node.translation.size() == 3) t.translate(Eigen::Vector3d(node.translation[0], node.translation[1], node.translation[2]));
  if (node.rotation.size() == 4) {
    Eigen::Quaterniond q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);  // glTF: x, y, z, w
    if (q.norm() > 0) t.rotate(q.normalized());
  }
  if (node.scale.size() == 3) t.scale(Eigen::Vector3d(node.scale[0], node.scale[1], node.scale[2]));
  return t.matrix();
}

std::vector<Matrix> gpu_instances(const tinygltf::Model& model, const tinygltf::Value& ext, const std::string& where);

// A mesh instance of the default scene: the mesh, its node's world matrix, and the node's skin
// (-1: none).
struct Instance {
  int mesh = -1;
  Matrix world;
  int skin = -1;
};

std::vector<Instance> instances(const tinygltf::Model& model, const std::string& name) {
  std::vector<Instance> out;
  if (model.nodes.empty() && model.scenes.empty()) {  // no nodes: every mesh once, as it is
    for (int m = 0; m < static_cast<int>(model.meshes.size()); ++m) out.push_back({m, Matrix::Identity(), -1});
    return out;
  }
  const std::vector<int>* roots = nullptr;
  if (!model.scenes.empty()) {
    const int scene = model.defaultScene >= 0 && model.defaultScene < static_cast<int>(model.scenes.size()) ? model.defaultScene : 0;
    roots = &model.scenes[static_cast<std::size_t>(scene)].nodes;
  }
  const auto children = [&](int i) -> const std::vector<int>& { return model.nodes[static_cast<std::size_t>(i)].children; };
  walk_default_scene(static_cast<int>(model.nodes.size()), roots, children, Matrix(Matrix::Identity()), [&](int index, const Matrix& parent) {
    const tinygltf::Node& node = model.nodes[static_cast<std::size_t>(index)];
    const Matrix world = parent * node_matrix(node);
    if (node.mesh >= 0) {
      if (node.mesh >= static_cast<int>(model.meshes.size()))
        throw InputError(name + ": node " + std::to_string(index) + " names mesh " + std::to_string(node.mesh) + ", which does not exist");
      if (const auto it = node.extensions.find("EXT_mesh_gpu_instancing"); it != node.extensions.end() && it->second.IsObject())
        for (const Matrix& instance : gpu_instances(model, it->second, name + ": node " + std::to_string(index) + "'s EXT_mesh_gpu_instancing"))
          out.push_back({node.mesh, world * instance, node.skin});
      else
        out.push_back({node.mesh, world, node.skin});
    }
    return world;
  }, name);
  return out;
}

// Reads an accessor into up to 4 doubles per element, normalised integers scaled to [0,1] or
// [-1,1], after checking that every byte it names lies inside its buffer.
class AccessorReader {
public:
  AccessorReader(const tinygltf::Model& model, const std::string& name) : model_(model), name_(name) {}

  const tinygltf::Accessor& accessor(int index, const std::string& what) const {
    if (index < 0 || index >= static_cast<int>(model_.accessors.size()))
      throw InputError(name_ + ": " + what + " names accessor " + std::to_string(index) + ", which does not exist");
    return model_.accessors[static_cast<std::size_t>(index)];
  }

  std::vector<std::array<double, 4>> read(int index, const std::string& what) const { return read_elements<4>(index, what); }

  /// Elements of up to N components (16: a skin's MAT4 inverse bind matrices, column-major).
  template <std::size_t N>
  std::vector<std::array<double, N>> read_elements(int index, const std::string& what) const {
    std::vector<std::array<double, N>> out;
    each_element<N>(
        index, what, [&](std::size_t count) { out.resize(count); },
        [&](std::size_t i, const std::array<double, N>& v) { out[i] = v; });
    return out;
  }

  /// A triangle list's or strip's indices: unsigned bytes, shorts or ints, read straight into
  /// vertex numbers (a 17.8M-face model has 53M of them).
  std::vector<std::uint32_t> read_indices(int index, const std::string& what) const {
    // Only unsigned integers are indices (a float one would not convert to a vertex number).
    const int type = accessor(index, what).componentType;
    if (type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT && type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
      throw InputError(name_ + ": " + what + " (accessor " + std::to_string(index) + ") have component type " + std::to_string(type) +
                       "; glTF indices are unsigned bytes, shorts or ints (5121, 5123, 5125)");
    std::vector<std::uint32_t> out;
    each_element<1>(
        index, what, [&](std::size_t count) { out.resize(count); },
        [&](std::size_t i, const std::array<double, 1>& v) { out[i] = static_cast<std::uint32_t>(v[0]); });
    return out;
  }

private:
  // Checks that every byte the accessor names lies inside its buffer, then calls start(count)
  // and f(i, element) for each element, its components as doubles.
  template <std::size_t N, class Start, class F>
  void each_element(int index, const std::string& what, Start&& start, F&& f) const {
    const tinygltf::Accessor& a = accessor(index, what);
    const std::string where = name_ + ": " + what + " (accessor " + std::to_string(index) + ")";
    if (a.sparse.isSparse) throw InputError(where + " is sparse, which meshtour does not read");
    const int components = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type));
    const int size = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType));
    if (components <= 0 || components > static_cast<int>(N) || size <= 0) throw InputError(where + " has a type meshtour does not read");
    if (a.bufferView < 0) {  // no data: all zeros (the specification's default)
      if (a.count > 100'000'000) throw InputError(where + " announces " + std::to_string(a.count) + " elements");
      start(a.count);
      for (std::size_t i = 0; i < a.count; ++i) f(i, std::array<double, N>{});
      return;
    }
    if (a.bufferView >= static_cast<int>(model_.bufferViews.size())) throw InputError(where + " names a buffer view that does not exist");
    const tinygltf::BufferView& view = model_.bufferViews[static_cast<std::size_t>(a.bufferView)];
    if (view.buffer < 0 || view.buffer >= static_cast<int>(model_.buffers.size())) throw InputError(where + " names a buffer that does not exist");
    const std::vector<unsigned char>& buffer = model_.buffers[static_cast<std::size_t>(view.buffer)].data;
    const std::size_t element = static_cast<std::size_t>(components) * static_cast<std::size_t>(size);
    const std::size_t stride = view.byteStride ? view.byteStride : element;
    if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
      throw InputError(where + ": its buffer view reaches past the end of its buffer (a truncated file?)");
    if (a.count > 0) {
      const std::size_t span_elements = a.count - 1;
      if (a.byteOffset > view.byteLength || stride < element ||
          span_elements > (view.byteLength - a.byteOffset) / stride ||
          span_elements * stride + element > view.byteLength - a.byteOffset)
        throw InputError(where + ": its " + std::to_string(a.count) + " elements reach past the end of its buffer view");
    }
    const unsigned char* base = buffer.data() + view.byteOffset + a.byteOffset;
    start(a.count);
    for (std::size_t i = 0; i < a.count; ++i) {
      const unsigned char* p = base + i * stride;
      std::array<double, N> v{};
      for (int c = 0; c < components; ++c) v[static_cast<std::size_t>(c)] = component(p + c * size, a.componentType, a.normalized);
      f(i, v);
    }
  }

  static double component(const unsigned char* p, int type, bool normalized) {
    const auto load = [p](auto value) {
      std::memcpy(&value, p, sizeof value);
      return value;
    };
    switch (type) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT: return load(float{});
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return load(std::uint8_t{}) / (normalized ? 255.0 : 1.0);
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return load(std::uint16_t{}) / (normalized ? 65535.0 : 1.0);
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return load(std::uint32_t{}) / (normalized ? 4294967295.0 : 1.0);
      case TINYGLTF_COMPONENT_TYPE_BYTE: return normalized ? std::max(load(std::int8_t{}) / 127.0, -1.0) : load(std::int8_t{});
      case TINYGLTF_COMPONENT_TYPE_SHORT: return normalized ? std::max(load(std::int16_t{}) / 32767.0, -1.0) : load(std::int16_t{});
      default: return 0.0;
    }
  }
  const tinygltf::Model& model_;
  const std::string& name_;
};

// EXT_mesh_gpu_instancing (scenes of repeated parts, vegetation, chess pieces): the node's mesh
// drawn once per instance, each with its TRANSLATION, ROTATION (unit quaternion x, y, z, w) and
// SCALE (each optional), applied under the node's own transform.
std::vector<Matrix> gpu_instances(const tinygltf::Model& model, const tinygltf::Value& ext, const std::string& where) {
  const AccessorReader reader(model, where);
  if (!ext.Has("attributes") || !ext.Get("attributes").IsObject()) throw InputError(where + " has no attributes");
  const tinygltf::Value& attributes = ext.Get("attributes");
  // A few bytes of accessor can announce millions of copies of a big mesh: beyond this many the
  // file is refused before anything is read (the memory budget of tour and render then counts
  // every instance's triangles, from the same instances()).
  constexpr std::size_t kMaxInstances = 1'000'000;
  std::optional<std::size_t> count;
  const auto read = [&](const char* key) {
    std::vector<std::array<double, 4>> values;
    if (!attributes.Has(key) || !attributes.Get(key).IsNumber()) return values;
    const int index = attributes.Get(key).GetNumberAsInt();
    const std::size_t n = reader.accessor(index, key).count;
    if (n > kMaxInstances)
      throw InputError(where + " announces " + std::to_string(n) + " instances; meshtour draws at most " + std::to_string(kMaxInstances));
    if (count && *count != n) throw InputError(where + ": its attributes differ in count");
    count = n;
    values = reader.read(index, key);
    return values;
  };
  const auto translation = read("TRANSLATION"), rotation = read("ROTATION"), scale = read("SCALE");
  if (!count) throw InputError(where + " has none of TRANSLATION, ROTATION and SCALE");
  std::vector<Matrix> out;
  for (std::size_t i = 0; i < *count; ++i) {
    Eigen::Affine3d t = Eigen::Affine3d::Identity();
    if (!translation.empty()) t.translate(Eigen::Vector3d(translation[i][0], translation[i][1], translation[i][2]));
    if (!rotation.empty()) {
      const Eigen::Quaterniond q(rotation[i][3], rotation[i][0], rotation[i][1], rotation[i][2]);
      if (q.norm() > 0) t.rotate(q.normalized());
    }
    if (!scale.empty()) t.scale(Eigen::Vector3d(scale[i][0], scale[i][1], scale[i][2]));
    out.push_back(t.matrix());
  }
  return out;
}

// Skinning (glTF 2.0, "Skins"): a skinned mesh's vertices are placed by its joints, each vertex
// by up to four joints per JOINTS_n/WEIGHTS_n set, with the matrix global(joint) x
// inverseBind(joint); the transform of the node holding the mesh is not applied. Rigged exports
// (Blender, Sketchfab characters) keep their bind pose in the mesh and put a scale or a rotation
// on the armature, or pose the joints: without skinning the model comes out at the wrong size,
// turned or unposed, and parts attached to bones (eyes, props) miss the body. The skin's joint
// matrices, in the skin's joint order.
std::vector<Matrix> joint_matrices(const tinygltf::Model& model, const AccessorReader& reader, int skin_index, const std::string& name) {
  const std::string where = name + ": skin " + std::to_string(skin_index);
  if (skin_index < 0 || skin_index >= static_cast<int>(model.skins.size()))
    throw InputError(name + ": a node names skin " + std::to_string(skin_index) + ", which does not exist");
  const tinygltf::Skin& skin = model.skins[static_cast<std::size_t>(skin_index)];
  if (skin.joints.empty()) throw InputError(where + " has no joints");
  const auto nodes = static_cast<int>(model.nodes.size());
  std::vector<int> parent(model.nodes.size(), -1);
  for (int i = 0; i < nodes; ++i)
    for (const int c : model.nodes[static_cast<std::size_t>(i)].children)
      if (c >= 0 && c < nodes) parent[static_cast<std::size_t>(c)] = i;
  const auto global = [&](int node) {
    Matrix m = Matrix::Identity();
    int depth = 0;
    for (int n = node; n >= 0; n = parent[static_cast<std::size_t>(n)]) {
      if (++depth > 256) throw InputError(where + ": joint " + std::to_string(node) + "'s ancestors form a cycle");
      m = node_matrix(model.nodes[static_cast<std::size_t>(n)]) * m;
    }
    return m;
  };
  std::vector<std::array<double, 16>> inverse_bind;
  if (skin.inverseBindMatrices >= 0) {
    const std::string what = "the inverse bind matrices of skin " + std::to_string(skin_index);
    const tinygltf::Accessor& a = reader.accessor(skin.inverseBindMatrices, what);
    if (a.type != TINYGLTF_TYPE_MAT4 || a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
      throw InputError(name + ": " + what + " are not float 4x4 matrices (MAT4, 5126)");
    inverse_bind = reader.read_elements<16>(skin.inverseBindMatrices, what);
    if (inverse_bind.size() < skin.joints.size())
      throw InputError(name + ": " + what + " are " + std::to_string(inverse_bind.size()) + ", fewer than its " +
                       std::to_string(skin.joints.size()) + " joints");
  }
  std::vector<Matrix> out;
  for (std::size_t k = 0; k < skin.joints.size(); ++k) {
    const int joint = skin.joints[k];
    if (joint < 0 || joint >= nodes) throw InputError(where + " names node " + std::to_string(joint) + " as a joint, which does not exist");
    Matrix inverse = Matrix::Identity();
    if (!inverse_bind.empty())
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) inverse(r, c) = inverse_bind[k][static_cast<std::size_t>(4 * c + r)];  // column-major
    out.push_back(global(joint) * inverse);
  }
  return out;
}

// Each vertex's blend of its skin's joint matrices (weights normalised to sum to 1), from every
// JOINTS_n/WEIGHTS_n set of the primitive.
std::vector<Matrix> skinning_matrices(const PrimitiveData& data, const std::vector<Matrix>& joints, const std::string& where) {
  const std::size_t count = data.positions.size();
  if (data.skin_sets.empty()) throw InputError(where + " belongs to a skinned node but has no JOINTS_0 and WEIGHTS_0");
  std::vector<Matrix> blend(count, Matrix::Zero());
  std::vector<double> total(count, 0.0);
  for (std::size_t set = 0; set < data.skin_sets.size(); ++set) {
    const auto& [joint, weight] = data.skin_sets[set];
    if (joint.size() != count || weight.size() != count)
      throw InputError(where + ": JOINTS_" + std::to_string(set) + ", WEIGHTS_" + std::to_string(set) + " and POSITION differ in count");
    for (std::size_t i = 0; i < count; ++i)
      for (std::size_t c = 0; c < 4; ++c) {
        const double wc = weight[i][c];
        if (wc == 0.0) continue;
        if (!(wc > 0.0 && wc <= 1.0)) throw InputError(where + ": vertex " + std::to_string(i) + " has a joint weight outside [0, 1]");
        if (!(joint[i][c] >= 0.0 && joint[i][c] < static_cast<double>(joints.size())))
          throw InputError(where + ": vertex " + std::to_string(i) + " names joint " + std::to_string(static_cast<long long>(joint[i][c])) +
                           ", but its skin has " + std::to_string(joints.size()));
        blend[i] += wc * joints[static_cast<std::size_t>(joint[i][c])];
        total[i] += wc;
      }
  }
  for (std::size_t i = 0; i < count; ++i) {
    if (!(total[i] > 0.0)) throw InputError(where + ": vertex " + std::to_string(i) + " has no joint weight (a skinned vertex needs one)");
    blend[i] /= total[i];
  }
  return blend;
}

// The triangles of a primitive's index list (or 0..n-1) in its mode: list, strip or fan.
// Room for `more` items, growing geometrically (many small primitives must not reallocate each time;
// one big scan reserves once, exactly).
template <class T>
void grow_for(std::vector<T>& items, std::size_t more) {
  if (items.size() + more > items.capacity()) items.reserve(std::max(items.size() + more, 2 * items.capacity()));
}

std::vector<std::array<std::uint32_t, 3>> triangles_of(const std::vector<std::uint32_t>& indices, std::size_t vertex_count, int mode) {
  // Without indices the vertices are drawn in order.
  const std::size_t n = indices.empty() ? vertex_count : indices.size();
  const auto at = [&](std::size_t i) { return indices.empty() ? static_cast<std::uint32_t>(i) : indices[i]; };
  std::vector<std::array<std::uint32_t, 3>> out;
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    out.reserve(n / 3);
    for (std::size_t i = 0; i + 2 < n; i += 3) out.push_back({at(i), at(i + 1), at(i + 2)});
  } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    out.reserve(n);
    for (std::size_t i = 0; i + 2 < n; ++i)
      out.push_back(i % 2 == 0 ? std::array<std::uint32_t, 3>{at(i), at(i + 1), at(i + 2)}
                               : std::array<std::uint32_t, 3>{at(i + 1), at(i), at(i + 2)});
  } else if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
    out.reserve(n);
    for (std::size_t i = 1; i + 1 < n; ++i) out.push_back({at(i), at(i + 1), at(0)});
  }
  return out;
}

float linear_to_srgb(double c) {
  c = std::clamp(c, 0.0, 1.0);
  return static_cast<float>(c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055);
}

// glTF splits a vertex wherever its texture coordinates or material change (every UV seam of a
// scan's atlas); OBJ shares the position. The tracer's smooth normals come from shared vertices,
// so vertices with bit-identical positions (and colours) are merged (mesh/vertex_weld.h), and the
// model shades as its OBJ form does. Texture coordinates are per triangle corner and stay as they
// are.
void weld_identical_vertices(TriangleMesh& mesh) {
  const std::size_t n = mesh.positions.size();
  const bool coloured = !mesh.colors.empty();
  weld_detail::VertexWelder<9> welder(n);  // a position's 3 doubles and a colour's 3 floats
  std::vector<std::uint32_t> remap(n);
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector3f> colors;
  for (std::size_t i = 0; i < n; ++i) {
    weld_detail::VertexWelder<9>::Key key{};
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint64_t bits = weld_detail::key_bits(mesh.positions[i][static_cast<Eigen::Index>(k)]);
      key[2 * k] = static_cast<std::uint32_t>(bits);
      key[2 * k + 1] = static_cast<std::uint32_t>(bits >> 32);
      if (coloured) key[6 + k] = weld_detail::key_bits(mesh.colors[i][static_cast<Eigen::Index>(k)]);
    }
    remap[i] = welder.vertex(key);
    if (remap[i] == positions.size()) {  // first seen: numbered in the order of first appearance
      positions.push_back(mesh.positions[i]);
      if (coloured) colors.push_back(mesh.colors[i]);
    }
  }
  for (auto& t : mesh.triangles)
    for (auto& v : t) v = remap[v];
  mesh.positions = std::move(positions);
  mesh.colors = std::move(colors);
}

}  // namespace

TriangleMesh load_gltf(const std::filesystem::path& file, std::vector<std::string>& warnings) {
  const std::string name = file.string();
  const tinygltf::Model model = read_model(file, name);
  const AccessorReader reader(model, name);

  TriangleMesh mesh;
  std::vector<std::optional<MaterialUse>> uses(model.materials.size());
  std::optional<std::uint32_t> default_material;  // for primitives without one: the look's colour
  std::vector<std::uint32_t> material_index(model.materials.size(), std::numeric_limits<std::uint32_t>::max());
  bool any_colors = false, any_uvs = false, any_normals = false, any_tangents = false;
  std::vector<bool> vertex_has_color;
  std::size_t skipped = 0;

  // A primitive's attributes read (and Draco-decoded) once, checked: the same for every instance
  // that draws it.
  const auto decode = [&](const tinygltf::Primitive& prim, int uv_set, bool skinned, const std::string& where) {
    PrimitiveData data;
    if (const auto draco = prim.extensions.find("KHR_draco_mesh_compression"); draco != prim.extensions.end()) {
      data = decode_draco(model, draco->second, uv_set, true, skinned, where);
    } else {
      const auto attribute = [&](const std::string& key) { return prim.attributes.find(key); };
      const auto position = attribute("POSITION");
      if (position == prim.attributes.end()) throw InputError(where + " has no POSITION attribute");
      data.positions = reader.read(position->second, "POSITION of " + where.substr(name.size() + 2));
      if (const auto c = attribute("COLOR_0"); c != prim.attributes.end())
        data.colors = reader.read(c->second, "COLOR_0 of " + where.substr(name.size() + 2));
      if (uv_set >= 0)
        if (const auto t = attribute("TEXCOORD_" + std::to_string(uv_set)); t != prim.attributes.end())
          data.uvs = reader.read(t->second, "TEXCOORD_" + std::to_string(uv_set) + " of " + where.substr(name.size() + 2));
      if (const auto n = attribute("NORMAL"); n != prim.attributes.end())
        data.normals = reader.read(n->second, "NORMAL of " + where.substr(name.size() + 2));
      if (const auto t = attribute("TANGENT"); t != prim.attributes.end())
        data.tangents = reader.read(t->second, "TANGENT of " + where.substr(name.size() + 2));
      if (prim.indices >= 0) data.indices = reader.read_indices(prim.indices, "the indices of " + where.substr(name.size() + 2));
      for (int set = 0; skinned; ++set) {
        const auto j = attribute("JOINTS_" + std::to_string(set)), w = attribute("WEIGHTS_" + std::to_string(set));
        if (j == prim.attributes.end() || w == prim.attributes.end()) break;
        const std::string what = "JOINTS_" + std::to_string(set) + " of " + where.substr(name.size() + 2);
        const int type = reader.accessor(j->second, what).componentType;
        if (type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT)
          throw InputError(name + ": " + what + " are not unsigned bytes or shorts (5121, 5123)");
        data.skin_sets.emplace_back(reader.read(j->second, what),
                                    reader.read(w->second, "WEIGHTS_" + std::to_string(set) + " of " + where.substr(name.size() + 2)));
      }
    }
    const std::size_t count = data.positions.size();
    if (!data.colors.empty() && data.colors.size() != count) throw InputError(where + ": COLOR_0 and POSITION differ in count");
    if (!data.uvs.empty() && data.uvs.size() != count) throw InputError(where + ": TEXCOORD and POSITION differ in count");
    if (!data.normals.empty() && data.normals.size() != count) throw InputError(where + ": NORMAL and POSITION differ in count");
    if (!data.tangents.empty() && data.tangents.size() != count) throw InputError(where + ": TANGENT and POSITION differ in count");
    // Tangents without normals mean nothing (the specification: "When tangents are not specified,
    // client implementations SHOULD calculate tangents"; they are relative to NORMAL).
    if (data.normals.empty()) data.tangents.clear();
    for (const auto i : data.indices)
      if (i >= count) throw InputError(where + ": an index (" + std::to_string(i) + ") names a vertex it does not have (" +
                                       std::to_string(count) + ")");
    return data;
  };
  // A mesh drawn by several instances (nodes sharing it, EXT_mesh_gpu_instancing) is decoded at
  // its first instance and kept until its last: decoded per instance, 64 copies of the bunny as one
  // Draco mesh took 1.00 s to load, now 0.58 s (bench/load_bench BM_LoadInstancedDracoGlb/64; the
  // rest is copying and welding). A mesh drawn once is not kept, so a big single scan holds its
  // decoded attributes only while it is copied into the model.
  const std::vector<Instance> drawn = instances(model, name);
  std::map<std::pair<int, bool>, std::size_t> draws_left;  // (mesh, skinned): instances still to come
  for (const Instance& instance : drawn) ++draws_left[{instance.mesh, instance.skin >= 0}];
  std::map<std::tuple<int, bool, std::size_t>, PrimitiveData> kept;  // (mesh, skinned, primitive)

  for (const auto& [mesh_index, world, skin] : drawn) {
    const tinygltf::Mesh& gm = model.meshes[static_cast<std::size_t>(mesh_index)];
    std::size_t& left = draws_left[{mesh_index, skin >= 0}];
    const bool drawn_again = --left > 0;
    const Eigen::Matrix3d linear = world.topLeftCorner<3, 3>();
    const bool mirrored = linear.determinant() < 0;
    const std::vector<Matrix> joints = skin >= 0 ? joint_matrices(model, reader, skin, name) : std::vector<Matrix>{};
    for (std::size_t p = 0; p < gm.primitives.size(); ++p) {
      const tinygltf::Primitive& prim = gm.primitives[p];
      const std::string where = name + ": mesh " + std::to_string(mesh_index) + " primitive " + std::to_string(p);
      if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != TINYGLTF_MODE_TRIANGLE_STRIP && prim.mode != TINYGLTF_MODE_TRIANGLE_FAN &&
          prim.mode != -1) {
        ++skipped;
        continue;
      }
      const int mode = prim.mode == -1 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
      // Material.
      std::uint32_t material = 0;
      int uv_set = -1;
      Eigen::Matrix<double, 2, 3> uv_transform = Eigen::Matrix<double, 2, 3>::Identity();
      if (prim.material >= static_cast<int>(model.materials.size()))
        throw InputError(where + " names material " + std::to_string(prim.material) + ", but the file has " +
                         std::to_string(model.materials.size()));
      if (prim.material >= 0) {
        auto& use = uses[static_cast<std::size_t>(prim.material)];
        if (!use) {
          use = material_use(model, prim.material, file, name, warnings);
          material_index[static_cast<std::size_t>(prim.material)] = static_cast<std::uint32_t>(mesh.materials.size());
          mesh.materials.push_back(use->material);
        }
        material = material_index[static_cast<std::size_t>(prim.material)];
        uv_set = use->uv_set;
        uv_transform = use->uv_transform;
      } else {
        if (!default_material) {
          default_material = static_cast<std::uint32_t>(mesh.materials.size());
          MeshMaterial none;
          none.name = "(no material)";
          mesh.materials.push_back(none);
        }
        material = *default_material;
      }
      // Geometry.
      const auto key = std::tuple{mesh_index, skin >= 0, p};
      auto it = kept.find(key);
      std::optional<PrimitiveData> once;
      if (it == kept.end()) {
        if (drawn_again) it = kept.emplace(key, decode(prim, uv_set, skin >= 0, where)).first;
        else once = decode(prim, uv_set, skin >= 0, where);
      }
      const PrimitiveData& data = once ? *once : it->second;
      const std::vector<Matrix> skinned = skin >= 0 ? skinning_matrices(data, joints, where) : std::vector<Matrix>{};
      const std::size_t count = data.positions.size();
      const auto base = static_cast<std::uint32_t>(mesh.positions.size());
      if (mesh.positions.size() + count > std::numeric_limits<std::uint32_t>::max()) throw InputError(name + ": too many vertices");
      std::vector<bool> vertex_mirrored;  // skinned: per vertex; else the node's `mirrored`
      grow_for(mesh.positions, count);
      for (std::size_t i = 0; i < count; ++i) {
        const auto& v = data.positions[i];
        const Matrix& m = skinned.empty() ? world : skinned[i];
        mesh.positions.push_back((m * Eigen::Vector4d(v[0], v[1], v[2], 1.0)).head<3>());
        if (!skinned.empty()) vertex_mirrored.push_back(m.topLeftCorner<3, 3>().determinant() < 0);
      }
      vertex_has_color.resize(mesh.positions.size(), false);
      if (!data.colors.empty()) {
        any_colors = true;
        mesh.colors.resize(mesh.positions.size(), Eigen::Vector3f::Ones());
        for (std::size_t i = 0; i < count; ++i) {
          mesh.colors[base + i] = {linear_to_srgb(data.colors[i][0]), linear_to_srgb(data.colors[i][1]), linear_to_srgb(data.colors[i][2])};
          vertex_has_color[base + i] = true;
        }
      }
      const std::vector<std::array<std::uint32_t, 3>> triangles = triangles_of(data.indices, count, mode);
      // The file's normals and tangents, in world space (normals by the inverse transpose, both
      // renormalised; a mirroring node turns the bitangent: w flips), per corner below.
      std::vector<Eigen::Vector3f> normals;
      std::vector<Eigen::Vector4f> tangents;
      if (!data.normals.empty()) {
        normals.reserve(count);
        for (std::size_t i = 0; i < count; ++i) {
          const Matrix& m = skinned.empty() ? world : skinned[i];
          const Eigen::Matrix3d normal_matrix = m.topLeftCorner<3, 3>().inverse().transpose();
          const auto& v = data.normals[i];
          const Eigen::Vector3d n = normal_matrix * Eigen::Vector3d(v[0], v[1], v[2]);
          normals.push_back(n.squaredNorm() > 0 && std::isfinite(n.squaredNorm()) ? Eigen::Vector3f(n.normalized().cast<float>())
                                                                                 : Eigen::Vector3f::Zero());
          if (data.tangents.empty()) continue;
          const auto& tv = data.tangents[i];
          const Eigen::Vector3d t = m.topLeftCorner<3, 3>() * Eigen::Vector3d(tv[0], tv[1], tv[2]);
          const float w = (tv[3] < 0 ? -1.0f : 1.0f) * (m.topLeftCorner<3, 3>().determinant() < 0 ? -1.0f : 1.0f);
          tangents.push_back(t.squaredNorm() > 0 && std::isfinite(t.squaredNorm())
                                 ? Eigen::Vector4f(static_cast<float>(t.normalized().x()), static_cast<float>(t.normalized().y()),
                                                   static_cast<float>(t.normalized().z()), w)
                                 : Eigen::Vector4f::Zero());
        }
      }
      if (!normals.empty() && !any_normals) {
        any_normals = true;
        mesh.corner_normals.resize(3 * mesh.triangles.size(), Eigen::Vector3f::Zero());
      }
      if (!tangents.empty() && !any_tangents) {
        any_tangents = true;
        mesh.corner_tangents.resize(3 * mesh.triangles.size(), Eigen::Vector4f::Zero());
      }
      if (any_normals) grow_for(mesh.corner_normals, 3 * triangles.size());
      if (any_tangents) grow_for(mesh.corner_tangents, 3 * triangles.size());
      // Corner coordinates are kept only once some primitive has them (zeros for those before and
      // after that have none): a scan without UVs does not hold 3 of them per triangle.
      if (!data.uvs.empty() && !any_uvs) {
        any_uvs = true;
        mesh.corner_uvs.resize(3 * mesh.triangles.size(), Eigen::Vector2f::Zero());
      }
      grow_for(mesh.triangles, triangles.size());
      grow_for(mesh.triangle_materials, triangles.size());
      if (any_uvs) grow_for(mesh.corner_uvs, 3 * triangles.size());
      for (auto t : triangles) {
        if (vertex_mirrored.empty() ? mirrored : vertex_mirrored[t[0]]) std::swap(t[1], t[2]);
        mesh.triangles.push_back({base + t[0], base + t[1], base + t[2]});
        mesh.triangle_materials.push_back(material);
        for (const auto corner : t) {
          if (any_normals) mesh.corner_normals.push_back(normals.empty() ? Eigen::Vector3f::Zero() : normals[corner]);
          if (any_tangents) mesh.corner_tangents.push_back(tangents.empty() ? Eigen::Vector4f::Zero() : tangents[corner]);
        }
        if (!any_uvs) continue;
        for (const auto corner : t) {
          Eigen::Vector2f uv = Eigen::Vector2f::Zero();
          if (!data.uvs.empty()) {
            const Eigen::Vector2d st = uv_transform * Eigen::Vector3d(data.uvs[corner][0], data.uvs[corner][1], 1.0);
            uv = {static_cast<float>(st.x()), static_cast<float>(1.0 - st.y())};  // glTF's v runs down the image
          }
          mesh.corner_uvs.push_back(uv);
        }
      }
      if (!drawn_again && it != kept.end()) kept.erase(it);  // its last instance: freed
    }
  }
  if (any_colors) mesh.colors.resize(mesh.positions.size(), Eigen::Vector3f::Ones());
  else mesh.colors.clear();
  weld_identical_vertices(mesh);
  if (!any_uvs) mesh.corner_uvs.clear();
  if (skipped) warnings.push_back(std::to_string(skipped) + " primitive(s) of points or lines skipped (only triangles are rendered)");
  if (std::find(model.extensionsUsed.begin(), model.extensionsUsed.end(), "KHR_lights_punctual") != model.extensionsUsed.end())
    warnings.push_back("the file's lights (KHR_lights_punctual) are not used: meshtour lights every model with its look (--preset)");
  if (mesh.triangles.empty()) throw InputError(name + ": the default scene has no triangles (no mesh, or only points and lines)");
  return mesh;
}

}  // namespace meshtour::gltf_detail
