#pragma once
// Batch manifests: the list of models of a catalogue job, one video per item, as CSV (a header
// row naming the columns) or JSON (an array of objects, or {"items": [...]}). Columns / keys:
//   mesh (required), output, and every option-registry row marked as a manifest column (named by
//   the row's id: up, preset, path, frame-count (also "frames"), seconds, width, ..., see docs/OPTIONS.md)
// A bad value makes only its item bad (it is reported and skipped), never the whole manifest.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "options/option_registry.h"

namespace meshtour {

struct BatchItem {
  int index = 0;     ///< 0-based position in the manifest (a farm's array task id)
  int line = 0;      ///< CSV line or JSON array position (1-based), for messages
  std::filesystem::path mesh;  ///< resolved against the manifest's folder
  std::string output;          ///< video file name inside the output directory (default <mesh stem>.mp4)
  options::Values values;      ///< the item's option columns (checked text)
  std::string error;  ///< why this item cannot be rendered ("" if it is fine)
};

/// Reads a manifest (.csv or .json, by extension).
/// \throw IoError if unreadable; InputError if it is not a manifest at all (no header/mesh
///        column, not JSON, no items). Problems of single items end up in BatchItem::error.
std::vector<BatchItem> read_batch_manifest(const std::filesystem::path& file);

}  // namespace meshtour
