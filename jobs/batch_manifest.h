#pragma once
// Batch manifests: the list of models of a catalogue job, one video per item, as CSV (a header
// row naming the columns) or JSON (an array of objects, or {"items": [...]}). Columns / keys:
//   mesh (required), output, up, preset, path, frames, seconds, width, height, fps, spp
// A bad value makes only its item bad (it is reported and skipped), never the whole manifest.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace meshtour {

struct BatchItem {
  int index = 0;     ///< 0-based position in the manifest (a farm's array task id)
  int line = 0;      ///< CSV line or JSON array position (1-based), for messages
  std::filesystem::path mesh;  ///< resolved against the manifest's folder
  std::string output;          ///< video file name inside the output directory (default <mesh stem>.mp4)
  std::optional<std::string> up, preset, path;
  std::optional<int> frames, width, height, fps, spp;
  std::optional<double> seconds;
  std::string error;  ///< why this item cannot be rendered ("" if it is fine)
};

/// Reads a manifest (.csv or .json, by extension).
/// \throw IoError if unreadable; InputError if it is not a manifest at all (no header/mesh
///        column, not JSON, no items). Problems of single items end up in BatchItem::error.
std::vector<BatchItem> read_batch_manifest(const std::filesystem::path& file);

}  // namespace meshtour
