#pragma once
// The triangle mesh every stage reads: flat arrays, double-precision positions, no topology.
// Stages that need topology (pathgen) build it from these arrays themselves.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace meshtour {

/// Axis-aligned bounding box.
struct Bounds {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(0.0);
  Eigen::Vector3d hi = Eigen::Vector3d::Constant(0.0);
  Eigen::Vector3d center() const { return 0.5 * (lo + hi); }
  Eigen::Vector3d extent() const { return hi - lo; }
  double diagonal() const { return (hi - lo).norm(); }
};

/// A triangle soup with shared vertices, as loaded from a file or made procedurally.
struct TriangleMesh {
  std::vector<Eigen::Vector3d> positions;
  /// Per-vertex colours in [0,1], as stored in the file (sRGB-encoded display values), or empty.
  std::vector<Eigen::Vector3f> colors;
  /// Vertex indices of each triangle, counter-clockwise seen from outside.
  std::vector<std::array<std::uint32_t, 3>> triangles;
  /// Texture coordinates per triangle corner (3 per triangle, in the order of `triangles`; OBJ
  /// `vt`, origin at the image's bottom left), or empty. Per corner because seams give one vertex
  /// several coordinates.
  std::vector<Eigen::Vector2f> corner_uvs;
  /// The diffuse colour texture (OBJ: `map_Kd` of the MTL file), resolved relative to the mesh
  /// file, or empty. Used only with `corner_uvs`.
  std::filesystem::path texture_file;

  std::size_t vertex_count() const { return positions.size(); }
  std::size_t face_count() const { return triangles.size(); }
  bool has_colors() const { return !colors.empty() && colors.size() == positions.size(); }
  bool has_texture() const { return !texture_file.empty() && corner_uvs.size() == 3 * triangles.size(); }
  /// Bounds of the vertices that some triangle uses (unreferenced vertices do not count).
  Bounds bounds() const;
};

/// The unit normal of the plane in which every vertex some triangle uses lies (within 1e-9 of the
/// bounding-box diagonal), or nothing if the mesh is not flat.
std::optional<Eigen::Vector3d> flat_plane_normal(const TriangleMesh& mesh);

/// What the loader did to the file's contents on the way in.
struct LoadReport {
  std::size_t polygons_triangulated = 0;  ///< faces with more than 3 corners, fan-triangulated
  std::size_t vertices_split = 0;         ///< vertices OpenMesh duplicated to keep non-manifold faces
  std::vector<std::string> warnings;      ///< messages from the reader, one per line
};

/// What a mesh file announces, found by check_mesh_file() without building the mesh.
struct MeshFileSummary {
  std::size_t vertices = 0;  ///< as stored (STL: 3 per triangle, before merging)
  std::size_t faces = 0;     ///< polygons as stored, before triangulation
  std::size_t corners = 0;   ///< sum of the faces' corner counts (3 per triangle)
  /// Triangles after fan triangulation.
  std::size_t triangles() const { return corners >= 2 * faces ? corners - 2 * faces : faces; }
};

/// Checks a mesh file's structure in one pass bounded by its size, before anything is allocated
/// for its contents: counts a header announces must fit in the file, coordinates must be finite,
/// faces must name vertices the file has. Called by load_mesh(); the CLI also calls it first to
/// estimate the memory a job will need.
/// \throw IoError if the file is missing or unreadable, InputError naming the file and the line
///        (text formats) or element at fault.
MeshFileSummary check_mesh_file(const std::filesystem::path& file);

/// Mesh formats the loader understands, for help texts: "obj, ply, off, stl".
std::string supported_mesh_formats();

/// Loads OBJ, PLY (ASCII or binary), OFF or STL through OpenMesh. Polygons are fan-triangulated
/// and per-vertex colours are kept when the file has them.
/// \throw IoError if the file is missing or unreadable, InputError if it holds no usable triangle
///        or its extension is not a supported format.
TriangleMesh load_mesh(const std::filesystem::path& file, LoadReport* report = nullptr);

/// Writes a mesh (PLY with vertex colours when present, or any format OpenMesh writes, by
/// extension). Used by tests and debug output. \throw IoError on failure.
void save_mesh(const TriangleMesh& mesh, const std::filesystem::path& file);

/// The built-in sculpture of the default scene: a pedestal with flat and curved faces, a ring
/// with a hole standing on it, and a bumpy sphere beside it. Y is up, sized about 2 units.
/// `detail` scales the tessellation (1 = about 60k triangles).
TriangleMesh make_sculpture(double detail = 1.0);

}  // namespace meshtour
