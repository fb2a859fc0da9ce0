#pragma once
// The OBJ reader (private to mesh/): one pass over the file that checks it (counts within the file,
// indices naming what is defined before them, finite coordinates, colours within 0..1; errors name
// the line) and, when asked, reads it: positions, vertex colours, faces fan-triangulated with
// their texture coordinates and material, and the materials of every MTL file it names. It
// replaced OpenMesh's reader and a second pass that matched OpenMesh's faces back to the file's
// for their materials: the bunny split to 4.5M faces as OBJ loaded in 23.4 s and was checked in
// 6.3 s more, now 1.75 s and 1.39 s (bench/load_bench BM_LoadObj: 22 ms to 6.1 s from 70k to
// 17.8M faces). Positions keep the file's double precision (OpenMesh rounded them to float), and
// non-manifold faces keep the file's vertices (OpenMesh gave them copies). Loading the 17.8M-face
// OBJ peaks at 0.73 GB (1.28 GB while every triangle carried texture coordinate and material
// slots, and was copied into the model's form; /usr/bin/time -v on a load_mesh call).
#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "mesh/mesh.h"

namespace meshtour::obj_detail {

/// One MTL map statement's file and the options meshtour uses (parse_map_statement).
struct MapStatement {
  std::string file;
  bool clamp = false;
  std::array<float, 4> uv_transform{1, 1, 0, 0};  // scale u, v; offset u, v
  float bump_multiplier = 1.0f;                   // -bm: a normal map's scale
};

struct ObjContents {
  MeshFileSummary summary;  ///< counts as stored (faces before triangulation)
  std::vector<Eigen::Vector3d> positions;
  /// Per vertex, when a vertex line carries a colour ("v x y z r g b"); white where one does not.
  std::vector<Eigen::Vector3f> colors;
  /// Vertex indices (0-based) per triangle: v0 v1 v2, v0 v2 v3, ... per face; the model's own
  /// form, moved into it. What only some files have is held only by them (a 17.8M-face scan
  /// without texture coordinates or materials held 28 bytes per triangle, now 12):
  std::vector<std::array<std::uint32_t, 3>> triangles;
  /// Per triangle, its corners' texture coordinate indices (0-based, -1 = none); empty when no
  /// face corner names one (-1 for the triangles before the first that does).
  std::vector<std::array<int, 3>> triangle_texcoords;
  /// Per triangle, its index into `materials` (-1 = before any usemtl); empty when no face
  /// follows a usemtl.
  std::vector<int> triangle_materials;
  std::size_t polygons = 0;         ///< faces with more than 3 corners
  bool corner_texcoords = false;    ///< some face corner names a texture coordinate
  std::vector<Eigen::Vector2f> texcoords;
  std::vector<MeshMaterial> materials;
  /// Per material: the map_Kd's -s (scale u, v) and -o (offset u, v) options.
  std::vector<std::array<float, 4>> uv_transforms;
  /// Per material: the image of its map_Bump or bump statement (and -bm) when it has no `norm`.
  /// The MTL specification's bump map is a height map, but exporters (Blender's among them) write
  /// tangent-space normal maps there: load_mesh() looks at the image and takes it as the normal
  /// map only if it is one (mesh/textures.h, reads_as_normal_map). Empty file: none.
  struct BumpMap {
    MeshTexture map;     ///< no file: none
    float scale = 1.0f;  ///< -bm
  };
  std::vector<BumpMap> bump_maps;
  std::vector<std::string> warnings;
  /// The MTL files the OBJ names (mtllib) that are missing or unreadable, as the OBJ names them.
  /// Their materials' faces are untextured; load_mesh() decides whether that is an error.
  std::vector<std::string> missing_libraries;
};

/// Checks an OBJ file and, with `read`, reads it (else only `summary` is filled). The file must
/// exist and not be empty (check_mesh_file and load_mesh say so first).
/// \throw InputError naming the file and the line of the first fault.
ObjContents read_obj(const std::filesystem::path& file, bool read);

/// Parses the argument of an MTL map statement ("-clamp on -s 2 2 1 my texture.jpg"): the file
/// name (the rest of the line after the options, so names may hold spaces) and the options used.
MapStatement parse_map_statement(const std::string& argument);

}  // namespace meshtour::obj_detail
