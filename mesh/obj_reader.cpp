#include "mesh/obj_reader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
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
  return index;
}

// Returns false when the file cannot be opened (missing, unreadable, a directory).
bool read_mtl(const std::filesystem::path& mtl_file, ObjContents& faces, std::map<std::string, int>& by_name) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(mtl_file, ec)) return false;
  std::ifstream in(mtl_file, std::ios::binary);
  if (!in) return false;
  int current = -1;
  for (std::string line; std::getline(in, line);) {
    const auto [key, rest] = split_statement(line);
    if (key == "newmtl") {
      if (by_name.count(rest)) {
        current = -1;  // a second definition of a name: ignored
        continue;
      }
      current = add_material(faces, by_name, rest);
    } else if ((key == "map_Kd" || key == "norm") && current >= 0 && !rest.empty()) {
      // map_Kd: the colour map, whose -o/-s move the material's coordinates. norm: a tangent-space
      // normal map (the statement of tinyobjloader and the exporters that write it) on those
      // coordinates, -bm its scale. map_Bump is a height map in the MTL specification and is not
      // read as a normal map.
      const MapStatement map = parse_map_statement(rest);
      if (map.file.empty()) continue;
      const std::filesystem::path image = portable_path(map.file);
      MeshMaterial& m = faces.materials[static_cast<std::size_t>(current)];
      MeshTexture& texture = key == "norm" ? m.normal_texture : m.texture;
      texture.file = image.is_absolute() ? image : mtl_file.parent_path() / image;
      texture.wrap_s = texture.wrap_t = map.clamp ? TextureWrap::clamp : TextureWrap::repeat;
      if (key == "norm") m.normal_scale = map.bump_multiplier;
      else faces.uv_transforms[static_cast<std::size_t>(current)] = map.uv_transform;
    }
  }
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
