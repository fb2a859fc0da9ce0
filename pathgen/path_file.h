#pragma once
// The path file: the JSON that `meshtour path` writes (results, metrics, options, timings) and
// from which read_path_file() rebuilds the camera path without the mesh.
#include <filesystem>
#include <memory>
#include <string>

#include "core/atomic_file.h"  // write_file_atomically, used by every writer in pathgen
#include "pathgen/camera_path.h"
#include "pathgen/paper_path.h"

namespace meshtour {

/// Version of the layout below; read_path_file() rejects any other.
inline constexpr int kPathFormatVersion = 1;

/// Writes the path file of `result` atomically (a temporary file in the same folder, renamed
/// over `file` when complete). `source` names the input mesh for the record ("" to omit).
/// \throw IoError if the file cannot be written.
void write_path_file(const PaperPathResult& result, const std::filesystem::path& file,
                     const std::string& source = "");

/// The JSON text write_path_file() writes.
std::string path_file_text(const PaperPathResult& result, const std::string& source = "");

/// Rebuilds the camera path (a PaperCameraPath, model units) from a path file alone.
/// \throw IoError if the file cannot be read, InputError (naming the file and the key) if it is
///        not a path file of format_version 1 or a key it needs is missing or invalid.
std::unique_ptr<CameraPath> read_path_file(const std::filesystem::path& file);

/// Same, returning the concrete type (its geometry() exposes the curves).
PaperCameraPath read_paper_path_file(const std::filesystem::path& file);


}  // namespace meshtour
