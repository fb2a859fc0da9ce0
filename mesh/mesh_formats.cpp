// The one dispatch by format (mesh/mesh_formats.h): the table, each format's check and reader,
// and check_mesh_file and load_mesh, which choose from it.
#include "mesh/mesh_formats.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>

#include "core/error.h"
#include "core/triangle_geometry.h"
#include "mesh/file_extension.h"
#include "mesh/gltf.h"
#include "mesh/obj_reader.h"
#include "mesh/off_reader.h"
#include "mesh/ply_reader.h"
#include "mesh/stl_reader.h"
#include "mesh/textures.h"

namespace meshtour::mesh_formats {
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
  // Vertex colours are the scan's colour: an MTL's Kd (exporters write 0.8 or 1 by default) does
  // not tint them (docs/FORMATS.md, OBJ materials).
  if (!mesh.colors.empty())
    for (MeshMaterial& m : obj.materials) m.base_color.reset();
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
    material.texture.file = image.is_absolute() ? image : file.parent_path() / image;
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
    return triangle_cross(mesh.positions, t).squaredNorm() > 0.0;
  });
  if (!has_area)
    throw InputError(name + ": all " + std::to_string(mesh.triangles.size()) +
                     " faces are degenerate (zero area: their corners are collinear or coincide)");
}

// The map_Bump/bump images of the materials some face uses (obj_reader.h): a normal map is the
// material's normal map (its -bm the scale); a height map is said and left out (meshtour does no
// bump mapping from heights). One that cannot be read is an error or, with --missing-textures
// grey, a warning, as any texture.
void take_bump_normal_maps(obj_detail::ObjContents& obj, const std::string& name, const LoadOptions& load_options,
                           std::vector<std::string>& warnings) {
  std::vector<bool> used(obj.materials.size(), obj.triangle_materials.empty());
  for (const int m : obj.triangle_materials)
    if (m >= 0 && static_cast<std::size_t>(m) < used.size()) used[static_cast<std::size_t>(m)] = true;
  for (std::size_t m = 0; m < obj.materials.size(); ++m) {
    const obj_detail::ObjContents::BumpMap& bump = obj.bump_maps[m];
    MeshMaterial& material = obj.materials[m];
    if (!bump.map.present() || !used[m] || material.normal_texture.present()) continue;
    if (!verify_or_warn(bump.map, material.name, "bump map", "without it", name, load_options, warnings)) continue;
    if (reads_as_normal_map(bump.map, material.name)) {
      material.normal_texture = bump.map;
      material.normal_scale = bump.scale;
    } else {
      warnings.push_back(bump.map.file.string() + ": the bump map of material '" + material.name +
                         "' is a height map, not a normal map; meshtour does not bump-map from heights, so its faces are "
                         "rendered without it");
    }
  }
}

ReadMesh read_obj_mesh(const std::filesystem::path& file, const LoadOptions& load_options) {
  const std::string name = file.string();
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
  if (load_options.check_textures) take_bump_normal_maps(obj, name, load_options, warnings);
  const std::size_t polygons = obj.polygons;
  return {obj_mesh(obj), std::move(warnings), polygons};
}

ReadMesh read_ply_mesh(const std::filesystem::path& file, const LoadOptions&) {
  ply_detail::PlyContents contents = ply_detail::read_ply(file, true);
  const std::size_t polygons = contents.polygons;
  return {ply_mesh(file, std::move(contents)), {}, polygons};
}

ReadMesh read_off_mesh(const std::filesystem::path& file, const LoadOptions&) {
  off_detail::OffContents off = off_detail::read_off(file, true);
  require_faces(off.triangles.size(), file.string());
  TriangleMesh mesh;
  mesh.positions = std::move(off.positions);
  mesh.colors = std::move(off.colors);
  mesh.triangles = std::move(off.triangles);
  return {std::move(mesh), {}, off.polygons};
}

ReadMesh read_stl_mesh(const std::filesystem::path& file, const LoadOptions&) {
  stl_detail::StlContents stl = stl_detail::read_stl(file, true);
  require_faces(stl.triangles.size(), file.string());
  TriangleMesh mesh;
  mesh.positions = std::move(stl.positions);
  mesh.triangles = std::move(stl.triangles);
  return {std::move(mesh), std::move(stl.warnings), stl.polygons};
}

// glTF's reader checks as it reads (a check first would parse the JSON twice).
ReadMesh read_gltf_mesh(const std::filesystem::path& file, const LoadOptions&) {
  ReadMesh read;
  read.mesh = gltf_detail::load_gltf(file, read.warnings);
  return read;
}

MeshFileSummary check_obj(const std::filesystem::path& file) { return obj_detail::read_obj(file, false).summary; }
MeshFileSummary check_ply(const std::filesystem::path& file) { return ply_detail::read_ply(file, false).summary; }
MeshFileSummary check_off(const std::filesystem::path& file) { return off_detail::read_off(file, false).summary; }
MeshFileSummary check_stl(const std::filesystem::path& file) { return stl_detail::read_stl(file, false).summary; }

// glTF 2.0 fixes +Y up (its specification, "Coordinate System and Units").
constexpr Axis kGltfUp{1, false};

const MeshFormat kFormats[] = {
    // The formats without an up axis are toured by shape: on the evaluation set --up auto is wrong
    // on far fewer models than +y (docs/EVALUATION.md#the-default-up-axis). glTF keeps its +Y
    // unless the shape clearly disagrees (then a warning), which is what auto does for it.
    {".obj", "obj", check_obj, read_obj_mesh, std::nullopt, true},
    {".ply", "ply (ascii or binary)", check_ply, read_ply_mesh, std::nullopt, true},
    {".off", "off", check_off, read_off_mesh, std::nullopt, true},
    {".stl", "stl", check_stl, read_stl_mesh, std::nullopt, true},
    {".gltf", "gltf", gltf_detail::gltf_summary, read_gltf_mesh, kGltfUp, true},
    {".glb", "glb", gltf_detail::gltf_summary, read_gltf_mesh, kGltfUp, true},
};

}  // namespace

std::span<const MeshFormat> all() { return kFormats; }

const MeshFormat* find(std::string_view extension) {
  std::string lower(extension);
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const MeshFormat& format : kFormats)
    if (format.extension == lower) return &format;
  return nullptr;
}

const MeshFormat& format_of_file(const std::filesystem::path& file) {
  const std::string name = file.string();
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) throw IoError(name + ": no such file");
  if (std::filesystem::is_directory(file, ec)) throw IoError(name + ": is a directory, not a mesh file");
  const std::string ext = lower_extension(file);
  const MeshFormat* format = find(ext);
  if (!format) throw InputError(name + ": unknown mesh format '" + ext + "' (supported: " + supported_mesh_formats() + ")");
  std::ifstream probe(file, std::ios::binary);
  if (!probe) throw IoError(name + ": cannot open for reading (check permissions)");
  if (probe.peek() == std::ifstream::traits_type::eof()) throw InputError(name + ": file is empty");
  return *format;
}

}  // namespace meshtour::mesh_formats

namespace meshtour {

std::string supported_mesh_formats() {
  std::string list;
  for (const mesh_formats::MeshFormat& format : mesh_formats::all()) {
    if (!list.empty()) list += ", ";
    list += format.help;
  }
  return list;
}

MeshFileSummary check_mesh_file(const std::filesystem::path& file) { return mesh_formats::format_of_file(file).check(file); }

TriangleMesh load_mesh(const std::filesystem::path& file, LoadReport* report, const LoadOptions& load_options) {
  const std::string name = file.string();
  mesh_formats::ReadMesh read = mesh_formats::format_of_file(file).read(file, load_options);
  // What every reader's model goes through last: the geometry's and the textures' checks, and
  // the report.
  mesh_formats::check_geometry(read.mesh, name);
  check_material_textures(read.mesh, name, load_options, read.warnings);
  if (report) {
    report->polygons_triangulated = read.polygons;
    report->warnings = std::move(read.warnings);
  }
  return std::move(read.mesh);
}

}  // namespace meshtour
