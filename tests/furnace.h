#pragma once
// White-furnace set-ups shared by the environment and material tests: a uniform environment, a
// look with nothing but it (no lights, no ground, raw linear frames), a camera on +z looking at
// a unit sphere at the origin, and the mean of the pixels the model covers wholly.
#include <Eigen/Core>

#include <memory>

#include "tracer/environment.h"
#include "tracer/tracer.h"

namespace meshtour::test {

inline std::shared_ptr<const EnvironmentImage> uniform_environment(float value, int width = 64) {
  auto env = std::make_shared<EnvironmentImage>();
  env->width = width;
  env->height = width / 2;
  env->rgb.assign(static_cast<std::size_t>(env->width) * env->height * 3, value);
  return env;
}

/// A sky of `sky` with a square sun of `sun` (`size` pixels a side, its top-left pixel at column i,
/// row j from the zenith), width x width / 2.
inline std::shared_ptr<EnvironmentImage> sun_environment(int width, float sky, float sun, int i, int j, int size) {
  auto env = std::make_shared<EnvironmentImage>();
  env->width = width;
  env->height = width / 2;
  env->rgb.assign(static_cast<std::size_t>(env->width) * env->height * 3, sky);
  for (int y = j; y < j + size; ++y)
    for (int x = i; x < i + size; ++x)
      for (int c = 0; c < 3; ++c) env->rgb[(static_cast<std::size_t>(y) * width + x) * 3 + c] = sun;
  return env;
}

/// An environment of two halves, 64 x 32: `sky` above the horizon, `floor` below it.
inline std::shared_ptr<const EnvironmentImage> sky_and_floor(const Eigen::Vector3f& sky, const Eigen::Vector3f& floor) {
  auto env = std::make_shared<EnvironmentImage>();
  env->width = 64;
  env->height = 32;
  env->rgb.resize(64 * 32 * 3);
  for (int j = 0; j < 32; ++j)
    for (int i = 0; i < 64; ++i)
      for (int c = 0; c < 3; ++c) env->rgb[(static_cast<std::size_t>(j) * 64 + i) * 3 + c] = (j < 16 ? sky : floor)[c];
  return env;
}

/// 64 x 64, `spp` samples, no denoising; the studio look without lights and ground, white base
/// colour, occlusion on, lit by `env` alone.
inline RenderOptions furnace(std::shared_ptr<const EnvironmentImage> env, int spp = 4) {
  RenderOptions options;
  options.width = 64;
  options.height = 64;
  options.samples_per_pixel = spp;
  options.denoise = false;
  options.shading = look_preset("studio");
  options.shading.lights.clear();
  options.shading.ground = false;
  options.shading.material.base_color = Eigen::Vector3f::Ones();
  options.shading.environment = std::move(env);
  return options;
}

inline const Camera kFurnaceCamera{{0, 0, 6}, {0, 0, 0}, {0, 1, 0}, 30.0};

/// The mean of the raw frame's RGB over pixels the model covers wholly (alpha 1).
inline Eigen::Vector3f covered_mean(const Image& img, int* count = nullptr) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int n = 0;
  for (std::size_t p = 0; p < static_cast<std::size_t>(img.width) * img.height; ++p)
    if (img.rgba[p * 4 + 3] >= 1.0f) {
      sum += Eigen::Vector3d(img.rgba[p * 4], img.rgba[p * 4 + 1], img.rgba[p * 4 + 2]);
      ++n;
    }
  if (count) *count = n;
  return n ? Eigen::Vector3f((sum / n).cast<float>()) : Eigen::Vector3f::Zero();
}

}  // namespace meshtour::test
