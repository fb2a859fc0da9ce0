// Interreflections (Shading::bounces): in a uniform white environment a white surface reflects
// exactly the light it receives, so whatever the shape the converged frame is 1.0 everywhere; a
// shape that hides part of its sky from itself falls short with occlusion alone and reaches 1
// as the bounces add the light its own walls send back. A coloured wall tints what faces it.
// Same bits on every thread count and tile kernel.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cstring>

#include "core/error.h"
#include "every_kernel.h"
#include "furnace.h"
#include "test_meshes.h"
#include "tracer/tracer.h"

namespace meshtour {
namespace {

using test::covered_mean;
using test::furnace;
using test::uniform_environment;

// A torus seen from above its plane: its inner side sees itself across the hole.
const Camera kTorusCamera{{0, -1.1, 1.4}, {0, 0, 0}, {0, 0, 1}, 30.0};

Eigen::Vector3f torus_mean(int bounces, const Eigen::Vector3f& albedo = Eigen::Vector3f::Ones()) {
  RenderOptions options = furnace(uniform_environment(1.0f), 16);
  options.shading.ao_distance = 10.0f;  // rays see the whole model: the physical answer
  options.shading.bounces = bounces;
  options.shading.material.base_color = albedo;
  return covered_mean(Renderer(test_meshes::torus(0.3, 0.12, 192, 64), options).render(kTorusCamera));
}

TEST(Interreflection, WhiteFurnaceConcaveShapeReachesOneWithBounces) {
  const float m0 = torus_mean(0).x(), m1 = torus_mean(1).x(), m2 = torus_mean(2).x(), m4 = torus_mean(4).x();
  // Occlusion alone loses the light the torus hides from itself (a few per cent of its pixels'
  // sky on average); each bounce gives most of the rest back.
  EXPECT_LT(m0, 0.97f);
  EXPECT_GT(m1, m0 + 0.5f * (1.0f - m0));
  EXPECT_GT(m2, m1);
  EXPECT_GE(m4, m2 - 1e-3f);
  EXPECT_NEAR(m4, 1.0f, 0.01f);
  EXPECT_LT(m4, 1.0f + 0.01f) << "interreflections may not create light";
}

// With albedo a, a pixel's light is a (its open sky) plus a * a (its own walls' light, itself
// reflected once) plus a^3 ...: the share the bounces add scales with a^2, so a grey surface
// (a = 0.3) gains about 0.09 of what a white one gains, not 0.3.
TEST(Interreflection, ADarkSurfaceGainsInProportionToItsAlbedoSquared) {
  const float white_gain = torus_mean(2).x() - torus_mean(0).x();
  const float a = 0.3f;
  const float grey_gain = torus_mean(2, Eigen::Vector3f::Constant(a)).x() - torus_mean(0, Eigen::Vector3f::Constant(a)).x();
  ASSERT_GT(white_gain, 0.02f);
  EXPECT_NEAR(grey_gain / white_gain, a * a, 0.4f * a * a);
}

// A white ball beside a red wall, lit by the sky alone: with a bounce, the side facing the wall
// turns red (more red than green), without one it stays grey.
TEST(Interreflection, AColouredWallTintsWhatFacesIt) {
  TriangleMesh ball = test_meshes::uv_sphere(0.3, 64, 32);
  TriangleMesh wall = test_meshes::transformed(test_meshes::plane(16), 2.0, Eigen::AngleAxisd(EIGEN_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix(),
                                               Eigen::Vector3d(0.45, 0, 0));
  TriangleMesh scene = test_meshes::combined(ball, wall);
  scene.colors.assign(scene.positions.size(), Eigen::Vector3f::Ones());
  for (std::size_t v = ball.positions.size(); v < scene.positions.size(); ++v) scene.colors[v] = Eigen::Vector3f(0.9f, 0.05f, 0.05f);
  const Camera camera{{0, 0, 2.5}, {0.1, 0, 0}, {0, 1, 0}, 30.0};
  const auto right_half_of_ball = [&](int bounces) {
    RenderOptions options = furnace(uniform_environment(1.0f), 16);
    options.shading.bounces = bounces;
    options.shading.ao_distance = 10.0f;
    const Image img = Renderer(scene, options).render(camera);
    // The ball spans the frame's middle; its right half faces the wall (x = 0.45).
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int y = 24; y < 40; ++y)
      for (int x = 34; x < 40; ++x) {
        const float* p = &img.rgba[(static_cast<std::size_t>(y) * img.width + x) * 4];
        sum += Eigen::Vector3d(p[0], p[1], p[2]);
      }
    return sum;
  };
  const Eigen::Vector3d grey = right_half_of_ball(0), tinted = right_half_of_ball(1);
  EXPECT_NEAR(grey.x() / grey.y(), 1.0, 1e-3);
  EXPECT_GT(tinted.x() / tinted.y(), 1.15);
  EXPECT_NEAR(tinted.y(), grey.y(), 0.05 * grey.y()) << "the red wall sends back almost no green";
}

TEST(Interreflection, SameBitsOnEveryThreadCountAndKernel) {
  RenderOptions options;
  options.width = 64;
  options.height = 48;
  options.samples_per_pixel = 16;
  options.shading.bounces = 2;
  options.shading.environment = test::sky_and_floor({1.0f, 0.6f, 0.4f}, {0.1f, 0.2f, 0.6f});
  const TriangleMesh torus = test_meshes::torus(0.3, 0.12, 96, 32);
  const Camera camera{{0, -1.0, 1.2}, {0, 0, 0}, {0, 0, 1}, 40.0};
  const Renderer renderer(torus, options);
  Image one, two;
  tbb::task_arena(1).execute([&] { one = renderer.render(camera, 5); });
  tbb::task_arena(2).execute([&] { two = renderer.render(camera, 5); });
  ASSERT_EQ(one.rgba.size(), two.rgba.size());
  EXPECT_EQ(0, std::memcmp(one.rgba.data(), two.rgba.data(), one.rgba.size() * sizeof(float)));
  for (int spp : {16, 5}) {
    options.samples_per_pixel = spp;
    test::expect_same_bits_on_every_kernel([&] { return Renderer(torus, options).render(camera, 5); }, "spp " + std::to_string(spp));
  }
  // And the bounces change the frame (they are not skipped).
  options.samples_per_pixel = 16;
  options.shading.bounces = 0;
  const Image none = Renderer(torus, options).render(camera, 5);
  EXPECT_NE(0, std::memcmp(one.rgba.data(), none.rgba.data(), one.rgba.size() * sizeof(float)));
}

TEST(Interreflection, OutOfRangeIsRefused) {
  RenderOptions options = furnace(uniform_environment(1.0f));
  options.shading.bounces = 5;
  EXPECT_THROW(Renderer(test_meshes::torus(), options), InputError);
  options.shading.bounces = -1;
  EXPECT_THROW(Renderer(test_meshes::torus(), options), InputError);
}

}  // namespace
}  // namespace meshtour
