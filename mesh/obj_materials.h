#pragma once
// The OBJ reader's own pass over the file (private to mesh/): faces after fan triangulation with
// their texture coordinates and material, and the materials of every MTL file the OBJ names.
// OpenMesh reads OBJ geometry; it keeps materials in per-face properties that vary between
// versions, so meshtour reads them itself.
#include <Eigen/Core>

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "mesh/mesh.h"

namespace meshtour::obj_detail {

struct ObjFaces {
  struct Triangle {
    std::array<int, 3> vertex, texcoord;  // 0-based; texcoord -1 = none
    int material = -1;                    // index into `materials`, -1 = before any usemtl
  };
  std::vector<Triangle> triangles;  // v0 v1 v2, v0 v2 v3, ... per face, as OpenMesh makes them
  std::vector<Eigen::Vector2f> texcoords;
  std::vector<MeshMaterial> materials;
  /// Per material: the map_Kd's -s (scale u, v) and -o (offset u, v) options.
  std::vector<std::array<float, 4>> uv_transforms;
  std::vector<std::string> warnings;
  /// The MTL files the OBJ names (mtllib) that are missing or unreadable, as the OBJ names them.
  /// Their materials' faces are untextured; load_mesh() decides whether that is an error.
  std::vector<std::string> missing_libraries;
};

/// Reads the faces and the materials of an OBJ whose structure check_mesh_file() has verified.
/// An MTL file it names that is missing or unreadable is listed in `missing_libraries`.
ObjFaces read_obj_faces(const std::filesystem::path& obj_file);

/// Parses the argument of an MTL map statement ("-clamp on -s 2 2 1 my texture.jpg"): the file
/// name (the rest of the line after the options, so names may hold spaces) and the options used.
struct MapStatement {
  std::string file;
  bool clamp = false;
  std::array<float, 4> uv_transform{1, 1, 0, 0};  // scale u, v; offset u, v
};
MapStatement parse_map_statement(const std::string& argument);

}  // namespace meshtour::obj_detail
