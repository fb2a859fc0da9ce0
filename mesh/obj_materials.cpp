#include "mesh/obj_materials.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

#include "core/error.h"

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
  if (word.empty()) return false;
  char* end = nullptr;
  std::strtod(word.c_str(), &end);
  return end == word.c_str() + word.size();
}

// Windows exporters write backslashes; a file name never holds one on the systems meshtour runs on.
std::filesystem::path portable_path(std::string name) {
  std::replace(name.begin(), name.end(), '\\', '/');
  return std::filesystem::path(name);
}

// Reads one MTL file's materials into `faces` (names already there are kept: the first wins).
// A new material named `name` (no texture, the identity UV transform); returns its index.
int add_material(ObjFaces& faces, std::map<std::string, int>& by_name, const std::string& name) {
  const int index = static_cast<int>(faces.materials.size());
  by_name[name] = index;
  MeshMaterial m;
  m.name = name;
  faces.materials.push_back(m);
  faces.uv_transforms.push_back({1, 1, 0, 0});
  return index;
}

// Returns false when the file cannot be opened (missing, unreadable, a directory).
bool read_mtl(const std::filesystem::path& mtl_file, ObjFaces& faces, std::map<std::string, int>& by_name) {
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
    } else if (key == "map_Kd" && current >= 0 && !rest.empty()) {
      const MapStatement map = parse_map_statement(rest);
      if (map.file.empty()) continue;
      const std::filesystem::path texture = portable_path(map.file);
      MeshMaterial& m = faces.materials[static_cast<std::size_t>(current)];
      m.texture_file = texture.is_absolute() ? texture : mtl_file.parent_path() / texture;
      m.wrap_s = m.wrap_t = map.clamp ? TextureWrap::clamp : TextureWrap::image_default;
      faces.uv_transforms[static_cast<std::size_t>(current)] = map.uv_transform;
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

ObjFaces read_obj_faces(const std::filesystem::path& file) {
  ObjFaces faces;
  std::map<std::string, int> by_name;
  std::ifstream in(file, std::ios::binary);
  long long vertices = 0;
  int current = -1;
  std::string line;
  while (std::getline(in, line)) {
    const std::size_t start = line.find_first_not_of(" \t");
    if (start == std::string::npos || line[start] == '#') continue;
    if (start > 0) line.erase(0, start);
    if (line[0] == 'v' && line.size() > 1 && std::isspace(static_cast<unsigned char>(line[1]))) {
      ++vertices;
      continue;
    }
    if (line[0] == 'f' && line.size() > 1 && std::isspace(static_cast<unsigned char>(line[1]))) {
      std::istringstream words(line.substr(2));
      std::vector<std::pair<int, int>> corners;
      for (std::string corner; words >> corner;) {
        // check_mesh_file() has verified the indices; negative ones count back from the end.
        const long long v = std::atoll(corner.c_str());
        const auto slash = corner.find('/');
        const long long t = slash == std::string::npos ? 0 : std::atoll(corner.c_str() + slash + 1);
        const long long uv_count = static_cast<long long>(faces.texcoords.size());
        corners.emplace_back(static_cast<int>(v < 0 ? vertices + v : v - 1),
                             static_cast<int>(t < 0 ? uv_count + t : t > 0 ? t - 1 : -1));
      }
      for (std::size_t k = 1; k + 1 < corners.size(); ++k)
        faces.triangles.push_back({{corners[0].first, corners[k].first, corners[k + 1].first},
                                   {corners[0].second, corners[k].second, corners[k + 1].second},
                                   current});
      continue;
    }
    const auto [key, rest] = split_statement(line);
    if (key == "vt") {
      std::istringstream words(rest);
      float u = 0, v = 0;
      words >> u >> v;
      faces.texcoords.emplace_back(u, v);
    } else if (key == "mtllib" && !rest.empty()) {
      // One file whose name may hold spaces, or several names separated by spaces.
      const std::filesystem::path whole = file.parent_path() / portable_path(rest);
      std::error_code ec;
      if (std::filesystem::is_regular_file(whole, ec)) {
        if (!read_mtl(whole, faces, by_name)) faces.missing_libraries.push_back(rest);
      } else {
        std::istringstream names(rest);
        for (std::string name; names >> name;)
          if (!read_mtl(file.parent_path() / portable_path(name), faces, by_name)) faces.missing_libraries.push_back(name);
      }
    } else if (key == "usemtl") {
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
  return faces;
}

}  // namespace meshtour::obj_detail
