// GCC 12 reports OpenMesh's default-constructed colour properties (VectorT<unsigned char, 3>,
// uninitialised by design and filled by the reader) as "may be used uninitialized" depending on
// its inlining choices for this file; the warning is about OpenMesh's code, not this file's.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include "mesh/mesh.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/interrupt.h"
#include "core/triangle_geometry.h"
#include "mesh/file_extension.h"
#include "mesh/gltf.h"
#include "mesh/obj_reader.h"
#include "mesh/openmesh_log.h"
#include "mesh/ply_contents.h"
#include "mesh/off_reader.h"
#include "mesh/stl_reader.h"
#include "mesh/textures.h"

namespace meshtour {
namespace {

struct LoaderTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  VertexAttributes(OpenMesh::Attributes::Status);
  FaceAttributes(OpenMesh::Attributes::Status);
};
using LoaderMesh = OpenMesh::TriMesh_ArrayKernelT<LoaderTraits>;

bool is_supported(const std::string& ext) {
  return ext == ".obj" || ext == ".ply" || ext == ".off" || ext == ".stl" || ext == ".gltf" || ext == ".glb";
}


}  // namespace

bool TriangleMesh::has_texture() const {
  return corner_uvs.size() == 3 * triangles.size() && !triangles.empty() &&
         std::any_of(materials.begin(), materials.end(), [](const MeshMaterial& m) { return m.has_texture(); });
}

Bounds TriangleMesh::bounds() const {
  // The used vertices are marked first, then read in order: a byte per vertex stays in cache where
  // reading each triangle's corners' positions jumped through all of them (9 % of loading a
  // 17.8M-face GLB).
  std::vector<unsigned char> used(positions.size(), 0);
  for (const auto& t : triangles)
    for (const auto vi : t) used[vi] = 1;
  Bounds b;
  bool first = true;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    if (!used[i]) continue;
    const Eigen::Vector3d& p = positions[i];
    if (first) {
      b.lo = b.hi = p;
      first = false;
    } else {
      b.lo = b.lo.cwiseMin(p);
      b.hi = b.hi.cwiseMax(p);
    }
  }
  return b;
}

std::optional<Eigen::Vector3d> flat_plane_normal(const TriangleMesh& mesh) {
  // The largest triangle gives the most reliable normal; all used vertices must lie in its plane.
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d n = triangle_cross(mesh.positions, t);
    if (n.squaredNorm() > normal.squaredNorm()) normal = n;
  }
  if (normal.squaredNorm() == 0.0 || mesh.triangles.empty()) return std::nullopt;
  normal.normalize();
  const Eigen::Vector3d origin = mesh.positions[mesh.triangles.front()[0]];
  const double tolerance = 1e-9 * mesh.bounds().diagonal();
  for (const auto& t : mesh.triangles)
    for (auto v : t)
      if (std::abs((mesh.positions[v] - origin).dot(normal)) > tolerance) return std::nullopt;
  return normal;
}

std::vector<double> face_areas(const std::vector<Eigen::Vector3d>& positions, const std::vector<std::array<std::uint32_t, 3>>& triangles) {
  std::vector<double> area(triangles.size());
  // Every chunk looks at the interrupt flag (a 17.8M-face model takes a while even here).
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, area.size(), 1024), [&](const tbb::blocked_range<std::size_t>& r) {
    throw_if_interrupted();
    for (std::size_t f = r.begin(); f < r.end(); ++f) area[f] = triangle_area(positions, triangles[f]);
  });
  return area;
}

namespace {

// An OBJ, built from what its reader read: positions, colours, triangles, and when it names
// materials, each triangle's material and (when its faces give them) its corners' texture
// coordinates, with each material's map_Kd -s and -o applied.
TriangleMesh obj_mesh(obj_detail::ObjContents& obj) {
  TriangleMesh mesh;
  mesh.positions = std::move(obj.positions);
  mesh.colors = std::move(obj.colors);
  const std::size_t triangles = obj.triangles.size();
  mesh.triangles = std::move(obj.triangles);
  if (obj.materials.empty()) return mesh;
  // Faces before any usemtl get a material of their own, untextured (the look's colour).
  const auto material_of = [&](std::size_t t) { return obj.triangle_materials.empty() ? -1 : obj.triangle_materials[t]; };
  const bool unassigned = obj.triangle_materials.empty() ||
                          std::any_of(obj.triangle_materials.begin(), obj.triangle_materials.end(), [](int m) { return m < 0; });
  const auto fallback = static_cast<std::uint32_t>(obj.materials.size());
  if (unassigned) {
    MeshMaterial none;
    none.name = "(faces before any usemtl)";
    obj.materials.push_back(none);
    obj.uv_transforms.push_back({1, 1, 0, 0});
  }
  const bool uvs = obj.corner_texcoords && !obj.texcoords.empty() && !obj.triangle_texcoords.empty();
  mesh.triangle_materials.reserve(triangles);
  if (uvs) mesh.corner_uvs.reserve(3 * triangles);
  for (std::size_t t = 0; t < triangles; ++t) {
    const int m = material_of(t);
    const std::uint32_t material = m < 0 ? fallback : static_cast<std::uint32_t>(m);
    mesh.triangle_materials.push_back(material);
    if (!uvs) continue;
    const auto& transform = obj.uv_transforms[material];
    for (const int index : obj.triangle_texcoords[t]) {
      Eigen::Vector2f uv = index >= 0 && index < static_cast<int>(obj.texcoords.size()) ? obj.texcoords[static_cast<std::size_t>(index)]
                                                                                         : Eigen::Vector2f::Zero();
      // map_Kd -s and -o: the texture is scaled, then moved, in texture space.
      if (transform != std::array<float, 4>{1, 1, 0, 0}) uv = {uv.x() * transform[0] + transform[2], uv.y() * transform[1] + transform[3]};
      mesh.corner_uvs.push_back(uv);
    }
  }
  mesh.materials = std::move(obj.materials);
  return mesh;
}

}  // namespace

namespace {

// Every reader refuses a file without faces with the same words.
void require_faces(std::size_t triangles, const std::string& name) {
  if (triangles == 0) throw InputError(name + ": mesh has no faces (a point cloud or an empty file cannot be rendered)");
}

// A PLY, built from what its check read: positions, colours, faces (fan-triangulated) and
// strips' triangles, and when it names a texture and has coordinates, their corners' coordinates
// and one material: the image of its TextureFile comment, relative to the PLY.
TriangleMesh ply_mesh(const std::filesystem::path& file, ply_detail::PlyContents contents) {
  TriangleMesh mesh;
  const bool textured = contents.per_vertex || contents.per_corner;
  if (textured) {
    MeshMaterial material;
    material.name = "TextureFile";
    std::string name = contents.texture_file;
    std::replace(name.begin(), name.end(), '\\', '/');
    const std::filesystem::path image(name);
    material.texture_file = image.is_absolute() ? image : file.parent_path() / image;
    material.wrap_s = material.wrap_t = TextureWrap::image_default;  // as OBJ
    mesh.materials.push_back(material);
  }
  mesh.positions = std::move(contents.positions);
  mesh.colors = std::move(contents.colors);
  mesh.triangles = std::move(contents.face_triangles);
  const std::size_t from_faces = mesh.triangles.size();
  mesh.triangles.insert(mesh.triangles.end(), contents.strip_triangles.begin(), contents.strip_triangles.end());
  if (textured) {
    // A corner takes its face's own coordinate (per_corner) where the face lists one per corner,
    // else its vertex's (per_vertex), else (0, 0).
    const auto vertex_uv = [&](std::uint32_t v) -> Eigen::Vector2f {
      return contents.per_vertex ? contents.vertex_uvs[v] : Eigen::Vector2f::Zero();
    };
    mesh.corner_uvs.reserve(3 * mesh.triangles.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
      for (std::size_t k = 0; k < 3; ++k) {
        const bool own = t < from_faces && contents.per_corner && !std::isnan(contents.face_corner_uvs[3 * t + k].x());
        mesh.corner_uvs.push_back(own ? contents.face_corner_uvs[3 * t + k] : vertex_uv(mesh.triangles[t][k]));
      }
  }
  require_faces(mesh.triangles.size(), file.string());
  return mesh;
}

// What every loader's result must have before any stage sees it: finite coordinates, an extent
// and one triangle with an area.
void check_geometry(const TriangleMesh& mesh, const std::string& name) {
  for (std::size_t i = 0; i < mesh.positions.size(); ++i)
    if (!mesh.positions[i].allFinite())
      throw InputError(name + ": vertex " + std::to_string(i) + " has a NaN or infinite coordinate");
  if (mesh.bounds().diagonal() <= 0.0)
    throw InputError(name + ": all vertices coincide; the mesh has no extent to render");
  // Every later stage divides by areas and normals: a mesh without one proper triangle is refused
  // here, naming the file, rather than deep in the path computation.
  const bool has_area = std::any_of(mesh.triangles.begin(), mesh.triangles.end(), [&](const auto& t) {
    const Eigen::Vector3d n = triangle_cross(mesh.positions, t);
    return n.squaredNorm() > 0.0;
  });
  if (!has_area)
    throw InputError(name + ": all " + std::to_string(mesh.triangles.size()) +
                     " faces are degenerate (zero area: their corners are collinear or coincide)");
}

}  // namespace

std::string supported_mesh_formats() { return "obj, ply (ascii or binary), off, stl, gltf, glb"; }

TriangleMesh load_mesh(const std::filesystem::path& file, LoadReport* report, const LoadOptions& load_options) {
  const std::string name = file.string();
  std::error_code ec;
  if (!std::filesystem::exists(file, ec))
    throw IoError(name + ": no such file");
  if (std::filesystem::is_directory(file, ec))
    throw IoError(name + ": is a directory, not a mesh file");
  const std::string ext = lower_extension(file);
  if (!is_supported(ext))
    throw InputError(name + ": unknown mesh format '" + ext + "' (supported: " + supported_mesh_formats() + ")");
  {
    std::ifstream probe(file, std::ios::binary);
    if (!probe) throw IoError(name + ": cannot open for reading (check permissions)");
    if (probe.peek() == std::ifstream::traits_type::eof()) throw InputError(name + ": file is empty");
  }

  // What every reader's model goes through last: the geometry's and the textures' checks, and
  // the report.
  const auto finished = [&](TriangleMesh mesh, std::vector<std::string> warnings, std::size_t polygons) {
    check_geometry(mesh, name);
    check_material_textures(mesh, name, load_options, warnings);
    if (report) {
      report->polygons_triangulated = polygons;
      report->warnings = std::move(warnings);
    }
    return mesh;
  };

  if (ext == ".ply") {
    ply_detail::PlyContents contents;
    ply_detail::read_ply(file, contents);
    const std::size_t polygons = contents.polygons;
    return finished(ply_mesh(file, std::move(contents)), {}, polygons);
  }
  if (ext == ".obj") {
    obj_detail::ObjContents obj = obj_detail::read_obj(file, true);
    require_faces(obj.triangles.size(), name);
    // A material library left behind when the OBJ was copied is the commonest way its textures go
    // missing: the same choice as for a missing texture (mesh/textures.h), an error by default.
    std::vector<std::string> warnings;
    for (const std::string& library : obj.missing_libraries) {
      const std::string what = "the material library '" + library + "' that its mtllib line names is missing or unreadable (looked for " +
                               std::filesystem::absolute(file.parent_path() / library).lexically_normal().string() + ")";
      if (!load_options.check_textures) continue;  // a command that does not render (path) needs no materials
      if (!load_options.missing_textures_grey)
        throw IoError(name + ": " + what + "; put it beside the OBJ, or pass --missing-textures grey to render the model untextured");
      warnings.push_back(what + "; its materials' faces are rendered untextured (--missing-textures grey)");
    }
    warnings.insert(warnings.end(), obj.warnings.begin(), obj.warnings.end());
    return finished(obj_mesh(obj), std::move(warnings), obj.polygons);
  }
  if (ext == ".stl") {
    stl_detail::StlContents stl = stl_detail::read_stl(file, true);
    require_faces(stl.triangles.size(), name);
    TriangleMesh mesh;
    mesh.positions = std::move(stl.positions);
    mesh.triangles = std::move(stl.triangles);
    return finished(std::move(mesh), std::move(stl.warnings), stl.polygons);
  }
  if (ext == ".gltf" || ext == ".glb") {  // its reader checks as it reads (check_mesh_file would parse it twice)
    std::vector<std::string> warnings;
    TriangleMesh mesh = gltf_detail::load_gltf(file, warnings);
    return finished(std::move(mesh), std::move(warnings), 0);
  }

  // OFF (PLY, OBJ, STL and glTF have returned above).
  off_detail::OffContents off = off_detail::read_off(file, true);
  require_faces(off.triangles.size(), name);
  TriangleMesh mesh;
  mesh.positions = std::move(off.positions);
  mesh.colors = std::move(off.colors);
  mesh.triangles = std::move(off.triangles);
  return finished(std::move(mesh), {}, off.polygons);
}

void save_mesh(const TriangleMesh& mesh, const std::filesystem::path& file) {
  LoaderMesh om;
  const bool colors = mesh.has_colors();
  if (colors) om.request_vertex_colors();
  std::vector<LoaderMesh::VertexHandle> handles;
  handles.reserve(mesh.positions.size());
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const auto& p = mesh.positions[i];
    handles.push_back(om.add_vertex(LoaderMesh::Point(p.x(), p.y(), p.z())));
    if (colors) {
      const auto& c = mesh.colors[i];
      auto to8 = [](float v) { return static_cast<unsigned char>(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f); };
      om.set_color(handles.back(), LoaderMesh::Color(to8(c.x()), to8(c.y()), to8(c.z())));
    }
  }
  OpenMeshLogCapture log;
  for (const auto& t : mesh.triangles) om.add_face(handles[t[0]], handles[t[1]], handles[t[2]]);
  OpenMesh::IO::Options options = OpenMesh::IO::Options::Binary;
  if (colors) options += OpenMesh::IO::Options::VertexColor;
  if (!OpenMesh::IO::write_mesh(om, file.string(), options))
    throw IoError(file.string() + ": cannot write mesh");
}

}  // namespace meshtour
