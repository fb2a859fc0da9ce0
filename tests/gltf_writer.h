#pragma once
// Small glTF 2.0 files written by hand for the tests (JSON + one binary buffer, as .gltf with an
// external .bin or as .glb), so that every case the loader handles can be built in a few lines.
// Header-only; needs nlohmann_json.
#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace meshtour::test {

struct GltfBuilder {
  nlohmann::json doc = {{"asset", {{"version", "2.0"}}}};
  std::vector<unsigned char> bin;

  /// Appends raw bytes as a buffer view (4-byte aligned); returns its index.
  int view(const void* data, std::size_t size) {
    while (bin.size() % 4) bin.push_back(0);
    const std::size_t offset = bin.size();
    bin.insert(bin.end(), static_cast<const unsigned char*>(data), static_cast<const unsigned char*>(data) + size);
    doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", size}});
    return static_cast<int>(doc["bufferViews"].size()) - 1;
  }
  /// A float accessor of `components` per element ("VEC2", "VEC3", ...).
  int floats(const std::vector<float>& values, int components) {
    const int v = view(values.data(), values.size() * sizeof(float));
    static const char* types[] = {"", "SCALAR", "VEC2", "VEC3", "VEC4"};
    nlohmann::json a = {{"bufferView", v}, {"componentType", 5126}, {"count", values.size() / components}, {"type", types[components]}};
    if (components == 3) {  // POSITION needs min and max
      std::vector<float> lo(3, 1e30f), hi(3, -1e30f);
      for (std::size_t i = 0; i < values.size(); ++i) {
        lo[i % 3] = std::min(lo[i % 3], values[i]);
        hi[i % 3] = std::max(hi[i % 3], values[i]);
      }
      a["min"] = lo;
      a["max"] = hi;
    }
    doc["accessors"].push_back(a);
    return static_cast<int>(doc["accessors"].size()) - 1;
  }
  int indices(const std::vector<std::uint32_t>& values) {
    const int v = view(values.data(), values.size() * 4);
    doc["accessors"].push_back({{"bufferView", v}, {"componentType", 5125}, {"count", values.size()}, {"type", "SCALAR"}});
    return static_cast<int>(doc["accessors"].size()) - 1;
  }
  /// An image stored in the buffer (GLB style); returns its index.
  int embedded_image(const std::vector<unsigned char>& bytes, const std::string& mime) {
    doc["images"].push_back({{"bufferView", view(bytes.data(), bytes.size())}, {"mimeType", mime}});
    return static_cast<int>(doc["images"].size()) - 1;
  }

  /// The file's buffers: `first` (the one `bin` fills) and any the test added after it in
  /// doc["buffers"] (e.g. an EXT_meshopt_compression fallback).
  nlohmann::json buffers_with(nlohmann::json first) const {
    nlohmann::json out = nlohmann::json::array({std::move(first)});
    if (doc.contains("buffers"))
      for (std::size_t i = 1; i < doc["buffers"].size(); ++i) out.push_back(doc["buffers"][i]);
    return out;
  }
  /// Writes a .gltf whose buffer is `<stem>.bin` beside it.
  void write_gltf(const std::filesystem::path& file) {
    nlohmann::json d = doc;
    const auto bin_file = file.parent_path() / (file.stem().string() + ".bin");
    d["buffers"] = buffers_with(nlohmann::json{{"byteLength", bin.size()}, {"uri", bin_file.filename().string()}});
    std::ofstream(bin_file, std::ios::binary).write(reinterpret_cast<const char*>(bin.data()), static_cast<std::streamsize>(bin.size()));
    std::ofstream(file) << d.dump(1);
  }
  /// Writes a .glb (JSON chunk + BIN chunk). `truncate` bytes are cut off the end of the file.
  void write_glb(const std::filesystem::path& file, std::size_t truncate = 0) {
    nlohmann::json d = doc;
    std::vector<unsigned char> data = bin;
    while (data.size() % 4) data.push_back(0);
    d["buffers"] = buffers_with(nlohmann::json{{"byteLength", data.size()}});
    std::string json = d.dump();
    while (json.size() % 4) json += ' ';
    std::vector<unsigned char> out;
    const auto u32 = [&out](std::uint32_t v) {
      for (int k = 0; k < 4; ++k) out.push_back(static_cast<unsigned char>(v >> (8 * k)));
    };
    u32(0x46546C67);  // "glTF"
    u32(2);
    u32(static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + data.size()));
    u32(static_cast<std::uint32_t>(json.size()));
    u32(0x4E4F534A);  // "JSON"
    out.insert(out.end(), json.begin(), json.end());
    u32(static_cast<std::uint32_t>(data.size()));
    u32(0x004E4942);  // "BIN"
    out.insert(out.end(), data.begin(), data.end());
    // erase, not resize: GCC 12 at -O1 warns of a memset past the maximum size on the resize path.
    out.erase(out.end() - static_cast<std::ptrdiff_t>(std::min(truncate, out.size())), out.end());
    std::ofstream(file, std::ios::binary).write(reinterpret_cast<const char*>(out.data()), static_cast<std::streamsize>(out.size()));
  }
};

inline std::vector<unsigned char> read_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace meshtour::test
