#pragma once
// The ray tracer: one Embree scene per job, frames rendered in parallel tiles, deterministic
// (a pixel's value depends only on the scene, the camera, the frame index and the pixel, never
// on threads, tile order or which process renders it).
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <span>
#include <vector>

#include "core/camera.h"
#include "mesh/mesh.h"

namespace meshtour {

class RayScene;  // mesh/ray_scene.h
struct EnvironmentImage;  // tracer/environment.h

/// A pinhole camera in model units.

/// A distant disc light (like the sun, or a large softbox far away) placed relative to the
/// camera, so that the lighting stays the same as the camera travels around the model. Its
/// apparent size makes shadows soft: 0 gives hard shadows.
struct Light {
  /// Direction the light comes from, in camera space (x right, y up, z towards the viewer).
  Eigen::Vector3f from_camera{-0.45f, 0.55f, 1.0f};
  Eigen::Vector3f color{1.0f, 1.0f, 1.0f};  ///< linear RGB
  float intensity = 1.0f;                   ///< irradiance on a surface facing the light
  float angular_diameter_deg = 10.0f;       ///< apparent size seen from the model
};

/// The model's surface: a diffuse base with a glossy (Blinn-Phong) coat.
struct Material {
  Eigen::Vector3f base_color{0.75f, 0.75f, 0.75f};  ///< linear RGB, used where the mesh has no colours/texture
  float roughness = 0.45f;  ///< 0 mirror-like highlight .. 1 no visible highlight
  float specular = 0.5f;    ///< highlight strength; 0.5 is a dielectric's 4 % reflectance
  bool use_vertex_colors = true;
  bool use_texture = true;  ///< the mesh's maps (base colour, normal, occlusion, ...), when it has them
  /// The file's own shading where it gives one: glTF's metallic-roughness BRDF in place of
  /// `roughness` and `specular`, its emission, KHR_materials_unlit. False: every surface gets this
  /// Material's diffuse base and highlight (on the file's colours and maps).
  bool use_file_material = true;
  /// Shading normals are smoothed across edges where the faces meet at less than this angle
  /// (degrees) and kept apart where they meet at more: a box, a plinth or a CAD part keeps flat
  /// faces and sharp edges, a scan's curved surface stays smooth. 180 smooths every edge.
  float crease_angle_deg = 60.0f;
};

enum class BackgroundKind { gradient, transparent };
/// The display tone curve (PNG frames, the video; EXR stays linear). clamp: none, values over 1
/// clip; filmic: Narkowicz's ACES fit, per channel; pbr_neutral: Khronos PBR Neutral (2024), per
/// pixel, which keeps base colours under 0.8 as they are (up to a 0.04 toe) and compresses only
/// highlights, desaturating them towards white: a material's colour shows as the file gives it.
enum class ToneMapping { clamp, filmic, pbr_neutral };
/// "clamp", "filmic", "pbr-neutral": the option's and the EXR header's spelling.
std::string_view tone_mapping_name(ToneMapping t);
/// The curve of that name, or nothing for another text.
std::optional<ToneMapping> tone_mapping_from_name(std::string_view name);
/// Every curve's name (static storage), the option's choices: {"filmic", "clamp", "pbr-neutral"}.
std::vector<std::string_view> tone_mapping_names();
/// Khronos PBR Neutral of one linear RGB value (the published reference formula).
Eigen::Vector3f pbr_neutral(Eigen::Vector3f linear);

/// How a frame looks: lights, shadows, ambient occlusion, ground, background, exposure.
/// Presets: `look_preset("studio")` and `look_preset("plain")`.
struct Shading {
  std::string preset = "studio";  ///< the preset these values started from (informational)
  Material material;
  std::vector<Light> lights;     ///< at most 8
  bool shadows = true;           ///< trace shadow rays (soft, from the lights' discs)
  Eigen::Vector3f ambient{0.25f, 0.25f, 0.25f};  ///< sky light from every direction, linear RGB
  /// Image-based light in place of `ambient` (tracer/environment.h): the environment's diffuse
  /// light (its irradiance), occluded by the sky rays as the ambient is; null = `ambient`.
  std::shared_ptr<const EnvironmentImage> environment;
  float environment_rotation_deg = 0.0f;  ///< turns the environment about the up axis
  float environment_intensity = 1.0f;     ///< multiplies its radiance
  /// Shows the environment behind the model (and, darkened by its shadows, on the ground) in
  /// place of the look's gradient; transparent frames stay transparent.
  bool environment_background = false;
  bool ambient_occlusion = true;  ///< the sky light is occluded by nearby geometry
  float ao_distance = 0.3f;       ///< AO ray length, fraction of the model's bounding-box diagonal
  /// Diffuse interreflections: where a sample's occlusion ray meets the model, the light that
  /// point reflects towards it (lights and sky, through further occlusion rays, up to this many
  /// surfaces deep) instead of darkness. 0: occlusion only, as before. Needs ambient_occlusion.
  int bounces = 0;
  /// Glossy reflections of glTF materials sample the environment's light as well as their BRDF
  /// (multiple importance sampling). false: the BRDF alone, for measurements and tests.
  bool sample_environment = true;
  bool ground = true;             ///< a shadow-catching floor under the model (perpendicular to RenderOptions::world_up)
  float ground_shadow = 0.85f;    ///< 0 = the floor shows nothing, 1 = full-strength shadows on it
  BackgroundKind background = BackgroundKind::gradient;
  Eigen::Vector3f background_top{0.50f, 0.51f, 0.53f};     ///< linear RGB, top of the frame
  Eigen::Vector3f background_bottom{0.16f, 0.16f, 0.17f};  ///< linear RGB, bottom of the frame
  float exposure = 0.0f;          ///< stops, applied for display outputs (PNG, video), not to EXR
  ToneMapping tone_mapping = ToneMapping::filmic;  ///< display outputs only; EXR stays linear
};

/// The named looks. "studio": key, fill and rim lights around the camera with soft shadows,
/// ambient occlusion, a shadow-catching ground and a soft gradient. Per camera sample it traces
/// one camera ray and, where that ray hits the model or the ground, at most one shadow ray towards
/// one light (chosen in proportion to its unshadowed irradiance at that point) and at most one
/// ambient-occlusion ray: at most 3 rays per sample (scenes/README.md has the details). "plain": even light from the camera's side, no
/// shadows, no occlusion, no ground, a light background, for catalogues; one camera ray per sample.
/// \throw InputError for another name.
Shading look_preset(const std::string& name);
/// The preset names, for help texts: "studio, plain".
std::string look_preset_names();

/// Optional extra layers of EXR frames, for compositing.
struct ExtraLayers {
  bool albedo = false;  ///< surface colour before lighting (albedo.R/G/B)
  bool normal = false;  ///< world-space shading normal (N.X/Y/Z)
  bool depth = false;   ///< distance along the camera's axis, +inf where nothing was hit (Z)
  bool any() const { return albedo || normal || depth; }
};

struct RenderOptions {
  int width = 1280;
  int height = 720;
  /// Owen-scrambled Sobol samples in Z order (tracer/sampler.h): the error falls a little faster
  /// than 1/sqrt(spp) (shadow edges and occlusion are not smooth); powers of two keep the points a net.
  int samples_per_pixel = 16;
  /// Radius of the Blackman-Harris reconstruction filter in pixels: samples are weighted by
  /// their distance to each pixel's centre, removing the jaggies a box filter leaves. 0.5..2.
  float filter_radius = 1.5f;
  /// The model's up axis (the ground plane is perpendicular to it). Need not be unit length.
  Eigen::Vector3d world_up = Eigen::Vector3d::UnitY();
  ExtraLayers layers;
  Shading shading = look_preset("studio");
  /// Also produce a denoised frame (Image::denoised; tracer/denoiser.h), which PNG frames and the
  /// video show; the raw frame stays in Image::rgba (the EXR's main layer).
  bool denoise = true;
  /// Another set of random numbers (0 = the frames meshtour renders): for benchmarks that
  /// measure how much two independent renders of a frame differ (flicker). Not an option.
  std::uint32_t sample_seed = 0;
};

/// What a frame records about how it was made, written into EXR headers.
struct FrameInfo {
  Camera camera;
  std::uint64_t frame_index = 0;
  int samples_per_pixel = 0;
  double render_seconds = 0.0;
};

/// A linear-light RGBA image, rows top to bottom.
/// With a transparent background, RGB is premultiplied by alpha (alpha is the coverage of the
/// model and of the shadows on the ground); otherwise RGB includes the background and alpha is
/// the model's coverage.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<float> rgba;    ///< width * height * 4
  std::vector<float> albedo;  ///< width * height * 3, or empty (see ExtraLayers)
  std::vector<float> normal;  ///< width * height * 3, or empty
  std::vector<float> depth;   ///< width * height, or empty
  /// The denoised frame, width * height * 4 like rgba, or empty (RenderOptions::denoise).
  std::vector<float> denoised;
  bool transparent = false;   ///< PNGs get an alpha channel
  // How display outputs (PNG, video) turn linear light into 8 bits.
  float exposure = 0.0f;  ///< stops
  ToneMapping tone_mapping = ToneMapping::clamp;
  FrameInfo info;

  /// What display outputs (PNG, video) show: the denoised frame when there is one, else rgba.
  const std::vector<float>& display_rgba() const { return denoised.empty() ? rgba : denoised; }
  /// The display value of one linear RGB value: exposure, tone curve, sRGB encoding, in [0,1].
  Eigen::Vector3f display(const Eigen::Vector3f& linear) const;
  /// The display value of a grey of this linear value (each channel of it, for the per-channel curves).
  float display(float linear) const { return display(Eigen::Vector3f::Constant(linear)).x(); }
  /// 8-bit sRGB-encoded RGB, rows top to bottom: what PNG frames and the video receive. A
  /// transparent image is shown over black here (premultiplied).
  std::vector<std::uint8_t> to_srgb8() const;
  /// 8-bit sRGB RGBA with straight (unassociated) alpha, as PNG expects.
  std::vector<std::uint8_t> to_srgba8() const;
};

/// Ray counts of one render (for benchmarks and the progress line).
struct RenderStats {
  std::uint64_t primary_rays = 0;
  std::uint64_t secondary_rays = 0;  ///< shadow and ambient-occlusion rays
};

/// Renders one mesh. Building the Embree scene (the BVH) happens once, in the constructor;
/// render() may then be called for any number of cameras, also concurrently.
class Renderer {
public:
  /// \throw InputError for a mesh without triangles or bad options, IoError for an unreadable
  ///        texture, RuntimeFailure if Embree fails.
  Renderer(const TriangleMesh& mesh, const RenderOptions& options);
  /// On the mesh's ray-tracing scene, built by the caller and shared (a tour's visibility tests
  /// use the same one: one BVH per job); null builds one. \throw InputError also if `rays` is of
  /// another mesh.
  Renderer(const TriangleMesh& mesh, const RenderOptions& options, std::shared_ptr<const RayScene> rays);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// Renders frame `frame_index` of a job, using the calling thread's TBB arena (limit threads
  /// with a task_arena or tbb::global_control around the call). The frame index seeds the
  /// random numbers, so frame k is the same whether it is rendered alone or in a sequence.
  Image render(const Camera& camera, std::uint64_t frame_index = 0, RenderStats* stats = nullptr) const;

  const RenderOptions& options() const;

  struct Impl;

private:
  friend struct RendererAccess;  // benchmarks: tracer/renderer_internal.h
  std::unique_ptr<Impl> impl_;
};

/// The vertical field of view (degrees) at which every vertex of `positions` stays inside the
/// frame of every camera in `cameras` (their own fov is ignored), with `margin` of the frame's
/// smaller side left free at every edge (0.05 = 5 %; core/camera.h frame_fill). Vertices behind a
/// camera are ignored.
/// \throw InputError if no vertex is in front of any camera or the model cannot fit in 170 degrees.
double fit_vertical_fov(const std::vector<Camera>& cameras, std::span<const Eigen::Vector3d> positions,
                        double aspect, double margin = 0.05);

/// The same field of view, reading only `hull` (the vertices of the convex hull of `positions`,
/// mesh/convex_hull.h) for every camera that has the whole hull in front of it: then every vertex
/// is in front, and the largest |y|/z and |x|/z over the vertices is reached at a hull vertex, so
/// the result is the one of every vertex. A camera with a hull vertex at or behind its eye (only
/// part of the model counts) reads every vertex of `positions`.
double fit_vertical_fov(const std::vector<Camera>& cameras, std::span<const Eigen::Vector3d> positions,
                        std::span<const Eigen::Vector3d> hull, double aspect, double margin = 0.05);

/// Writes `image` by extension: ".png" as 8-bit sRGB (RGBA when the image is transparent),
/// tone mapped, of the denoised frame when there is one; ".exr" as half-float linear RGBA (the
/// raw frame) plus the denoised frame as the layer `denoised.R/G/B/A` when there is one and the
/// image's extra layers (Z as float),
/// with the camera and render settings in the header, and the display transform of the PNG
/// (meshtour:exposure, meshtour:toneMapping: tone_mapping_name()) for turning it into video.
/// The file is written under a temporary name and renamed, so it is either complete or absent.
/// \throw InputError for an unknown extension, IoError if the file cannot be written.
void write_image(const Image& image, const std::filesystem::path& file);

}  // namespace meshtour
