// Renderer tests with analytic expectations: where a sphere appears, how it is lit, and that
// the result depends on nothing but the inputs.
#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>

#include "core/error.h"
#include "every_kernel.h"
#include "helpers.h"
#include "mesh/convex_hull.h"
#include "test_meshes.h"
#include "tracer/color.h"
#include "tracer/renderer_internal.h"
#include "tracer/tracer.h"

namespace meshtour {
namespace {

using test_meshes::uv_sphere;

const float* pixel(const Image& img, int x, int y) { return &img.rgba[(static_cast<std::size_t>(y) * img.width + x) * 4]; }

TEST(Renderer, SphereAppearsWhereThePinholeModelPutsIt) {
  RenderOptions options;
  options.width = 101;
  options.height = 101;
  options.samples_per_pixel = 4;
  options.shading = look_preset("plain");  // no shadows, no occlusion, no ground: analytic
  const Renderer renderer(uv_sphere(1.0, 96, 48), options);
  // Camera 5 units away with a 30 degree vertical fov: the sphere's silhouette has angular radius
  // asin(1/5), i.e. tan(asin(0.2)) / tan(15 deg) of the half image = 0.7618 * 50.5 = 38.5 pixels.
  const Image img = renderer.render(Camera{{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 30.0});
  const double expected = std::tan(std::asin(0.2)) / std::tan(15 * std::numbers::pi / 180) * 50.5;
  double covered_in_row = 0;
  for (int x = 0; x < 101; ++x) covered_in_row += pixel(img, x, 50)[3];
  EXPECT_NEAR(covered_in_row, 2 * expected, 1.0);  // alpha is coverage: sums to the chord
  EXPECT_FLOAT_EQ(pixel(img, 50, 50)[3], 1.0f);
  EXPECT_FLOAT_EQ(pixel(img, 0, 0)[3], 0.0f);
  // The plain preset's light comes from above the camera: the top of the sphere is brighter.
  EXPECT_GT(pixel(img, 50, 35)[0], pixel(img, 50, 65)[0]);
  // Centre pixel: normal faces the camera; colour = albedo * (ambient + E cos) + highlight * E cos.
  const Shading& sh = options.shading;
  ASSERT_EQ(sh.lights.size(), 1u);
  const Eigen::Vector3f l = sh.lights[0].from_camera.normalized();
  const float shininess = 2.0f / std::pow(sh.material.roughness, 4.0f) - 2.0f;
  const float spec = 0.08f * sh.material.specular * (shininess + 8) / 8 *
                     std::pow((l + Eigen::Vector3f(0, 0, 1)).normalized().z(), shininess);
  const float e = sh.lights[0].intensity * l.z();
  const float expected_center = sh.material.base_color.x() * (sh.ambient.x() + e) + spec * e;
  EXPECT_NEAR(pixel(img, 50, 50)[0], expected_center, 0.01f);
}

// One shadow ray per sample, to one light chosen at random and weighted by 1/probability, must
// average to the sum of all the lights: on a lone convex sphere nothing casts a shadow, so the
// studio look with shadow rays must match, pixel for pixel up to noise, the same look with every
// light evaluated unshadowed. A wrong probability weight would shift the mean by the ratio of
// the lights' intensities (tens of percent); 256 spp leaves about 0.3 % of noise in the mean.
TEST(Renderer, OneShadowRayToOneLightAveragesToAllLights) {
  RenderOptions options;
  options.width = 48;
  options.height = 48;
  options.samples_per_pixel = 256;
  options.shading = look_preset("studio");
  options.shading.ground = false;
  options.shading.ambient_occlusion = false;
  const Camera camera{{0.8, 0.6, 4.5}, {0, 0, 0}, {0, 1, 0}, 30.0};
  const TriangleMesh sphere = uv_sphere(1.0, 192, 96);
  const Image sampled = Renderer(sphere, options).render(camera);
  options.shading.shadows = false;
  const Image exact = Renderer(sphere, options).render(camera);
  double sum_sampled = 0, sum_exact = 0;
  int covered = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 48; ++x) {
      if (pixel(exact, x, y)[3] < 1.0f) continue;  // the sphere's interior only
      ++covered;
      for (int c = 0; c < 3; ++c) {
        sum_sampled += pixel(sampled, x, y)[c];
        sum_exact += pixel(exact, x, y)[c];
      }
    }
  ASSERT_GT(covered, 300);
  EXPECT_NEAR(sum_sampled / sum_exact, 1.0, 0.01);
  // Both are the same image up to noise: no region is systematically darker or brighter.
  EXPECT_NEAR(pixel(sampled, 24, 24)[0], pixel(exact, 24, 24)[0], 0.05f * pixel(exact, 24, 24)[0] + 0.01f);
}

Camera studio_camera(int k) {
  const double a = 0.4 * k;
  return Camera{{4 * std::sin(a), 1.5, 4 * std::cos(a)}, {0, 0, 0}, {0, 1, 0}, 35.0};
}

// Textures are colours as the image stores them: an 8-bit PNG (or JPEG, WebP) holds sRGB-encoded
// values, decoded to linear like vertex colours, so a texture and vertex colours of one colour
// render alike (OpenImageIO 2.4's texture system returns the stored values; before this was
// decoded, a black stone scan rendered light grey). A float EXR holds linear values, used as they are.
// Embree must ignore a packet's lanes outside its valid mask, but on CPUs without AVX-512 it
// splits a 16-ray packet into two of 8, and Debian's Embree then asserts that every ray of a half
// is valid: a camera ray that missed (its hit point, the next rays' origin, at infinity) aborted
// the whole render there (tour, farm and evaluate tests on an AMD EPYC with AVX2). So every lane
// of every packet the renderer traces holds a valid ray, as Embree's RayK::valid() has it:
// coordinates of origin and direction within 1.844e18, tnear and tfar not NaN. Checked on the
// studio look from below the horizon (shadow rays from the ground, sky rays) with the background
// in view, where whole packets mix hits and misses.
TEST(Renderer, EveryLaneOfATracedPacketIsAValidRay) {
  RenderOptions options;
  options.width = 96;
  options.height = 64;
  options.samples_per_pixel = 2;
  options.denoise = false;
  options.shading = look_preset("studio");
  options.world_up = Eigen::Vector3d::UnitY();
  const TriangleMesh mesh = uv_sphere(1.0, 32, 16);
  const Renderer renderer(mesh, options);
  std::size_t checked = 0;
  for (const double elevation_deg : {5.0, -45.0}) {
    const double e = elevation_deg * std::numbers::pi / 180.0;
    const Camera camera{Eigen::Vector3d(0.0, 6.0 * std::sin(e), 6.0 * std::cos(e)), {0, 0, 0}, {0, 1, 0}, 35.0};
    RayRecording recording;
    recording.tile_stride = 1;
    RendererAccess::render(renderer, camera, 0, nullptr, &recording);
    const auto expect_valid = [&](const auto& rays, const ValidMask& lanes, const char* kind) {
      if (std::none_of(lanes.lanes.begin(), lanes.lanes.end(), [](int v) { return v != 0; })) return;  // not traced
      for (int l = 0; l < 16; ++l) {
        const float values[6] = {rays.org_x[l], rays.org_y[l], rays.org_z[l], rays.dir_x[l], rays.dir_y[l], rays.dir_z[l]};
        for (const float v : values) EXPECT_LE(std::abs(v), 1.844e18f) << kind << " lane " << l << (lanes.lanes[l] ? " (in use)" : " (not in use)");
        EXPECT_FALSE(std::isnan(rays.tnear[l]) || std::isnan(rays.tfar[l])) << kind << " lane " << l;
        ++checked;
      }
    };
    for (const RayRecording::Tile& tile : recording.tiles)
      for (const RayRecording::Packet& p : tile.packets) {
        expect_valid(p.primary.ray, p.primary_valid, "camera");
        expect_valid(p.shadow, p.shadow_valid, "shadow");
        expect_valid(p.sky, p.sky_valid, "sky");
      }
  }
  EXPECT_GT(checked, 1000u);
}

TEST(Renderer, TexturesAreDecodedLikeVertexColours) {
  const auto dir = test::scratch_dir();
  const float encoded = 0.2f, linear = 0.35f;
  {
    OIIO::ImageBuf png(OIIO::ImageSpec(8, 8, 3, OIIO::TypeDesc::UINT8));
    const float v[3] = {encoded, encoded, encoded};
    OIIO::ImageBufAlgo::fill(png, v);
    ASSERT_TRUE(png.write((dir / "grey.png").string()));
    OIIO::ImageBuf exr(OIIO::ImageSpec(8, 8, 3, OIIO::TypeDesc::HALF));
    const float l[3] = {linear, linear, linear};
    OIIO::ImageBufAlgo::fill(exr, l);
    ASSERT_TRUE(exr.write((dir / "grey.exr").string()));
  }
  RenderOptions options;
  options.width = 48;
  options.height = 32;
  options.samples_per_pixel = 1;
  options.layers.albedo = true;
  const Camera camera{{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 30.0};
  const auto albedo_at_centre = [&](const TriangleMesh& mesh) {
    const Image img = Renderer(mesh, options).render(camera);
    return img.albedo[(static_cast<std::size_t>(options.height / 2) * options.width + options.width / 2) * 3];
  };
  const auto textured = [&](const std::string& file) {
    TriangleMesh mesh = uv_sphere(1.0, 32, 16);
    MeshMaterial m;
    m.texture.file = dir / file;
    mesh.materials = {m};
    mesh.triangle_materials.assign(mesh.triangles.size(), 0);
    mesh.corner_uvs.assign(3 * mesh.triangles.size(), Eigen::Vector2f(0.5f, 0.5f));
    return mesh;
  };
  TriangleMesh coloured = uv_sphere(1.0, 32, 16);
  const float stored = std::round(encoded * 255.0f) / 255.0f;  // the PNG's 8-bit value
  coloured.colors.assign(coloured.positions.size(), Eigen::Vector3f::Constant(stored));
  const float from_colours = albedo_at_centre(coloured);
  EXPECT_NEAR(from_colours, srgb_to_linear(stored), 1e-6f);
  EXPECT_NEAR(albedo_at_centre(textured("grey.png")), from_colours, 1e-4f);
  EXPECT_NEAR(albedo_at_centre(textured("grey.exr")), linear, 1e-3f);  // half precision
}

TEST(Renderer, SamePixelsWithOneOrTwoThreads) {
  RenderOptions options;  // studio: soft shadows, occlusion, ground: every random number in use
  options.width = 96;
  options.height = 64;
  options.samples_per_pixel = 4;
  options.layers = {true, true, true};
  const Renderer renderer(uv_sphere(1.0, 64, 32), options);
  Image one, two;
  tbb::task_arena(1).execute([&] { one = renderer.render(studio_camera(1), 7); });
  tbb::task_arena(2).execute([&] { two = renderer.render(studio_camera(1), 7); });
  ASSERT_EQ(one.rgba.size(), two.rgba.size());
  EXPECT_EQ(0, std::memcmp(one.rgba.data(), two.rgba.data(), one.rgba.size() * sizeof(float)));
  ASSERT_EQ(one.denoised.size(), one.rgba.size());  // on by default
  EXPECT_EQ(0, std::memcmp(one.denoised.data(), two.denoised.data(), one.denoised.size() * sizeof(float)));
  EXPECT_EQ(one.albedo, two.albedo);
  EXPECT_EQ(one.normal, two.normal);
  EXPECT_EQ(0, std::memcmp(one.depth.data(), two.depth.data(), one.depth.size() * sizeof(float)));
}

// The look's shading on every tile kernel (every_kernel.h).
TEST(Renderer, SamePixelsWithEveryInstructionSet) {
  for (int spp : {16, 5}) {  // whole packets per pixel (summed in one tree), and packets across pixels
    RenderOptions options;
    options.width = 64;
    options.height = 48;
    options.samples_per_pixel = spp;
    options.layers = {true, true, true};
    const TriangleMesh sphere = uv_sphere(1.0, 48, 24);
    test::expect_same_bits_on_every_kernel([&] { return Renderer(sphere, options).render(studio_camera(1), 3); },
                                           "spp " + std::to_string(spp));
  }
}

TEST(Renderer, FrameAloneEqualsFrameInSequence) {
  RenderOptions options;
  options.width = 80;
  options.height = 48;
  options.samples_per_pixel = 2;
  const TriangleMesh sphere = uv_sphere(1.0, 48, 24);
  Image in_sequence;
  {
    const Renderer renderer(sphere, options);
    for (int k = 0; k < 4; ++k) {
      Image img = renderer.render(studio_camera(k), static_cast<std::uint64_t>(k));
      if (k == 2) in_sequence = std::move(img);
    }
  }
  const Renderer fresh(sphere, options);  // another job, as another process would build it
  const Image alone = fresh.render(studio_camera(2), 2);
  ASSERT_EQ(alone.rgba.size(), in_sequence.rgba.size());
  EXPECT_EQ(0, std::memcmp(alone.rgba.data(), in_sequence.rgba.data(), alone.rgba.size() * sizeof(float)));
  // The frame index seeds the noise: another index gives other noise on the same view.
  const Image other = fresh.render(studio_camera(2), 3);
  EXPECT_NE(0, std::memcmp(alone.rgba.data(), other.rgba.data(), alone.rgba.size() * sizeof(float)));
}

TEST(Renderer, StudioShadowFallsOnTheGroundAndTransparentKeepsIt) {
  RenderOptions options;
  options.width = 64;
  options.height = 64;
  options.samples_per_pixel = 4;
  options.shading.background = BackgroundKind::transparent;
  const Renderer renderer(uv_sphere(1.0, 48, 24), options);
  const Image img = renderer.render(Camera{{0, 3, 5}, {0, 0, 0}, {0, 1, 0}, 40.0});
  EXPECT_TRUE(img.transparent);
  // Corners: lit ground or sky, fully transparent. Just under the sphere (contact shadow): the
  // ground's alpha carries the shadow.
  EXPECT_LT(pixel(img, 0, 0)[3], 0.02f);
  EXPECT_LT(pixel(img, 0, 63)[3], 0.05f);
  float max_shadow = 0;
  // (0.2: the contact shadow's alpha is about 0.25 there; the old jittered samples' noise at
  // 4 spp put single pixels above 0.3.)
  float max_denoised = 0;
  for (int x = 20; x < 44; ++x) {
    const std::size_t p = (60u * 64u + static_cast<std::size_t>(x)) * 4u;
    max_shadow = std::max(max_shadow, img.rgba[p + 3] * (img.rgba[p] < 0.02f));
    max_denoised = std::max(max_denoised, img.denoised[p + 3] * (img.denoised[p] < 0.02f));
  }
  EXPECT_GT(max_shadow, 0.2f);
  EXPECT_GT(max_denoised, 0.12f);  // the denoiser keeps the shadow in alpha (a little spread out at 4 spp)
  const auto rgba = img.to_srgba8();
  EXPECT_EQ(rgba.size(), 64u * 64u * 4u);
}

TEST(Renderer, FarFromTheOriginKeepsPrecision) {
  RenderOptions options;
  options.width = 64;
  options.height = 64;
  options.samples_per_pixel = 1;
  options.shading = look_preset("plain");  // no random secondary rays that a rounding could flip
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

TEST(Renderer, FitFovKeepsEveryVertexInFrame) {
  const TriangleMesh sphere = uv_sphere(1.0, 64, 32);
  const Camera c{{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 1.0};
  // Wide frame: the height limits. The vertices reach at most tan(asin(1/5)) off the axis
  // (slightly less: the tessellation lies inside the sphere).
  const double fov = fit_vertical_fov({c}, sphere.positions, 16.0 / 9.0, 0.0);
  EXPECT_LE(fov, 2 * std::asin(0.2) * 180 / std::numbers::pi + 1e-6);
  EXPECT_GT(fov, 2 * std::atan(0.98 * 1.0 / 4.8) * 180 / std::numbers::pi - 1.0);
  // A margin widens the lens; a portrait frame is limited by its width.
  EXPECT_GT(fit_vertical_fov({c}, sphere.positions, 16.0 / 9.0, 0.1), fov);
  EXPECT_GT(fit_vertical_fov({c}, sphere.positions, 0.5, 0.0), fov);
  EXPECT_THROW(fit_vertical_fov({Camera{{0, 0, 5}, {0, 0, 10}, {0, 1, 0}, 1.0}}, sphere.positions, 1.0), InputError);
}

TEST(Renderer, FitFovOnTheHullIsTheFitOnEveryVertex) {
  // A squashed, shifted icosphere seen from around it; then with a point behind the cameras (the
  // hull is not all in front of them, so they read every vertex).
  TriangleMesh model = test_meshes::icosphere(4);
  for (auto& p : model.positions)
    p = Eigen::Vector3d(1.5 * p.x(), p.y() + 0.2 * p.x() * p.x(), 0.6 * p.z()) + Eigen::Vector3d(0.3, 2.0, -1.0);
  std::vector<Camera> around;
  for (int k = 0; k < 24; ++k) {
    const double a = 2 * std::numbers::pi * k / 24;
    around.push_back(Camera{{0.3 + 5 * std::cos(a), 3.0, -1.0 + 5 * std::sin(a)}, {0.3, 2.0, -1.0}, {0, 1, 0}, 40.0});
  }
  const std::vector<Eigen::Vector3d> hull = convex_hull_vertices(model.positions);
  for (const double aspect : {16.0 / 9.0, 0.7})
    EXPECT_EQ(fit_vertical_fov(around, model.positions, hull, aspect, 0.05), fit_vertical_fov(around, model.positions, aspect, 0.05));

  std::vector<Eigen::Vector3d> with_behind = model.positions;
  with_behind.emplace_back(0.3, 2.0, 9.0);
  const std::vector<Camera> front{Camera{{0.3, 2.5, 5.0}, {0.3, 2.0, -1.0}, {0, 1, 0}, 40.0}};
  EXPECT_EQ(fit_vertical_fov(front, with_behind, convex_hull_vertices(with_behind), 1.5, 0.0),
            fit_vertical_fov(front, model.positions, 1.5, 0.0));
}

// A unit cube of 12 triangles (two per face, outward).
TriangleMesh unit_cube() {
  TriangleMesh cube;
  for (int i = 0; i < 8; ++i) cube.positions.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    cube.triangles.push_back({static_cast<std::uint32_t>(q[0]), static_cast<std::uint32_t>(q[1]), static_cast<std::uint32_t>(q[2])});
    cube.triangles.push_back({static_cast<std::uint32_t>(q[0]), static_cast<std::uint32_t>(q[2]), static_cast<std::uint32_t>(q[3])});
  }
  return cube;
}

struct Shaded {
  std::vector<Eigen::Vector3f> positions, normals;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<std::uint32_t> copied_from;
};
Shaded shade(const TriangleMesh& mesh, float crease_deg) {
  Shaded s;
  for (const auto& p : mesh.positions) s.positions.push_back(p.cast<float>());
  s.triangles = mesh.triangles;
  s.normals = crease_normals(s.positions, s.triangles, crease_deg, s.copied_from);
  return s;
}

// Hard edges stay hard, smooth surfaces stay smooth: on a cube every corner's normal is its
// face's (8 vertices become 24, at the same places); with the crease at 180 degrees every edge is
// smoothed (no copies, the corners' normals point along the diagonals); a 12-sided prism with caps
// keeps its sides smooth (30 degrees apart) and splits only at the caps' rims (90 degrees).
TEST(ShadingNormals, CreasesSplitHardEdgesOnly) {
  const TriangleMesh cube = unit_cube();
  const Shaded hard = shade(cube, 60.0f);
  EXPECT_EQ(hard.positions.size(), 24u);
  ASSERT_EQ(hard.copied_from.size(), 16u);
  for (std::size_t i = 0; i < hard.copied_from.size(); ++i) EXPECT_EQ(hard.positions[8 + i], hard.positions[hard.copied_from[i]]);
  for (std::size_t t = 0; t < hard.triangles.size(); ++t) {
    const auto& tri = hard.triangles[t];
    const Eigen::Vector3f face = (hard.positions[tri[1]] - hard.positions[tri[0]]).cross(hard.positions[tri[2]] - hard.positions[tri[0]]).normalized();
    for (const std::uint32_t v : tri) EXPECT_LT((hard.normals[v] - face).norm(), 1e-6f) << "triangle " << t;
  }
  const Shaded soft = shade(cube, 180.0f);
  EXPECT_EQ(soft.positions.size(), 8u);
  EXPECT_TRUE(soft.copied_from.empty());
  for (std::size_t v = 0; v < 8; ++v) {
    const Eigen::Vector3f outward = (soft.positions[v] - Eigen::Vector3f::Constant(0.5f)).normalized();
    EXPECT_LT((soft.normals[v] - outward).norm(), 1e-6f) << "vertex " << v;
  }
  // The prism: 12 side quads, a fan cap at each end around a centre vertex.
  TriangleMesh prism;
  const int sides = 12;
  for (int ring = 0; ring < 2; ++ring)
    for (int k = 0; k < sides; ++k) {
      const double a = 2.0 * std::numbers::pi * k / sides;
      prism.positions.emplace_back(std::cos(a), ring, -std::sin(a));
    }
  prism.positions.emplace_back(0, 0, 0);
  prism.positions.emplace_back(0, 1, 0);
  const auto at = [&](int ring, int k) { return static_cast<std::uint32_t>(ring * sides + (k % sides)); };
  for (int k = 0; k < sides; ++k) {
    prism.triangles.push_back({at(0, k), at(0, k + 1), at(1, k + 1)});
    prism.triangles.push_back({at(0, k), at(1, k + 1), at(1, k)});
    prism.triangles.push_back({static_cast<std::uint32_t>(2 * sides), at(0, k + 1), at(0, k)});
    prism.triangles.push_back({static_cast<std::uint32_t>(2 * sides + 1), at(1, k), at(1, k + 1)});
  }
  const Shaded p = shade(prism, 60.0f);
  EXPECT_EQ(p.copied_from.size(), static_cast<std::size_t>(2 * sides));  // each rim vertex: one side normal, one cap normal
  for (std::size_t t = 0; t < p.triangles.size(); t += 4)                  // the sides' corners: horizontal, radial
    for (const std::uint32_t v : p.triangles[t]) {
      EXPECT_NEAR(p.normals[v].y(), 0.0f, 1e-6f);
      const Eigen::Vector3f radial(p.positions[v].x(), 0.0f, p.positions[v].z());
      EXPECT_LT((p.normals[v] - radial.normalized()).norm(), 1e-6f);
    }
  // A smooth, finely tessellated sphere gets no copies.
  const TriangleMesh sphere = test_meshes::icosphere(4);
  const Shaded welded = shade(sphere, 60.0f);
  EXPECT_TRUE(welded.copied_from.empty());
  // The same sphere as a triangle soup (every triangle its own three vertices, as STL converters
  // write, and as a PLY splits vertices at texture seams) is shaded as smoothly: the normals are
  // taken over the vertices at the same coordinates, not over the file's vertex indices.
  const Shaded soup = shade(test_meshes::soup(sphere), 60.0f);
  EXPECT_TRUE(soup.copied_from.empty());
  double worst = 0.0;
  for (std::size_t t = 0; t < sphere.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      worst = std::max(worst, static_cast<double>((soup.normals[soup.triangles[t][k]] - welded.normals[welded.triangles[t][k]]).norm()));
  EXPECT_LT(worst, 1e-6) << "a soup's normal differs from the welded mesh's";
}

// What a viewer sees: in the plain look (even light, no shadows) without highlights a cube's faces
// are flat, one colour each; smoothing every edge (crease 180) shades them with gradients.
TEST(ShadingNormals, ACubesFacesRenderFlat) {
  RenderOptions options;
  options.width = options.height = 96;
  options.samples_per_pixel = 4;
  options.shading = look_preset("plain");
  options.shading.material.specular = 0.0f;
  const Camera camera{{2.6, 2.1, 3.1}, {0.5, 0.5, 0.5}, {0, 1, 0}, 30.0};
  const auto face_spread = [&](float crease) {
    RenderOptions o = options;
    o.shading.material.crease_angle_deg = crease;
    o.layers.normal = true;
    const Image img = Renderer(unit_cube(), o).render(camera);
    // Each pixel's face: the dominant axis and sign of its shading normal. Per face, the spread
    // of the pixels whose 7x7 neighbourhood is all on the model and on that face (away from the
    // edges, where the filter mixes two faces).
    const auto face = [&](int x, int y) {
      const float* n = &img.normal[(static_cast<std::size_t>(y) * img.width + x) * 3];
      int axis = 0;
      for (int k = 1; k < 3; ++k)
        if (std::abs(n[k]) > std::abs(n[axis])) axis = k;
      return pixel(img, x, y)[3] < 1.0f ? -1 : 2 * axis + (n[axis] < 0.0f ? 1 : 0);
    };
    float worst = 0.0f;
    for (int f = 0; f < 6; ++f) {
      float lo = 1e9f, hi = 0.0f;
      int count = 0;
      for (int y = 3; y < img.height - 3; ++y)
        for (int x = 3; x < img.width - 3; ++x) {
          bool inside = true;
          for (int dy = -3; dy <= 3; ++dy)
            for (int dx = -3; dx <= 3; ++dx) inside = inside && face(x + dx, y + dy) == f;
          if (!inside) continue;
          const float g = pixel(img, x, y)[1];
          lo = std::min(lo, g), hi = std::max(hi, g), ++count;
        }
      if (count > 50) worst = std::max(worst, (hi - lo) / hi);
    }
    return worst;
  };
  const float hard = face_spread(60.0f), smooth = face_spread(180.0f);
  std::printf("largest spread within a face: crease 60: %.4f, 180: %.4f\n", hard, smooth);
  EXPECT_LT(hard, 0.01f);
  EXPECT_GT(smooth, 0.05f);
}

TEST(Renderer, RejectsBadOptions) {
  RenderOptions options;
  options.width = 0;
  EXPECT_THROW(Renderer(uv_sphere(1, 8, 4), options), InputError);
  options = RenderOptions{};
  options.samples_per_pixel = 0;
  EXPECT_THROW(Renderer(uv_sphere(1, 8, 4), options), InputError);
  EXPECT_THROW(Renderer(TriangleMesh{}, RenderOptions{}), InputError);
  options = RenderOptions{};
  options.filter_radius = 3.0f;
  EXPECT_THROW(Renderer(uv_sphere(1, 8, 4), options), InputError);
  EXPECT_THROW(look_preset("dramatic"), InputError);
}

TEST(Images, FilmicCurveForDisplayOnly) {
  Image img;
  img.width = 1;
  img.height = 1;
  img.tone_mapping = ToneMapping::filmic;
  EXPECT_NEAR(img.display(0.0f), 0.0f, 1e-3f);
  EXPECT_NEAR(img.display(1000.0f), 1.0f, 1e-3f);  // highlights roll off to white, no clipping step
  EXPECT_LT(img.display(1.0f), img.display(2.0f));
  EXPECT_LT(img.display(2.0f), img.display(4.0f));
  img.exposure = 1.0f;  // one stop: twice the light
  const float brighter = img.display(0.5f);
  img.exposure = 0.0f;
  EXPECT_FLOAT_EQ(brighter, img.display(1.0f));
}

// Khronos PBR Neutral, checked against values worked out by hand from its published formula.
TEST(Images, PbrNeutralFollowsTheKhronosFormula) {
  const auto near = [](const Eigen::Vector3f& a, const Eigen::Vector3f& b) { return (a - b).cwiseAbs().maxCoeff() < 1e-5f; };
  // Above the toe a colour loses exactly 0.04 (the offset), and under 0.76 nothing else.
  EXPECT_TRUE(near(pbr_neutral({0.5f, 0.5f, 0.5f}), {0.46f, 0.46f, 0.46f}));
  EXPECT_TRUE(near(pbr_neutral({0.1f, 0.3f, 0.7f}), {0.06f, 0.26f, 0.66f}));
  // In the toe the offset is x - 6.25 x^2 of the smallest channel x = 0.02: 0.0175.
  EXPECT_TRUE(near(pbr_neutral({0.02f, 0.3f, 0.6f}), {0.0025f, 0.2825f, 0.5825f}));
  // A highlight of 2: peak 1.96 compressed to 1 - 0.24^2 / 1.44 = 0.96; a grey stays grey.
  EXPECT_TRUE(near(pbr_neutral({2.0f, 2.0f, 2.0f}), {0.96f, 0.96f, 0.96f}));
  // A saturated highlight is desaturated towards white: g = 1 - 1 / (0.15 (peak - new peak) + 1).
  const Eigen::Vector3f hot = pbr_neutral({3.0f, 1.0f, 0.5f});
  const float peak = 2.96f, new_peak = 1.0f - 0.0576f / (peak + 0.24f - 0.76f), g = 1.0f - 1.0f / (0.15f * (peak - new_peak) + 1.0f);
  const Eigen::Vector3f expected = (1.0f - g) * Eigen::Vector3f(2.96f, 0.96f, 0.46f) * (new_peak / peak) + Eigen::Vector3f::Constant(g * new_peak);
  EXPECT_TRUE(near(hot, expected)) << hot.transpose() << " vs " << expected.transpose();
  EXPECT_NEAR(hot.maxCoeff(), new_peak, 1e-5f);
  // Monotonic in grey and never above 1.
  float last = -1.0f;
  for (float x = 0.0f; x < 100.0f; x = x * 1.1f + 0.01f) {
    const float y = pbr_neutral(Eigen::Vector3f::Constant(x)).x();
    EXPECT_GE(y, last) << x;
    EXPECT_LE(y, 1.0f) << x;
    last = y;
  }
  // As a display transform: a mid colour is shown as its own sRGB value, to within the offset.
  Image img;
  img.tone_mapping = ToneMapping::pbr_neutral;
  const Eigen::Vector3f shown = img.display(Eigen::Vector3f(0.2f, 0.4f, 0.6f));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(shown[c], linear_to_srgb(0.2f * (c + 1) - 0.04f), 1e-5f);
  for (const ToneMapping t : {ToneMapping::clamp, ToneMapping::filmic, ToneMapping::pbr_neutral})
    EXPECT_EQ(tone_mapping_from_name(tone_mapping_name(t)), t);
  EXPECT_FALSE(tone_mapping_from_name("aces").has_value());
}

TEST(Images, TransparentPngHasStraightAlpha) {
  Image img;
  img.width = 2;
  img.height = 1;
  img.transparent = true;
  img.rgba = {0.25f, 0.25f, 0.25f, 0.5f, 0.0f, 0.0f, 0.0f, 0.0f};  // premultiplied: 0.5 grey at half coverage
  const auto px = img.to_srgba8();
  EXPECT_EQ(px[0], 188);  // 0.5 linear, unpremultiplied
  EXPECT_EQ(px[3], 128);
  EXPECT_EQ(px[7], 0);
  const auto dir = test::scratch_dir();
  write_image(img, dir / "t.png");
  OIIO::ImageBuf png((dir / "t.png").string());
  ASSERT_TRUE(png.init_spec(png.name(), 0, 0));
  EXPECT_EQ(png.spec().nchannels, 4);
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
