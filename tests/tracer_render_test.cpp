// Renderer tests with analytic expectations: where a sphere appears, how it is lit, and that
// the result depends on nothing but the inputs.
#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <OpenImageIO/imagebuf.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <numbers>

#include "core/error.h"
#include "helpers.h"
#include "tracer/color.h"
#include "tracer/tracer.h"

namespace meshtour {
namespace {

TriangleMesh uv_sphere(double radius, int segments, int rings) {
  TriangleMesh m;
  for (int j = 0; j <= rings; ++j)
    for (int i = 0; i < segments; ++i) {
      const double th = std::numbers::pi * j / rings, ph = 2 * std::numbers::pi * i / segments;
      m.positions.emplace_back(radius * std::sin(th) * std::cos(ph), radius * std::cos(th), radius * std::sin(th) * std::sin(ph));
    }
  for (int j = 0; j < rings; ++j)
    for (int i = 0; i < segments; ++i) {
      const auto a = static_cast<std::uint32_t>(j * segments + i), b = static_cast<std::uint32_t>(j * segments + (i + 1) % segments);
      const auto c = a + segments, d = b + segments;
      m.triangles.push_back({a, c, b});
      m.triangles.push_back({b, c, d});
    }
  return m;
}

const float* pixel(const Image& img, int x, int y) { return &img.rgba[(static_cast<std::size_t>(y) * img.width + x) * 4]; }

TEST(Renderer, SphereAppearsWhereThePinholeModelPutsIt) {
  RenderOptions options;
  options.width = 101;
  options.height = 101;
  options.samples_per_pixel = 1;
  const Renderer renderer(uv_sphere(1.0, 96, 48), options);
  // Camera 5 units away with a 30 degree vertical fov: the sphere's silhouette has angular radius
  // asin(1/5), i.e. tan(asin(0.2)) / tan(15 deg) of the half image = 0.7618 * 50.5 = 38.5 pixels.
  const Image img = renderer.render(Camera{{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 30.0});
  const double expected = std::tan(std::asin(0.2)) / std::tan(15 * std::numbers::pi / 180) * 50.5;
  int covered_in_row = 0;
  for (int x = 0; x < 101; ++x) covered_in_row += pixel(img, x, 50)[3] > 0.5f;
  EXPECT_NEAR(covered_in_row, 2 * expected, 2.5);
  EXPECT_FLOAT_EQ(pixel(img, 50, 50)[3], 1.0f);
  EXPECT_FLOAT_EQ(pixel(img, 0, 0)[3], 0.0f);
  // Lit from above-left of the camera: the upper-left of the sphere is brighter than the lower-right.
  EXPECT_GT(pixel(img, 40, 40)[0], pixel(img, 60, 60)[0]);
  // Centre pixel: normal faces the camera, so diffuse = light_dir.z component (light direction
  // normalized in camera space) and the colour is albedo * (ambient + intensity * diffuse) + specular.
  const Shading& sh = options.shading;
  const float nz = sh.light_from_camera.normalized().z();
  const Eigen::Vector3f half = (sh.light_from_camera.normalized() + Eigen::Vector3f(0, 0, 1)).normalized();
  const float expected_center = sh.base_color.x() * (sh.ambient + sh.light_intensity * nz) + sh.specular * std::pow(half.z(), sh.shininess);
  EXPECT_NEAR(pixel(img, 50, 50)[0], expected_center, 0.01f);
}

TEST(Renderer, SamePixelsWithOneOrTwoThreads) {
  RenderOptions options;
  options.width = 96;
  options.height = 64;
  options.samples_per_pixel = 4;
  const Renderer renderer(uv_sphere(1.0, 64, 32), options);
  const Camera camera{{2, 1.5, 4}, {0, 0, 0}, {0, 1, 0}, 35.0};
  Image one, two;
  tbb::task_arena(1).execute([&] { one = renderer.render(camera); });
  tbb::task_arena(2).execute([&] { two = renderer.render(camera); });
  ASSERT_EQ(one.rgba.size(), two.rgba.size());
  EXPECT_EQ(0, std::memcmp(one.rgba.data(), two.rgba.data(), one.rgba.size() * sizeof(float)));
}

TEST(Renderer, FarFromTheOriginKeepsPrecision) {
  RenderOptions options;
  options.width = 64;
  options.height = 64;
  options.samples_per_pixel = 1;
  TriangleMesh near = uv_sphere(1.0, 64, 32), far = near;
  const Eigen::Vector3d shift(5e6, -3e6, 2e6);  // georeferenced scans live here
  for (auto& p : far.positions) p += shift;
  const Camera camera{{0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 40.0};
  const Image a = Renderer(near, options).render(camera);
  const Image b = Renderer(far, options).render(Camera{camera.eye + shift, camera.target + shift, camera.up, 40.0});
  double max_diff = 0;
  for (std::size_t i = 0; i < a.rgba.size(); ++i) max_diff = std::max(max_diff, double(std::abs(a.rgba[i] - b.rgba[i])));
  EXPECT_LT(max_diff, 1e-4);
}

TEST(Renderer, RejectsBadOptions) {
  RenderOptions options;
  options.width = 0;
  EXPECT_THROW(Renderer(uv_sphere(1, 8, 4), options), InputError);
  options = RenderOptions{};
  options.samples_per_pixel = 0;
  EXPECT_THROW(Renderer(uv_sphere(1, 8, 4), options), InputError);
  EXPECT_THROW(Renderer(TriangleMesh{}, RenderOptions{}), InputError);
}

TEST(Images, PngIsSrgbAndExrIsLinearHalf) {
  const auto dir = test::scratch_dir();
  Image img;
  img.width = 4;
  img.height = 2;
  img.rgba = {0.0f, 0.18f, 1.0f, 1.0f, 0.5f, 0.5f, 0.5f, 1.0f, 2.0f, -1.0f, 0.0031308f, 0.0f, 0.22f, 0.22f, 0.22f, 1.0f,
              0.0f, 0.0f, 0.0f, 0.0f, 1.0f, 1.0f, 1.0f, 1.0f, 0.25f, 0.25f, 0.25f, 0.5f, 0.75f, 0.75f, 0.75f, 1.0f};
  const auto srgb = img.to_srgb8();
  EXPECT_EQ(srgb[0], 0);
  EXPECT_EQ(srgb[1], 118);   // 0.18 linear = 46.1% sRGB
  EXPECT_EQ(srgb[2], 255);
  EXPECT_EQ(srgb[3], 188);   // 0.5 linear
  EXPECT_EQ(srgb[6], 255);   // clamped above 1
  EXPECT_EQ(srgb[7], 0);     // clamped below 0
  EXPECT_EQ(srgb[8], 10);    // the linear segment's end: 0.04045 * 255
  EXPECT_EQ(srgb[9], 129);   // 0.22 linear: 1.055 * 0.22^(1/2.4) - 0.055 = 0.5064

  write_image(img, dir / "f.png");
  write_image(img, dir / "f.exr");
  OIIO::ImageBuf png((dir / "f.png").string()), exr((dir / "f.exr").string());
  ASSERT_TRUE(png.init_spec(png.name(), 0, 0));
  EXPECT_EQ(png.spec().nchannels, 3);
  EXPECT_EQ(png.spec().format, OIIO::TypeDesc::UINT8);
  ASSERT_TRUE(exr.init_spec(exr.name(), 0, 0));
  EXPECT_EQ(exr.spec().nchannels, 4);
  EXPECT_EQ(exr.spec().format, OIIO::TypeDesc::HALF);
  float v[4];
  exr.getpixel(1, 0, v);
  EXPECT_FLOAT_EQ(v[0], 0.5f);  // linear, not sRGB-encoded
  EXPECT_EQ(std::filesystem::directory_iterator(dir) == std::filesystem::directory_iterator(), false);
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    EXPECT_EQ(entry.path().filename().string().find("partial"), std::string::npos) << "temporary file left behind";
  EXPECT_THROW(write_image(img, dir / "f.jpg"), InputError);
  EXPECT_THROW(write_image(img, dir / "missing-dir" / "f.png"), IoError);
}

}  // namespace
}  // namespace meshtour
