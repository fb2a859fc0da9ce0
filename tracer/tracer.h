#pragma once
// The ray tracer: one Embree scene per job, frames rendered in parallel tiles, deterministic
// (a pixel's value depends only on the scene, the camera and the pixel, never on threads).
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

#include "mesh/mesh.h"

namespace meshtour {

/// A pinhole camera in model units.
struct Camera {
  Eigen::Vector3d eye = Eigen::Vector3d(0, 0, 5);
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  Eigen::Vector3d up = Eigen::Vector3d::UnitY();
  double vertical_fov_deg = 40.0;
};

/// How surfaces and the background look. Colours are linear RGB.
struct Shading {
  Eigen::Vector3f base_color{0.75f, 0.75f, 0.75f};  ///< used where the mesh has no vertex colours
  bool use_vertex_colors = true;
  float ambient = 0.22f;         ///< uniform ambient term
  float light_intensity = 0.95f; ///< the light attached to the camera
  /// Direction the camera-attached light comes from, in camera space (x right, y up, z towards
  /// the viewer): above and to the left of the camera, as photographers place a key light.
  Eigen::Vector3f light_from_camera{-0.45f, 0.55f, 1.0f};
  float specular = 0.12f;        ///< Blinn-Phong highlight strength
  float shininess = 40.0f;
  Eigen::Vector3f background_top{0.32f, 0.32f, 0.33f};
  Eigen::Vector3f background_bottom{0.10f, 0.10f, 0.11f};
};

struct RenderOptions {
  int width = 1280;
  int height = 720;
  int samples_per_pixel = 4;  ///< stratified over the pixel, box-filtered
  Shading shading;
};

/// A linear-light RGBA image, rows top to bottom. Alpha is the model's pixel coverage.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<float> rgba;  ///< width * height * 4

  /// 8-bit sRGB-encoded RGB, rows top to bottom: what PNG frames and the video receive.
  std::vector<std::uint8_t> to_srgb8() const;
};

/// Renders one mesh. Building the Embree scene (the BVH) happens once, in the constructor;
/// render() may then be called for any number of cameras, also concurrently.
class Renderer {
public:
  /// \throw InputError for a mesh without triangles or bad options, RuntimeFailure if Embree fails.
  Renderer(const TriangleMesh& mesh, const RenderOptions& options);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// Renders one frame, using the calling thread's TBB arena (limit threads with a task_arena
  /// or tbb::global_control around the call).
  Image render(const Camera& camera) const;

  const RenderOptions& options() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Writes `image` by extension: ".png" as 8-bit sRGB RGB, ".exr" as half-float linear RGBA.
/// The file is written under a temporary name and renamed, so it is either complete or absent.
/// \throw InputError for an unknown extension, IoError if the file cannot be written.
void write_image(const Image& image, const std::filesystem::path& file);

}  // namespace meshtour
