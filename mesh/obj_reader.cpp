#include "mesh/obj_reader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string_view>

#include "core/error.h"
#include "mesh/mesh_text.h"

namespace meshtour::obj_detail {
namespace {

std::string trimmed(std::string s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
  std::size_t begin = 0;
  while (begin < s.size() && std::isspace(static_cast<unsigned char>(s[begin]))) ++begin;
  return s.substr(begin);
}

// The statement's keyword and the rest of its line (trimmed).
std::pair<std::string, std::string> split_statement(const std::string& line) {
  std::istringstream words(line);
  std::string key;
  if (!(words >> key)) return {};
  std::string rest;
  std::getline(words, rest);
  return {key, trimmed(rest)};
}

bool is_number(const std::string& word) {
  double ignored = 0.0;
  return mesh_text::parse_double(word, ignored);
}

// Windows exporters write backslashes; a file name never holds one on the systems meshtour runs on.
std::filesystem::path portable_path(std::string name) {
  std::replace(name.begin(), name.end(), '\\', '/');
  return std::filesystem::path(name);
}

// Reads one MTL file's materials into `faces` (names already there are kept: the first wins).
// A new material named `name` (no texture, the identity UV transform); returns its index.
int add_material(ObjContents& faces, std::map<std::string, int>& by_name, const std::string& name) {
  const int index = static_cast<int>(faces.materials.size());
  by_name[name] = index;
  MeshMaterial m;
  m.name = name;
  faces.materials.push_back(m);
  faces.uv_transforms.push_back({1, 1, 0, 0});
  faces.bump_maps.emplace_back();
  return index;
}

// What one material's statements said, turned into its MeshMaterial once the file is read
// (statements may come in any order: Kd applies only when no map_Kd follows, d wins over Tr).
struct MtlStatements {
  std::optional<Eigen::Vector3f> kd, ks, ke;
  std::optional<float> ns, d, tr, pr, pm;
  std::optional<float> illum;  // an illumination model number, 0 to 10 (kept as read: 1e30 is no int)
  std::filesystem::path map_d;
};

// Up to three numbers ("Kd 0.8 0.5 0.2"; "Kd 0.8" is grey, as the MTL specification allows), or
// nothing when the statement is not that ("Kd spectral file.rfl", "Kd xyz ...").
std::optional<Eigen::Vector3f> colour_of(const std::string& rest) {
  std::istringstream words(rest);
  std::vector<double> values;
  for (std::string w; words >> w;) {
    double v = 0.0;
    // Finite as a float too (1e40 is a double, not a float).
    if (!mesh_text::parse_double(w, v) || !std::isfinite(static_cast<float>(v))) return std::nullopt;
    values.push_back(v);
  }
  if (values.empty() || values.size() > 3) return std::nullopt;
  while (values.size() < 3) values.push_back(values[0]);
  return Eigen::Vector3f(static_cast<float>(values[0]), static_cast<float>(values[1]), static_cast<float>(values[2]));
}

std::optional<float> number_of(const std::string& rest) {
  double v = 0.0;
  if (!mesh_text::parse_double(rest, v) || !std::isfinite(static_cast<float>(v))) return std::nullopt;
  return static_cast<float>(v);
}

// The MTL statements beyond the maps, as the common readers take them (Blender's importer and
// three.js's MTLLoader; docs/FORMATS.md, "OBJ materials"):
// - Kd, when the material has no map_Kd: its colour, linear (Blender writes and reads it so).
// - d (opacity), else Tr (transparency, 1 - d): below 1, a blended surface (glTF's BLEND). Tr 1
//   is read as opaque: Agisoft Metashape writes "Tr 1" on every opaque scan material.
// - map_d: when it names map_Kd's image, the surface takes that image's alpha channel (blended).
// - Pr, Pm (the PBR extension): roughness and metallic; else Ns and Ks: Blender's roughness
//   1 - sqrt(Ns / 1000), metallic 0; Ks black or illum 0/1 (no highlight) is roughness 1. The
//   material then has glTF's metallic-roughness BRDF; without any of these statements it keeps
//   the look's diffuse and highlight, as before.
// - Ke: emitted radiance, linear; map_Ke its image (sRGB), times Ke, or as it is without Ke.
void apply_statements(MeshMaterial& m, const MtlStatements& st, std::vector<std::string>& warnings) {
  const auto unit = [](float v) { return std::clamp(v, 0.0f, 1.0f); };
  if (st.kd && !m.texture.present()) m.base_color = st.kd->cwiseMax(0.0f).cwiseMin(1.0f);
  float alpha = 1.0f;
  if (st.d) alpha = unit(*st.d);
  else if (st.tr && *st.tr < 1.0f) alpha = 1.0f - unit(*st.tr);
  if (!st.map_d.empty()) {
    if (m.texture.present() && st.map_d == m.texture.file) {
      m.alpha_mode = MeshMaterial::AlphaMode::blend;
    } else {
      warnings.push_back("material '" + m.name + "': map_d names " + st.map_d.filename().string() +
                         ", another image than its map_Kd; a separate opacity map is not read (put the opacity in the alpha "
                         "channel of the map_Kd image)");
    }
  }
  if (alpha < 1.0f) m.alpha_mode = MeshMaterial::AlphaMode::blend;
  m.alpha = alpha;
  if (st.pr || st.pm || st.ns || st.ks) {
    MeshMaterial::MetallicRoughness mr;
    mr.metallic = st.pm ? unit(*st.pm) : 0.0f;
    const bool no_highlight = (st.ks && !(st.ks->maxCoeff() > 0.0f)) || (st.illum && *st.illum < 2.0f);
    if (st.pr) mr.roughness = unit(*st.pr);
    else if (no_highlight || !st.ns) mr.roughness = 1.0f;
    else mr.roughness = 1.0f - std::sqrt(std::clamp(*st.ns, 0.0f, 1000.0f) / 1000.0f);
    m.metallic_roughness = mr;
  }
  if (st.ke) m.emissive = st.ke->cwiseMax(0.0f);
  else if (m.emissive_texture.present()) m.emissive = Eigen::Vector3f::Ones();
}

// Returns false when the file cannot be opened (missing, unreadable, a directory).
bool read_mtl(const std::filesystem::path& mtl_file, ObjContents& faces, std::map<std::string, int>& by_name) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(mtl_file, ec)) return false;
  std::ifstream in(mtl_file, std::ios::binary);
  if (!in) return false;
  int current = -1;
  std::map<int, MtlStatements> statements;  // this file's materials
  // A map statement's image, relative to the MTL, with its -clamp.
  const auto texture_of = [&](const MapStatement& map) {
    MeshTexture texture;
    const std::filesystem::path image = portable_path(map.file);
    texture.file = image.is_absolute() ? image : mtl_file.parent_path() / image;
    texture.wrap_s = texture.wrap_t = map.clamp ? TextureWrap::clamp : TextureWrap::repeat;
    return texture;
  };
  for (std::string line; std::getline(in, line);) {
    // Named, not bound: a lambda below uses them, and clang cannot capture structured bindings.
    const auto statement = split_statement(line);
    const std::string& key = statement.first;
    const std::string& rest = statement.second;
    if (key == "newmtl") {
      if (by_name.count(rest)) {
        current = -1;  // a second definition of a name: ignored
        continue;
      }
      current = add_material(faces, by_name, rest);
      statements[current];
      continue;
    }
    if (current < 0 || rest.empty()) continue;
    MeshMaterial& m = faces.materials[static_cast<std::size_t>(current)];
    MtlStatements& st = statements[current];
    // A statement meshtour reads whose value it cannot: said once, then the statement is ignored.
    const auto unreadable = [&](const char* what) {
      faces.warnings.push_back(mtl_file.filename().string() + ": material '" + m.name + "': " + key + " '" + rest + "' is not " + what +
                               "; ignored");
    };
    if (key == "map_Kd" || key == "norm") {
      // map_Kd: the colour map, whose -o/-s move the material's coordinates. norm: a tangent-space
      // normal map (the statement of tinyobjloader and the exporters that write it) on those
      // coordinates, -bm its scale.
      const MapStatement map = parse_map_statement(rest);
      if (map.file.empty()) continue;
      (key == "norm" ? m.normal_texture : m.texture) = texture_of(map);
      if (key == "norm") {
        m.normal_scale = map.bump_multiplier;
        faces.bump_maps[static_cast<std::size_t>(current)] = {};  // norm says what it is: any bump is not needed
      } else {
        faces.uv_transforms[static_cast<std::size_t>(current)] = map.uv_transform;
      }
    } else if (key == "map_Bump" || key == "map_bump" || key == "bump") {
      const MapStatement map = parse_map_statement(rest);
      if (map.file.empty() || m.normal_texture.present()) continue;
      faces.bump_maps[static_cast<std::size_t>(current)] = {texture_of(map), map.bump_multiplier};
    } else if (key == "map_Ke") {
      // The emission's image (sRGB, on the colour map's coordinates), times Ke, or as it is without Ke.
      const MapStatement map = parse_map_statement(rest);
      if (map.file.empty()) continue;
      m.emissive_texture = texture_of(map);
    } else if (key == "map_d") {
      const MapStatement map = parse_map_statement(rest);
      if (!map.file.empty()) st.map_d = texture_of(map).file;
    } else if (key == "Kd" || key == "Ks" || key == "Ke") {
      const auto colour = colour_of(rest);
      if (!colour) {
        unreadable("one to three numbers");
        continue;
      }
      (key == "Kd" ? st.kd : key == "Ks" ? st.ks : st.ke) = colour;
    } else if (key == "Ns" || key == "d" || key == "Tr" || key == "Pr" || key == "Pm" || key == "illum") {
      const auto value = number_of(rest);
      if (!value) {
        unreadable("a number");
        continue;
      }
      if (key == "Ns") st.ns = value;
      else if (key == "d") st.d = value;
      else if (key == "Tr") st.tr = value;
      else if (key == "Pr") st.pr = value;
      else if (key == "Pm") st.pm = value;
      else st.illum = value;
    }
  }
  for (const auto& [index, st] : statements) apply_statements(faces.materials[static_cast<std::size_t>(index)], st, faces.warnings);
  return true;
}

}  // namespace

MapStatement parse_map_statement(const std::string& argument) {
  MapStatement map;
  std::istringstream words(argument);
  std::vector<std::string> tokens;
  for (std::string w; words >> w;) tokens.push_back(w);
  // Options and their argument counts (MTL specification); -o, -s and -t take 1 to 3 numbers.
  static const std::map<std::string, int> fixed = {{"-blendu", 1}, {"-blendv", 1}, {"-bm", 1},     {"-boost", 1},
                                                   {"-cc", 1},     {"-clamp", 1},  {"-imfchan", 1}, {"-mm", 2},
                                                   {"-texres", 1}, {"-type", 1}};
  std::size_t i = 0;
  while (i < tokens.size() && tokens[i].size() > 1 && tokens[i][0] == '-' && !is_number(tokens[i])) {
    const std::string option = tokens[i++];
    if (option == "-o" || option == "-s" || option == "-t") {
      float values[3] = {option == "-s" ? 1.0f : 0.0f, option == "-s" ? 1.0f : 0.0f, 0.0f};
      for (int k = 0; k < 3 && i < tokens.size() && is_number(tokens[i]); ++k)
        values[k] = std::strtof(tokens[i++].c_str(), nullptr);
      if (option == "-s") map.uv_transform[0] = values[0], map.uv_transform[1] = values[1];
      if (option == "-o") map.uv_transform[2] = values[0], map.uv_transform[3] = values[1];
      continue;
    }
    const auto it = fixed.find(option);
    const int count = it == fixed.end() ? 0 : it->second;  // unknown option: taken as a flag
    if (option == "-clamp" && i < tokens.size()) map.clamp = tokens[i] == "on";
    if (option == "-bm" && i < tokens.size() && is_number(tokens[i])) map.bump_multiplier = std::strtof(tokens[i].c_str(), nullptr);
    i = std::min(tokens.size(), i + static_cast<std::size_t>(count));
  }
  // The file name is the rest of the line from the first word that is not an option, so that
  // names with spaces survive: find that word's position in the original text.
  if (i >= tokens.size()) return map;
  std::size_t pos = 0;
  for (std::size_t k = 0; k <= i; ++k) {
    pos = argument.find(tokens[k], pos);
    if (k < i) pos += tokens[k].size();
  }
  map.file = trimmed(argument.substr(pos));
  return map;
}

ObjContents read_obj(const std::filesystem::path& file, bool read) {
  const std::string name = file.string();
  ObjContents faces;
  MeshFileSummary& s = faces.summary;
  std::map<std::string, int> by_name;
  mesh_text::LineReader lines(file);
  std::size_t texcoords = 0, normals = 0;
  bool keep_texcoords = false, keep_materials = false;
  int current = -1;
  std::vector<std::string_view> words;
  std::vector<std::pair<int, int>> corners;
  std::string_view line;
  for (std::size_t number = 1; lines.next(line); ++number) {
    // OpenMesh skipped leading blanks (" f /11 2 3" reached an assertion in its reader: fuzzing).
    while (!line.empty() && (line[0] == ' ' || line[0] == '\t' || line[0] == '\r' || line[0] == '\v' || line[0] == '\f')) line.remove_prefix(1);
    if (line.size() < 2 || line[0] == '#') continue;
    mesh_text::split_words(line, words);
    if (words.empty()) continue;
    const std::string_view key = words[0];
    auto fail = [&](const std::string& what) -> void { throw InputError(name + ": line " + std::to_string(number) + ": " + what); };
    if (key == "v") {
      ++s.vertices;
      if (words.size() < 4) fail("vertex " + std::to_string(s.vertices) + " has fewer than 3 coordinates");
      double value[7] = {};
      for (std::size_t k = 1; k < words.size(); ++k) {
        double c = 0.0;
        const bool parsed = mesh_text::parse_double(words[k], c);
        if (k <= 3) {
          if (!parsed) fail("vertex " + std::to_string(s.vertices) + " has a coordinate that is not a number: '" + std::string(words[k]) + "'");
          if (!std::isfinite(c)) fail("vertex " + std::to_string(s.vertices) + " has a NaN or infinite coordinate ('" + std::string(words[k]) + "')");
        } else if (!parsed || !std::isfinite(c)) {
          // Every extra value must be a plain number ("0+5" was read by OpenMesh as 0 and 5).
          fail("vertex " + std::to_string(s.vertices) + " has a value that is not a number: '" + std::string(words[k]) + "'");
        }
        if (k < 7) value[k] = c;
      }
      // "v x y z r g b": a colour in 0..1 (OpenMesh converted it to bytes without a range check,
      // undefined behaviour beyond 0..1, found by fuzzing).
      if (words.size() >= 6)
        for (std::size_t k = 4; k < words.size() && k <= 6; ++k)
          if (!(value[k] >= 0.0 && value[k] <= 1.0))
            fail("vertex " + std::to_string(s.vertices) + " has a colour component '" + std::string(words[k]) + "' outside 0 to 1");
      if (read) {
        faces.positions.emplace_back(value[1], value[2], value[3]);
        if (words.size() >= 7) {
          faces.colors.resize(faces.positions.size() - 1, Eigen::Vector3f::Ones());
          faces.colors.emplace_back(static_cast<float>(value[4]), static_cast<float>(value[5]), static_cast<float>(value[6]));
        }
      }
    } else if (key == "vt") {
      ++texcoords;
      if (read) {
        double u = 0.0, v = 0.0;
        if (words.size() > 1) mesh_text::parse_double(words[1], u);
        if (words.size() > 2) mesh_text::parse_double(words[2], v);
        faces.texcoords.emplace_back(static_cast<float>(u), static_cast<float>(v));
      }
    } else if (key == "vn") {
      ++normals;
    } else if (key == "f") {
      ++s.faces;
      if (words.size() < 4) fail("face with fewer than 3 corners");
      s.corners += words.size() - 1;
      corners.clear();
      for (std::size_t k = 1; k < words.size(); ++k) {
        // v, v/vt, v//vn or v/vt/vn; OBJ indices start at 1, negative ones count back from the end.
        const std::string_view corner = words[k];
        const std::size_t counts[3] = {s.vertices, texcoords, normals};
        const char* what[3] = {"vertex", "texture coordinate", "normal"};
        long long parts[3] = {0, 0, 0};
        std::size_t begin = 0;
        for (int part = 0; part < 3 && begin <= corner.size(); ++part) {
          const std::size_t end = std::min(corner.find('/', begin), corner.size());
          const std::string_view index_text = corner.substr(begin, end - begin);
          begin = end + 1;
          if (index_text.empty() && part > 0) continue;
          long long index = 0;
          if (!mesh_text::parse_integer(index_text, index)) fail("face corner '" + std::string(corner) + "' is not an index");
          const long long count = static_cast<long long>(counts[part]);
          if (index == 0 || index > count || index < -count)
            fail("face refers to " + std::string(what[part]) + " " + std::to_string(index) + " but only " + std::to_string(count) + " " +
                 (part == 0 ? "vertices" : part == 1 ? "texture coordinates" : "normals") + (count == 1 ? " is" : " are") +
                 " defined before it");
          parts[part] = index < 0 ? count + index + 1 : index;  // 1-based
          if (end == corner.size()) break;
        }
        if (parts[1] != 0) faces.corner_texcoords = true;
        corners.emplace_back(static_cast<int>(parts[0] - 1), static_cast<int>(parts[1] - 1));
      }
      if (!read) continue;
      faces.polygons += corners.size() > 3 ? 1 : 0;
      // Texture coordinate indices and materials are kept from the first face that has them on
      // (the triangles before get none).
      if (!keep_texcoords && std::any_of(corners.begin(), corners.end(), [](const auto& c) { return c.second >= 0; })) {
        keep_texcoords = true;
        faces.triangle_texcoords.resize(faces.triangles.size(), {-1, -1, -1});
      }
      if (!keep_materials && current >= 0) {
        keep_materials = true;
        faces.triangle_materials.resize(faces.triangles.size(), -1);
      }
      for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
        faces.triangles.push_back({static_cast<std::uint32_t>(corners[0].first), static_cast<std::uint32_t>(corners[k].first),
                                   static_cast<std::uint32_t>(corners[k + 1].first)});
        if (keep_texcoords) faces.triangle_texcoords.push_back({corners[0].second, corners[k].second, corners[k + 1].second});
        if (keep_materials) faces.triangle_materials.push_back(current);
      }
    } else if (read && (key == "mtllib" || key == "usemtl")) {
      const auto [statement, rest] = split_statement(std::string(line));
      if (statement == "mtllib" && !rest.empty()) {
        // One file whose name may hold spaces, or several names separated by spaces.
        const std::filesystem::path whole = file.parent_path() / portable_path(rest);
        std::error_code ec;
        if (std::filesystem::is_regular_file(whole, ec)) {
          if (!read_mtl(whole, faces, by_name)) faces.missing_libraries.push_back(rest);
        } else {
          std::istringstream names(rest);
          for (std::string library; names >> library;)
            if (!read_mtl(file.parent_path() / portable_path(library), faces, by_name)) faces.missing_libraries.push_back(library);
        }
      } else if (statement == "usemtl") {
        const auto it = by_name.find(rest);
        if (it != by_name.end()) {
          current = it->second;
        } else {
          // A name no MTL defines: its faces get the look's colour, as before any usemtl.
          faces.warnings.push_back("material '" + rest + "' (usemtl) is not defined in any material library; its faces are untextured");
          current = add_material(faces, by_name, rest);
        }
      }
    }
  }
  if (!faces.colors.empty()) faces.colors.resize(faces.positions.size(), Eigen::Vector3f::Ones());
  return faces;
}

}  // namespace meshtour::obj_detail
