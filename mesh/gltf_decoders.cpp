// The glTF extensions that compress data: EXT_meshopt_compression's buffer views
// (libmeshoptimizer) and KHR_draco_mesh_compression's primitives (libdraco).
#include <draco/compression/decode.h>
#include <meshoptimizer.h>

#include <limits>
#include <memory>

#include "mesh/gltf_parts.h"

namespace meshtour::gltf_detail {

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
  read(attribute("NORMAL"), data.normals);
  read(attribute("TANGENT"), data.tangents);
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

}  // namespace meshtour::gltf_detail
