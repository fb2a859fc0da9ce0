// glTF materials as meshtour uses them: the base colour factor and texture (embedded, in a data
// URI or an external file), its sampler's wrap modes and filters, coordinate set and
// KHR_texture_transform; the normal, occlusion, metallic-roughness and emissive maps and factors
// (KHR_materials_emissive_strength), KHR_materials_unlit.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <memory>
#include <optional>
#include <string_view>

#include "mesh/gltf_parts.h"

namespace meshtour::gltf_detail {
namespace {

TextureWrap wrap_of(int mode) {
  if (mode == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE) return TextureWrap::clamp;
  if (mode == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT) return TextureWrap::mirror;
  return TextureWrap::repeat;
}

// A sampler's magFilter and minFilter (absent: linear, mipmapped linear; an unknown value too).
void set_filters(MeshTexture& m, const tinygltf::Sampler& sampler) {
  m.mag_filter = sampler.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST ? TextureFilter::nearest : TextureFilter::linear;
  switch (sampler.minFilter) {
    case TINYGLTF_TEXTURE_FILTER_NEAREST: m.min_filter = TextureFilter::nearest, m.mip_filter = MipFilter::none; break;
    case TINYGLTF_TEXTURE_FILTER_LINEAR: m.min_filter = TextureFilter::linear, m.mip_filter = MipFilter::none; break;
    case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_NEAREST: m.min_filter = TextureFilter::nearest, m.mip_filter = MipFilter::nearest_level; break;
    case TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_NEAREST: m.min_filter = TextureFilter::linear, m.mip_filter = MipFilter::nearest_level; break;
    case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_LINEAR: m.min_filter = TextureFilter::nearest, m.mip_filter = MipFilter::linear; break;
    default: m.min_filter = TextureFilter::linear, m.mip_filter = MipFilter::linear; break;
  }
}

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
// precedence where a reader supports it; its specular and glossiness are not read (such a surface
// gets the look's highlight).
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

}  // namespace

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

namespace {

// A texture reference's coordinate set and KHR_texture_transform, as a 2x3 matrix on (u, v, 1).
struct TextureCoordinates {
  int set = 0;
  Eigen::Matrix<double, 2, 3> transform = Eigen::Matrix<double, 2, 3>::Identity();
  bool operator==(const TextureCoordinates&) const = default;
};

TextureCoordinates coordinates_of(int tex_coord, const tinygltf::Value* transform) {
  TextureCoordinates out;
  out.set = std::max(0, tex_coord);
  if (!transform || !transform->IsObject()) return out;
  const tinygltf::Value& t = *transform;
  const auto pair = [&](const char* key, double fallback) {
    std::array<double, 2> v{fallback, fallback};
    if (t.Has(key) && t.Get(key).IsArray() && t.Get(key).ArrayLen() >= 2)
      for (int k = 0; k < 2; ++k)
        if (t.Get(key).Get(k).IsNumber()) v[static_cast<std::size_t>(k)] = t.Get(key).Get(k).GetNumberAsDouble();
    return v;
  };
  const auto offset = pair("offset", 0.0), scale = pair("scale", 1.0);
  const double rotation = t.Has("rotation") && t.Get("rotation").IsNumber() ? t.Get("rotation").GetNumberAsDouble() : 0.0;
  if (t.Has("texCoord") && t.Get("texCoord").IsNumber()) out.set = std::max(0, t.Get("texCoord").GetNumberAsInt());
  const double c = std::cos(rotation), s = std::sin(rotation);
  // The extension's matrix: translation * rotation * scale.
  out.transform << c * scale[0], s * scale[1], offset[0], -s * scale[0], c * scale[1], offset[1];
  return out;
}

// The image and sampler of texture `index` (`what`: "texture" or "normal texture", for messages).
MeshTexture texture_of(const tinygltf::Model& model, int index, const std::filesystem::path& file, const std::string& where,
                       const std::string& what) {
  MeshTexture out;
  if (index >= static_cast<int>(model.textures.size()))
    throw InputError(where + " names " + what + " " + std::to_string(index) + ", which does not exist");
  const tinygltf::Texture& texture = model.textures[static_cast<std::size_t>(index)];
  // EXT_texture_webp names a WebP image in place of (or as well as) the core PNG/JPEG source;
  // a reader that decodes WebP (OpenImageIO does) uses it.
  int source = texture.source;
  if (const auto it = texture.extensions.find("EXT_texture_webp"); it != texture.extensions.end() && it->second.IsObject() &&
                                                                   it->second.Has("source") && it->second.Get("source").IsNumber())
    source = it->second.Get("source").GetNumberAsInt();
  if (source < 0 && texture.extensions.count("KHR_texture_basisu"))
    throw InputError(where + " has only a KTX2 / Basis Universal image (KHR_texture_basisu, texture " + std::to_string(index) +
                     "), which meshtour does not decode; export the model with PNG or JPEG textures");
  if (source < 0 || source >= static_cast<int>(model.images.size()))
    throw InputError(where + " has a " + what + " whose image does not exist (texture " + std::to_string(index) + ")");
  if (texture.sampler >= static_cast<int>(model.samplers.size()))
    throw InputError(where + " has a " + what + " whose sampler does not exist (texture " + std::to_string(index) + ")");
  if (texture.sampler >= 0) {
    const tinygltf::Sampler& sampler = model.samplers[static_cast<std::size_t>(texture.sampler)];
    out.wrap_s = wrap_of(sampler.wrapS);
    out.wrap_t = wrap_of(sampler.wrapT);
    set_filters(out, sampler);
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
    out.file = relative.is_absolute() ? relative : file.parent_path() / relative;
    return out;
  }
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
  const std::string ext = mime == "image/jpeg" ? ".jpg" : mime == "image/png" ? ".png" : mime == "image/webp" ? ".webp" : "";
  out.file = file.string() + "#image" + std::to_string(source) + ext;
  out.bytes = std::make_shared<const std::vector<unsigned char>>(std::move(bytes));
  return out;
}

}  // namespace

MaterialUse material_use(const tinygltf::Model& model, int index, const std::filesystem::path& file, const std::string& name,
                         std::vector<std::string>& warnings) {
  MaterialUse use;
  use.material.texture_times_vertex_colors = true;
  const tinygltf::Material& m = model.materials[static_cast<std::size_t>(index)];
  use.material.name = m.name.empty() ? "material " + std::to_string(index) : m.name;
  const BaseColor base = base_color_of(m);
  const auto& factor = base.factor;
  use.material.base_color = factor.size() >= 3 ? Eigen::Vector3f(static_cast<float>(factor[0]), static_cast<float>(factor[1]),
                                                                 static_cast<float>(factor[2]))
                                               : Eigen::Vector3f::Ones();
  const std::string where = name + ": material '" + use.material.name + "'";
  std::optional<TextureCoordinates> coordinates;
  if (base.index >= 0) {
    use.material.texture = texture_of(model, base.index, file, where, "texture");
    coordinates = coordinates_of(base.tex_coord, base.transform);
  }
  // A further map (normal, occlusion) on the coordinates the triangles carry: the other maps'.
  // Scans, photogrammetry and the sample models share them; a file that does not is told so.
  const auto map_on_shared_coordinates = [&](const auto& info, const char* kind, MeshTexture& out) {
    if (info.index < 0) return false;
    const auto it = info.extensions.find("KHR_texture_transform");
    const TextureCoordinates own = coordinates_of(info.texCoord, it != info.extensions.end() ? &it->second : nullptr);
    if (coordinates && !(*coordinates == own)) {
      warnings.push_back(where + ": its " + kind + " reads other texture coordinates (set or KHR_texture_transform) than its other "
                         "maps, which meshtour does not do; the " + kind + " is not used");
      return false;
    }
    out = texture_of(model, info.index, file, where, kind);
    coordinates = own;
    return true;
  };
  if (map_on_shared_coordinates(m.normalTexture, "normal texture", use.material.normal_texture))
    use.material.normal_scale = static_cast<float>(m.normalTexture.scale);
  if (map_on_shared_coordinates(m.occlusionTexture, "occlusion texture", use.material.occlusion_texture))
    use.material.occlusion_strength = static_cast<float>(std::clamp(m.occlusionTexture.strength, 0.0, 1.0));
  MeshMaterial& out = use.material;
  out.unlit = m.extensions.count("KHR_materials_unlit") > 0;
  out.double_sided = m.doubleSided;
  if (factor.size() >= 4) out.alpha = static_cast<float>(std::clamp(factor[3], 0.0, 1.0));
  if (m.alphaMode == "MASK") {
    out.alpha_mode = MeshMaterial::AlphaMode::mask;
    out.alpha_cutoff = static_cast<float>(std::max(0.0, m.alphaCutoff));
  } else if (m.alphaMode == "BLEND") {
    out.alpha_mode = MeshMaterial::AlphaMode::blend;
  }
  // Spec-gloss materials keep the look's highlight: meshtour reads their diffuse colour only.
  if (!out.unlit && !m.extensions.count("KHR_materials_pbrSpecularGlossiness")) {
    const tinygltf::PbrMetallicRoughness& pbr = m.pbrMetallicRoughness;
    MeshMaterial::MetallicRoughness mr;
    mr.metallic = static_cast<float>(std::clamp(pbr.metallicFactor, 0.0, 1.0));
    mr.roughness = static_cast<float>(std::clamp(pbr.roughnessFactor, 0.0, 1.0));
    map_on_shared_coordinates(pbr.metallicRoughnessTexture, "metallic-roughness texture", mr.texture);
    out.metallic_roughness = std::move(mr);
  }
  if (!out.unlit) {
    double strength = 1.0;
    if (const auto it = m.extensions.find("KHR_materials_emissive_strength"); it != m.extensions.end() && it->second.IsObject() &&
                                                                          it->second.Has("emissiveStrength") &&
                                                                          it->second.Get("emissiveStrength").IsNumber())
      strength = std::clamp(it->second.Get("emissiveStrength").GetNumberAsDouble(), 0.0, 1e6);
    if (m.emissiveFactor.size() >= 3)
      for (int k = 0; k < 3; ++k)
        out.emissive[k] = static_cast<float>(std::clamp(m.emissiveFactor[static_cast<std::size_t>(k)], 0.0, 1e6) * strength);
    if (out.emissive.squaredNorm() > 0.0f) map_on_shared_coordinates(m.emissiveTexture, "emissive texture", out.emissive_texture);
  }
  if (coordinates) {
    use.uv_set = coordinates->set;
    use.uv_transform = coordinates->transform;
  }
  return use;
}

}  // namespace meshtour::gltf_detail
