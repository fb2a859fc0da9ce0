// Image-based light (tracer/environment.h): white-furnace checks with no ground, no lights, no
// tone curve, on the raw linear frame: in a uniform white environment a white diffuse sphere
// renders 1.0 and a textured convex surface its texture's colour; the light comes from where the
// environment is bright, and turns with --environment-rotation; bad images are refused by name.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>

#include "core/error.h"
#include "furnace.h"
#include "helpers.h"
#include "test_meshes.h"
#include "tracer/environment.h"
#include "tracer/tracer.h"

namespace meshtour {
namespace {

namespace fs = std::filesystem;
using test_meshes::uv_sphere;

using test::covered_mean;
using test::furnace;
using test::uniform_environment;
const Camera& kCamera = test::kFurnaceCamera;

TEST(Environment, WhiteFurnaceSphereRendersOne) {
  const Image img = Renderer(uv_sphere(1.0, 96, 48), furnace(uniform_environment(1.0f))).render(kCamera);
  int covered = 0;
  const Eigen::Vector3f mean = covered_mean(img, &covered);
  EXPECT_GT(covered, 400);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean[c], 1.0f, 0.01f) << "channel " << c;
  // Every pixel, not only the mean.
  for (std::size_t p = 0; p < img.rgba.size() / 4; ++p) {
    if (img.rgba[p * 4 + 3] < 1.0f) continue;
    ASSERT_NEAR(img.rgba[p * 4], 1.0f, 0.01f) << "pixel " << p;
  }
}

TEST(Environment, WhiteFurnaceTexturedConvexSurfaceRendersItsTexture) {
  const fs::path dir = test::scratch_dir();
  OIIO::ImageBuf tex(OIIO::ImageSpec(4, 4, 3, OIIO::TypeDesc::FLOAT));
  const float colour[3] = {0.7f, 0.35f, 0.1f};
  OIIO::ImageBufAlgo::fill(tex, colour);
  ASSERT_TRUE(tex.write((dir / "colour.exr").string()));
  TriangleMesh sphere = uv_sphere(1.0, 96, 48);
  MeshMaterial m;
  m.texture.file = dir / "colour.exr";
  sphere.materials = {m};
  sphere.corner_uvs.assign(3 * sphere.triangles.size(), Eigen::Vector2f(0.5f, 0.5f));
  const Eigen::Vector3f mean = covered_mean(Renderer(sphere, furnace(uniform_environment(1.0f))).render(kCamera));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean[c], colour[c], 0.01f * colour[c]) << "channel " << c;
}

// An occlusion map darkens the indirect light only: in the furnace a sphere whose map holds 0.25
// renders 1 + strength * (0.25 - 1); under a light alone (no sky) the map changes nothing.
TEST(Environment, AnOcclusionMapDarkensTheSkyOnly) {
  const fs::path dir = test::scratch_dir();
  OIIO::ImageBuf tex(OIIO::ImageSpec(4, 4, 1, OIIO::TypeDesc::FLOAT));
  const float value[1] = {0.25f};
  OIIO::ImageBufAlgo::fill(tex, value);
  ASSERT_TRUE(tex.write((dir / "occlusion.exr").string()));
  const auto sphere = [&](std::optional<float> strength) {
    TriangleMesh mesh = uv_sphere(1.0, 96, 48);
    MeshMaterial m;
    if (strength) {
      m.occlusion_texture.file = dir / "occlusion.exr";
      m.occlusion_strength = *strength;
    }
    mesh.materials = {m};
    mesh.corner_uvs.assign(3 * mesh.triangles.size(), Eigen::Vector2f(0.5f, 0.5f));
    return mesh;
  };
  const RenderOptions options = furnace(uniform_environment(1.0f));
  EXPECT_NEAR(covered_mean(Renderer(sphere(1.0f), options).render(kCamera)).x(), 0.25f, 0.0025f);
  EXPECT_NEAR(covered_mean(Renderer(sphere(0.5f), options).render(kCamera)).x(), 0.625f, 0.00625f);
  RenderOptions lit = options;
  lit.shading.environment = nullptr;
  lit.shading.ambient = Eigen::Vector3f::Zero();
  lit.shading.lights = look_preset("studio").lights;
  const Image with_map = Renderer(sphere(1.0f), lit).render(kCamera), without = Renderer(sphere(std::nullopt), lit).render(kCamera);
  EXPECT_EQ(with_map.rgba, without.rgba);
}

// Light from one side: an environment bright where +x of its frame lies (u > 0.5 is +x, as
// Blender lays it out), 2.0 against 0.1. The sphere's right half, seen from +z, is then brighter
// (at the equator's 16th and 48th pixels 1.75 against 0.40); turned 180 degrees the left one is.
TEST(Environment, LightComesFromTheBrightSideAndTurnsWithTheRotation) {
  auto env = std::make_shared<EnvironmentImage>();
  env->width = 64;
  env->height = 32;
  env->rgb.resize(64 * 32 * 3);
  for (int j = 0; j < 32; ++j)
    for (int i = 0; i < 64; ++i)
      for (int c = 0; c < 3; ++c) env->rgb[(static_cast<std::size_t>(j) * 64 + i) * 3 + c] = i >= 32 ? 2.0f : 0.1f;
  const auto sides = [&](float rotation) {
    RenderOptions options = furnace(env);
    options.shading.environment_rotation_deg = rotation;
    const Image img = Renderer(uv_sphere(1.0, 64, 32), options).render(kCamera);
    double left = 0, right = 0;
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) {
        const std::size_t p = static_cast<std::size_t>(y) * 64 + x;
        if (img.rgba[p * 4 + 3] < 1.0f) continue;
        (x < 32 ? left : right) += img.rgba[p * 4];
      }
    return std::pair{left, right};
  };
  // The halves' sums (their middles face the camera, lit alike): 1.9 to 1 here.
  const auto [left, right] = sides(0.0f);
  EXPECT_GT(right, 1.5 * left);
  const auto [left_turned, right_turned] = sides(180.0f);
  EXPECT_GT(left_turned, 1.5 * right_turned);
  EXPECT_NEAR(left_turned, right, 0.02 * right);  // mirror images
}

// --environment-background shown: the environment behind the model, per pixel along the
// camera ray (a red sky above the horizon, a blue floor below it, on the frame's top and bottom
// rows); hidden, the look's grey gradient; transparent frames stay transparent.
TEST(Environment, ShownAsTheBackgroundAlongTheCameraRays) {
  RenderOptions options = furnace(test::sky_and_floor({1.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}));
  const auto pixel = [](const Image& img, int x, int y) {
    const float* p = &img.rgba[(static_cast<std::size_t>(y) * img.width + x) * 4];
    return Eigen::Vector4f(p[0], p[1], p[2], p[3]);
  };
  const Image hidden = Renderer(uv_sphere(1.0, 64, 32), options).render(kCamera);
  EXPECT_NEAR(pixel(hidden, 2, 2).x(), pixel(hidden, 2, 2).z(), 0.05f) << "the gradient is grey";
  options.shading.environment_background = true;
  const Image shown = Renderer(uv_sphere(1.0, 64, 32), options).render(kCamera);
  EXPECT_NEAR(pixel(shown, 2, 2).x(), 1.0f, 1e-5f);
  EXPECT_NEAR(pixel(shown, 2, 2).z(), 0.0f, 1e-5f);
  EXPECT_NEAR(pixel(shown, 2, 61).z(), 1.0f, 1e-5f);
  EXPECT_NEAR(pixel(shown, 2, 61).x(), 0.0f, 1e-5f);
  EXPECT_EQ(pixel(shown, 32, 32), pixel(hidden, 32, 32)) << "the model's own pixels do not change";
  options.shading.background = BackgroundKind::transparent;
  const Image transparent = Renderer(uv_sphere(1.0, 64, 32), options).render(kCamera);
  EXPECT_EQ(pixel(transparent, 2, 2), Eigen::Vector4f::Zero());
}

TEST(Environment, NeutralLightsAWhiteSurfaceFacingUpAsOne) {
  const EnvironmentImage env = neutral_environment();
  EXPECT_EQ(env.width, 2 * env.height);
  EXPECT_NEAR(upward_irradiance(env, 1.0f).x(), 1.0f, 1e-4f);
  const IrradianceMap map = irradiance_map(env, Eigen::Vector3f::UnitY(), 0.0f, 1.0f);
  EXPECT_NEAR(map(Eigen::Vector3f::UnitY()).x(), 1.0f, 0.01f);
  // Darker below than above, brighter in front (the softbox) than behind, and lit from the left
  // more than from the right (the strips).
  EXPECT_LT(map(-Eigen::Vector3f::UnitY()).x(), 0.5f * map(Eigen::Vector3f::UnitY()).x());
  EXPECT_GT(map(-Eigen::Vector3f::UnitZ()).x(), map(Eigen::Vector3f::UnitZ()).x());
}

// The irradiance map against a numerical integral of the radiance the rays see
// (EnvironmentRadiance, bilinear in the full image) on a grid far finer than the map, for normals
// all round, under a small sun (a sharp kink at its terminator) and the neutral studio: within 1 %
// of the largest irradiance everywhere, and within 2 % of the value where it is at least a tenth.
TEST(Environment, TheIrradianceMapIsTheIntegralOfTheRadiance) {
  const std::shared_ptr<EnvironmentImage> sun = test::sun_environment(256, 0.2f, 400.0f, 180, 30, 6);
  const auto neutral = std::make_shared<EnvironmentImage>(neutral_environment());
  const Eigen::Vector3f up = Eigen::Vector3f(0.2f, 1.0f, -0.1f).normalized();
  for (const auto& env : {sun, neutral}) {
    const IrradianceMap map = irradiance_map(*env, up, 25.0f, 1.5f);
    const EnvironmentRadiance radiance = environment_radiance(env, up, 25.0f, 1.5f);
    const int nt = 512, np = 1024;
    std::vector<std::pair<Eigen::Vector3f, float>> directions;  // world direction, solid angle
    for (int a = 0; a < nt; ++a)
      for (int b = 0; b < np; ++b) {
        const double theta = (a + 0.5) / nt * std::numbers::pi, phi = (b + 0.5) / np * 2.0 * std::numbers::pi;
        const Eigen::Vector3f w(static_cast<float>(std::sin(theta) * std::cos(phi)), static_cast<float>(std::cos(theta)),
                                static_cast<float>(std::sin(theta) * std::sin(phi)));
        directions.emplace_back(w, static_cast<float>(std::sin(theta) * (std::numbers::pi / nt) * (2.0 * std::numbers::pi / np)));
      }
    std::vector<float> lum(directions.size());
    for (std::size_t k = 0; k < directions.size(); ++k) lum[k] = radiance(directions[k].first).x();
    double largest = 0.0;
    std::vector<std::pair<double, double>> pairs;
    for (int k = 0; k < 40; ++k) {
      const double t = std::acos(1.0 - 2.0 * (k + 0.5) / 40), p = k * 2.399963;  // a spiral of normals
      const Eigen::Vector3f n(static_cast<float>(std::sin(t) * std::cos(p)), static_cast<float>(std::cos(t)), static_cast<float>(std::sin(t) * std::sin(p)));
      double e = 0.0;
      for (std::size_t d = 0; d < directions.size(); ++d) e += lum[d] * std::max(0.0f, n.dot(directions[d].first)) * directions[d].second;
      e /= std::numbers::pi;
      pairs.emplace_back(map(n).x(), e);
      largest = std::max(largest, e);
    }
    double worst = 0.0;
    for (const auto& [mapped, integral] : pairs) {
      EXPECT_NEAR(mapped, integral, 0.01 * largest) << env->source;
      if (integral > 0.1 * largest) {
        EXPECT_NEAR(mapped, integral, 0.02 * integral) << env->source;
      }
      worst = std::max(worst, std::abs(mapped - integral) / largest);
    }
    std::printf("%s: the map's worst departure from the integral %.4f of the largest irradiance\n", env->source.empty() ? "sun" : env->source.c_str(), worst);
  }
}

TEST(Environment, BadImagesAreRefusedByName) {
  const fs::path dir = test::scratch_dir();
  const auto write = [&](const std::string& name, int w, int h, float value) {
    OIIO::ImageBuf img(OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::FLOAT));
    const float v[3] = {value, value, value};
    OIIO::ImageBufAlgo::fill(img, v);
    EXPECT_TRUE(img.write((dir / name).string()));
    return dir / name;
  };
  const auto message = [](const fs::path& file) {
    try {
      read_environment(file);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message(write("square.exr", 32, 32, 1.0f)).find("twice as wide as high"), std::string::npos);
  EXPECT_NE(message(write("negative.exr", 32, 16, -1.0f)).find("negative or non-finite"), std::string::npos);
  EXPECT_NE(message(dir / "missing.hdr").find("missing.hdr"), std::string::npos);
  // A big image is read at 512 x 256 for its light; a uniform one keeps its value.
  const EnvironmentImage big = read_environment(write("big.exr", 1024, 512, 0.5f));
  EXPECT_EQ(big.width, 512);
  EXPECT_EQ(big.height, 256);
  EXPECT_NEAR(big.rgb[1000], 0.5f, 1e-6f);
}

}  // namespace
}  // namespace meshtour
