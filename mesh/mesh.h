#pragma once
// The triangle mesh every stage reads: flat arrays, double-precision positions, no topology.
// Stages that need topology (pathgen) build it from these arrays themselves.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
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

/// How a texture lookup outside [0,1] is resolved: glTF sampler wrapS/wrapT; OBJ and PLY repeat,
/// as MTL says (and Blender does), unless `-clamp on`.
enum class TextureWrap { repeat, clamp, mirror };

/// How texels become a colour (glTF sampler magFilter, and minFilter's first part): linear =
/// bilinear between the four nearest texels, nearest = the texel under the point.
enum class TextureFilter { linear, nearest };
/// How minification uses the mipmap (glTF minFilter's second part): none = the full-resolution
/// image alone (glTF NEAREST, LINEAR: aliasing as asked), nearest_level = the one level whose
/// texels match the footprint, linear = between the two nearest levels (trilinear; the default).
enum class MipFilter { none, nearest_level, linear };

/// One image map of a material and how it is looked up.
struct MeshTexture {
  /// The image, resolved relative to the file that names it, or empty (no map). For an embedded
  /// image (glTF data URI or buffer view) a name unique within the model.
  std::filesystem::path file;
  /// The embedded image's encoded bytes (PNG, JPEG, WebP), or null: the image is read from `file`.
  std::shared_ptr<const std::vector<unsigned char>> bytes;
  TextureWrap wrap_s = TextureWrap::repeat, wrap_t = TextureWrap::repeat;
  TextureFilter mag_filter = TextureFilter::linear;  ///< a texel larger than the sample's footprint
  TextureFilter min_filter = TextureFilter::linear;  ///< a footprint larger than a texel
  MipFilter mip_filter = MipFilter::linear;
  bool present() const { return !file.empty(); }
};

/// The names of a material's maps, in messages and (spaces and hyphens as underscores) `info`.
inline constexpr std::array<const char*, 5> kMaterialMapKinds = {"texture", "normal texture", "occlusion texture",
                                                                 "metallic-roughness texture", "emissive texture"};

/// A surface as the file gives it: a colour (factor and optional texture) and an optional normal
/// map. UV transforms (OBJ `-o`/`-s`, glTF KHR_texture_transform) are applied to the triangles'
/// corner_uvs by the loader, so every map of a material reads the same coordinates.
struct MeshMaterial {
  std::string name;  ///< as the file names it (OBJ newmtl, glTF material name or "material <i>")
  /// Linear RGB multiplying the texture or the vertex colours; without a texture and vertex
  /// colours it is the surface's colour. Nothing = the look's base colour (untextured) or 1.
  std::optional<Eigen::Vector3f> base_color;
  /// The base (diffuse) colour texture: sRGB-encoded unless the image is float or says linear.
  MeshTexture texture;
  /// A tangent-space normal map (glTF normalTexture, OBJ `norm`): linear RGB = (x, y, z) * 0.5 +
  /// 0.5, +x along increasing u, +y along increasing v (OBJ's v, up the image), +z the surface
  /// normal; x and y are multiplied by `normal_scale`.
  MeshTexture normal_texture;
  float normal_scale = 1.0f;
  /// An ambient-occlusion map (glTF occlusionTexture): its first (red) channel, linear, darkens the
  /// indirect light only (the sky or environment, not the look's lights), mixed in by `strength`:
  /// 1 + strength * (value - 1).
  MeshTexture occlusion_texture;
  float occlusion_strength = 1.0f;
  /// glTF's metallic-roughness model (the specification's Appendix B BRDF: GGX, Smith, Schlick,
  /// the metal/dielectric mix), or nothing: the look's own diffuse and highlight (OBJ, PLY).
  struct MetallicRoughness {
    float metallic = 1.0f, roughness = 1.0f;  ///< the factors (glTF's defaults), in [0, 1]
    /// Linear; its blue channel multiplies `metallic`, its green `roughness`.
    MeshTexture texture;
  };
  std::optional<MetallicRoughness> metallic_roughness;
  /// Emitted radiance, linear RGB (glTF emissiveFactor times KHR_materials_emissive_strength),
  /// times `emissive_texture` (sRGB) where it has one. Zero: none.
  Eigen::Vector3f emissive = Eigen::Vector3f::Zero();
  MeshTexture emissive_texture;
  /// KHR_materials_unlit: the base colour shows as it is, lit by nothing and casting no light.
  bool unlit = false;
  /// glTF alphaMode. The surface's alpha is `alpha` (baseColorFactor's fourth component) times
  /// the base colour texture's alpha channel where it has one. opaque: alpha is ignored; mask: the
  /// surface is not there where alpha < alpha_cutoff (leaves, lace, cut-outs); blend: it stops a
  /// share alpha of the light and of the view (glass, gauze), the rest passes straight through.
  enum class AlphaMode { opaque, mask, blend };
  AlphaMode alpha_mode = AlphaMode::opaque;
  float alpha = 1.0f;
  float alpha_cutoff = 0.5f;
  /// glTF doubleSided (its default is false): whether a face has a back. False: every ray that
  /// meets a face from behind passes through it (back-face culling, for shadows and occlusion
  /// too, as a rasterizer culls in every pass). OBJ, PLY, STL and OFF say nothing, and an open
  /// scan must show its inside: true.
  bool double_sided = true;
  /// Whether rays must ask the material before they stop at a face (alpha, a single side).
  bool rays_filtered() const { return alpha_mode != AlphaMode::opaque || !double_sided; }
  /// Whether vertex colours multiply the texture (glTF COLOR_0); otherwise a texture replaces them.
  bool texture_times_vertex_colors = false;
  bool has_texture() const { return texture.present(); }
  /// The maps the material has, with their names (kMaterialMapKinds).
  std::vector<std::pair<const MeshTexture*, const char*>> named_maps() const {
    const MeshTexture* all[] = {&texture, &normal_texture, &occlusion_texture,
                                metallic_roughness ? &metallic_roughness->texture : nullptr, &emissive_texture};
    static_assert(std::size(all) == kMaterialMapKinds.size());
    std::vector<std::pair<const MeshTexture*, const char*>> out;
    for (std::size_t k = 0; k < kMaterialMapKinds.size(); ++k)
      if (all[k] && all[k]->present()) out.emplace_back(all[k], kMaterialMapKinds[k]);
    return out;
  }
  /// The same, writable (the texture checks drop a map that cannot be read).
  std::vector<std::pair<MeshTexture*, const char*>> named_maps() {
    std::vector<std::pair<MeshTexture*, const char*>> out;
    for (const auto& [map, name] : std::as_const(*this).named_maps()) out.emplace_back(const_cast<MeshTexture*>(map), name);
    return out;
  }
  /// The maps alone (for checks and memory estimates).
  std::vector<const MeshTexture*> maps() const {
    std::vector<const MeshTexture*> out;
    for (const auto& m : named_maps()) out.push_back(m.first);
    return out;
  }
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
  /// The model's materials (OBJ `usemtl`/MTL, glTF materials), or empty.
  std::vector<MeshMaterial> materials;
  /// Index into `materials` per triangle; empty = every triangle uses material 0 (if any).
  std::vector<std::uint32_t> triangle_materials;
  /// The file's shading normals per triangle corner (3 per triangle, like corner_uvs; glTF
  /// NORMAL), unit length, or empty: the renderer computes smooth normals with creases. A zero
  /// vector: this corner has none (a primitive without NORMAL beside ones with it).
  std::vector<Eigen::Vector3f> corner_normals;
  /// The file's tangents per triangle corner (glTF TANGENT: xyz unit, w = +1 or -1, the bitangent
  /// being cross(normal, tangent) * w), or empty: generated where a normal map needs them.
  std::vector<Eigen::Vector4f> corner_tangents;

  std::size_t vertex_count() const { return positions.size(); }
  std::size_t face_count() const { return triangles.size(); }
  bool has_colors() const { return !colors.empty() && colors.size() == positions.size(); }
  /// Whether some material has a map (colour or normal) and every triangle corner has texture coordinates.
  bool has_texture() const;
  /// The material of triangle `t` (nullptr if the mesh has no materials).
  const MeshMaterial* material_of(std::size_t t) const {
    if (materials.empty()) return nullptr;
    const std::size_t m = triangle_materials.empty() ? 0 : triangle_materials[t];
    return m < materials.size() ? &materials[m] : nullptr;
  }
  /// Bounds of the vertices that some triangle uses (unreferenced vertices do not count).
  Bounds bounds() const;
};

/// Moves every vertex by the affine transform `m` (a scene document's pose of the model). A
/// transform that mirrors (negative determinant) also reverses each triangle's winding, so that
/// faces keep facing out. \throw InputError if `m` is singular or not affine.
void transform_mesh(TriangleMesh& mesh, const Eigen::Matrix4d& m);

/// The unit normal of the plane in which every vertex some triangle uses lies (within 1e-9 of the
/// bounding-box diagonal), or nothing if the mesh is not flat.
std::optional<Eigen::Vector3d> flat_plane_normal(const TriangleMesh& mesh);

/// The area of each triangle (triangle_area, core/triangle_geometry.h), computed in parallel:
/// for a TriangleMesh and for any other mesh held as these two arrays (pathgen's SurfaceMesh).
std::vector<double> face_areas(const std::vector<Eigen::Vector3d>& positions, const std::vector<std::array<std::uint32_t, 3>>& triangles);
inline std::vector<double> face_areas(const TriangleMesh& mesh) { return face_areas(mesh.positions, mesh.triangles); }

/// What the loader did to the file's contents on the way in.
struct LoadReport {
  std::size_t polygons_triangulated = 0;  ///< faces with more than 3 corners, fan-triangulated
  std::vector<std::string> warnings;      ///< messages from the reader, one per line
};

/// How the loader treats the files a model refers to.
struct LoadOptions {
  /// A texture that is missing or unreadable: false = an error naming the file and the material;
  /// true (--missing-textures grey) = that material is drawn untextured and the report warns.
  bool missing_textures_grey = false;
  /// false: the materials' textures are not opened (commands that do not render, e.g. `path`).
  bool check_textures = true;
};

/// The size of a material's texture as its file's header gives it.
struct TextureSize {
  int width = 0, height = 0, channels = 0;
};

/// Opens a material's texture (file or embedded bytes) and reads its header.
/// 	hrow IoError naming the texture and the material if it is missing or not a readable image.
TextureSize probe_texture(const MeshTexture& map, const std::string& material_name);
/// The same for the material's base colour texture.
inline TextureSize probe_texture(const MeshMaterial& material) { return probe_texture(material.texture, material.name); }

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

/// Loads OBJ, PLY (ASCII or binary), OFF (text or binary), STL (ASCII or binary), glTF or GLB
/// with meshtour's own readers (tinygltf parses glTF). Polygons are fan-triangulated, per-vertex
/// colours are kept when the file has them, and the file's vertices are kept as it lists them
/// (STL's per-facet corners merged where bit-identical, glTF's where every attribute agrees).
/// \throw IoError if the file is missing or unreadable, InputError if it holds no usable triangle
///        or its extension is not a supported format.
TriangleMesh load_mesh(const std::filesystem::path& file, LoadReport* report = nullptr, const LoadOptions& options = {});

/// Writes a mesh through OpenMesh (PLY with vertex colours when present, or any format OpenMesh
/// writes, by extension). Used by tests and debug output. \throw IoError on failure.
void save_mesh(const TriangleMesh& mesh, const std::filesystem::path& file);

/// The built-in sculpture of the default scene: a pedestal with flat and curved faces, a ring
/// with a hole standing on it, and a bumpy sphere beside it. Y is up, sized about 2 units.
/// `detail` scales the tessellation (1 = about 60k triangles).
TriangleMesh make_sculpture(double detail = 1.0);

}  // namespace meshtour
