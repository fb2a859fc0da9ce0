#pragma once
// The path file: the JSON that `meshtour path -o` writes for every path mode (the paper path's
// results, metrics, options and timings; the feature orbit's and the turntable's fitted geometry)
// and from which read_path_file() rebuilds the very same camera path without the mesh and without
// a search. Format 2 also records what the path was made for (made_for: the settings it depends
// on), which a renderer compares with its own; format 1 (paper path only) is still read.
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/atomic_file.h"  // write_file_atomically, used by every writer in pathgen
#include "pathgen/camera_path.h"
#include "pathgen/feature_orbit.h"
#include "pathgen/paper_path.h"
#include "pathgen/turntable.h"

namespace meshtour {

/// Version of the layout written; read_path_file() reads it and kOldestPathFormatVersion (1: the
/// paper path without "mode" and "made_for") and refuses any other.
inline constexpr int kPathFormatVersion = 2;
inline constexpr int kOldestPathFormatVersion = 1;

/// The settings a path was made for, by name ("up" -> "y", "aspect" -> "1.7777777777777777"):
/// each one the path depends on, as text that compares equal exactly when the setting is equal.
using PathSettings = std::vector<std::pair<std::string, std::string>>;

/// A number as PathSettings hold it: the shortest text that reads back as the same double.
std::string setting_text(double value);

/// The path search's options as a path file records them (compact JSON, without the up direction
/// and the sample count of samples.csv): equal texts mean the same search.
std::string search_options_text(const PaperPathOptions& options);
std::string search_options_text(const SurfaceOptions& options);

/// What a path file records besides the path itself.
struct PathRecord {
  std::string source;               ///< the input mesh ("" to omit)
  PathSettings made_for;            ///< what the path depends on (checked by check_path_settings)
  int frames = 0;                   ///< the frame count frame_scores are for (0: none recorded)
  std::vector<double> frame_scores; ///< the feature orbit's score of each frame's view
};

/// Writes the path file of `result` atomically (a temporary file in the same folder, renamed
/// over `file` when complete). `source` names the input mesh for the record ("" to omit).
/// \throw IoError if the file cannot be written.
void write_path_file(const PaperPathResult& result, const std::filesystem::path& file,
                     const std::string& source = "");

/// The JSON text write_path_file() writes.
std::string path_file_text(const PaperPathResult& result, const std::string& source = "");
std::string path_file_text(const PaperPathResult& result, const PathRecord& record);
/// The path file of a feature orbit (mode "feature-orbit") and of a turntable ("turntable").
std::string path_file_text(const FeatureOrbitGeometry& orbit, const PathRecord& record);
std::string path_file_text(const TurntableGeometry& turntable, const PathRecord& record);

/// A path file as read: the path rebuilt (model units) and what the file records.
struct PathFile {
  int format_version = kPathFormatVersion;
  std::string mode;                  ///< "paper", "feature-orbit" or "turntable" (format 1: "paper")
  std::unique_ptr<CameraPath> path;  ///< PaperCameraPath, FeatureOrbitPath or TurntablePath
  PathRecord record;                 ///< made_for is empty for format 1
};

/// Reads a path file of any mode.
/// \throw IoError if the file cannot be read, InputError (naming the file and the key) if it is
///        not a path file of format_version 1 or 2 or a key it needs is missing or invalid.
PathFile load_path_file(const std::filesystem::path& file);

/// The camera path of a path file alone (load_path_file(file).path).
std::unique_ptr<CameraPath> read_path_file(const std::filesystem::path& file);

/// The paper path of a path file, as the concrete type (its geometry() exposes the curves).
/// \throw InputError as load_path_file(), and if the file holds another mode's path.
PaperCameraPath read_paper_path_file(const std::filesystem::path& file);

/// Refuses (InputError naming the file, the setting and both values) a path file whose recorded
/// made_for differs from `current` on a setting both name. Format 1 files record none.
void check_path_settings(const PathFile& file, const PathSettings& current, const std::filesystem::path& name);


}  // namespace meshtour
