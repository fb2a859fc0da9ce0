// The renderer: the Embree scene's set-up, and a frame's flow: its set-up (camera, lights,
// ground), its tiles traced by the tile kernel (tile_kernel.cpp) onto the Film (film.h), the Film
// gathered, the denoiser run on the Film's layers, and the layers written into the Image.
#include <Eigen/Geometry>
#include <OpenImageIO/imagecache.h>
#include <OpenImageIO/strutil.h>
#include <OpenImageIO/texture.h>
#include <embree3/rtcore.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <cmath>
#include <limits>
#include <mutex>
#include <numbers>
#include <string>

#include "core/error.h"
#include "core/interrupt.h"
#include "core/portable_math.h"
#include "tracer/color.h"
#include "tracer/denoiser.h"
#include "tracer/film.h"
#include "tracer/random.h"
#include "mesh/tangents.h"
#include "tracer/renderer_impl.h"
#include "tracer/renderer_internal.h"
#include "tracer/tracer.h"


namespace meshtour {
namespace {

float luminance(const Eigen::Vector3f& c) { return 0.2126f * c.x() + 0.7152f * c.y() + 0.0722f * c.z(); }

// An orthonormal basis around a unit vector (Duff et al. 2017, "Building an orthonormal basis,
// revisited"): branch-free apart from the sign, and continuous away from n.z = -1.
void basis(const Eigen::Vector3f& n, Eigen::Vector3f& t, Eigen::Vector3f& b) {
  const float sign = std::copysign(1.0f, n.z());
  const float a = -1.0f / (sign + n.z());
  const float c = n.x() * n.y() * a;
  t = Eigen::Vector3f(1.0f + sign * n.x() * n.x() * a, sign * c, -sign * n.x());
  b = Eigen::Vector3f(c, sign + n.y() * n.y() * a, -n.y());
}

// The widest instruction set this CPU runs (all give the same pixels). The variable
// MESHTOUR_TILE_KERNEL=baseline|x86-64-v3|x86-64-v4 forces one (tests compare them).
InstructionSet choose_instruction_set() {
#if defined(MESHTOUR_TILE_KERNELS_X86_64)
  const bool v3 = cpu_runs(InstructionSet::x86_64_v3), v4 = cpu_runs(InstructionSet::x86_64_v4);
  if (const char* forced = std::getenv("MESHTOUR_TILE_KERNEL"); forced && *forced) {
    const std::string name = forced;
    if (name == "baseline") return InstructionSet::baseline;
    if (name == "x86-64-v3" && v3) return InstructionSet::x86_64_v3;
    if (name == "x86-64-v4" && v4) return InstructionSet::x86_64_v4;
    throw InputError("MESHTOUR_TILE_KERNEL=" + name + ": not a kernel this CPU runs (baseline" + (v3 ? ", x86-64-v3" : "") +
                     (v4 ? ", x86-64-v4" : "") + ")");
  }
  if (v4) return InstructionSet::x86_64_v4;
  if (v3) return InstructionSet::x86_64_v3;
#endif
  return InstructionSet::baseline;
}

// The copy of the tile kernel compiled for `set`.
Renderer::Impl::TileKernel tile_kernel_for(InstructionSet set) {
  using Impl = Renderer::Impl;
  switch (set) {
#if defined(MESHTOUR_TILE_KERNELS_X86_64)
    case InstructionSet::x86_64_v3: return &Impl::render_tile<InstructionSet::x86_64_v3>;
    case InstructionSet::x86_64_v4: return &Impl::render_tile<InstructionSet::x86_64_v4>;
#endif
    default: return &Impl::render_tile<InstructionSet::baseline>;
  }
}

OIIO::TextureOpt::Wrap wrap_mode(TextureWrap wrap) {
  switch (wrap) {
    case TextureWrap::clamp: return OIIO::TextureOpt::WrapClamp;
    case TextureWrap::mirror: return OIIO::TextureOpt::WrapMirror;
    case TextureWrap::repeat: break;
  }
  return OIIO::TextureOpt::WrapPeriodic;
}

OIIO::TextureOpt::InterpMode interp_mode(TextureFilter filter) {
  return filter == TextureFilter::nearest ? OIIO::TextureOpt::InterpClosest : OIIO::TextureOpt::InterpBilinear;
}

OIIO::TextureOpt::MipMode mip_mode(MipFilter filter) {
  switch (filter) {
    case MipFilter::none: return OIIO::TextureOpt::MipModeNoMIP;
    case MipFilter::nearest_level: return OIIO::TextureOpt::MipModeOneLevel;
    case MipFilter::linear: break;
  }
  return OIIO::TextureOpt::MipModeTrilinear;
}

// What a map holds: colour (8-bit values sRGB-encoded), a normal (linear RGB) or a scalar in its
// first channel (linear; glTF occlusion's red channel, a grey image's grey).
enum class MapData { colour, normal, scalar };

// Opens one map of a material in the renderer's texture system (made at the first map: its cache
// holds the tiles of every atlas within one memory budget).
Renderer::Impl::Map open_map(Renderer::Impl& s, const MeshTexture& t, const std::string& material, const char* kind, MapData data) {
  const bool colour = data == MapData::colour;
  Renderer::Impl::Map map;
  map.wrap_s = wrap_mode(t.wrap_s);
  map.wrap_t = wrap_mode(t.wrap_t);
  map.mag_interp = interp_mode(t.mag_filter);
  map.min_interp = interp_mode(t.min_filter);
  map.mip = mip_mode(t.mip_filter);
  if (!s.textures) {
    s.textures.reset(OIIO::TextureSystem::create(/*shared=*/false));
    // Untiled images (JPEG, PNG atlases) are cached in 64x64 tiles rather than whole, so the
    // cache's memory cap holds for 16k atlases too (the texels and the filtering are the same).
    s.textures->attribute("autotile", 64);
    // Colours as the file stores them, alpha apart (glTF's and PNG's straight alpha): the
    // default would premultiply them, darkening every partly transparent texel's colour.
    s.textures->attribute("unassociatedalpha", 1);
  }
  const OIIO::ustring texture_name(t.file.string());
  if (t.bytes) {
    s.embedded_bytes.push_back(t.bytes);
    s.embedded_images.push_back(std::make_unique<ImageBytesReader>(t.bytes->data(), t.bytes->size()));
    OIIO::ImageSpec config;
    void* proxy = s.embedded_images.back().get();
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
    s.textures->imagecache()->add_file(texture_name, nullptr, &config);
  }
  int readable = 0;  // "exists" is 1 only for a file OpenImageIO can open as an image
  s.textures->get_texture_info(texture_name, 0, OIIO::ustring("exists"), OIIO::TypeInt, &readable);
  map.handle = readable ? s.textures->get_texture_handle(texture_name) : nullptr;
  if (!map.handle || !s.textures->good(map.handle))
    throw IoError(t.file.string() + ": cannot read the " + kind + " of material '" + material + "' (" + s.textures->geterror() +
                  "); check the file the model names it in, or pass --missing-textures grey");
  // OpenImageIO 2.4's texture system returns the file's values as stored (it has no colour
  // transform), so the encoding is decided here: integer colour images (PNG, JPEG, WebP, 8/16-bit
  // TIFF: scans' atlases, glTF base colour) are sRGB-encoded unless the file says linear; float
  // images (EXR, HDR) and every normal map hold linear values.
  int format = 0;
  s.textures->get_texture_info(map.handle, nullptr, 0, OIIO::ustring("format"), OIIO::TypeInt, &format);
  OIIO::ustring color_space;
  s.textures->get_texture_info(map.handle, nullptr, 0, OIIO::ustring("oiio:ColorSpace"), OIIO::TypeString, &color_space);
  const bool float_data = format == OIIO::TypeDesc::HALF || format == OIIO::TypeDesc::FLOAT || format == OIIO::TypeDesc::DOUBLE;
  // A grey map (1 channel, or grey and alpha) is looked up as its first channel, made grey RGB.
  int channels = 3;
  s.textures->get_texture_info(map.handle, nullptr, 0, OIIO::ustring("channels"), OIIO::TypeInt, &channels);
  map.grey = channels <= 2;
  map.alpha_channel = channels == 4 ? 3 : channels == 2 ? 1 : -1;
  if (data == MapData::normal && map.grey)
    throw InputError(t.file.string() + ": the " + std::string(kind) + " of material '" + material +
                     "' is a grey image; a normal map needs RGB (x, y, z)");
  int resolution[2] = {1, 1};
  s.textures->get_texture_info(map.handle, nullptr, 0, OIIO::ustring("resolution"), OIIO::TypeDesc(OIIO::TypeDesc::INT, 2), resolution);
  map.texels_across = static_cast<float>(std::max({resolution[0], resolution[1], 1}));
  map.srgb = colour && !float_data && !OIIO::Strutil::iequals(color_space.string(), "linear");
  return map;
}

// One Surface per mesh material, with its maps opened.
void set_up_surfaces(Renderer::Impl& s, const TriangleMesh& mesh, bool use_texture, bool file_material) {
  if (mesh.materials.empty()) return;
  const bool textured = use_texture && mesh.has_texture();
  for (const MeshMaterial& m : mesh.materials) {
    Renderer::Impl::Surface surface;
    surface.factor = m.base_color.value_or(Eigen::Vector3f::Ones());
    surface.replaces_base_color = m.base_color.has_value();
    surface.texture_times_vertex_colors = m.texture_times_vertex_colors;
    if (textured && m.texture.present()) surface.texture = open_map(s, m.texture, m.name, "texture", MapData::colour);
    if (textured && m.normal_texture.present()) {
      surface.normal_map = open_map(s, m.normal_texture, m.name, "normal texture", MapData::normal);
      surface.normal_scale = m.normal_scale;
    }
    if (textured && m.occlusion_texture.present()) {
      surface.occlusion_map = open_map(s, m.occlusion_texture, m.name, "occlusion texture", MapData::scalar);
      surface.occlusion_strength = m.occlusion_strength;
    }
    // The file's own shading (its BRDF, light and unlit flag) where the look takes it.
    if (file_material && m.metallic_roughness) {
      surface.metallic_roughness = true;
      surface.metallic = std::clamp(m.metallic_roughness->metallic, 0.0f, 1.0f);
      surface.roughness = std::clamp(m.metallic_roughness->roughness, 0.0f, 1.0f);
      if (textured && m.metallic_roughness->texture.present())
        surface.metallic_roughness_map = open_map(s, m.metallic_roughness->texture, m.name, "metallic-roughness texture", MapData::scalar);
    }
    if (file_material) {
      surface.emissive = m.emissive.cwiseMax(0.0f);
      if (textured && m.emissive_texture.present() && surface.emissive.squaredNorm() > 0.0f)
        surface.emissive_map = open_map(s, m.emissive_texture, m.name, "emissive texture", MapData::colour);
      surface.unlit = m.unlit;
    }
    surface.alpha_mode = m.alpha_mode;
    surface.alpha = std::clamp(m.alpha, 0.0f, 1.0f);
    surface.alpha_cutoff = m.alpha_cutoff;
    surface.double_sided = m.double_sided;
    s.filtered_rays = s.filtered_rays || surface.rays_filtered();
    s.surfaces.push_back(surface);
  }
  s.triangle_surface = mesh.triangle_materials;
  for (const std::uint32_t m : s.triangle_surface)
    if (m >= s.surfaces.size()) throw InputError("the mesh has a triangle whose material index is out of range");
  if (!s.textures) return;
  s.corner_uvs = mesh.corner_uvs;
  s.uv_scale.resize(s.triangles.size());
  for (std::size_t i = 0; i < s.triangles.size(); ++i) {
    const auto& t = s.triangles[i];
    const float world = (s.positions[t[1]] - s.positions[t[0]]).cross(s.positions[t[2]] - s.positions[t[0]]).norm();
    const Eigen::Vector2f a = s.corner_uvs[3 * i + 1] - s.corner_uvs[3 * i], b = s.corner_uvs[3 * i + 2] - s.corner_uvs[3 * i];
    const float uv = std::abs(a.x() * b.y() - a.y() * b.x());
    s.uv_scale[i] = world > 0.0f ? std::sqrt(uv / world) : 0.0f;
  }
}

// The shading normals per corner where the file has its own (a corner without one takes the
// smooth vertex normal), and, where some surface has a normal map, per-corner tangents: the
// file's, else generated (mesh/tangents.h) against these normals.
void set_up_corner_frames(Renderer::Impl& s, const TriangleMesh& mesh) {
  const std::size_t corners = 3 * s.triangles.size();
  const bool mapped = std::any_of(s.surfaces.begin(), s.surfaces.end(), [](const Renderer::Impl::Surface& f) { return f.normal_map.handle; });
  const bool own_normals = mesh.corner_normals.size() == corners;
  if (!own_normals && !mapped) return;
  s.corner_normals.resize(corners);
  for (std::size_t c = 0; c < corners; ++c) {
    const Eigen::Vector3f vertex = s.normals[s.triangles[c / 3][c % 3]];
    s.corner_normals[c] = own_normals && mesh.corner_normals[c].squaredNorm() > 0.0f ? mesh.corner_normals[c] : vertex;
  }
  if (!mapped) return;
  if (mesh.corner_tangents.size() == corners && own_normals) {
    s.corner_tangents = mesh.corner_tangents;
    // A corner the file gives no tangent (a primitive without TANGENT) gets a generated one.
    if (std::any_of(s.corner_tangents.begin(), s.corner_tangents.end(), [](const Eigen::Vector4f& t) { return t.w() == 0.0f; })) {
      const std::vector<Eigen::Vector4f> generated = corner_tangents(s.positions, s.triangles, s.corner_normals, s.corner_uvs);
      for (std::size_t c = 0; c < corners; ++c)
        if (s.corner_tangents[c].w() == 0.0f) s.corner_tangents[c] = generated[c];
    }
  } else {
    s.corner_tangents = corner_tangents(s.positions, s.triangles, s.corner_normals, s.corner_uvs);
  }
}

}  // namespace

namespace render_detail {

RayContext ray_context(const Renderer::Impl& r, Scratch& scratch, bool camera) {
  RayContext c;
  rtcInitIntersectContext(&c.embree);
  c.embree.flags = camera ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  if (r.filtered_rays) {
    c.embree.filter = &filter_hits;
    c.renderer = &r;
    c.scratch = &scratch;
  }
  return c;
}

void filter_hits(const RTCFilterFunctionNArguments* args) {
  const RayContext& c = *reinterpret_cast<const RayContext*>(args->context);
  const Renderer::Impl& r = *c.renderer;
  const unsigned n = args->N;
  for (unsigned i = 0; i < n; ++i) {
    if (args->valid[i] != -1) continue;
    const std::uint32_t prim = RTCHitN_primID(args->hit, n, i);
    const Renderer::Impl::Surface& surface = r.surfaces[r.triangle_surface.empty() ? 0 : r.triangle_surface[prim]];
    if (!surface.rays_filtered()) continue;
    const Eigen::Vector3f dir(RTCRayN_dir_x(args->ray, n, i), RTCRayN_dir_y(args->ray, n, i), RTCRayN_dir_z(args->ray, n, i));
    if (!surface.double_sided) {
      // The face's own winding (counter-clockwise seen from its front), not Embree's convention.
      const auto& t = r.triangles[prim];
      const Eigen::Vector3f front = (r.positions[t[1]] - r.positions[t[0]]).cross(r.positions[t[2]] - r.positions[t[0]]);
      if (front.dot(dir) > 0.0f) {
        args->valid[i] = 0;
        continue;
      }
    }
    if (surface.alpha_mode == MeshMaterial::AlphaMode::opaque) continue;
    float alpha = surface.alpha;
    if (surface.texture.handle && surface.texture.alpha_channel >= 0 && !r.corner_uvs.empty()) {
      const float u = RTCHitN_u(args->hit, n, i), v = RTCHitN_v(args->hit, n, i), w = 1.0f - u - v;
      const Eigen::Vector2f uv = w * r.corner_uvs[3 * std::size_t{prim}] + u * r.corner_uvs[3 * std::size_t{prim} + 1] +
                                 v * r.corner_uvs[3 * std::size_t{prim} + 2];
      OIIO::TextureOpt opt;
      opt.swrap = surface.texture.wrap_s;
      opt.twrap = surface.texture.wrap_t;
      opt.interpmode = surface.texture.mag_interp;
      opt.mipmode = OIIO::TextureOpt::MipModeNoMIP;
      opt.firstchannel = surface.texture.alpha_channel;
      float a = 1.0f;
      if (r.textures->texture(surface.texture.handle, c.scratch->texture_thread, opt, uv.x(), 1.0f - uv.y(), 0, 0, 0, 0, 1, &a))
        alpha *= std::clamp(a, 0.0f, 1.0f);
    }
    bool there = true;
    if (surface.alpha_mode == MeshMaterial::AlphaMode::mask) {
      there = alpha >= surface.alpha_cutoff;
    } else {
      // Blend: the face stops the ray with probability alpha. The number is a hash of the ray's
      // bits and the face, the same in every run and on every thread.
      std::uint32_t bits[6];
      const float values[6] = {RTCRayN_org_x(args->ray, n, i), RTCRayN_org_y(args->ray, n, i), RTCRayN_org_z(args->ray, n, i),
                               dir.x(), dir.y(), dir.z()};
      std::memcpy(bits, values, sizeof bits);
      std::uint64_t key = rng::mix64(prim + 0x632be59bd9b4e019ULL);
      for (const std::uint32_t b : bits) key = rng::mix64(key ^ b);
      there = static_cast<float>(key >> 40) * 0x1.0p-24f < alpha;
    }
    if (!there) args->valid[i] = 0;
  }
}

}  // namespace render_detail

// For each vertex, the smallest index of a vertex at bit-identical coordinates (itself when
// alone): the vertices that are one point of the surface. Files split vertices where their
// attributes differ (a PLY's per-vertex UVs at a texture seam) or not at all (triangle soups from
// STL converters); without this the normals would see a seam, or every triangle alone (a faceted
// model). Sorted by a hash of the coordinates, then by index, and compared exactly within equal
// hashes.
std::vector<std::uint32_t> coincident_representatives(const std::vector<Eigen::Vector3f>& positions) {
  const std::size_t n = positions.size();
  const auto bits = [&](std::size_t v, int k) {
    std::uint32_t b = 0;
    const float x = positions[v][k] == 0.0f ? 0.0f : positions[v][k];  // -0 and +0 are one place
    std::memcpy(&b, &x, sizeof b);
    return b;
  };
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keys(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 16), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t v = range.begin(); v < range.end(); ++v) {
      std::uint64_t h = 0x9e3779b97f4a7c15ull;
      for (int k = 0; k < 3; ++k) h = (h ^ bits(v, k)) * 0xff51afd7ed558ccdull, h ^= h >> 29;
      keys[v] = {h, static_cast<std::uint32_t>(v)};
    }
  });
  // Least-significant-digit radix sort by the hash, 16 bits a pass: stable, so equal hashes stay
  // in index order (4 linear passes; std::sort took 2 s on 8.9M vertices).
  {
    std::vector<std::pair<std::uint64_t, std::uint32_t>> other(n);
    std::vector<std::size_t> start(65537);
    for (int shift = 0; shift < 64; shift += 16) {
      std::fill(start.begin(), start.end(), 0);
      for (const auto& k : keys) ++start[((k.first >> shift) & 0xffff) + 1];
      for (std::size_t d = 1; d < start.size(); ++d) start[d] += start[d - 1];
      for (const auto& k : keys) other[start[(k.first >> shift) & 0xffff]++] = k;
      keys.swap(other);
    }
  }
  std::vector<std::uint32_t> representative(n);
  for (std::size_t v = 0; v < n; ++v) representative[v] = static_cast<std::uint32_t>(v);
  for (std::size_t begin = 0; begin < n;) {
    std::size_t end = begin + 1;
    while (end < n && keys[end].first == keys[begin].first) ++end;
    for (std::size_t i = begin + 1; i < end; ++i)  // usually one earlier entry; collisions compare each
      for (std::size_t j = begin; j < i; ++j)
        if (positions[keys[i].second] == positions[keys[j].second]) {
          representative[keys[i].second] = representative[keys[j].second];
          break;
        }
    begin = end;
  }
  return representative;
}

// Shading normals with creases (renderer_internal.h). Each corner's normal is the average of the
// normals of the faces around its point (the vertices at its coordinates) that meet its own face
// at less than the crease angle, weighted by their angles there (Thürmer and Wüthrich 1998). Where
// a vertex's corners get different normals (the edge of a box), each normal after the first gets
// its own copy of the vertex, appended to `positions` (bit-identical coordinates: Embree's robust
// traversal leaves no crack), and the corners are re-pointed: the tile kernel keeps one normal
// per vertex.
// Two linear passes do almost all of it: the smooth normal of every point (all its faces), and
// each point's widest angle between one of its faces and that normal. Where every face is within
// half the crease angle of the smooth normal, any two faces are within the crease angle, so the
// smooth normal is the answer (a scan's surface: nearly every point). Only the other points are
// gathered with their corners and solved face by face. Deterministic: sums in triangle order.
std::vector<Eigen::Vector3f> crease_normals(std::vector<Eigen::Vector3f>& positions, std::vector<std::array<std::uint32_t, 3>>& tris,
                                            float crease_angle_deg, std::vector<std::uint32_t>& copied_from) {
  const std::size_t vertex_count = positions.size();
  if (tris.size() > (std::numeric_limits<std::uint32_t>::max() - 2) / 3)
    throw InputError("the mesh has more triangles than meshtour can shade (over 1.4 billion)");
  const std::vector<std::uint32_t> point = coincident_representatives(positions);
  // One face's corners and cross product (twice its area along its normal; zero when degenerate),
  // and the angle at its corner k: every pass measures faces through these two.
  struct Face {
    Eigen::Vector3d p[3], cross;
    double len;
    double angle(int k) const { return portable_atan2(len, (p[(k + 1) % 3] - p[k]).dot(p[(k + 2) % 3] - p[k])); }
  };
  const auto face_of = [&](const std::array<std::uint32_t, 3>& t) {
    Face f{{positions[t[0]].cast<double>(), positions[t[1]].cast<double>(), positions[t[2]].cast<double>()}, {}, 0.0};
    f.cross = (f.p[1] - f.p[0]).cross(f.p[2] - f.p[0]);
    f.len = f.cross.norm();
    return f;
  };
  const auto normalised = [](const Eigen::Vector3d& sum) {
    const double len = sum.norm();
    return len > 0.0 ? Eigen::Vector3f((sum / len).cast<float>()) : Eigen::Vector3f::UnitY();
  };
  // 1. Smooth normals per point. The corners' weighted normals (three arctangents a face) are
  // computed in parallel a block of faces at a time and added in triangle order, so the sums are
  // the same bits for any number of threads.
  std::vector<Eigen::Vector3d> sums(vertex_count, Eigen::Vector3d::Zero());
  {
    constexpr std::size_t kBlock = std::size_t{1} << 16;
    std::vector<Eigen::Vector3d> weighted(3 * std::min(kBlock, tris.size()));
    std::vector<char> proper(std::min(kBlock, tris.size()));  // not degenerate: has a normal
    for (std::size_t first = 0; first < tris.size(); first += kBlock) {
      const std::size_t count = std::min(kBlock, tris.size() - first);
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 1024), [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t i = range.begin(); i < range.end(); ++i) {
          const Face f = face_of(tris[first + i]);
          proper[i] = f.len > 0.0;
          if (!proper[i]) continue;
          const Eigen::Vector3d unit = f.cross / f.len;
          for (int k = 0; k < 3; ++k) weighted[3 * i + k] = f.angle(k) * unit;
        }
      });
      for (std::size_t i = 0; i < count; ++i) {
        if (!proper[i]) continue;
        const auto& t = tris[first + i];
        for (int k = 0; k < 3; ++k) sums[point[t[k]]] += weighted[3 * i + k];
      }
    }
  }
  std::vector<Eigen::Vector3f> normals(vertex_count);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, vertex_count, 1 << 14), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t v = range.begin(); v < range.end(); ++v) normals[v] = point[v] == v ? normalised(sums[v]) : Eigen::Vector3f::Zero();
  });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, vertex_count, 1 << 14), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t v = range.begin(); v < range.end(); ++v) normals[v] = normals[point[v]];
  });
  sums = {};
  if (crease_angle_deg >= 180.0f) return normals;
  const double cos_crease = std::cos(static_cast<double>(crease_angle_deg) * std::numbers::pi / 180.0);
  const double cos_half = std::cos(0.5 * static_cast<double>(crease_angle_deg) * std::numbers::pi / 180.0);
  // 2. The points some face of which is further than half the angle from their smooth normal.
  std::vector<char> suspect(vertex_count, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tris.size(), 1 << 12), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      const auto& t = tris[i];
      const Face f = face_of(t);
      if (!(f.len > 0.0)) continue;
      for (const std::uint32_t v : t)
        if (f.cross.dot(normals[v].cast<double>()) < cos_half * f.len)
          std::atomic_ref<char>(suspect[point[v]]).store(1, std::memory_order_relaxed);  // faces share points
    }
  });
  // 3. Those points' corners (3 * triangle + k), grouped by point in triangle order, solved exactly.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> gathered;
  for (std::size_t t = 0; t < tris.size(); ++t)
    for (int k = 0; k < 3; ++k)
      if (suspect[point[tris[t][k]]]) gathered.emplace_back(point[tris[t][k]], static_cast<std::uint32_t>(3 * t + k));
  std::stable_sort(gathered.begin(), gathered.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  std::vector<Eigen::Vector3d> unit;    // per corner of the point: its face's unit normal (zero: degenerate)
  std::vector<double> angle;            // its angle at the point
  std::vector<Eigen::Vector3f> result;  // its normal
  std::vector<std::uint32_t> vertex;    // its vertex in the file
  std::vector<std::uint32_t> assigned;  // the vertex it is re-pointed to
  for (std::size_t begin = 0; begin < gathered.size();) {
    std::size_t end = begin;
    while (end < gathered.size() && gathered[end].first == gathered[begin].first) ++end;
    const std::size_t n = end - begin;
    unit.resize(n);
    angle.resize(n);
    vertex.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t c = gathered[begin + i].second;
      const Face f = face_of(tris[c / 3]);
      const bool proper = f.len > 0.0;
      unit[i] = proper ? Eigen::Vector3d(f.cross / f.len) : Eigen::Vector3d::Zero();
      angle[i] = proper ? f.angle(static_cast<int>(c % 3)) : 0.0;
      vertex[i] = tris[c / 3][c % 3];
    }
    const auto average = [&](std::size_t i) {  // corner i's normal: the faces within the angle of its face
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (std::size_t j = 0; j < n; ++j)
        if (unit[i].isZero() || unit[j].dot(unit[i]) >= cos_crease) sum += angle[j] * unit[j];
      return normalised(sum);
    };
    result.resize(n);
    assigned.resize(n);
    for (std::size_t i = 0; i < n; ++i) result[i] = average(i);
    // Per vertex of the file: its first corner's normal is its own, another normal a copy of it.
    for (std::size_t i = 0; i < n; ++i) {
      std::size_t first = i, same = i;
      for (std::size_t j = 0; j < i; ++j)
        if (vertex[j] == vertex[i]) {
          if (first == i) first = j;
          if (same == i && result[j] == result[i]) same = j;
        }
      if (first == i) {
        assigned[i] = vertex[i];
        normals[vertex[i]] = result[i];
      } else if (same < i) {
        assigned[i] = assigned[same];
      } else {
        assigned[i] = static_cast<std::uint32_t>(positions.size());
        positions.push_back(positions[vertex[i]]);
        normals.push_back(result[i]);
        copied_from.push_back(vertex[i]);
      }
    }
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t c = gathered[begin + i].second;
      tris[c / 3][c % 3] = assigned[i];
    }
    begin = end;
  }
  return normals;
}

Renderer::Renderer(const TriangleMesh& mesh, const RenderOptions& options) : Renderer(mesh, options, nullptr) {}

Renderer::Renderer(const TriangleMesh& mesh, const RenderOptions& options, std::shared_ptr<const RayScene> rays)
    : impl_(std::make_unique<Impl>()) {
  if (options.width <= 0 || options.height <= 0 || options.width > 16384 || options.height > 16384)
    throw InputError("image size must be between 1x1 and 16384x16384, got " + std::to_string(options.width) + "x" +
                     std::to_string(options.height));
  if (options.samples_per_pixel < 1 || options.samples_per_pixel > 4096)
    throw InputError("samples per pixel must be between 1 and 4096, got " + std::to_string(options.samples_per_pixel));
  if (!(options.filter_radius >= 0.5f && options.filter_radius <= 2.0f))
    throw InputError("the filter radius must be between 0.5 and 2 pixels, got " + std::to_string(options.filter_radius));
  if (options.shading.lights.size() > 8)
    throw InputError("at most 8 lights are supported, got " + std::to_string(options.shading.lights.size()));
  if (!(options.world_up.norm() > 0.0)) throw InputError("the up axis must not be the zero vector");
  if (mesh.triangles.empty()) throw InputError("the mesh has no triangles to render");

  Impl& s = *impl_;
  s.instruction_set = choose_instruction_set();
  s.tile_kernel = tile_kernel_for(s.instruction_set);
  s.options = options;
  s.filter = ReconstructionFilter(options.filter_radius);
  const Bounds bounds = mesh.bounds();  // a pass over every vertex: once
  s.origin = bounds.center();
  s.scale = static_cast<float>(std::max(bounds.diagonal(), 1e-30));
  s.positions.reserve(mesh.positions.size() + 1);
  for (const auto& p : mesh.positions) s.positions.push_back((p - s.origin).cast<float>());
  s.triangles = mesh.triangles;
  for (const auto& t : s.triangles)
    for (auto v : t)
      if (v >= mesh.positions.size()) throw InputError("the mesh has a triangle that refers to a missing vertex");
  const Material& material = options.shading.material;
  std::vector<std::uint32_t> copied_from;  // the vertices crease_normals() copied, in order
  s.normals = crease_normals(s.positions, s.triangles, material.crease_angle_deg, copied_from);
  if (mesh.has_colors() && material.use_vertex_colors) {
    s.colors.reserve(mesh.colors.size() + copied_from.size());
    for (const auto& c : mesh.colors) s.colors.push_back(srgb_to_linear(c));
    for (const std::uint32_t v : copied_from) s.colors.push_back(s.colors[v]);
  }
  set_up_surfaces(s, mesh, material.use_texture, material.use_file_material);
  set_up_corner_frames(s, mesh);

  s.rays = rays ? std::move(rays) : std::make_shared<const RayScene>(mesh);
  if (s.rays->triangle_count() != mesh.triangles.size())
    throw InputError("the ray-tracing scene given to the renderer is of another mesh (" + std::to_string(s.rays->triangle_count()) +
                     " triangles, not " + std::to_string(mesh.triangles.size()) + ")");

  s.up = options.world_up.normalized().cast<float>();
  if (options.shading.bounces < 0 || options.shading.bounces > render_detail::kMaxBounces)
    throw InputError("bounces must be 0 to " + std::to_string(render_detail::kMaxBounces) + ", got " + std::to_string(options.shading.bounces));
  if (const Shading& sh = options.shading; sh.environment) {
    if (!(sh.environment_intensity >= 0.0f) || !std::isfinite(sh.environment_intensity))
      throw InputError("the environment's intensity must be 0 or more, got " + std::to_string(sh.environment_intensity));
    s.environment_light = irradiance_map(*sh.environment, s.up, sh.environment_rotation_deg, sh.environment_intensity);
    s.environment_radiance = environment_radiance(sh.environment, s.up, sh.environment_rotation_deg, sh.environment_intensity);
    s.environment_upward = luminance(upward_irradiance(*sh.environment, sh.environment_intensity));
    if (sh.sample_environment && sh.environment_intensity > 0.0f) {
      s.environment_distribution = environment_distribution(*sh.environment, s.up, sh.environment_rotation_deg);
      if (s.environment_distribution->empty()) s.environment_distribution.reset();
    }
  }
  if (options.shading.ground) {
    float lowest = std::numeric_limits<float>::infinity();
    for (const auto& t : s.triangles)
      for (auto v : t) lowest = std::min(lowest, s.positions[v].dot(s.up));
    // A hair below the model: a flat base resting on the ground must not fight with it.
    s.has_ground = true;
    s.ground_height = lowest - 5e-4f * s.scale;
    s.ground_half = 100.0f * s.scale;  // far beyond any shadow; looks infinite
  }
}

Renderer::~Renderer() = default;

const RenderOptions& Renderer::options() const { return impl_->options; }

Image Renderer::render(const Camera& camera, std::uint64_t frame_index, RenderStats* stats) const {
  return impl_->render(camera, frame_index, stats, nullptr);
}

RTCScene RendererAccess::scene(const Renderer& renderer) { return renderer.impl_->rays->scene(); }
Image RendererAccess::render(const Renderer& renderer, const Camera& camera, std::uint64_t frame_index, RenderStats* stats,
                             RayRecording* recording) {
  return renderer.impl_->render(camera, frame_index, stats, recording);
}

Frame Renderer::Impl::frame_for(const Camera& camera, std::uint64_t frame) const {
  const int width = options.width, height = options.height;
  const Shading& sh = options.shading;
  const Material& mat = sh.material;
  Frame f;
  f.index = frame;
  f.width = width;
  f.height = height;
  f.transparent = sh.background == BackgroundKind::transparent;

  // Camera frame, in the scene's local (centred) coordinates.
  const LookAtFrame view = look_at(camera);
  const Eigen::Vector3d& forward_d = view.forward;
  const Eigen::Vector3d& right_d = view.right;
  const Eigen::Vector3d& up_d = view.up;
  f.eye = (camera.eye - origin).cast<float>();
  f.forward = forward_d.cast<float>();
  const Eigen::Vector3f right = right_d.cast<float>(), cam_up = up_d.cast<float>();
  const float tan_half = static_cast<float>(std::tan(camera.vertical_fov_deg * std::numbers::pi / 360.0));
  const float aspect = static_cast<float>(width) / static_cast<float>(height);
  f.step_x = (2.0f * tan_half * aspect / static_cast<float>(width)) * right;
  f.step_y = (-2.0f * tan_half / static_cast<float>(height)) * cam_up;
  f.corner = f.forward - tan_half * aspect * right + tan_half * cam_up;
  if (sh.environment_background && environment_radiance && !f.transparent) {
    f.backdrop_rgb.resize(static_cast<std::size_t>(width) * height * 3);
    tbb::parallel_for(tbb::blocked_range<int>(0, height, 16), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y < rows.end(); ++y)
        for (int x = 0; x < width; ++x) {
          // The kernel's camera ray at the pixel's centre (tile_kernel.cpp, camera_rays).
          const Eigen::Vector3f dir = (f.corner + (static_cast<float>(x) + 0.5f) * f.step_x + (static_cast<float>(y) + 0.5f) * f.step_y).normalized();
          const Eigen::Vector3f rgb = (*environment_radiance)(dir);
          std::copy(rgb.data(), rgb.data() + 3, &f.backdrop_rgb[(static_cast<std::size_t>(y) * width + x) * 3]);
        }
    });
  }

  for (const Light& l : sh.lights) {
    const Eigen::Vector3f d = l.from_camera.x() * right + l.from_camera.y() * cam_up - l.from_camera.z() * f.forward;
    if (!(d.norm() > 0.0f) || !(l.intensity > 0.0f)) continue;
    FrameLight fl;
    fl.direction = d.normalized();
    basis(fl.direction, fl.tangent, fl.bitangent);
    fl.radiance = l.color * l.intensity;
    fl.radiance_luminance = luminance(fl.radiance);
    const double half_angle = std::clamp(l.angular_diameter_deg, 0.0f, 90.0f) * std::numbers::pi / 360.0;
    fl.one_minus_cos_half_angle = 1.0f - static_cast<float>(std::cos(half_angle));
    fl.cos_half_angle = static_cast<float>(std::cos(half_angle));
    fl.sin_half_angle = static_cast<float>(std::sin(half_angle));
    f.lights.push_back(fl);
  }
  const std::size_t nlights = f.lights.size();
  f.base_color = mat.base_color;
  f.ambient = sh.ambient;
  f.environment = environment_light.has_value();
  if (environment_light) f.sky_light = &*environment_light;
  if (environment_radiance) f.sky_radiance = &*environment_radiance;
  if (environment_distribution) f.sky_distribution = &*environment_distribution;
  f.background_top = sh.background_top;
  f.background_bottom = sh.background_bottom;
  f.shadows = sh.shadows;
  f.ambient_occlusion = sh.ambient_occlusion;
  f.bounces = sh.ambient_occlusion ? sh.bounces : 0;
  // Blinn-Phong exponent from roughness (alpha = roughness^2, Walter et al.'s mapping n = 2/alpha^2 - 2),
  // normalised so that the highlight's energy stays the same as it widens.
  const float alpha = std::max(0.02f, mat.roughness * mat.roughness);
  f.shininess = std::max(1.0f, 2.0f / (alpha * alpha) - 2.0f);
  f.spec_scale = 0.08f * mat.specular * (f.shininess + 8.0f) / 8.0f;
  // Below this cosine the highlight is under 1e-4 of its peak: skip it.
  f.spec_cutoff = std::pow(1e-4f, 1.0f / f.shininess);
  f.has_ground = has_ground;
  // From below the ground the camera must see the model, not the ground's underside.
  f.ground_visible = has_ground && f.eye.dot(up) > ground_height;
  f.ground_height = ground_height;
  f.ground_half = ground_half;
  f.eps = 1e-4f * scale;
  f.ao_length = sh.ao_distance * scale;
  f.model_radius = 0.5f * scale * 1.001f;  // bounding sphere around the box's centre (the origin)
  f.ground_ao_reach2 = (f.model_radius + f.ao_length) * (f.model_radius + f.ao_length);
  f.sample_sky = environment_radiance && sh.ambient_occlusion;
  f.sky_length = f.sample_sky ? std::numeric_limits<float>::infinity() : f.ao_length;
  if (f.sample_sky) {
    // Half the sky rays at most go to the environment's light: the cosine half keeps an even
    // sky's light free of the mixture's noise (an even sky has no peak and gets none).
    if (environment_distribution) f.sky_environment_share = std::min(0.9f, environment_distribution->peak_share);
    f.sky_upward = environment_upward;
  }
  f.pixel_angle = 2.0f * tan_half / static_cast<float>(height);  // texture filter footprint
  f.inv_height = 1.0f / static_cast<float>(height);

  // The ground is flat and the lights are fixed for the frame, so everything about its shading
  // but the background colour and the visibility of the chosen light and the sky is known here:
  // the ground shows the background, darkened by the share of light and sky the model takes
  // away from it (a shadow catcher); transparent frames get the shadow as alpha.
  for (std::size_t i = 0; i < nlights; ++i) {
    f.ground_weights[i] = std::max(0.0f, up.dot(f.lights[i].direction)) * f.lights[i].radiance_luminance;
    f.ground_light_total += f.ground_weights[i];
  }
  const Eigen::Vector3f sky_on_ground = environment_light ? (*environment_light)(up) : sh.ambient;
  const float ground_sky = sh.ambient_occlusion || !sh.shadows ? luminance(sky_on_ground) : 0.0f;
  const float ground_total = f.ground_light_total + ground_sky;
  f.ground_shadow = ground_total > 0.0f ? sh.ground_shadow : 0.0f;
  f.ground_light_share = ground_total > 0.0f ? f.ground_shadow * f.ground_light_total / ground_total : 0.0f;
  f.ground_sky_share = ground_total > 0.0f ? f.ground_shadow * ground_sky / ground_total : 0.0f;
  f.up = up;
  basis(up, f.up_t1, f.up_t2);

  f.spp = options.samples_per_pixel;
  f.seed = static_cast<std::uint64_t>(options.sample_seed) << 40;
  return f;
}

Image Renderer::Impl::render(const Camera& camera, std::uint64_t frame, RenderStats* stats, RayRecording* recording) const {
  const auto start = std::chrono::steady_clock::now();
  const Frame f = frame_for(camera, frame);
  Film film(f.width, f.height, f.spp, filter, options.layers, options.denoise, film_memory);
  const TileCounts counts = trace_tiles(f, film, recording);
  film.gather();
  Image image;
  // The denoiser, a stage of its own on the Film's layers once the frame is rendered.
  if (options.denoise) image.denoised = denoise_film(film, f.transparent);
  film.write_to(image);
  image.transparent = f.transparent;
  image.exposure = options.shading.exposure;
  image.tone_mapping = options.shading.tone_mapping;
  if (stats) {
    stats->primary_rays += counts.primary;
    stats->secondary_rays += counts.secondary;
  }
  image.info.camera = camera;
  image.info.frame_index = frame;
  image.info.samples_per_pixel = f.spp;
  image.info.render_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return image;
}

TileCounts Renderer::Impl::trace_tiles(const Frame& f, Film& film, RayRecording* recording) const {
  const int ntiles = film.tile_count();
  if (recording) recording->tiles.assign((ntiles + recording->tile_stride - 1) / recording->tile_stride, {});
  std::atomic<std::uint64_t> primary_count{0}, secondary_count{0};
  tbb::enumerable_thread_specific<Scratch> scratch_per_thread;
  tbb::parallel_for(tbb::blocked_range<int>(0, ntiles, 1), [&](const tbb::blocked_range<int>& range) {
    Scratch& scratch = scratch_per_thread.local();
    if (textures && !scratch.texture_thread) scratch.texture_thread = textures->get_perthread_info();
    TileCounts counts;
    for (int tile = range.begin(); tile != range.end(); ++tile) {
      const FilmTile film_tile = film.tile(tile);
      RayRecording::Tile* recorded =
          recording && tile % recording->tile_stride == 0 ? &recording->tiles[tile / recording->tile_stride] : nullptr;
      (this->*tile_kernel)(f, scratch, film_tile, recorded, counts);
      film.finish_tile(film_tile);
    }
    primary_count += counts.primary;
    secondary_count += counts.secondary;
  });
  return TileCounts{primary_count, secondary_count};
}

std::vector<float> Renderer::Impl::denoise_film(const Film& film, bool transparent) const {
  DenoiseSettings settings;
  settings.transparent = transparent;
  settings.instruction_set = instruction_set;  // the copy of its passes that matches the tile kernel
  DenoiseWorkspace workspace = denoiser_memory.take();
  std::vector<float> denoised = denoise(film.beauty(), *film.denoiser_guides(), settings, &workspace);
  denoiser_memory.give_back(std::move(workspace));
  return denoised;
}

}  // namespace meshtour
