#pragma once
// The bunny's studio frame of the speed comparisons: tracer_bench's frame, the one
// bench/cycles_frame.py sets up in Blender (the same camera, lights and samples), and the
// "bunny-studio" case of denoise_quality (the equal-error comparison, bench/cycles_equal_error.sh).
// One place, so that the three cannot drift apart.
#include <cmath>
#include <numbers>

#include "mesh/mesh.h"
#include "tracer/tracer.h"

namespace meshtour::bench {

struct StudioFrame {
  RenderOptions options;
  Camera camera;
};

/// `width` x (width * 9 / 16), 16 spp, the studio look, Y up, not denoised (the ray tracing alone,
/// as bare Embree does it); the camera 18 degrees above the bounds' centre, the whole model in a
/// 35-degree vertical lens (the default turntable's first frame).
inline StudioFrame studio_frame(const TriangleMesh& mesh, int width) {
  StudioFrame f;
  f.options.width = width;
  f.options.height = width * 9 / 16;
  f.options.samples_per_pixel = 16;
  f.options.denoise = false;
  f.options.shading = look_preset("studio");
  f.options.world_up = Eigen::Vector3d::UnitY();
  const Bounds b = mesh.bounds();
  const double fov = 35.0, elevation = 18.0 * std::numbers::pi / 180.0;
  const double distance = 0.55 * b.diagonal() / std::tan(fov * std::numbers::pi / 360.0);
  f.camera.target = b.center();
  f.camera.eye = b.center() + distance * Eigen::Vector3d(0.0, std::sin(elevation), std::cos(elevation));
  f.camera.up = Eigen::Vector3d::UnitY();
  f.camera.vertical_fov_deg = fov;
  return f;
}

}  // namespace meshtour::bench
