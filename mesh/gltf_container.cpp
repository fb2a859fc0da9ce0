// The glTF file and its JSON: the GLB container, the JSON pre-pass that readies compressed
// files for tinygltf, read_model(), and gltf_summary() from the JSON alone.
#include <cctype>
#include <fstream>
#include <optional>
#include <set>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "mesh/file_extension.h"
#include "mesh/gltf.h"
#include "mesh/gltf_parts.h"

namespace meshtour::gltf_detail {
namespace {

// Extensions meshtour reads. Any other one a file lists in extensionsRequired changes geometry or
// colour in a way meshtour would get wrong, so it is refused by name.
const std::set<std::string> kSupported = {"KHR_draco_mesh_compression", "EXT_meshopt_compression", "KHR_texture_transform",
                                          "KHR_mesh_quantization", "KHR_materials_unlit", "KHR_materials_pbrSpecularGlossiness",
                                          "EXT_texture_webp", "EXT_mesh_gpu_instancing", "KHR_lights_punctual",
                                          "KHR_materials_emissive_strength"};

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
  std::string supported;
  for (const auto& e : kSupported) supported += (supported.empty() ? "" : ", ") + e;
  throw InputError(name + ": requires the glTF extension" + (unsupported.size() > 1 ? "s " : " ") + list +
                   ", which meshtour does not read (it would change the model's geometry or colours); export the "
                   "model without it (supported: " + supported + ")");
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

}  // namespace

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
