#pragma once
// The renderer's private parts, shared by renderer.cpp (scene set-up, frames) and
// tile_kernel.cpp (the per-tile hot loop, compiled once per instruction set). Not public API.
#include <Eigen/Core>
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/texture.h>
#include <embree3/rtcore.h>

#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "core/error.h"
#include "mesh/image_bytes_reader.h"
#include "mesh/ray_scene.h"
#include "tracer/denoiser.h"
#include "tracer/environment.h"
#include "tracer/film.h"
#include "tracer/instruction_set.h"
#include "tracer/renderer_internal.h"
#include "tracer/tracer.h"

namespace meshtour {
namespace render_detail {

struct TextureSystemDeleter {
  void operator()(OIIO::TextureSystem* t) const { OIIO::TextureSystem::destroy(t); }
};
using TextureSystemPtr = std::unique_ptr<OIIO::TextureSystem, TextureSystemDeleter>;

// The Embree scene holds the model alone (mesh/ray_scene.h, shared with the visibility module);
// the ground is a plane the kernel intersects itself.
constexpr unsigned kModelGeometry = RayScene::kModelGeometry, kModelMask = RayScene::kModelMask;

// A light as one frame sees it: world direction, colour and its disc's size.
struct FrameLight {
  Eigen::Vector3f direction;  // towards the light
  Eigen::Vector3f tangent, bitangent;
  Eigen::Vector3f radiance;   // colour * intensity
  float radiance_luminance;
  float one_minus_cos_half_angle;  // the disc's solid angle / 2 pi
  float cos_half_angle, sin_half_angle;
};

// The most interreflections a sample follows (Shading::bounces).
constexpr int kMaxBounces = 4;

// Everything about a frame that its tiles share: camera, lights, material, ground and sampling.
struct Frame {
  std::uint64_t index = 0;
  int width = 0, height = 0, spp = 1;
  bool transparent = false;
  Eigen::Vector3f eye, forward;
  // Camera ray through film position (fx, fy): corner + fx * step_x + fy * step_y, normalised.
  Eigen::Vector3f corner, step_x, step_y;
  // The ground (a square of half side ground_half around the model, perpendicular to `up`, at
  // dot(point, up) = ground_height): whether there is one, and whether camera rays see it (from
  // below, the camera must see the model, not the ground's underside).
  bool has_ground = false, ground_visible = false;
  float ground_height = 0.0f, ground_half = 0.0f;
  std::vector<FrameLight> lights;
  Eigen::Vector3f base_color, ambient, background_top, background_bottom;
  // With an environment, the sky's light at normal n is sky_light(n) (E(n) / pi) instead of
  // `ambient`, and the rays see `sky_radiance` in the directions they sample.
  bool environment = false;
  const IrradianceMap* sky_light = nullptr;
  const EnvironmentRadiance* sky_radiance = nullptr;
  // Where glossy reflections sample the environment's light beside their BRDF (null: the BRDF alone).
  const EnvironmentDistribution* sky_distribution = nullptr;
  // With an environment image and occlusion rays: the sky's light on a sample is the image's
  // radiance along its occlusion ray (traced to any distance: a sun's shadow is long), not the
  // irradiance times the ray's visibility. A diffuse sample's ray is picked from the
  // environment's distribution with probability sky_environment_share (else cosine-distributed)
  // and weighed by the mixture's density; sky_upward is E(up) / pi, the ground's unblocked mean.
  bool sample_sky = false;
  float sky_environment_share = 0.0f, sky_length = 0.0f, sky_upward = 0.0f;
  // Shading::environment_background: per pixel, the environment's radiance along the camera ray
  // through the pixel's centre (RGB), the backdrop of every sample of the pixel; empty: the
  // gradient. One lookup a pixel, not a sample (the image is at most 512 x 256: finer than it).
  std::vector<float> backdrop_rgb;
  bool shadows = true, ambient_occlusion = true;
  int bounces = 0;  // Shading::bounces where there are occlusion rays, else 0
  float shininess = 1.0f, spec_scale = 0.0f, spec_cutoff = 1.0f;
  float eps = 0.0f, ao_length = 0.0f, model_radius = 0.0f, ground_ao_reach2 = 0.0f;
  float pixel_angle = 0.0f, inv_height = 0.0f;
  // The ground's light choice and the shares of its light the model can take away.
  float ground_weights[8] = {};
  float ground_light_total = 0.0f, ground_shadow = 0.0f, ground_light_share = 0.0f, ground_sky_share = 0.0f;
  Eigen::Vector3f up, up_t1, up_t2;  // the ground's normal and tangents, for its occlusion rays
  std::uint64_t seed = 0;  // RenderOptions::sample_seed, placed above any frame index
};

// Per-thread buffers, reused from tile to tile.
struct Scratch {
  RTCRayHit16 primary;
  RTCRay16 shadow, sky;
  RTCRayHit16 bounce;  // occlusion rays that find what they meet, with interreflections
  OIIO::TextureSystem::Perthread* texture_thread = nullptr;
};

// A tile's rays' context: Embree's (first, so that Embree's pointer to it is one to this), and
// what filter_hits needs: the renderer and the thread's texture handle.
struct RayContext {
  RTCIntersectContext embree;
  const Renderer::Impl* renderer = nullptr;
  Scratch* scratch = nullptr;
};
// Embree's context filter for scenes with alpha or single-sided materials: a hit on a face whose
// surface is not there for this ray (alpha under the mask's cutoff; a blend's share 1 - alpha,
// decided by a hash of the ray and the face, so the same in every run; a single-sided face met
// from behind, by any ray) is rejected, and the ray goes on.
void filter_hits(const RTCFilterFunctionNArguments* args);
// The context of a tile's camera rays (coherent) or secondary rays (incoherent).
RayContext ray_context(const Renderer::Impl& r, Scratch& scratch, bool camera);

// One tile's ray and sample counts.
struct TileCounts {
  std::uint64_t primary = 0, secondary = 0;
};

}  // namespace render_detail

using namespace render_detail;

struct Renderer::Impl {
  RenderOptions options;
  std::shared_ptr<const RayScene> rays;  // the model's BVH, perhaps shared with the visibility module
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
  bool has_ground = false;
  float ground_height = 0.0f;  // dot(point, up) of the ground plane
  float ground_half = 0.0f;    // half its side: far beyond any shadow; looks infinite
  // One image map of a material as the tiles look it up: its handle and the format's rules.
  struct Map {
    OIIO::TextureSystem::TextureHandle* handle = nullptr;  // none: no map
    OIIO::TextureOpt::Wrap wrap_s = OIIO::TextureOpt::WrapPeriodic, wrap_t = OIIO::TextureOpt::WrapPeriodic;
    // The format's filters (MeshTexture): the magnification one where a sample's footprint is
    // under a texel of the largest side, the minification one and the mipmap mode elsewhere.
    OIIO::TextureOpt::InterpMode mag_interp = OIIO::TextureOpt::InterpBilinear, min_interp = OIIO::TextureOpt::InterpBilinear;
    OIIO::TextureOpt::MipMode mip = OIIO::TextureOpt::MipModeTrilinear;
    float texels_across = 1.0f;  // the image's larger side in texels
    bool grey = false;  // a 1- or 2-channel (grey, grey + alpha) image: its first channel is grey
    bool srgb = false;  // the values are sRGB-encoded: decoded to linear after the lookup
    int alpha_channel = -1;  // the image's alpha (straight, not premultiplied), or none
  };
  // The mesh's materials as the tiles use them: maps, colour factor.
  struct Surface {
    Map texture;     // the base colour map
    Map normal_map;  // a tangent-space normal map
    float normal_scale = 1.0f;
    Map occlusion_map;  // its first channel darkens the sky's light
    float occlusion_strength = 1.0f;
    Eigen::Vector3f factor{1.0f, 1.0f, 1.0f};
    bool replaces_base_color = false;   // untextured with a colour of its own (not the look's)
    bool texture_times_vertex_colors = false;
    // glTF's metallic-roughness BRDF in place of the look's highlight (MeshMaterial), its
    // factors and map (blue: metal, green: roughness).
    bool metallic_roughness = false;
    float metallic = 0.0f, roughness = 1.0f;
    Map metallic_roughness_map;
    Eigen::Vector3f emissive = Eigen::Vector3f::Zero();  // linear radiance, times the map
    Map emissive_map;
    bool unlit = false;  // the base colour as it is, no light
    // What rays ask before they stop at one of its faces (filter_hits): its alpha (the factor,
    // times the base colour map's alpha channel) and whether its back is seen.
    MeshMaterial::AlphaMode alpha_mode = MeshMaterial::AlphaMode::opaque;
    float alpha = 1.0f, alpha_cutoff = 0.5f;
    bool double_sided = true;
    bool rays_filtered() const { return alpha_mode != MeshMaterial::AlphaMode::opaque || !double_sided; }
  };
  bool filtered_rays = false;  // some surface's rays_filtered(): the tiles' contexts carry filter_hits
  std::vector<Surface> surfaces;              // empty: the look's material everywhere
  std::vector<std::uint32_t> triangle_surface;  // per triangle; empty = surface 0
  // Per-corner UVs, when some surface has a map.
  std::vector<Eigen::Vector2f> corner_uvs;
  // Per-corner shading normals, when the file has its own or a normal map needs them (else
  // `normals` per vertex), and per-corner tangents (xyz, w = bitangent sign) for normal maps.
  std::vector<Eigen::Vector3f> corner_normals;
  std::vector<Eigen::Vector4f> corner_tangents;
  std::vector<float> uv_scale;  // per triangle: sqrt(uv area / world area), for the filter footprint
  // Embedded images (glTF) read through these; declared before `textures`, which reads them until
  // it is destroyed.
  std::vector<std::unique_ptr<ImageBytesReader>> embedded_images;
  std::vector<std::shared_ptr<const std::vector<unsigned char>>> embedded_bytes;
  TextureSystemPtr textures;
  // The environment's irradiance in the world frame (Shading::environment), once per job.
  std::optional<IrradianceMap> environment_light;
  std::optional<EnvironmentRadiance> environment_radiance;
  std::optional<EnvironmentDistribution> environment_distribution;  // unset: nothing to sample
  float environment_upward = 0.0f;  // luminance of upward_irradiance(): the ground's unblocked sky
  ReconstructionFilter filter;
  // The Film's and the denoiser's memory, kept between frames (one per concurrent render()).
  mutable FilmMemory film_memory;
  mutable SparePool<DenoiseWorkspace> denoiser_memory;

  // A frame: its set-up, its tiles traced onto the Film, the Film gathered, the denoiser run on
  // the Film's layers, and the layers written into the Image.
  Image render(const Camera& camera, std::uint64_t frame, RenderStats* stats, RayRecording* recording) const;
  // What the tiles of frame `frame` seen by `camera` share.
  Frame frame_for(const Camera& camera, std::uint64_t frame) const;
  // Every tile of the frame through the tile kernel onto `film`, in parallel; the rays traced.
  TileCounts trace_tiles(const Frame& f, Film& film, RayRecording* recording) const;
  // The denoised frame from the gathered Film's beauty and guides.
  std::vector<float> denoise_film(const Film& film, bool transparent) const;
  // Traces frame `f`'s samples in `tile` and splats them onto it (the tile's sums and layers,
  // cleared by Film::tile). One definition (tile_kernel.cpp) specialised once per instruction set
  // (instruction_set.h); `tile_kernel` is the copy this CPU runs, `instruction_set` its set.
  template <InstructionSet>
  void render_tile(const Frame& f, Scratch& scratch, const FilmTile& tile, RayRecording::Tile* recorded, TileCounts& counts) const;
  using TileKernel = void (Impl::*)(const Frame&, Scratch&, const FilmTile&, RayRecording::Tile*, TileCounts&) const;
  InstructionSet instruction_set = InstructionSet::baseline;
  TileKernel tile_kernel = &Impl::render_tile<InstructionSet::baseline>;

};

// Each copy of the kernel is compiled in its own set's copy of tile_kernel.cpp only (with that
// set's -march; tracer/CMakeLists.txt), and nowhere else. Without these declarations a file
// that takes a copy's address while it sees the template's body (renderer.cpp and
// tile_kernel.cpp in one unity batch) compiles that copy again with the baseline's flags, and
// the linker may keep that one (from 84c641f to c6bc695 every set ran SSE2 code, at half the
// speed). render_tile's static_assert refuses such a copy.
extern template void Renderer::Impl::render_tile<InstructionSet::baseline>(const Frame&, Scratch&, const FilmTile&, RayRecording::Tile*,
                                                                           TileCounts&) const;
extern template void Renderer::Impl::render_tile<InstructionSet::x86_64_v3>(const Frame&, Scratch&, const FilmTile&, RayRecording::Tile*,
                                                                            TileCounts&) const;
extern template void Renderer::Impl::render_tile<InstructionSet::x86_64_v4>(const Frame&, Scratch&, const FilmTile&, RayRecording::Tile*,
                                                                            TileCounts&) const;

}  // namespace meshtour
