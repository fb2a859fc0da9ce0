#pragma once
// Sizes of memory as people write them (--max-memory): a number with an optional unit.
#include <cctype>
#include <cstdint>
#include <exception>
#include <string>

#include "core/error.h"

namespace meshtour {

/// "512M", "8G", "1.5g", "2T", "2000000" (bytes), "4096K" -> bytes (powers of 1024), between 1M and
/// 1000000T. \throw InputError for anything else.
inline std::uint64_t parse_memory_size(const std::string& text) {
  const std::string bad = "--max-memory '" + text + "' is not a size; write e.g. 512M, 8G or 1.5T";
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    throw InputError(bad);
  }
  std::string unit = text.substr(used);
  for (auto& c : unit) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  if (unit.size() == 3 && unit.substr(1) == "IB") unit = unit.substr(0, 1);  // 8GiB
  if (unit.size() == 2 && unit[1] == 'B') unit = unit.substr(0, 1);            // 8GB
  double scale = 1;
  if (unit == "K") scale = 1024.0;
  else if (unit == "M") scale = 1024.0 * 1024;
  else if (unit == "G") scale = 1024.0 * 1024 * 1024;
  else if (unit == "T") scale = 1024.0 * 1024 * 1024 * 1024;
  else if (!unit.empty() && unit != "B") throw InputError(bad);
  const double bytes = value * scale;
  if (!(bytes >= 1024 * 1024) || bytes > 1e18) throw InputError("--max-memory '" + text + "' must be between 1M and 1000000T");
  return static_cast<std::uint64_t>(bytes);
}

}  // namespace meshtour
