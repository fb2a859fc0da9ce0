#include "mesh/gltf.h"

#include <draco/compression/decode.h>
#include <meshoptimizer.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string_view>
#include <tuple>

#include <nlohmann/json.hpp>

#include <fstream>
#include <iterator>

#include "core/error.h"
#include "mesh/file_extension.h"
#include "mesh/tinygltf_config.h"
#include "mesh/vertex_weld.h"

namespace meshtour::gltf_detail {
namespace {

using Matrix = Eigen::Matrix4d;

// Extensions meshtour reads. Any other one a file lists in extensionsRequired changes geometry or
// colour in a way meshtour would get wrong, so it is refused by name.
const std::set<std::string> kSupported = {"KHR_draco_mesh_compression", "EXT_meshopt_compression", "KHR_texture_transform",
                                          "KHR_mesh_quantization", "KHR_materials_unlit", "KHR_materials_pbrSpecularGlossiness",
                                          "EXT_texture_webp", "EXT_mesh_gpu_instancing", "KHR_lights_punctual"};

// Images keep their encoded bytes (OpenImageIO decodes them when the tracer needs them). An image
// in a buffer view is left for encoded_image_bytes(): tinygltf 2.7 hands over the view's range
// without checking that it lies inside its buffer.
bool keep_encoded_image(tinygltf::Image* image, const int, std::string*, std::string*, int, int, const unsigned char* bytes,
                        int size, void*) {
  if (image->bufferView < 0) image->image.assign(bytes, bytes + std::max(size, 0));
  image->as_is = true;
  return true;
}

// External buffers and images are read only from regular files: a URI that resolves to the
// model's folder (an empty or malformed one) would otherwise be "read" by tinygltf 2.7 with the
// size a directory reports for its end (2^63 - 1 on ext4), as found by fuzz_gltf.
bool regular_file_exists(const std::string& path, void*) {
  std::error_code error;
  return std::filesystem::is_regular_file(path, error);
}

bool read_regular_file(std::vector<unsigned char>* out, std::string* error, const std::string& path, void*) {
  std::error_code code;
  if (!std::filesystem::is_regular_file(path, code)) {
    if (error) *error += "'" + path + "' is not a file\n";
    return false;
  }
  const std::uintmax_t size = std::filesystem::file_size(path, code);
  std::ifstream in(path, std::ios::binary);
  if (code || !in) {
    if (error) *error += "cannot read '" + path + "'\n";
    return false;
  }
  out->resize(static_cast<std::size_t>(size));
  if (size > 0) in.read(reinterpret_cast<char*>(out->data()), static_cast<std::streamsize>(size));
  if (!in) {
    if (error) *error += "cannot read '" + path + "'\n";
    return false;
  }
  return true;
}

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

std::size_t count_of(const nlohmann::json& o, const char* key, const std::string& where, bool required = true) {
  if (!o.contains(key)) {
    if (required) throw InputError(where + " has no " + key);
    return 0;
  }
  const auto& v = o[key];
  if (!v.is_number_unsigned() && !(v.is_number_integer() && v.get<std::int64_t>() >= 0))
    throw InputError(where + ": " + key + " is not a non-negative whole number");
  return v.get<std::size_t>();
}

// tinygltf (2.7, built without Draco) refuses a Draco primitive's index accessor, which has no
// buffer view by design: such primitives' "indices" move into their extension object, where
// gltf_summary() finds the count; the triangles come from the Draco data. Nor does it read
// EXT_meshopt_compression: a fallback buffer (no data by design) gets a one-byte data URI so
// that the reader accepts it, and decode_meshopt() gives it its real length and fills it.
// `doc` is `json_text` parsed (discarded when it does not parse: the reader then says what is wrong).
Prepared prepare_json(nlohmann::json doc, const std::string& json_text, const std::string& name) {
  Prepared out{json_text, {}, {}};
  const bool draco = json_text.find("KHR_draco_mesh_compression") != std::string::npos;
  const bool meshopt = json_text.find("EXT_meshopt_compression") != std::string::npos;
  if (!draco && !meshopt) return out;
  if (doc.is_discarded() || !doc.is_object()) return out;
  if (draco && doc.contains("meshes") && doc["meshes"].is_array())
    for (auto& mesh : doc["meshes"]) {
      if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
      for (auto& prim : mesh["primitives"]) {
        if (!prim.is_object() || !prim.contains("indices") || !prim.contains("extensions") || !prim["extensions"].is_object()) continue;
        auto& ext = prim["extensions"];
        if (!ext.contains("KHR_draco_mesh_compression") || !ext["KHR_draco_mesh_compression"].is_object()) continue;
        ext["KHR_draco_mesh_compression"]["indices"] = prim["indices"];
        prim.erase("indices");
      }
    }
  if (meshopt && doc.contains("buffers") && doc["buffers"].is_array()) {
    auto& buffers = doc["buffers"];
    for (std::size_t b = 0; b < buffers.size(); ++b) {
      auto& buffer = buffers[b];
      if (!buffer.is_object() || buffer.contains("uri") || !buffer.contains("extensions") || !buffer["extensions"].is_object()) continue;
      const auto& ext = buffer["extensions"];
      if (!ext.contains("EXT_meshopt_compression") || !ext["EXT_meshopt_compression"].is_object()) continue;
      const std::string where = name + ": buffer " + std::to_string(b);
      out.fallbacks.emplace_back(b, count_of(buffer, "byteLength", where));
      buffer["byteLength"] = 1;
      buffer["uri"] = "data:application/octet-stream;base64,AA==";
    }
    if (doc.contains("bufferViews") && doc["bufferViews"].is_array())
      for (std::size_t v = 0; v < doc["bufferViews"].size(); ++v) {
        const auto& view = doc["bufferViews"][v];
        if (!view.is_object() || !view.contains("extensions") || !view["extensions"].is_object()) continue;
        const auto& ext = view["extensions"];
        if (!ext.contains("EXT_meshopt_compression")) continue;
        const std::string where = name + ": buffer view " + std::to_string(v) + "'s EXT_meshopt_compression";
        const auto& e = ext["EXT_meshopt_compression"];
        if (!e.is_object()) throw InputError(where + " is not an object");
        MeshoptView m;
        m.view = v;
        m.source = count_of(e, "buffer", where);
        m.offset = count_of(e, "byteOffset", where, false);
        m.length = count_of(e, "byteLength", where);
        m.stride = count_of(e, "byteStride", where);
        m.count = count_of(e, "count", where);
        if (!e.contains("mode") || !e["mode"].is_string()) throw InputError(where + " has no mode");
        m.mode = e["mode"].get<std::string>();
        m.filter = e.contains("filter") && e["filter"].is_string() ? e["filter"].get<std::string>() : "NONE";
        out.meshopt.push_back(std::move(m));
      }
  }
  out.json = doc.dump();
  return out;
}

// Decodes every EXT_meshopt_compression view into its buffer. Everything the decoder is given is
// checked first: libmeshoptimizer asserts on strides and counts it does not support, and a crash
// inside it could not be mended here (it is safe on corrupt compressed bytes, which it reports).
void decode_meshopt(tinygltf::Model& model, const Prepared& prepared, const std::string& name) {
  if (prepared.meshopt.empty() && prepared.fallbacks.empty()) return;
  // The decoded data cannot be much larger than its compressed bytes (the codecs' best case is
  // about 32 to 1): a fallback announcing more is corrupt, and is not allocated.
  std::size_t compressed = 0;
  for (const MeshoptView& m : prepared.meshopt) compressed += m.length;
  for (const auto& [buffer, length] : prepared.fallbacks) {
    if (buffer >= model.buffers.size()) continue;
    if (length / 64 > compressed + 4096)
      throw InputError(name + ": buffer " + std::to_string(buffer) + " announces " + std::to_string(length) +
                       " bytes of EXT_meshopt_compression data, far more than its " + std::to_string(compressed) +
                       " compressed bytes could hold (the file is corrupt)");
    model.buffers[buffer].data.assign(length, 0);
  }
  // A fallback buffer has no bytes of its own: a view into it that nothing decodes would read zeros.
  std::vector<bool> fallback(model.buffers.size(), false), decoded(model.bufferViews.size(), false);
  for (const auto& f : prepared.fallbacks)
    if (f.first < fallback.size()) fallback[f.first] = true;
  for (const MeshoptView& m : prepared.meshopt)
    if (m.view < decoded.size()) decoded[m.view] = true;
  for (std::size_t v = 0; v < model.bufferViews.size(); ++v) {
    const int buffer = model.bufferViews[v].buffer;
    if (buffer >= 0 && static_cast<std::size_t>(buffer) < fallback.size() && fallback[static_cast<std::size_t>(buffer)] && !decoded[v])
      throw InputError(name + ": buffer view " + std::to_string(v) + " lies in buffer " + std::to_string(buffer) +
                       ", an EXT_meshopt_compression fallback with no data of its own, but has no compressed data to "
                       "decode (the file is corrupt)");
  }
  for (const MeshoptView& m : prepared.meshopt) {
    const std::string where = name + ": buffer view " + std::to_string(m.view) + " (EXT_meshopt_compression)";
    if (m.view >= model.bufferViews.size()) continue;
    const tinygltf::BufferView& view = model.bufferViews[m.view];
    if (m.source >= model.buffers.size()) throw InputError(where + " names buffer " + std::to_string(m.source) + ", which does not exist");
    const std::vector<unsigned char>& source = model.buffers[m.source].data;
    if (m.offset > source.size() || m.length > source.size() - m.offset)
      throw InputError(where + ": its compressed bytes lie outside buffer " + std::to_string(m.source) + " (the file is truncated or corrupt)");
    const bool indices = m.mode == "TRIANGLES" || m.mode == "INDICES";
    if (m.mode != "ATTRIBUTES" && !indices) throw InputError(where + ": unknown mode '" + m.mode + "'");
    if (indices ? (m.stride != 2 && m.stride != 4) : (m.stride == 0 || m.stride > 256 || m.stride % 4 != 0))
      throw InputError(where + ": byteStride " + std::to_string(m.stride) + " is not valid for mode " + m.mode);
    if (m.mode == "TRIANGLES" && m.count % 3 != 0) throw InputError(where + ": a triangle list's count " + std::to_string(m.count) + " is not a multiple of 3");
    const bool filter_fits = m.filter == "NONE" || (m.filter == "OCTAHEDRAL" && (m.stride == 4 || m.stride == 8)) ||
                             (m.filter == "QUATERNION" && m.stride == 8) || (m.filter == "EXPONENTIAL" && m.stride % 4 == 0);
    if (indices ? m.filter != "NONE" : !filter_fits)
      throw InputError(where + ": filter '" + m.filter + "' is unknown or does not fit byteStride " + std::to_string(m.stride));
    if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model.buffers.size())
      throw InputError(where + " lies in a buffer that does not exist");
    std::vector<unsigned char>& target = model.buffers[static_cast<std::size_t>(view.buffer)].data;
    if (m.count > (std::numeric_limits<std::size_t>::max() / 2) / m.stride || m.count * m.stride > view.byteLength ||
        view.byteOffset > target.size() || view.byteLength > target.size() - view.byteOffset)
      throw InputError(where + ": " + std::to_string(m.count) + " elements of " + std::to_string(m.stride) +
                       " bytes do not fit the view or its buffer (the file is corrupt)");
    unsigned char* out = target.data() + view.byteOffset;
    const unsigned char* in = source.data() + m.offset;
    const int status = m.mode == "ATTRIBUTES" ? meshopt_decodeVertexBuffer(out, m.count, m.stride, in, m.length)
                       : m.mode == "TRIANGLES" ? meshopt_decodeIndexBuffer(out, m.count, m.stride, in, m.length)
                                               : meshopt_decodeIndexSequence(out, m.count, m.stride, in, m.length);
    if (status != 0) throw InputError(where + ": the compressed data is corrupt (meshoptimizer error " + std::to_string(status) + ")");
    if (m.filter == "OCTAHEDRAL") meshopt_decodeFilterOct(out, m.count, m.stride);
    else if (m.filter == "QUATERNION") meshopt_decodeFilterQuat(out, m.count, m.stride);
    else if (m.filter == "EXPONENTIAL") meshopt_decodeFilterExp(out, m.count, m.stride);
  }
}

InputError glb_truncated(const std::string& name, const std::string& what, unsigned long long size) {
  return InputError(name + ": truncated GLB: " + what + " but the file holds " + std::to_string(size) + " bytes");
}

std::uint32_t read_u32(const std::vector<unsigned char>& bytes, std::size_t at) {
  return static_cast<std::uint32_t>(bytes[at]) | static_cast<std::uint32_t>(bytes[at + 1]) << 8 |
         static_cast<std::uint32_t>(bytes[at + 2]) << 16 | static_cast<std::uint32_t>(bytes[at + 3]) << 24;
}

// The GLB container (glTF 2.0, "Binary glTF Layout"): a 12-byte header (magic 'glTF', version 2,
// total length), then chunks of (length, type, data), the JSON chunk first at byte 12 (its data
// at 20), then optionally the binary one. Checked in one place for the loader, which holds the
// whole file, and the check before it (gltf_summary), which reads only the headers.
constexpr std::uint32_t kGlbMagic = 0x46546C67u, kJsonChunk = 0x4E4F534Au, kBinChunk = 0x004E4942u;
struct GlbLayout {
  unsigned long long length = 0;  // the total the header announces (<= the file's size)
  std::uint32_t json_length = 0;  // the JSON chunk's data, from byte 20
};

// `head`: the file's first 20 bytes, or all of it when shorter; `size`: the file's size.
GlbLayout glb_layout(const std::vector<unsigned char>& head, unsigned long long size, const std::string& name) {
  if (head.size() < 12 || read_u32(head, 0) != kGlbMagic) throw InputError(name + ": cannot read glTF: not a GLB file (it does not begin with 'glTF')");
  if (read_u32(head, 4) != 2) throw InputError(name + ": cannot read glTF: GLB version " + std::to_string(read_u32(head, 4)) + " (meshtour reads glTF 2.0)");
  GlbLayout layout;
  layout.length = read_u32(head, 8);
  if (layout.length > size) throw glb_truncated(name, "its header announces " + std::to_string(layout.length) + " bytes", size);
  if (head.size() < 20 || read_u32(head, 16) != kJsonChunk) throw InputError(name + ": cannot read glTF: the GLB's first chunk is not its JSON");
  layout.json_length = read_u32(head, 12);
  if (20 + static_cast<unsigned long long>(layout.json_length) > layout.length)
    throw glb_truncated(name, "its JSON chunk announces " + std::to_string(layout.json_length) + " bytes", size);
  return layout;
}

// `chunk_head`: the 8 bytes after the JSON chunk, where the binary chunk's header is if there is one.
std::optional<std::uint32_t> glb_bin_length(const std::vector<unsigned char>& chunk_head, const GlbLayout& layout, unsigned long long size,
                                            const std::string& name) {
  if (chunk_head.size() < 8 || 20ull + layout.json_length + 8 > layout.length || read_u32(chunk_head, 4) != kBinChunk) return std::nullopt;
  const std::uint32_t bin_length = read_u32(chunk_head, 0);
  if (20ull + layout.json_length + 8 + bin_length > layout.length)
    throw glb_truncated(name, "its binary chunk announces " + std::to_string(bin_length) + " bytes", size);
  return bin_length;
}

// The JSON text of a .gltf file or of a GLB's JSON chunk.
std::string json_text_of(const std::vector<unsigned char>& bytes, bool glb, const std::string& name) {
  if (!glb) return std::string(bytes.begin(), bytes.end());
  const GlbLayout layout = glb_layout(bytes, bytes.size(), name);
  return std::string(bytes.begin() + 20, bytes.begin() + 20 + static_cast<std::ptrdiff_t>(layout.json_length));
}

// The GLB `bytes` with its JSON chunk replaced by `json` (the container was checked by json_text_of()).
std::vector<unsigned char> glb_with_json(const std::vector<unsigned char>& bytes, std::string json) {
  const std::size_t json_length = read_u32(bytes, 12);
  while (json.size() % 4) json += ' ';
  std::vector<unsigned char> out(bytes.begin(), bytes.begin() + 12);
  const auto put = [&out](std::size_t at, std::uint32_t v) {
    for (int k = 0; k < 4; ++k) out[at + static_cast<std::size_t>(k)] = static_cast<unsigned char>(v >> (8 * k));
  };
  out.resize(20);
  put(12, static_cast<std::uint32_t>(json.size()));
  put(16, kJsonChunk);
  out.insert(out.end(), json.begin(), json.end());
  out.insert(out.end(), bytes.begin() + 20 + static_cast<std::ptrdiff_t>(json_length), bytes.end());
  put(8, static_cast<std::uint32_t>(out.size()));
  return out;
}

// Refuses, by name, the extensions in `required` that meshtour does not read.
void refuse_unsupported(const std::vector<std::string>& required, const std::string& name) {
  std::vector<std::string> unsupported;
  for (const auto& e : required)
    if (!kSupported.count(e)) unsupported.push_back(e);
  if (unsupported.empty()) return;
  std::string list;
  for (const auto& e : unsupported) list += (list.empty() ? "" : ", ") + e;
  throw InputError(name + ": requires the glTF extension" + (unsupported.size() > 1 ? "s " : " ") + list +
                   ", which meshtour does not read (it would change the model's geometry or colours); export the "
                   "model without it (supported: KHR_draco_mesh_compression, EXT_meshopt_compression, "
                   "KHR_mesh_quantization, KHR_texture_transform, KHR_materials_unlit, "
                   "KHR_materials_pbrSpecularGlossiness, EXT_texture_webp, EXT_mesh_gpu_instancing, "
                   "KHR_lights_punctual)");
}

// extensionsRequired as the parsed JSON lists it (strings only; nothing when it did not parse).
std::vector<std::string> required_extensions(const nlohmann::json& doc) {
  std::vector<std::string> out;
  if (doc.is_discarded() || !doc.is_object() || !doc.contains("extensionsRequired") || !doc["extensionsRequired"].is_array()) return out;
  for (const auto& e : doc["extensionsRequired"])
    if (e.is_string()) out.push_back(e.get<std::string>());
  return out;
}

// The whole file in one read (through istreambuf_iterator, a byte at a time, it was a fifth of
// loading a big GLB).
template <class Bytes>
Bytes whole_file(const std::filesystem::path& file, const std::string& name) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw IoError(name + ": cannot open for reading (check permissions)");
  Bytes bytes(static_cast<std::size_t>(std::filesystem::file_size(file)), 0);
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (static_cast<std::size_t>(in.gcount()) != bytes.size()) throw IoError(name + ": could not read the whole file");
  return bytes;
}

tinygltf::Model read_model(const std::filesystem::path& file, const std::string& name) {
  tinygltf::TinyGLTF reader;
  reader.SetImageLoader(keep_encoded_image, nullptr);
  reader.SetFsCallbacks({regular_file_exists, tinygltf::ExpandFilePath, read_regular_file, nullptr, nullptr});
  tinygltf::Model model;
  std::string error, warning;
  bool ok = false;
  Prepared prepared;
  const std::string ext = lower_extension(file);
  const std::string base_dir = file.parent_path().string();
  try {
    std::vector<unsigned char> bytes = whole_file<std::vector<unsigned char>>(file, name);
    // A required extension meshtour does not read is named before the reader sees the file: such
    // files are often unreadable without it (a compression extension's views have no data of
    // their own), and the reader's own complaint would not say why.
    const bool glb = ext == ".glb";
    const std::string json = json_text_of(bytes, glb, name);
    // Parsed once, for the required extensions and for the rewrites; malformed JSON is left to
    // the reader to refuse.
    nlohmann::json doc = nlohmann::json::parse(json, nullptr, /*allow_exceptions=*/false);
    refuse_unsupported(required_extensions(doc), name);
    prepared = prepare_json(std::move(doc), json, name);
    if (glb) {
      if (prepared.json != json) bytes = glb_with_json(bytes, prepared.json);
      ok = reader.LoadBinaryFromMemory(&model, &error, &warning, bytes.data(), static_cast<unsigned>(bytes.size()), base_dir);
    } else {
      ok = reader.LoadASCIIFromString(&model, &error, &warning, prepared.json.c_str(), static_cast<unsigned>(prepared.json.size()), base_dir);
    }
    if (ok) decode_meshopt(model, prepared, name);
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw InputError(name + ": the glTF file announces more data than this machine's memory holds, or is corrupt");
  } catch (const std::exception& e) {
    throw InputError(name + ": cannot read glTF: " + e.what());
  }
  if (!ok) {
    while (!error.empty() && std::isspace(static_cast<unsigned char>(error.back()))) error.pop_back();
    std::replace(error.begin(), error.end(), '\n', ';');
    throw InputError(name + ": cannot read glTF: " + (error.empty() ? std::string("not a valid glTF 2.0 file") : error));
  }
  refuse_unsupported(model.extensionsRequired, name);
  return model;
}

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

// One primitive's data before it joins the mesh.
struct PrimitiveData {
  std::vector<std::array<double, 4>> positions, colors, uvs;
  std::vector<std::uint32_t> indices;  // as the primitive lists them (mode applies), or empty
  // A skinned primitive's JOINTS_n and WEIGHTS_n, one pair per set n.
  std::vector<std::pair<std::vector<std::array<double, 4>>, std::vector<std::array<double, 4>>>> skin_sets;
};

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


// Decodes a KHR_draco_mesh_compression primitive. The buffer view is checked before libdraco
// sees a byte of it; libdraco then decodes into its own structures, whose indices are checked.
PrimitiveData decode_draco(const tinygltf::Model& model, const tinygltf::Value& ext, int uv_set, bool want_colors, bool want_skin,
                           const std::string& where) {
  if (!ext.IsObject() || !ext.Has("bufferView") || !ext.Get("bufferView").IsNumber() || !ext.Has("attributes") ||
      !ext.Get("attributes").IsObject())
    throw InputError(where + ": its KHR_draco_mesh_compression has no bufferView or no attributes");
  const int view_index = ext.Get("bufferView").GetNumberAsInt();
  if (view_index < 0 || view_index >= static_cast<int>(model.bufferViews.size()))
    throw InputError(where + ": its Draco data names buffer view " + std::to_string(view_index) + ", which does not exist");
  const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(view_index)];
  if (view.buffer < 0 || view.buffer >= static_cast<int>(model.buffers.size()))
    throw InputError(where + ": its Draco data names a buffer that does not exist");
  const std::vector<unsigned char>& buffer = model.buffers[static_cast<std::size_t>(view.buffer)].data;
  if (view.byteLength == 0 || view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
    throw InputError(where + ": its Draco data reaches past the end of its buffer (a truncated file?)");

  draco::DecoderBuffer input;
  input.Init(reinterpret_cast<const char*>(buffer.data() + view.byteOffset), view.byteLength);
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&input);
  if (!decoded.ok()) throw InputError(where + ": corrupt Draco data: " + decoded.status().error_msg_string());
  const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
  if (!mesh) throw InputError(where + ": corrupt Draco data (no mesh decoded)");

  const tinygltf::Value& attributes = ext.Get("attributes");
  const auto attribute = [&](const std::string& key) -> const draco::PointAttribute* {
    if (!attributes.Has(key) || !attributes.Get(key).IsNumber()) return nullptr;
    const draco::PointAttribute* a = mesh->GetAttributeByUniqueId(static_cast<std::uint32_t>(attributes.Get(key).GetNumberAsInt()));
    if (!a) throw InputError(where + ": its Draco data has no attribute " + key + " although the file says so");
    return a;
  };
  const std::size_t points = mesh->num_points();
  const auto read = [&](const draco::PointAttribute* a, std::vector<std::array<double, 4>>& out) {
    if (!a) return;
    const int n = std::min<int>(a->num_components(), 4);
    out.resize(points);
    for (std::size_t i = 0; i < points; ++i) {
      const draco::AttributeValueIndex value = a->mapped_index(draco::PointIndex(static_cast<std::uint32_t>(i)));
      if (value.value() >= a->size()) throw InputError(where + ": corrupt Draco data (an attribute index is out of range)");
      float v[4] = {0, 0, 0, 1};
      if (!a->ConvertValue<float>(value, static_cast<std::int8_t>(n), v))
        throw InputError(where + ": corrupt Draco data (an attribute cannot be read)");
      out[i] = {v[0], v[1], v[2], v[3]};
    }
  };
  PrimitiveData data;
  const draco::PointAttribute* position = attribute("POSITION");
  if (!position) throw InputError(where + ": its Draco data has no POSITION attribute");
  read(position, data.positions);
  if (want_colors) read(attribute("COLOR_0"), data.colors);
  if (uv_set >= 0) read(attribute("TEXCOORD_" + std::to_string(uv_set)), data.uvs);
  for (int set = 0; want_skin; ++set) {
    const draco::PointAttribute* joints = attribute("JOINTS_" + std::to_string(set));
    const draco::PointAttribute* weights = attribute("WEIGHTS_" + std::to_string(set));
    if (!joints || !weights) break;
    read(joints, data.skin_sets.emplace_back().first);
    read(weights, data.skin_sets.back().second);
  }
  data.indices.reserve(3 * static_cast<std::size_t>(mesh->num_faces()));
  for (draco::FaceIndex f(0); f < mesh->num_faces(); ++f)
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t p = mesh->face(f)[c].value();
      if (p >= points) throw InputError(where + ": corrupt Draco data (a face names a missing point)");
      data.indices.push_back(p);
    }
  return data;
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

TextureWrap wrap_of(int mode) {
  if (mode == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE) return TextureWrap::clamp;
  if (mode == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT) return TextureWrap::mirror;
  return TextureWrap::repeat;
}

std::string percent_decoded(const std::string& uri) {
  std::string out;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
      out += static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

// A glTF material as meshtour uses it, with the texture coordinate set and UV transform its
// base colour texture names.
struct MaterialUse {
  MeshMaterial material;
  int uv_set = -1;  // -1: untextured
  Eigen::Matrix<double, 2, 3> uv_transform = Eigen::Matrix<double, 2, 3>::Identity();
};

// The bytes of base64 text (RFC 4648; padding optional). \throw InputError on another character.
std::vector<unsigned char> base64_decoded(std::string_view text, const std::string& where) {
  std::vector<unsigned char> out;
  out.reserve(text.size() / 4 * 3);
  std::uint32_t bits = 0;
  int count = 0;
  for (const char c : text) {
    if (c == '=') break;
    const int value = c >= 'A' && c <= 'Z'   ? c - 'A'
                      : c >= 'a' && c <= 'z' ? c - 'a' + 26
                      : c >= '0' && c <= '9' ? c - '0' + 52
                      : c == '+'             ? 62
                      : c == '/'             ? 63
                                             : -1;
    if (value < 0) throw InputError(where + ": its image's data URI has a character that is not base64");
    bits = (bits << 6) | static_cast<std::uint32_t>(value);
    if (++count == 4) {
      out.push_back(static_cast<unsigned char>(bits >> 16));
      out.push_back(static_cast<unsigned char>(bits >> 8));
      out.push_back(static_cast<unsigned char>(bits));
      bits = 0, count = 0;
    }
  }
  if (count == 2) out.push_back(static_cast<unsigned char>(bits >> 4));
  if (count == 3) out.push_back(static_cast<unsigned char>(bits >> 10)), out.push_back(static_cast<unsigned char>(bits >> 2));
  return out;
}

// The base colour of a material: its factor and the texture it names (`index` -1: none), with
// the texture's coordinate set and KHR_texture_transform. From pbrMetallicRoughness, or from
// KHR_materials_pbrSpecularGlossiness's diffuse (older Sketchfab and Blender exports), which takes
// precedence where a reader supports it; its specular and glossiness, like metallic and roughness,
// are not part of meshtour's studio look.
struct BaseColor {
  std::vector<double> factor;
  int index = -1, tex_coord = 0;
  const tinygltf::Value* transform = nullptr;
};

BaseColor base_color_of(const tinygltf::Material& m) {
  BaseColor out;
  if (const auto it = m.extensions.find("KHR_materials_pbrSpecularGlossiness"); it != m.extensions.end() && it->second.IsObject()) {
    const tinygltf::Value& sg = it->second;
    if (sg.Has("diffuseFactor") && sg.Get("diffuseFactor").IsArray())
      for (int k = 0; k < static_cast<int>(sg.Get("diffuseFactor").ArrayLen()); ++k)
        out.factor.push_back(sg.Get("diffuseFactor").Get(k).IsNumber() ? sg.Get("diffuseFactor").Get(k).GetNumberAsDouble() : 1.0);
    if (sg.Has("diffuseTexture") && sg.Get("diffuseTexture").IsObject()) {
      const tinygltf::Value& info = sg.Get("diffuseTexture");
      out.index = info.Has("index") && info.Get("index").IsNumber() ? info.Get("index").GetNumberAsInt() : -1;
      if (info.Has("texCoord") && info.Get("texCoord").IsNumber()) out.tex_coord = info.Get("texCoord").GetNumberAsInt();
      if (info.Has("extensions") && info.Get("extensions").Has("KHR_texture_transform"))
        out.transform = &info.Get("extensions").Get("KHR_texture_transform");
    }
    return out;
  }
  out.factor = m.pbrMetallicRoughness.baseColorFactor;
  const tinygltf::TextureInfo& info = m.pbrMetallicRoughness.baseColorTexture;
  out.index = info.index;
  out.tex_coord = info.texCoord;
  if (const auto it = info.extensions.find("KHR_texture_transform"); it != info.extensions.end()) out.transform = &it->second;
  return out;
}

MaterialUse material_use(const tinygltf::Model& model, int index, const std::filesystem::path& file, const std::string& name) {
  MaterialUse use;
  use.material.texture_times_vertex_colors = true;
  const tinygltf::Material& m = model.materials[static_cast<std::size_t>(index)];
  use.material.name = m.name.empty() ? "material " + std::to_string(index) : m.name;
  const BaseColor base = base_color_of(m);
  const auto& factor = base.factor;
  use.material.base_color = factor.size() >= 3 ? Eigen::Vector3f(static_cast<float>(factor[0]), static_cast<float>(factor[1]),
                                                                 static_cast<float>(factor[2]))
                                               : Eigen::Vector3f::Ones();
  if (base.index < 0) return use;
  const std::string where = name + ": material '" + use.material.name + "'";
  if (base.index >= static_cast<int>(model.textures.size()))
    throw InputError(where + " names texture " + std::to_string(base.index) + ", which does not exist");
  const tinygltf::Texture& texture = model.textures[static_cast<std::size_t>(base.index)];
  // EXT_texture_webp names a WebP image in place of (or as well as) the core PNG/JPEG source;
  // a reader that decodes WebP (OpenImageIO does) uses it.
  int source = texture.source;
  if (const auto it = texture.extensions.find("EXT_texture_webp"); it != texture.extensions.end() && it->second.IsObject() &&
                                                                   it->second.Has("source") && it->second.Get("source").IsNumber())
    source = it->second.Get("source").GetNumberAsInt();
  if (source < 0 || source >= static_cast<int>(model.images.size()))
    throw InputError(where + " has a texture whose image does not exist (texture " + std::to_string(base.index) + ")");
  if (texture.sampler >= static_cast<int>(model.samplers.size()))
    throw InputError(where + " has a texture whose sampler does not exist (texture " + std::to_string(base.index) + ")");
  if (texture.sampler >= 0) {
    const tinygltf::Sampler& sampler = model.samplers[static_cast<std::size_t>(texture.sampler)];
    use.material.wrap_s = wrap_of(sampler.wrapS);
    use.material.wrap_t = wrap_of(sampler.wrapT);
  }
  use.uv_set = std::max(0, base.tex_coord);
  if (base.transform && base.transform->IsObject()) {
    const tinygltf::Value& t = *base.transform;
    const auto pair = [&](const char* key, double fallback) {
      std::array<double, 2> v{fallback, fallback};
      if (t.Has(key) && t.Get(key).IsArray() && t.Get(key).ArrayLen() >= 2)
        for (int k = 0; k < 2; ++k)
          if (t.Get(key).Get(k).IsNumber()) v[static_cast<std::size_t>(k)] = t.Get(key).Get(k).GetNumberAsDouble();
      return v;
    };
    const auto offset = pair("offset", 0.0), scale = pair("scale", 1.0);
    const double rotation = t.Has("rotation") && t.Get("rotation").IsNumber() ? t.Get("rotation").GetNumberAsDouble() : 0.0;
    if (t.Has("texCoord") && t.Get("texCoord").IsNumber()) use.uv_set = std::max(0, t.Get("texCoord").GetNumberAsInt());
    const double c = std::cos(rotation), s = std::sin(rotation);
    // The extension's matrix: translation * rotation * scale.
    use.uv_transform << c * scale[0], s * scale[1], offset[0], -s * scale[0], c * scale[1], offset[1];
  }
  const tinygltf::Image& image = model.images[static_cast<std::size_t>(source)];
  // tinygltf decodes the data URIs of PNG and JPEG images; a WebP one arrives as its text.
  std::string data_uri_mime;
  std::vector<unsigned char> data_uri_bytes;
  if (image.image.empty() && image.uri.starts_with("data:")) {
    const std::size_t comma = image.uri.find(','), marker = image.uri.rfind(";base64", comma);
    if (comma == std::string::npos || marker == std::string::npos || marker + 7 != comma)
      throw InputError(where + ": its image " + std::to_string(source) + " is a data URI that is not base64");
    data_uri_mime = image.uri.substr(5, marker - 5);
    data_uri_bytes = base64_decoded(std::string_view(image.uri).substr(comma + 1), where);
  }
  if (!image.uri.empty() && image.image.empty() && data_uri_mime.empty()) {  // an external file
    const std::filesystem::path relative(percent_decoded(image.uri));
    use.material.texture_file = relative.is_absolute() ? relative : file.parent_path() / relative;
  } else {
    std::vector<unsigned char> bytes = data_uri_mime.empty() ? image.image : std::move(data_uri_bytes);
    const std::string& mime = data_uri_mime.empty() ? image.mimeType : data_uri_mime;
    if (image.bufferView >= 0) {  // checked here, not by tinygltf (keep_encoded_image)
      if (static_cast<std::size_t>(image.bufferView) >= model.bufferViews.size())
        throw InputError(where + ": its image " + std::to_string(source) + " names a buffer view that does not exist");
      const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(image.bufferView)];
      if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model.buffers.size())
        throw InputError(where + ": its image " + std::to_string(source) + " names a buffer that does not exist");
      const std::vector<unsigned char>& buffer = model.buffers[static_cast<std::size_t>(view.buffer)].data;
      if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
        throw InputError(where + ": its image " + std::to_string(source) + " lies outside its buffer (truncated file?)");
      bytes.assign(buffer.begin() + static_cast<std::ptrdiff_t>(view.byteOffset),
                   buffer.begin() + static_cast<std::ptrdiff_t>(view.byteOffset + view.byteLength));
    }
    if (bytes.empty()) throw InputError(where + ": its image " + std::to_string(source) + " has no data");
    const std::string ext = mime == "image/jpeg" ? ".jpg" : mime == "image/png" ? ".png"
                            : mime == "image/webp" ? ".webp"
                                                             : "";
    use.material.texture_file = file.string() + "#image" + std::to_string(source) + ext;
    use.material.texture_bytes = std::make_shared<const std::vector<unsigned char>>(std::move(bytes));
  }
  return use;
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
  bool any_colors = false, any_uvs = false;
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
          use = material_use(model, prim.material, file, name);
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

namespace {

// A JSON member that must be an array of whole numbers (a node's children, a scene's nodes).
std::vector<int> int_array(const nlohmann::json& o, const char* key, const std::string& where) {
  std::vector<int> out;
  if (!o.is_object() || !o.contains(key)) return out;
  const nlohmann::json& a = o[key];
  if (!a.is_array()) throw InputError(where + ": " + key + " is not an array");
  for (const auto& v : a) {
    if (!v.is_number_integer()) throw InputError(where + ": " + key + " holds something that is not a whole number");
    const auto n = v.get<std::int64_t>();
    out.push_back(n < std::numeric_limits<int>::min() || n > std::numeric_limits<int>::max() ? -1 : static_cast<int>(n));
  }
  return out;
}

// The element `index` of the top-level array `key` ("accessors", "meshes"), or an error naming it.
const nlohmann::json& element(const nlohmann::json& doc, const char* key, std::int64_t index, const std::string& where) {
  const nlohmann::json* list = doc.contains(key) ? &doc[key] : nullptr;
  if (!list || !list->is_array() || index < 0 || static_cast<std::size_t>(index) >= list->size() || !(*list)[static_cast<std::size_t>(index)].is_object())
    throw InputError(where + " names " + std::string(key).substr(0, std::string(key).size() - 1) + " " + std::to_string(index) +
                     ", which does not exist");
  return (*list)[static_cast<std::size_t>(index)];
}

std::int64_t index_of(const nlohmann::json& o, const char* key, const std::string& where) {
  const nlohmann::json& v = o[key];
  if (!v.is_number_integer()) throw InputError(where + ": " + key + " is not a whole number");
  return v.get<std::int64_t>();
}

}  // namespace

// From the JSON alone: the memory check comes before anything big is read, so neither the GLB's
// binary chunk nor external buffers are loaded here (parsing the whole 320 MB GLB of a 17.8M-face
// scan took 0.34 s and 750 MB), only their sizes checked against what the JSON says they hold.
MeshFileSummary gltf_summary(const std::filesystem::path& file) {
  const std::string name = file.string();
  const std::string ext = lower_extension(file);
  const unsigned long long size = std::filesystem::file_size(file);
  std::string json;
  std::optional<unsigned long long> bin_length;  // the GLB's binary chunk
  if (ext == ".glb") {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw IoError(name + ": cannot open for reading (check permissions)");
    const auto read_up_to = [&in](std::size_t count) {
      std::vector<unsigned char> bytes(count, 0);
      in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(count));
      bytes.resize(static_cast<std::size_t>(in.gcount()));
      return bytes;
    };
    const GlbLayout layout = glb_layout(read_up_to(20), size, name);
    json.resize(layout.json_length);
    in.read(json.data(), static_cast<std::streamsize>(layout.json_length));
    bin_length = glb_bin_length(read_up_to(8), layout, size, name);
  } else {
    json = whole_file<std::string>(file, name);  // the JSON is the file (data URIs can make it big)
  }
  const nlohmann::json doc = nlohmann::json::parse(json, nullptr, /*allow_exceptions=*/false);
  if (doc.is_discarded() || !doc.is_object()) throw InputError(name + ": cannot read glTF: its JSON is not valid");
  refuse_unsupported(required_extensions(doc), name);

  // The buffers hold what the JSON says they do (a truncated download is refused here).
  if (doc.contains("buffers") && doc["buffers"].is_array())
    for (std::size_t b = 0; b < doc["buffers"].size(); ++b) {
      const nlohmann::json& buffer = doc["buffers"][b];
      const std::string where = name + ": buffer " + std::to_string(b);
      if (!buffer.is_object()) throw InputError(where + " is not an object");
      const std::size_t byte_length = count_of(buffer, "byteLength", where);
      const bool has_uri = buffer.contains("uri") && buffer["uri"].is_string();
      if (!has_uri) {  // a GLB's own buffer (a compression extension's fallback has no data by design)
        const bool fallback = buffer.contains("extensions") && buffer["extensions"].is_object() &&
                              buffer["extensions"].contains("EXT_meshopt_compression");
        if (ext == ".glb" && b == 0 && !fallback && (!bin_length || byte_length > *bin_length))
          throw InputError(where + " holds " + std::to_string(byte_length) + " bytes but the GLB's binary chunk " +
                           (bin_length ? "holds " + std::to_string(*bin_length) : std::string("is missing")) + " (truncated file?)");
        continue;
      }
      const std::string uri = buffer["uri"].get<std::string>();
      if (uri.starts_with("data:")) continue;
      const std::filesystem::path data = file.parent_path() / std::filesystem::path(percent_decoded(uri));
      std::error_code ec;
      const auto data_size = std::filesystem::file_size(data, ec);
      if (ec) throw InputError(where + "'s file '" + uri + "' is missing or unreadable (looked for " + data.string() + ")");
      if (data_size < byte_length)
        throw InputError(where + "'s file '" + uri + "' holds " + std::to_string(data_size) + " bytes, not the " +
                         std::to_string(byte_length) + " it should (truncated?)");
    }

  // How many times each mesh is drawn: the loader's walk of the default scene.
  const nlohmann::json no_nodes = nlohmann::json::array();
  const nlohmann::json& nodes = doc.contains("nodes") && doc["nodes"].is_array() ? doc["nodes"] : no_nodes;
  const std::size_t mesh_count = doc.contains("meshes") && doc["meshes"].is_array() ? doc["meshes"].size() : 0;
  std::vector<std::size_t> draws(mesh_count, 0);
  std::vector<std::vector<int>> children(nodes.size());
  for (std::size_t n = 0; n < nodes.size(); ++n) children[n] = int_array(nodes[n], "children", name + ": node " + std::to_string(n));
  const bool has_scenes = doc.contains("scenes") && doc["scenes"].is_array() && !doc["scenes"].empty();
  if (nodes.empty() && !has_scenes) {
    std::fill(draws.begin(), draws.end(), 1);
  } else {
    std::vector<int> roots;
    if (has_scenes) {
      std::int64_t scene = doc.contains("scene") && doc["scene"].is_number_integer() ? doc["scene"].get<std::int64_t>() : 0;
      if (scene < 0 || static_cast<std::size_t>(scene) >= doc["scenes"].size()) scene = 0;
      roots = int_array(doc["scenes"][static_cast<std::size_t>(scene)], "nodes", name + ": scene " + std::to_string(scene));
    }
    walk_default_scene(static_cast<int>(nodes.size()), has_scenes ? &roots : nullptr,
                       [&](int i) -> const std::vector<int>& { return children[static_cast<std::size_t>(i)]; }, 0,
                       [&](int index, int) {
                         const nlohmann::json& node = nodes[static_cast<std::size_t>(index)];
                         const std::string where = name + ": node " + std::to_string(index);
                         if (!node.is_object() || !node.contains("mesh")) return 0;
                         const std::int64_t mesh = index_of(node, "mesh", where);
                         if (mesh < 0 || static_cast<std::size_t>(mesh) >= mesh_count)
                           throw InputError(where + " names mesh " + std::to_string(mesh) + ", which does not exist");
                         std::size_t copies = 1;
                         if (node.contains("extensions") && node["extensions"].is_object() && node["extensions"].contains("EXT_mesh_gpu_instancing")) {
                           const nlohmann::json& instancing = node["extensions"]["EXT_mesh_gpu_instancing"];
                           const std::string at = where + "'s EXT_mesh_gpu_instancing";
                           if (!instancing.is_object() || !instancing.contains("attributes") || !instancing["attributes"].is_object() ||
                               instancing["attributes"].empty())
                             throw InputError(at + " has none of TRANSLATION, ROTATION and SCALE");
                           const nlohmann::json& attribute = instancing["attributes"].begin().value();
                           if (!attribute.is_number_integer()) throw InputError(at + ": an attribute is not an accessor index");
                           copies = count_of(element(doc, "accessors", attribute.get<std::int64_t>(), at), "count", at);
                         }
                         std::size_t& drawn = draws[static_cast<std::size_t>(mesh)];
                         drawn = copies > std::numeric_limits<std::size_t>::max() - drawn ? std::numeric_limits<std::size_t>::max() : drawn + copies;
                         return 0;
                       },
                       name);
  }

  // Each drawn primitive's vertices and triangles, from its accessors' counts.
  MeshFileSummary summary;
  for (std::size_t m = 0; m < mesh_count; ++m) {
    if (draws[m] == 0) continue;
    const nlohmann::json& mesh = doc["meshes"][m];
    const std::string where = name + ": mesh " + std::to_string(m);
    if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) throw InputError(where + " has no primitives");
    for (std::size_t p = 0; p < mesh["primitives"].size(); ++p) {
      const nlohmann::json& prim = mesh["primitives"][p];
      const std::string at = where + " primitive " + std::to_string(p);
      if (!prim.is_object() || !prim.contains("attributes") || !prim["attributes"].is_object() || !prim["attributes"].contains("POSITION")) continue;
      const std::size_t vertices = count_of(element(doc, "accessors", index_of(prim["attributes"], "POSITION", at), at), "count", at);
      std::optional<std::int64_t> indices;
      if (prim.contains("indices")) indices = index_of(prim, "indices", at);
      const std::size_t corners = indices ? count_of(element(doc, "accessors", *indices, at), "count", at) : vertices;
      const std::int64_t mode = prim.contains("mode") ? index_of(prim, "mode", at) : TINYGLTF_MODE_TRIANGLES;
      const std::size_t triangles = mode == TINYGLTF_MODE_TRIANGLES ? corners / 3
                                    : (mode == TINYGLTF_MODE_TRIANGLE_STRIP || mode == TINYGLTF_MODE_TRIANGLE_FAN) && corners >= 3
                                        ? corners - 2
                                        : 0;
      // Saturating: a few bytes of JSON can announce any count, and the memory check must then
      // refuse the file, not see a count wrapped round to a small one.
      const auto add = [&](std::size_t& total, std::size_t each) {
        const std::size_t most = std::numeric_limits<std::size_t>::max();
        const std::size_t all = each != 0 && draws[m] > most / each ? most : draws[m] * each;
        total = all > most - total ? most : total + all;
      };
      add(summary.vertices, vertices);
      add(summary.faces, triangles);
      add(summary.corners, triangles > std::numeric_limits<std::size_t>::max() / 3 ? std::numeric_limits<std::size_t>::max() : 3 * triangles);
    }
  }
  return summary;
}

}  // namespace meshtour::gltf_detail
