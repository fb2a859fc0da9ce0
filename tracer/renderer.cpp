// The renderer: Embree scene set-up, and per tile: camera rays in packets, shading, one batch
// of shadow and occlusion rays, and the reconstruction filter.
#include <Eigen/Geometry>
#include <OpenImageIO/texture.h>
#include <embree3/rtcore.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <numbers>
#include <string>

#include "core/error.h"
#include "tracer/color.h"
#include "tracer/film.h"
#include "tracer/random.h"
#include "tracer/renderer_internal.h"
#include "tracer/tracer.h"

namespace meshtour {
namespace {

// Embree reports errors through a callback; keep the first message so the throwing site can
// quote it (exceptions must not cross Embree's C frames).
struct EmbreeErrorSink {
  std::mutex mutex;
  std::string message;
};

void embree_error(void* user, RTCError code, const char* text) {
  auto* sink = static_cast<EmbreeErrorSink*>(user);
  std::lock_guard lock(sink->mutex);
  if (sink->message.empty()) sink->message = "Embree error " + std::to_string(code) + ": " + (text ? text : "");
}

struct DeviceDeleter {
  void operator()(RTCDevice d) const { rtcReleaseDevice(d); }
};
struct SceneDeleter {
  void operator()(RTCScene s) const { rtcReleaseScene(s); }
};
struct TextureSystemDeleter {
  void operator()(OIIO::TextureSystem* t) const { OIIO::TextureSystem::destroy(t); }
};
using DevicePtr = std::unique_ptr<RTCDeviceTy, DeviceDeleter>;
using ScenePtr = std::unique_ptr<RTCSceneTy, SceneDeleter>;
using TextureSystemPtr = std::unique_ptr<OIIO::TextureSystem, TextureSystemDeleter>;

// 16 x 16 pixels: at 16 spp a tile's rays (4096 camera rays, up to 8192 secondary) stay in the
// L2 cache, and a 1280x720 frame has 3600 tiles, plenty to balance two or more threads.
constexpr int kTileSize = 16;
constexpr int kPacket = 16;
constexpr unsigned kModelGeometry = 0, kGroundGeometry = 1;
constexpr unsigned kModelMask = 1, kGroundMask = 2;

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

std::vector<Eigen::Vector3f> angle_weighted_normals(const std::vector<Eigen::Vector3f>& p,
                                                    const std::vector<std::array<std::uint32_t, 3>>& tris) {
  std::vector<Eigen::Vector3d> acc(p.size(), Eigen::Vector3d::Zero());
  for (const auto& t : tris) {
    const Eigen::Vector3d a = p[t[0]].cast<double>(), b = p[t[1]].cast<double>(), c = p[t[2]].cast<double>();
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double len = n.norm();
    if (!(len > 0.0)) continue;
    const Eigen::Vector3d unit = n / len;
    const Eigen::Vector3d corners[3] = {a, b, c};
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d e1 = corners[(k + 1) % 3] - corners[k], e2 = corners[(k + 2) % 3] - corners[k];
      const double angle = std::atan2(e1.cross(e2).norm(), e1.dot(e2));
      acc[t[k]] += angle * unit;
    }
  }
  std::vector<Eigen::Vector3f> out(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double len = acc[i].norm();
    out[i] = len > 0.0 ? Eigen::Vector3f((acc[i] / len).cast<float>()) : Eigen::Vector3f::UnitY();
  }
  return out;
}

// What a camera sample contributes, once its secondary rays are answered:
// base + (shadow ray unblocked ? with_light : 0) + (occlusion ray unblocked ? with_sky : 0).
// Folding the shading into these three terms lets all secondary rays of a tile be traced in one
// Embree call between shading and filtering.
struct SampleRecord {
  float offset_x, offset_y;  // position inside its pixel, in [0, 1)
  Eigen::Vector4f base, with_light, with_sky;
  std::int32_t shadow_ray, sky_ray;  // index into the tile's secondary rays, or -1
};

// Per-thread buffers, reused from tile to tile: no allocation once the first tiles have run.
struct Scratch {
  std::vector<RTCRayHit16> packets;
  std::vector<ValidMask> valid;
  std::vector<SampleRecord> samples;
  std::vector<RTCRay> secondary;
  OIIO::TextureSystem::Perthread* texture_thread = nullptr;
};

// A light as one frame sees it: world direction, colour and its disc's size.
struct FrameLight {
  Eigen::Vector3f direction;  // towards the light
  Eigen::Vector3f tangent, bitangent;
  Eigen::Vector3f radiance;   // colour * intensity
  float radiance_luminance;
  float one_minus_cos_half_angle;  // the disc's solid angle / 2 pi
  float cos_half_angle, sin_half_angle;
};

// sin and cos of 2 pi u for u in [0, 1]: quadrant reduction and short Taylor polynomials on
// [-pi/4, pi/4] (error < 4e-7, far below what a 24-bit random number resolves). Cheaper than
// libm's sincosf, and plain arithmetic, so every CPU and libm give the same bits.
// The quadrant is random, so it selects through tables rather than branches (which would be
// mispredicted half of the time).
inline void sincos_turns(float u, float& s, float& c) {
  // Rounded by truncation (u >= 0): std::nearbyint would save and restore the rounding mode.
  const int quadrant = static_cast<int>(4.0f * u + 0.5f);  // 0..4
  const float x = (u - 0.25f * static_cast<float>(quadrant)) * (2.0f * std::numbers::pi_v<float>);
  const float x2 = x * x;
  const float sin_x = x * (1.0f + x2 * (-1.0f / 6 + x2 * (1.0f / 120 + x2 * (-1.0f / 5040))));
  const float cos_x = 1.0f + x2 * (-0.5f + x2 * (1.0f / 24 + x2 * (-1.0f / 720 + x2 * (1.0f / 40320))));
  static constexpr float kSinFromSin[4] = {1, 0, -1, 0}, kSinFromCos[4] = {0, 1, 0, -1};
  const int q = quadrant & 3;
  s = kSinFromSin[q] * sin_x + kSinFromCos[q] * cos_x;
  c = kSinFromSin[q] * cos_x - kSinFromCos[q] * sin_x;
}

// Picks index i with probability weights[i] / total (total = the sum of the weights, > 0).
std::size_t choose(const float* weights, std::size_t n, float total, float u) {
  const float target = u * total;
  float acc = 0.0f;
  std::size_t last = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!(weights[i] > 0.0f)) continue;
    last = i;
    acc += weights[i];
    if (target < acc) return i;
  }
  return last;  // rounding left the target at the very top: the last light with a weight
}

}  // namespace

struct Renderer::Impl {
  RenderOptions options;
  EmbreeErrorSink errors;
  DevicePtr device;
  ScenePtr scene;
  // The scene is stored relative to the model's centre in float; cameras are shifted the same
  // way, so models far from the origin (georeferenced scans) keep their precision.
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  float scale = 1.0f;  // the model's bounding-box diagonal: sets ray offsets and AO length
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3f> normals;  // smooth, angle-weighted vertex normals
  std::vector<Eigen::Vector3f> colors;   // linear vertex colours, or empty
  std::vector<std::array<std::uint32_t, 3>> triangles;
  // Ground: a large square perpendicular to `up`, just under the model's lowest vertex.
  Eigen::Vector3f up = Eigen::Vector3f::UnitY();
  float ground_height = 0.0f;  // dot(point, up) of the ground plane
  std::vector<Eigen::Vector3f> ground_vertices;
  std::vector<std::array<std::uint32_t, 3>> ground_triangles;
  // Texture (OBJ map_Kd): per-corner UVs, and the texture system's handle.
  std::vector<Eigen::Vector2f> corner_uvs;
  std::vector<float> uv_scale;  // per triangle: sqrt(uv area / world area), for the filter footprint
  TextureSystemPtr textures;
  OIIO::TextureSystem::TextureHandle* texture = nullptr;
  FilterTable filter;

  void check(const char* what) {
    std::lock_guard lock(errors.mutex);
    if (!errors.message.empty()) throw RuntimeFailure(std::string(what) + ": " + errors.message);
  }
  Image render(const Camera& camera, std::uint64_t frame, RenderStats* stats, RayRecording* recording) const;

  // Splats a tile's samples (stored pixel by pixel, rows of the tile) into its buffer, whose
  // pixel (apron, apron) is the tile's first pixel.
  template <int Reach>
  void splat_tile(const Scratch& scratch, float* sums, int stride, int tile_w, int tile_h, int apron) const {
    const int spp = options.samples_per_pixel;
    std::size_t k = 0;
    for (int y = 0; y < tile_h; ++y)
      for (int x = 0; x < tile_w; ++x) {
        PixelSplat<Reach> pixel;
        for (int s = 0; s < spp; ++s, ++k) {
          const SampleRecord& rec = scratch.samples[k];
          Eigen::Vector4f v = rec.base;
          if (rec.shadow_ray >= 0 && scratch.secondary[rec.shadow_ray].tfar >= 0.0f) v += rec.with_light;
          if (rec.sky_ray >= 0 && scratch.secondary[rec.sky_ray].tfar >= 0.0f) v += rec.with_sky;
          pixel.add(filter, rec.offset_x, rec.offset_y, Float4{v[0], v[1], v[2], v[3]});
        }
        pixel.flush(sums, stride, x + apron, y + apron);
      }
  }
};

Renderer::Renderer(const TriangleMesh& mesh, const RenderOptions& options) : impl_(std::make_unique<Impl>()) {
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
  s.options = options;
  s.filter = FilterTable(options.filter_radius);
  s.origin = mesh.bounds().center();
  s.scale = static_cast<float>(std::max(mesh.bounds().diagonal(), 1e-30));
  s.positions.reserve(mesh.positions.size() + 1);
  for (const auto& p : mesh.positions) s.positions.push_back((p - s.origin).cast<float>());
  s.triangles = mesh.triangles;
  for (const auto& t : s.triangles)
    for (auto v : t)
      if (v >= mesh.positions.size()) throw InputError("the mesh has a triangle that refers to a missing vertex");
  s.normals = angle_weighted_normals(s.positions, s.triangles);
  const Material& material = options.shading.material;
  if (mesh.has_colors() && material.use_vertex_colors) {
    s.colors.reserve(mesh.colors.size());
    for (const auto& c : mesh.colors) s.colors.push_back(srgb_to_linear(c));
  }
  if (mesh.has_texture() && material.use_texture) {
    s.textures.reset(OIIO::TextureSystem::create(/*shared=*/false));
    // Textures are usually sRGB-encoded 8-bit images; lookups must return linear values.
    s.textures->attribute("colorspace", "linear");
    const OIIO::ustring texture_name(mesh.texture_file.string());
    int readable = 0;  // "exists" is 1 only for a file OpenImageIO can open as an image
    s.textures->get_texture_info(texture_name, 0, OIIO::ustring("exists"), OIIO::TypeInt, &readable);
    s.texture = readable ? s.textures->get_texture_handle(texture_name) : nullptr;
    if (!s.texture || !s.textures->good(s.texture))
      throw IoError(mesh.texture_file.string() + ": cannot read the model's texture (" + s.textures->geterror() +
                    "); check the map_Kd line of the model's MTL file");
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

  s.device.reset(rtcNewDevice(nullptr));
  if (!s.device) throw RuntimeFailure("cannot create the Embree device (error " + std::to_string(rtcGetDeviceError(nullptr)) + ")");
  rtcSetDeviceErrorFunction(s.device.get(), embree_error, &s.errors);

  s.scene.reset(rtcNewScene(s.device.get()));
  // Robust traversal: no cracks between triangles sharing an edge, which a turntable would show
  // as flickering pixels.
  rtcSetSceneFlags(s.scene.get(), RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(s.scene.get(), RTC_BUILD_QUALITY_HIGH);
  // Shared buffers: Embree reads our arrays directly. The vertex buffer needs 16-byte padding at
  // its end, which the 3-float stride plus one spare vertex provides.
  auto attach = [&](std::vector<Eigen::Vector3f>& vertices, std::vector<std::array<std::uint32_t, 3>>& tris,
                    unsigned id, unsigned mask) {
    RTCGeometry geometry = rtcNewGeometry(s.device.get(), RTC_GEOMETRY_TYPE_TRIANGLE);
    vertices.push_back(Eigen::Vector3f::Zero());
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, vertices.data(), 0,
                               sizeof(Eigen::Vector3f), vertices.size() - 1);
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, tris.data(), 0,
                               sizeof(std::array<std::uint32_t, 3>), tris.size());
    rtcSetGeometryMask(geometry, mask);
    rtcCommitGeometry(geometry);
    rtcAttachGeometryByID(s.scene.get(), geometry, id);
    rtcReleaseGeometry(geometry);
  };
  attach(s.positions, s.triangles, kModelGeometry, kModelMask);

  s.up = options.world_up.normalized().cast<float>();
  if (options.shading.ground) {
    float lowest = std::numeric_limits<float>::infinity();
    for (const auto& t : s.triangles)
      for (auto v : t) lowest = std::min(lowest, s.positions[v].dot(s.up));
    // A hair below the model: a flat base resting on the ground must not fight with it.
    s.ground_height = lowest - 5e-4f * s.scale;
    Eigen::Vector3f e1, e2;
    basis(s.up, e1, e2);
    const float half = 100.0f * s.scale;  // far beyond any shadow; looks infinite
    const Eigen::Vector3f c = s.ground_height * s.up;
    s.ground_vertices = {c - half * e1 - half * e2, c + half * e1 - half * e2, c + half * e1 + half * e2, c - half * e1 + half * e2};
    s.ground_triangles = {{0, 1, 2}, {0, 2, 3}};
    attach(s.ground_vertices, s.ground_triangles, kGroundGeometry, kGroundMask);
  }
  rtcCommitScene(s.scene.get());
  s.check("building the ray-tracing scene");
}

Renderer::~Renderer() = default;

const RenderOptions& Renderer::options() const { return impl_->options; }

Image Renderer::render(const Camera& camera, std::uint64_t frame_index, RenderStats* stats) const {
  return impl_->render(camera, frame_index, stats, nullptr);
}

RTCScene RendererAccess::scene(const Renderer& renderer) { return renderer.impl_->scene.get(); }
Image RendererAccess::render(const Renderer& renderer, const Camera& camera, std::uint64_t frame_index, RenderStats* stats,
                             RayRecording* recording) {
  return renderer.impl_->render(camera, frame_index, stats, recording);
}

Image Renderer::Impl::render(const Camera& camera, std::uint64_t frame, RenderStats* stats, RayRecording* recording) const {
  const auto start = std::chrono::steady_clock::now();
  const int width = options.width, height = options.height;
  const Shading& sh = options.shading;
  const Material& mat = sh.material;
  const bool transparent = sh.background == BackgroundKind::transparent;
  Image image;
  image.width = width;
  image.height = height;
  image.transparent = transparent;
  image.exposure = sh.exposure;
  image.tone_mapping = sh.tone_mapping;
  const std::size_t npix = static_cast<std::size_t>(width) * height;
  image.rgba.assign(npix * 4, 0.0f);
  if (options.layers.albedo) image.albedo.assign(npix * 3, 0.0f);
  if (options.layers.normal) image.normal.assign(npix * 3, 0.0f);
  if (options.layers.depth) image.depth.assign(npix, std::numeric_limits<float>::infinity());

  // Camera frame, in the scene's local (centred) coordinates.
  const Eigen::Vector3d forward_d = (camera.target - camera.eye).normalized();
  Eigen::Vector3d right_d = forward_d.cross(camera.up);
  if (!(right_d.norm() > 1e-9)) right_d = forward_d.unitOrthogonal();
  right_d.normalize();
  const Eigen::Vector3d up_d = right_d.cross(forward_d);
  const Eigen::Vector3f eye = (camera.eye - origin).cast<float>();
  const Eigen::Vector3f forward = forward_d.cast<float>(), right = right_d.cast<float>(), cam_up = up_d.cast<float>();
  const float tan_half = static_cast<float>(std::tan(camera.vertical_fov_deg * std::numbers::pi / 360.0));
  const float aspect = static_cast<float>(width) / static_cast<float>(height);

  std::vector<FrameLight> lights;
  for (const Light& l : sh.lights) {
    const Eigen::Vector3f d = l.from_camera.x() * right + l.from_camera.y() * cam_up - l.from_camera.z() * forward;
    if (!(d.norm() > 0.0f) || !(l.intensity > 0.0f)) continue;
    FrameLight f;
    f.direction = d.normalized();
    basis(f.direction, f.tangent, f.bitangent);
    f.radiance = l.color * l.intensity;
    f.radiance_luminance = luminance(f.radiance);
    const double half_angle = std::clamp(l.angular_diameter_deg, 0.0f, 90.0f) * std::numbers::pi / 360.0;
    f.one_minus_cos_half_angle = 1.0f - static_cast<float>(std::cos(half_angle));
    f.cos_half_angle = static_cast<float>(std::cos(half_angle));
    f.sin_half_angle = static_cast<float>(std::sin(half_angle));
    lights.push_back(f);
  }
  const std::size_t nlights = lights.size();
  // Blinn-Phong exponent from roughness (alpha = roughness^2, Walter et al.'s mapping n = 2/alpha^2 - 2),
  // normalised so that the highlight's energy stays the same as it widens.
  const float alpha = std::max(0.02f, mat.roughness * mat.roughness);
  const float shininess = std::max(1.0f, 2.0f / (alpha * alpha) - 2.0f);
  const float spec_scale = 0.08f * mat.specular * (shininess + 8.0f) / 8.0f;
  // Below this cosine the highlight is under 1e-4 of its peak: skip the pow().
  const float spec_cutoff = std::pow(1e-4f, 1.0f / shininess);
  const bool has_ground = !ground_vertices.empty();
  // From below the ground the camera must see the model, not the ground's underside.
  const unsigned camera_mask = has_ground && eye.dot(up) > ground_height ? (kModelMask | kGroundMask) : kModelMask;
  const float eps = 1e-4f * scale;
  const float ao_length = sh.ao_distance * scale;
  const float model_radius = 0.5f * scale * 1.001f;  // bounding sphere around the box's centre (the origin)
  const float ground_ao_reach2 = (model_radius + ao_length) * (model_radius + ao_length);
  const float pixel_angle = 2.0f * tan_half / static_cast<float>(height);  // texture filter footprint
  const float inv_height = 1.0f / static_cast<float>(height);

  // The ground is flat and the lights are fixed for the frame, so everything about its shading
  // but the background colour and the visibility of the chosen light and the sky is known here:
  // the ground shows the background, darkened by the share of light and sky the model takes
  // away from it (a shadow catcher); transparent frames get the shadow as alpha.
  float ground_weights[8] = {};
  float ground_light_total = 0.0f;
  for (std::size_t i = 0; i < nlights; ++i) {
    ground_weights[i] = std::max(0.0f, up.dot(lights[i].direction)) * lights[i].radiance_luminance;
    ground_light_total += ground_weights[i];
  }
  const float ground_sky = sh.ambient_occlusion || !sh.shadows ? luminance(sh.ambient) : 0.0f;
  const float ground_total = ground_light_total + ground_sky;
  const float ground_shadow = ground_total > 0.0f ? sh.ground_shadow : 0.0f;
  const float ground_light_share = ground_total > 0.0f ? ground_shadow * ground_light_total / ground_total : 0.0f;
  const float ground_sky_share = ground_total > 0.0f ? ground_shadow * ground_sky / ground_total : 0.0f;
  Eigen::Vector3f up_t1, up_t2;  // the ground's tangents, for its occlusion rays
  basis(up, up_t1, up_t2);

  const int spp = options.samples_per_pixel;
  int rows = static_cast<int>(std::sqrt(static_cast<double>(spp)));
  while (spp % rows != 0) --rows;
  const int cols = spp / rows;
  // The corner of each stratum (a rows x cols grid over the unit square), computed once: the
  // integer divisions would otherwise cost more than the rest of a sample's set-up.
  std::vector<Eigen::Vector2f> strata(spp);
  for (int j = 0; j < spp; ++j)
    strata[j] = Eigen::Vector2f(static_cast<float>(j % cols) / static_cast<float>(cols), static_cast<float>(j / cols) / static_cast<float>(rows));
  const Eigen::Vector2f stratum_size(1.0f / static_cast<float>(cols), 1.0f / static_cast<float>(rows));
  auto stratum = [&](int j, rng::Uniform2 u) { return Eigen::Vector2f(strata[j] + Eigen::Vector2f(u.u, u.v).cwiseProduct(stratum_size)); };
  // Camera ray through film position (fx, fy): corner + fx * step_x + fy * step_y, normalised.
  const Eigen::Vector3f step_x = (2.0f * tan_half * aspect / static_cast<float>(width)) * right;
  const Eigen::Vector3f step_y = (-2.0f * tan_half / static_cast<float>(height)) * cam_up;
  const Eigen::Vector3f corner = forward - tan_half * aspect * right + tan_half * cam_up;

  const int tiles_x = (width + kTileSize - 1) / kTileSize, tiles_y = (height + kTileSize - 1) / kTileSize;
  const int ntiles = tiles_x * tiles_y;
  const int apron = filter.apron();
  const int buf_w = kTileSize + 2 * apron;
  const std::size_t buf_floats = static_cast<std::size_t>(buf_w) * buf_w * 5;
  // Each tile splats its samples into its own buffer (with an apron for the filter's reach);
  // the buffers are summed afterwards in a fixed order, so no sum depends on thread timing.
  // One allocation for the frame; each tile clears its own part (in parallel, while it is hot).
  const std::unique_ptr<float[]> tile_sums(new float[buf_floats * static_cast<std::size_t>(ntiles)]);
  if (recording) recording->tiles.assign((ntiles + recording->tile_stride - 1) / recording->tile_stride, {});
  std::atomic<std::uint64_t> primary_count{0}, secondary_count{0};
  tbb::enumerable_thread_specific<Scratch> scratch_per_thread;

  tbb::parallel_for(tbb::blocked_range<int>(0, ntiles, 1), [&](const tbb::blocked_range<int>& range) {
    Scratch& scratch = scratch_per_thread.local();
    if (textures && !scratch.texture_thread) scratch.texture_thread = textures->get_perthread_info();
    RTCIntersectContext coherent;
    rtcInitIntersectContext(&coherent);
    coherent.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    RTCIntersectContext incoherent;
    rtcInitIntersectContext(&incoherent);
    incoherent.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;

    for (int tile = range.begin(); tile != range.end(); ++tile) {
      const int tx = tile % tiles_x, ty = tile / tiles_x;
      const int x0 = tx * kTileSize, y0 = ty * kTileSize;
      const int x1 = std::min(width, x0 + kTileSize), y1 = std::min(height, y0 + kTileSize);
      const std::size_t nsamples = static_cast<std::size_t>(x1 - x0) * (y1 - y0) * spp;
      const std::size_t npackets = (nsamples + kPacket - 1) / kPacket;
      scratch.packets.resize(npackets);
      scratch.valid.resize(npackets);
      scratch.samples.resize(nsamples);
      scratch.secondary.clear();

      // 1. Camera rays, stratified and jittered inside each pixel, in packets of 16 (one pixel
      //    at 16 spp): neighbouring rays traverse the BVH together.
      std::size_t k = 0;
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
          const std::uint64_t pixel_key = rng::pixel_key(frame, static_cast<std::uint64_t>(y) * width + x);
          for (int s = 0; s < spp; ++s, ++k) {
            const rng::SampleStream r(pixel_key, static_cast<std::uint64_t>(s));
            const Eigen::Vector2f jitter = stratum(s, r.pair(0));
            const float fx = static_cast<float>(x) + jitter.x(), fy = static_cast<float>(y) + jitter.y();
            Eigen::Vector3f dir = corner + fx * step_x + fy * step_y;
            dir *= 1.0f / std::sqrt(dir.squaredNorm());
            SampleRecord& rec = scratch.samples[k];
            rec.offset_x = jitter.x();
            rec.offset_y = jitter.y();
            RTCRayHit16& p = scratch.packets[k / kPacket];
            const std::size_t lane = k % kPacket;
            p.ray.org_x[lane] = eye.x();
            p.ray.org_y[lane] = eye.y();
            p.ray.org_z[lane] = eye.z();
            p.ray.dir_x[lane] = dir.x();
            p.ray.dir_y[lane] = dir.y();
            p.ray.dir_z[lane] = dir.z();
            p.ray.tnear[lane] = 0.0f;
            p.ray.tfar[lane] = std::numeric_limits<float>::infinity();
            p.ray.time[lane] = 0.0f;
            p.ray.mask[lane] = camera_mask;
            p.ray.id[lane] = 0;
            p.ray.flags[lane] = 0;
            p.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
            p.hit.instID[0][lane] = RTC_INVALID_GEOMETRY_ID;
          }
        }
      for (std::size_t i = 0; i < npackets; ++i) scratch.valid[i].lanes.fill(-1);
      for (std::size_t lane = nsamples - (npackets - 1) * kPacket; lane < kPacket; ++lane) scratch.valid[npackets - 1][lane] = 0;
      RayRecording::Tile* rec_tile = recording && tile % recording->tile_stride == 0 ? &recording->tiles[tile / recording->tile_stride] : nullptr;
      if (rec_tile) {
        rec_tile->packets = scratch.packets;
        rec_tile->valid = scratch.valid;
      }
      for (std::size_t i = 0; i < npackets; ++i)
        rtcIntersect16(scratch.valid[i].data(), scene.get(), &coherent, &scratch.packets[i]);

      // 2. Shading: everything but the visibility of the chosen light and of the sky.
      auto add_ray = [&](const Eigen::Vector3f& org, const Eigen::Vector3f& d, float tfar) {
        RTCRay& ray = scratch.secondary.emplace_back();
        ray.org_x = org.x();
        ray.org_y = org.y();
        ray.org_z = org.z();
        ray.tnear = 0.0f;
        ray.dir_x = d.x();
        ray.dir_y = d.y();
        ray.dir_z = d.z();
        ray.time = 0.0f;
        ray.tfar = tfar;
        ray.mask = kModelMask | kGroundMask;
        ray.id = 0;
        ray.flags = 0;
        return static_cast<std::int32_t>(scratch.secondary.size() - 1);
      };
      k = 0;
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
          const std::uint64_t pixel = static_cast<std::uint64_t>(y) * width + x;
          const std::uint64_t pixel_key = rng::pixel_key(frame, pixel);
          // The secondary rays' strata are shifted per pixel, so that they do not line up with
          // the camera-ray strata (a sample in the top row would always test the same light area).
          const rng::SampleStream pr(pixel_key, ~0ULL);
          const int light_shift = static_cast<int>(pr.bits(0) % static_cast<std::uint32_t>(spp));
          const int sky_shift = static_cast<int>(pr.bits(1) % static_cast<std::uint32_t>(spp));
          for (int s = 0; s < spp; ++s, ++k) {
            SampleRecord& rec = scratch.samples[k];
            const RTCRayHit16& p = scratch.packets[k / kPacket];
            const std::size_t lane = k % kPacket;
            rec.shadow_ray = rec.sky_ray = -1;
            rec.with_light.setZero();
            rec.with_sky.setZero();
            const float t_bg = std::clamp((static_cast<float>(y) + rec.offset_y) * inv_height, 0.0f, 1.0f);
            const Eigen::Vector3f bg = transparent ? Eigen::Vector3f::Zero()
                                                   : Eigen::Vector3f((1.0f - t_bg) * sh.background_top + t_bg * sh.background_bottom);
            const unsigned geom = p.hit.geomID[lane];
            if (geom == RTC_INVALID_GEOMETRY_ID) {
              rec.base = Eigen::Vector4f(bg.x(), bg.y(), bg.z(), 0.0f);
              continue;
            }
            const Eigen::Vector3f dir(p.ray.dir_x[lane], p.ray.dir_y[lane], p.ray.dir_z[lane]);  // unit length
            const float t = p.ray.tfar[lane];
            const Eigen::Vector3f hit = eye + t * dir;
            Eigen::Vector3f ng(p.hit.Ng_x[lane], p.hit.Ng_y[lane], p.hit.Ng_z[lane]);
            const float ng_len2 = ng.squaredNorm();
            // Two-sided: open scans show their inside.
            ng *= (ng.dot(dir) > 0.0f ? -1.0f : 1.0f) / (ng_len2 > 0.0f ? std::sqrt(ng_len2) : 1.0f);
            const Eigen::Vector3f org = hit + eps * ng;
            // The random numbers of the secondary rays: stratified over the pixel's samples.
            const rng::SampleStream r(pixel_key, static_cast<std::uint64_t>(s));
            const int j_light = s + light_shift >= spp ? s + light_shift - spp : s + light_shift;
            const int j_sky = s + sky_shift >= spp ? s + sky_shift - spp : s + sky_shift;
            // Each random number is drawn only where it is used (most of the ground needs none).
            auto light_direction = [&](const FrameLight& l) {
              // Uniform over the light's disc (a spherical cap).
              const Eigen::Vector2f u_light = stratum(j_light, r.pair(1));
              const float cos_t = 1.0f - u_light.x() * l.one_minus_cos_half_angle;
              const float sin_t = std::sqrt(std::max(0.0f, 1.0f - cos_t * cos_t));
              float sin_phi, cos_phi;
              sincos_turns(u_light.y(), sin_phi, cos_phi);
              return Eigen::Vector3f(cos_t * l.direction + sin_t * (cos_phi * l.tangent + sin_phi * l.bitangent));
            };
            auto sky_direction = [&](const Eigen::Vector3f& n, const Eigen::Vector3f& t1, const Eigen::Vector3f& t2) {
              // Cosine-weighted over the hemisphere: the fraction of unblocked rays is then exactly
              // the occlusion of a diffuse surface's sky light.
              const Eigen::Vector2f u_sky = stratum(j_sky, r.pair(2));
              const float rad = std::sqrt(u_sky.x());
              float sin_phi, cos_phi;
              sincos_turns(u_sky.y(), sin_phi, cos_phi);
              return Eigen::Vector3f(rad * cos_phi * t1 + rad * sin_phi * t2 + std::sqrt(std::max(0.0f, 1.0f - u_sky.x())) * n);
            };

            if (geom == kGroundGeometry) {
              // The background's share that reaches the camera without a ray's help (and, as alpha,
              // the shadow that is certain); the shares whose rays are traced come back if unblocked.
              float unshadowed = 1.0f - ground_shadow;
              const auto term = [&](float f) {
                return Eigen::Vector4f(bg.x() * f, bg.y() * f, bg.z() * f, transparent ? -f : 0.0f);
              };
              // Only the model casts shadows on the ground: a ray that misses the model's bounding
              // sphere is known to be unblocked and is not traced (most of the visible ground).
              auto may_hit_model = [&](const Eigen::Vector3f& d) {
                const float b = org.dot(d), c = org.squaredNorm() - model_radius * model_radius;
                return c < 0.0f || (b < 0.0f && b * b >= c);
              };
              // The same test for a light's whole disc, before sampling a direction in it: the cone
              // around the light's centre misses the sphere when the angle between its axis and
              // the sphere's centre exceeds the cone's half angle plus the sphere's angular radius.
              const float dist2 = org.squaredNorm();
              const float dist = std::sqrt(dist2);
              const float sin_r = std::min(1.0f, model_radius / dist), cos_r = std::sqrt(1.0f - sin_r * sin_r);
              auto disc_may_hit_model = [&](const FrameLight& l) {
                if (dist2 <= model_radius * model_radius) return true;
                const float cos_limit = l.cos_half_angle * cos_r - l.sin_half_angle * sin_r;  // cos(half angle + radius)
                const float cos_axis = -org.dot(l.direction) / dist;
                return cos_axis >= cos_limit - 1e-4f;  // margin for rounding
              };
              bool shadow_possible = false;  // from some light with a share of the ground's light
              if (sh.shadows)
                for (std::size_t i = 0; i < nlights && !shadow_possible; ++i)
                  shadow_possible = ground_weights[i] > 0.0f && disc_may_hit_model(lights[i]);
              if (ground_light_share > 0.0f) {
                const FrameLight* l = shadow_possible ? &lights[choose(ground_weights, nlights, ground_light_total, r.pair(3).u)] : nullptr;
                Eigen::Vector3f d;
                if (l && disc_may_hit_model(*l) && may_hit_model(d = light_direction(*l))) {
                  rec.with_light = term(ground_light_share);
                  rec.shadow_ray = add_ray(org, d, std::numeric_limits<float>::infinity());
                } else {
                  unshadowed += ground_light_share;
                }
              }
              if (ground_sky_share > 0.0f) {
                // Beyond the AO length from the model's bounding sphere nothing can occlude the sky.
                if (sh.ambient_occlusion && dist2 < ground_ao_reach2) {
                  rec.with_sky = term(ground_sky_share);
                  rec.sky_ray = add_ray(org, sky_direction(up, up_t1, up_t2), ao_length);
                } else {
                  unshadowed += ground_sky_share;
                }
              }
              rec.base = Eigen::Vector4f(bg.x() * unshadowed, bg.y() * unshadowed, bg.z() * unshadowed,
                                         transparent ? 1.0f - unshadowed : 0.0f);
              continue;
            }

            // The model.
            const std::size_t prim = p.hit.primID[lane];
            const auto& tri = triangles[prim];
            const float bu = p.hit.u[lane], bv = p.hit.v[lane], bw = 1.0f - bu - bv;
            Eigen::Vector3f n = bw * normals[tri[0]] + bu * normals[tri[1]] + bv * normals[tri[2]];
            const float n_len2 = n.squaredNorm();
            n = n_len2 > 0.0f ? Eigen::Vector3f(n * (1.0f / std::sqrt(n_len2))) : ng;
            if (n.dot(dir) > 0.0f) n = -n;
            Eigen::Vector3f albedo = mat.base_color;
            if (!colors.empty()) albedo = bw * colors[tri[0]] + bu * colors[tri[1]] + bv * colors[tri[2]];
            if (texture) {
              const Eigen::Vector2f uv = bw * corner_uvs[3 * prim] + bu * corner_uvs[3 * prim + 1] + bv * corner_uvs[3 * prim + 2];
              // Isotropic footprint of one sample in texture space: the pixel's width at this
              // distance, stretched by the slant, divided by sqrt(spp) because the samples already
              // average over the pixel.
              const float slant = std::max(0.2f, std::abs(ng.dot(dir)));
              const float width_uv = uv_scale[prim] * t * pixel_angle / slant / std::sqrt(static_cast<float>(spp));
              OIIO::TextureOpt opt;
              float rgb[3] = {0, 0, 0};
              // OBJ's v runs upwards; OpenImageIO's t runs down the image.
              if (textures->texture(texture, scratch.texture_thread, opt, uv.x(), 1.0f - uv.y(), width_uv, 0.0f, 0.0f, width_uv, 3, rgb))
                albedo = Eigen::Vector3f(rgb[0], rgb[1], rgb[2]);
            }
            const Eigen::Vector3f view = -dir;
            // Unshadowed Blinn-Phong light from light i (cos_l = cosine of its incidence, > 0).
            auto reflected = [&](std::size_t i, float cos_l) {
              const Eigen::Vector3f half = lights[i].direction + view;
              const float cos_h = n.dot(half) / std::sqrt(half.squaredNorm());
              const float spec = cos_h > spec_cutoff ? spec_scale * std::pow(cos_h, shininess) : 0.0f;
              return Eigen::Vector3f(lights[i].radiance.cwiseProduct(albedo + Eigen::Vector3f::Constant(spec)) * cos_l);
            };
            rec.base = Eigen::Vector4f(0.0f, 0.0f, 0.0f, 1.0f);
            float cosines[8];
            for (std::size_t i = 0; i < nlights; ++i) cosines[i] = n.dot(lights[i].direction);
            if (sh.shadows) {
              // One shadow ray to one light, chosen in proportion to the light it brings here
              // unshadowed (its irradiance's luminance) and weighted by 1/probability: unbiased,
              // and the light that matters most here gets most of the rays. Only the chosen
              // light's reflection is evaluated.
              float weights[8] = {};
              float light_total = 0.0f;
              for (std::size_t i = 0; i < nlights; ++i) {
                weights[i] = cosines[i] > 0.0f ? cosines[i] * lights[i].radiance_luminance : 0.0f;
                light_total += weights[i];
              }
              if (light_total > 0.0f) {
                const std::size_t i = choose(weights, nlights, light_total, r.pair(3).u);
                const Eigen::Vector3f c = reflected(i, cosines[i]) * (light_total / weights[i]);
                rec.with_light = Eigen::Vector4f(c.x(), c.y(), c.z(), 0.0f);
                rec.shadow_ray = add_ray(org, light_direction(lights[i]), std::numeric_limits<float>::infinity());
              }
            } else {
              for (std::size_t i = 0; i < nlights; ++i)
                if (cosines[i] > 0.0f) rec.base.head<3>() += reflected(i, cosines[i]);
            }
            const Eigen::Vector3f sky = sh.ambient.cwiseProduct(albedo);
            if (sh.ambient_occlusion) {
              rec.with_sky = Eigen::Vector4f(sky.x(), sky.y(), sky.z(), 0.0f);
              Eigen::Vector3f t1, t2;
              basis(n, t1, t2);
              rec.sky_ray = add_ray(org, sky_direction(n, t1, t2), ao_length);
            } else {
              rec.base.head<3>() += sky;
            }
            // Extra layers: averaged over the pixel's own samples (no filter: they are data, not light).
            if (!image.albedo.empty())
              for (int c = 0; c < 3; ++c) image.albedo[pixel * 3 + c] += albedo[c] / static_cast<float>(spp);
            if (!image.normal.empty())
              for (int c = 0; c < 3; ++c) image.normal[pixel * 3 + c] += n[c];
            if (!image.depth.empty()) image.depth[pixel] = std::min(image.depth[pixel], t * dir.dot(forward));
          }
        }
      if (!image.normal.empty())
        for (int py = y0; py < y1; ++py)
          for (int px = x0; px < x1; ++px) {
            float* nn = &image.normal[(static_cast<std::size_t>(py) * width + px) * 3];
            const float len = std::sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
            if (len > 0.0f)
              for (int c = 0; c < 3; ++c) nn[c] /= len;
          }

      // 3. All shadow and occlusion rays of the tile in one call: Embree stops at the first hit.
      if (rec_tile) rec_tile->secondary = scratch.secondary;
      if (!scratch.secondary.empty())
        rtcOccluded1M(scene.get(), &incoherent, scratch.secondary.data(), static_cast<unsigned>(scratch.secondary.size()),
                      sizeof(RTCRay));

      // 4. Reconstruction filter: every sample is splatted onto the pixels within the radius.
      float* sums = tile_sums.get() + buf_floats * static_cast<std::size_t>(tile);
      std::fill(sums, sums + buf_floats, 0.0f);
      switch (filter.reach()) {
        case 0: splat_tile<0>(scratch, sums, buf_w, x1 - x0, y1 - y0, apron); break;
        case 1: splat_tile<1>(scratch, sums, buf_w, x1 - x0, y1 - y0, apron); break;
        default: splat_tile<2>(scratch, sums, buf_w, x1 - x0, y1 - y0, apron); break;
      }
      primary_count += nsamples;
      secondary_count += scratch.secondary.size();
    }
  });

  // Each pixel gathers the tile buffers that reach it, always in the same order.
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& range) {
    for (int y = range.begin(); y != range.end(); ++y)
      for (int x = 0; x < width; ++x) {
        float acc[5] = {0, 0, 0, 0, 0};
        for (int ty = std::max(0, (y - apron) / kTileSize); ty <= std::min(tiles_y - 1, (y + apron) / kTileSize); ++ty)
          for (int tx = std::max(0, (x - apron) / kTileSize); tx <= std::min(tiles_x - 1, (x + apron) / kTileSize); ++tx) {
            const int bx = x - (tx * kTileSize - apron), by = y - (ty * kTileSize - apron);
            if (bx < 0 || by < 0 || bx >= buf_w || by >= buf_w) continue;
            const float* src = tile_sums.get() + buf_floats * static_cast<std::size_t>(ty * tiles_x + tx) +
                               (static_cast<std::size_t>(by) * buf_w + bx) * 5;
            for (int c = 0; c < 5; ++c) acc[c] += src[c];
          }
        float* dst = &image.rgba[(static_cast<std::size_t>(y) * width + x) * 4];
        for (int c = 0; c < 4; ++c) dst[c] = acc[4] > 0.0f ? acc[c] / acc[4] : 0.0f;
      }
  });

  if (stats) {
    stats->primary_rays += primary_count;
    stats->secondary_rays += secondary_count;
  }
  image.info.camera = camera;
  image.info.frame_index = frame;
  image.info.samples_per_pixel = spp;
  image.info.render_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return image;
}

}  // namespace meshtour
