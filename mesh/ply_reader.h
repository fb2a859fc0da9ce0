#pragma once
// The PLY reader (private to mesh/): one pass over the file that checks it (the header's strict
// grammar, counts within the file, finite coordinates, colours within 0..1, faces naming vertices
// the file has; errors name the line or element) and, when asked, reads it. load_mesh builds every
// PLY from what it reads rather than through OpenMesh: the check walks the whole body anyway, and
// OpenMesh then read it again and built half-edges the loader threw away: the bunny split to 17.8M
// faces loaded in 17.6 s, now 1.38 s (bench/load_bench BM_LoadPly/4). It also keeps the file's
// vertices where OpenMesh gave non-manifold faces copies of theirs. And it reads what OpenMesh
// cannot: MeshLab's and scanners' texture coordinates, per vertex (texture_u/texture_v, s/t or
// u/v) or per face corner (a face list 'texcoord' of 2 values per corner) with the image named in
// a header comment 'comment TextureFile x.jpg', and triangle strips.
#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "mesh/mesh.h"

namespace meshtour::ply_detail {

struct PlyContents {
  MeshFileSummary summary;   ///< vertices, faces and corners as stored (strips' triangles as faces)
  std::string texture_file;  ///< the TextureFile comment's name, as written, or empty
  bool per_vertex = false;   ///< vertex_uvs holds one coordinate per vertex (a texture is named)
  bool per_corner = false;   ///< faces carry their corners' coordinates (a texture is named)
  std::vector<Eigen::Vector2f> vertex_uvs;
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector3f> colors;  ///< sRGB-encoded in [0,1], or empty
  /// The faces, fan-triangulated in file order, and with per_corner, each triangle corner's
  /// coordinates (NaN where the face's texcoord list does not match its corners: the vertex's).
  std::vector<std::array<std::uint32_t, 3>> face_triangles;
  std::vector<Eigen::Vector2f> face_corner_uvs;
  std::size_t polygons = 0;  ///< faces with more than 3 corners
  /// Triangle strips (an element 'tristrips' with a list 'vertex_indices', -1 ending a strip, as
  /// Cyberware and some Stanford scans are stored). Alternate triangles of a strip are turned so
  /// that all keep the strip's winding; degenerate ones (a repeated index, which joins strips) are
  /// dropped.
  std::vector<std::array<std::uint32_t, 3>> strip_triangles;
};

/// Checks a PLY file and, with `read`, reads it (else only `summary` is filled). The file must
/// exist and not be empty (check_mesh_file and load_mesh say so first).
/// \throw InputError naming the file and the header line or element of the first fault.
PlyContents read_ply(const std::filesystem::path& file, bool read);

}  // namespace meshtour::ply_detail
