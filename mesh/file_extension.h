#pragma once
// A mesh file's extension in lower case (".PLY" and ".ply" are one format), private to mesh/:
// the readers are chosen by it.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>

namespace meshtour {

inline std::string lower_extension(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

}  // namespace meshtour
