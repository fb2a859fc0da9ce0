#pragma once
// The mesh formats meshtour reads, one row each (private to mesh/; as pmp's io/ chooses a reader
// by extension in one place): the extension, the words help texts show, the check that reads a
// file's structure without building its model (check_mesh_file), the reader that builds the model
// (load_mesh), and the up axis the format's specification fixes. check_mesh_file, load_mesh,
// supported_mesh_formats and format_up_axis all read this table; a new format is a new row.
#include <cstddef>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/axis.h"
#include "mesh/mesh.h"

namespace meshtour::mesh_formats {

/// What a format's reader gives load_mesh before the checks every model goes through.
struct ReadMesh {
  TriangleMesh mesh;
  std::vector<std::string> warnings;  ///< one message per line, for LoadReport::warnings
  std::size_t polygons = 0;           ///< faces with more than 3 corners, fan-triangulated
};

struct MeshFormat {
  std::string_view extension;  ///< lower case, with the dot: ".ply"
  std::string_view help;       ///< as supported_mesh_formats() lists it: "ply (ascii or binary)"
  /// check_mesh_file() for the format: a pass over the file that builds nothing.
  MeshFileSummary (*check)(const std::filesystem::path& file);
  /// Reads the model (the file exists and is not empty). \throw InputError / IoError naming the file.
  ReadMesh (*read)(const std::filesystem::path& file, const LoadOptions& options);
  /// The up axis the format's specification prescribes (glTF: +Y), if any.
  std::optional<Axis> up;
  /// Without --up, whether the up axis is chosen by shape (--up auto, which keeps `up` where the
  /// format prescribes one unless the shape clearly disagrees), or is +y. The decision and the
  /// evaluation it rests on: docs/EVALUATION.md#the-default-up-axis.
  bool up_by_shape = false;
};

/// Every format, in the order help texts list them.
std::span<const MeshFormat> all();

/// The row for `extension` (any case, with the dot), or null.
const MeshFormat* find(std::string_view extension);

/// The row for `file`'s extension, once the file is known to be there and readable.
/// \throw IoError if the file is missing, a directory or unreadable; InputError if its extension
///        is not a supported format or it is empty.
const MeshFormat& format_of_file(const std::filesystem::path& file);

}  // namespace meshtour::mesh_formats
