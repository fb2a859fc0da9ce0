#pragma once
// Texture coordinates of a PLY file (private to mesh/): MeshLab and scanner software write them
// per vertex (texture_u/texture_v, s/t or u/v) or per face corner (a face list 'texcoord' of
// 2 values per corner), and name the image in a header comment 'comment TextureFile x.jpg'.
#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "mesh/mesh.h"

namespace meshtour::ply_detail {

struct PlyTexture {
  std::string texture_file;  ///< the TextureFile comment's name, as written, or empty
  bool per_vertex = false;   ///< vertex_uvs holds one coordinate per vertex
  bool per_corner = false;   ///< faces carry their corners' coordinates
  std::vector<Eigen::Vector2f> vertex_uvs;
  // OpenMesh's PLY reader misreads faces that carry a list after their vertex indices, so a
  // textured PLY is built from what the check collected: positions and colours too.
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector3f> colors;  ///< sRGB-encoded in [0,1], or empty
  struct Face {
    std::vector<std::uint32_t> vertices;
    std::vector<Eigen::Vector2f> uvs;  ///< per corner, when per_corner
  };
  std::vector<Face> faces;  ///< kept only when the file has a texture and coordinates
  /// Triangle strips (an element 'tristrips' with a list 'vertex_indices', -1 ending a strip, as
  /// Cyberware and some Stanford scans are stored): OpenMesh reads no faces from them, so a PLY
  /// that has them is built from what the check collected, like a textured one. Alternate
  /// triangles of a strip are turned so that all keep the strip's winding; degenerate ones (a
  /// repeated index, which joins strips) are dropped.
  bool strips = false;
  std::vector<std::array<std::uint32_t, 3>> strip_triangles;
};

/// check_mesh_file() for a PLY, also collecting its texture coordinates into `texture`.
MeshFileSummary check_ply_with_texture(const std::filesystem::path& file, PlyTexture& texture);

}  // namespace meshtour::ply_detail
