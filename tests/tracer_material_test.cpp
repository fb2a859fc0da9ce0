// The file's own materials (glTF 2.0 metallic-roughness, emission, KHR_materials_unlit): the
// reader takes every factor and map, and the renderer's BRDF is the specification's Appendix B.
// Energy is checked against an independent numerical integration of that BRDF: in a uniform white
// environment (no lights, no ground, raw linear frame) a white metal sphere reflects exactly the
// GGX lobe's directional albedo at each pixel's view angle, and loses the rest.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>

#include "every_kernel.h"
#include "furnace.h"
#include "golden.h"
#include "gltf_writer.h"
#include "helpers.h"
#include "mesh/mesh.h"
#include "test_meshes.h"
#include "tracer/environment.h"
#include "tracer/tracer.h"

namespace meshtour {
namespace {

namespace fs = std::filesystem;
using test_meshes::uv_sphere;
constexpr double kPi = std::numbers::pi;

using test::covered_mean;
const Camera& kSphereCamera = test::kFurnaceCamera;
std::shared_ptr<const EnvironmentImage> uniform_white() { return test::uniform_environment(1.0f); }
RenderOptions furnace_options(std::shared_ptr<const EnvironmentImage> env, int spp = 64) { return test::furnace(std::move(env), spp); }

// A unit sphere of one material.
TriangleMesh sphere_of(const MeshMaterial& m) {
  TriangleMesh sphere = uv_sphere(1.0, 128, 64);
  sphere.materials = {m};
  return sphere;
}
MeshMaterial metal(float metallic, float roughness, Eigen::Vector3f base = Eigen::Vector3f::Ones()) {
  MeshMaterial m;
  m.base_color = base;
  m.metallic_roughness = MeshMaterial::MetallicRoughness{metallic, roughness, {}};
  return m;
}

// The directional albedo of GGX with F = 1 (a white metal) for the view at cosine mu: the
// integral over the hemisphere of D(h) G2(v, l) / (4 mu) (the BRDF times cos_l), by the midpoint
// rule in (theta_l, phi_l), with the height-correlated Smith G2 of the specification.
double ggx_albedo(double roughness, double mu) {
  const double alpha = roughness * roughness, a2 = alpha * alpha;
  const auto lambda = [&](double c) {
    const double t2 = (1.0 - c * c) / (c * c);
    return 0.5 * (std::sqrt(1.0 + a2 * t2) - 1.0);
  };
  const double sv = std::sqrt(std::max(0.0, 1.0 - mu * mu));
  const int nt = 400, np = 400;
  double sum = 0.0;
  for (int i = 0; i < nt; ++i) {
    const double theta = (i + 0.5) * (kPi / 2) / nt, ct = std::cos(theta), st = std::sin(theta);
    for (int j = 0; j < np; ++j) {
      const double phi = (j + 0.5) * 2 * kPi / np;
      // v = (sv, 0, mu), l = (st cos phi, st sin phi, ct), h = normalize(v + l).
      const double hx = sv + st * std::cos(phi), hy = st * std::sin(phi), hz = mu + ct;
      const double nh = hz / std::sqrt(hx * hx + hy * hy + hz * hz);
      const double q = nh * nh * (a2 - 1.0) + 1.0;
      const double d = a2 / (kPi * q * q);
      const double g2 = 1.0 / (1.0 + lambda(mu) + lambda(ct));
      sum += d * g2 / (4.0 * mu) * st;
    }
  }
  return sum * (kPi / 2 / nt) * (2 * kPi / np);
}

// The cosine between the normal and the view at the centre of pixel (x, y) where its ray meets
// the unit sphere (the renderer's pinhole camera at kSphereCamera), or nothing.
std::optional<double> view_cosine(int x, int y, int size) {
  const double tan_half = std::tan(kSphereCamera.vertical_fov_deg * kPi / 360.0);
  const Eigen::Vector3d eye = kSphereCamera.eye;
  const Eigen::Vector3d dir =
      Eigen::Vector3d((2.0 * (x + 0.5) / size - 1.0) * tan_half, (1.0 - 2.0 * (y + 0.5) / size) * tan_half, -1.0).normalized();
  const double b = eye.dot(dir), c = eye.squaredNorm() - 1.0, disc = b * b - c;
  if (disc < 0) return std::nullopt;
  const Eigen::Vector3d p = eye + (-b - std::sqrt(disc)) * dir;
  return p.normalized().dot(-dir);
}

TEST(Material, RoughWhiteMetalLosesWhatTheIntegralOfItsBrdfSays) {
  for (const float roughness : {1.0f, 0.5f}) {
    const Image img = Renderer(sphere_of(metal(1.0f, roughness)), furnace_options(uniform_white())).render(kSphereCamera);
    // The expected albedo per pixel, from a table over mu (it is smooth in mu).
    std::vector<double> table(101);
    for (int k = 0; k <= 100; ++k) table[static_cast<std::size_t>(k)] = ggx_albedo(roughness, std::max(0.02, k / 100.0));
    const auto expected = [&](double mu) {
      const double at = std::clamp(mu, 0.02, 1.0) * 100.0;
      const int k = std::min(99, static_cast<int>(at));
      return table[static_cast<std::size_t>(k)] + (at - k) * (table[static_cast<std::size_t>(k) + 1] - table[static_cast<std::size_t>(k)]);
    };
    // Also in three bands of the view angle: the albedo's fall towards grazing views, not only its mean.
    double got = 0.0, want = 0.0, band_got[3] = {}, band_want[3] = {};
    int n = 0;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        const std::size_t p = static_cast<std::size_t>(y) * img.width + x;
        const auto mu = view_cosine(x, y, img.width);
        if (img.rgba[p * 4 + 3] < 1.0f || !mu || *mu < 0.3) continue;  // inside, away from the outline
        const double e = expected(*mu);
        const int band = *mu < 0.6 ? 0 : *mu < 0.85 ? 1 : 2;
        got += img.rgba[p * 4 + 1], band_got[band] += img.rgba[p * 4 + 1];
        want += e, band_want[band] += e;
        ++n;
      }
    ASSERT_GT(n, 300);
    std::printf("roughness %.2f: mean albedo rendered %.4f, integrated %.4f (facing the camera %.4f); bands of cos 0.3-0.6, "
                "0.6-0.85, 0.85-1: %.4f/%.4f %.4f/%.4f %.4f/%.4f\n",
                roughness, got / n, want / n, ggx_albedo(roughness, 1.0), band_got[0], band_want[0], band_got[1], band_want[1],
                band_got[2], band_want[2]);
    EXPECT_NEAR(got / n, want / n, 0.01 * want / n) << "roughness " << roughness;
    for (int b = 0; b < 3; ++b) EXPECT_NEAR(band_got[b], band_want[b], 0.02 * band_want[b]) << "roughness " << roughness << ", band " << b;
    // A rough metal loses energy (single scattering): what the integral says, not nothing.
    if (roughness == 1.0f) {
      EXPECT_LT(want / n, 0.9);
    }
  }
}

// A mirror-like metal shows the environment where the mirror direction points: red sky above,
// blue ground below, so the sphere's top rows are red and its bottom rows blue (a metal without
// its specular reflection of the environment would be black; one reflected the wrong way round,
// the other colour).
TEST(Material, SmoothMetalReflectsTheEnvironmentTheRightWayUp) {
  const auto env = test::sky_and_floor({1.0f, 0.05f, 0.05f}, {0.05f, 0.05f, 1.0f});
  const Image img = Renderer(sphere_of(metal(1.0f, 0.1f)), furnace_options(env, 16)).render(kSphereCamera);
  const auto row_mean = [&](int y, int c) {
    double sum = 0;
    int n = 0;
    for (int x = 0; x < img.width; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * img.width + x;
      if (img.rgba[p * 4 + 3] < 1.0f) continue;
      sum += img.rgba[p * 4 + c];
      ++n;
    }
    return n ? sum / n : 0.0;
  };
  // Rows 20 and 44 of 64: a third of the way above and below the sphere's centre.
  EXPECT_GT(row_mean(20, 0), 0.7);
  EXPECT_LT(row_mean(20, 2), 0.2);
  EXPECT_GT(row_mean(44, 2), 0.7);
  EXPECT_LT(row_mean(44, 0), 0.2);
}

// The metallic-roughness map: blue multiplies metalness, green roughness. A map of (0, 0.2, 1)
// with factors 1 renders as the factors (1, 0.2) with no map; the channels swapped, it does not.
TEST(Material, MetallicRoughnessMapReadsBlueAsMetalAndGreenAsRoughness) {
  const fs::path dir = test::scratch_dir();
  const auto map = [&](const char* name, float g, float b) {
    OIIO::ImageBuf tex(OIIO::ImageSpec(4, 4, 3, OIIO::TypeDesc::FLOAT));
    const float value[3] = {0.0f, g, b};
    OIIO::ImageBufAlgo::fill(tex, value);
    EXPECT_TRUE(tex.write((dir / name).string()));
    return dir / name;
  };
  const auto render = [&](float metallic, float roughness, std::optional<fs::path> file) {
    MeshMaterial m = metal(metallic, roughness);
    if (file) m.metallic_roughness->texture.file = *file;
    TriangleMesh sphere = sphere_of(m);
    sphere.corner_uvs.assign(3 * sphere.triangles.size(), Eigen::Vector2f(0.5f, 0.5f));
    // Under the studio's lights alone: a smooth metal is dark but for its highlights, a rough
    // dielectric diffusely lit (in a white furnace the two would reflect about as much).
    RenderOptions options = furnace_options(nullptr, 16);
    options.shading.lights = look_preset("studio").lights;
    options.shading.ambient = Eigen::Vector3f::Zero();
    return Renderer(sphere, options).render(kSphereCamera);
  };
  const Image factors = render(1.0f, 0.2f, std::nullopt);
  const Image mapped = render(1.0f, 1.0f, map("mr.exr", 0.2f, 1.0f));
  const Image swapped = render(1.0f, 1.0f, map("rm.exr", 1.0f, 0.2f));
  const double same = test::mean_pixel_difference(factors, mapped), other = test::mean_pixel_difference(factors, swapped);
  std::printf("mean difference from the factors: the map %.3f/255, the swapped map %.3f/255\n", same, other);
  EXPECT_LT(same, 0.05);
  EXPECT_GT(other, 5.0);
}

// Emission is added as it is: with no light at all a sphere shows its emissive colour, times the
// emissive texture decoded from sRGB (8-bit PNG 188 is linear 0.5).
TEST(Material, EmissionShowsWithoutLightAndItsTextureIsSrgb) {
  const fs::path dir = test::scratch_dir();
  OIIO::ImageBuf tex(OIIO::ImageSpec(4, 4, 3, OIIO::TypeDesc::UINT8));
  const float value[3] = {188.0f / 255.0f, 1.0f, 1.0f};
  OIIO::ImageBufAlgo::fill(tex, value);
  ASSERT_TRUE(tex.write((dir / "glow.png").string()));
  RenderOptions options = furnace_options(nullptr, 4);
  options.shading.ambient = Eigen::Vector3f::Zero();
  MeshMaterial m = metal(0.0f, 0.5f, Eigen::Vector3f(0.5f, 0.5f, 0.5f));
  m.emissive = Eigen::Vector3f(0.8f, 0.4f, 0.2f);
  const Eigen::Vector3f plain = covered_mean(Renderer(sphere_of(m), options).render(kSphereCamera));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(plain[c], m.emissive[c], 1e-4f) << "channel " << c;
  m.emissive_texture.file = dir / "glow.png";
  TriangleMesh textured = sphere_of(m);
  textured.corner_uvs.assign(3 * textured.triangles.size(), Eigen::Vector2f(0.5f, 0.5f));
  const Eigen::Vector3f mapped = covered_mean(Renderer(textured, options).render(kSphereCamera));
  EXPECT_NEAR(mapped.x(), 0.8f * 0.5029f, 2e-3f);  // sRGB 188/255 = 0.5029 linear
  EXPECT_NEAR(mapped.y(), 0.4f, 1e-4f);
}

// KHR_materials_unlit: the base colour as it is under the studio's lights, shadows and sky.
TEST(Material, UnlitShowsItsBaseColourUnderAnyLight) {
  RenderOptions options = furnace_options(nullptr, 4);
  options.shading.lights = look_preset("studio").lights;
  MeshMaterial m;
  m.base_color = Eigen::Vector3f(0.3f, 0.6f, 0.9f);
  m.unlit = true;
  const Image img = Renderer(sphere_of(m), options).render(kSphereCamera);
  for (std::size_t p = 0; p < img.rgba.size() / 4; ++p) {
    if (img.rgba[p * 4 + 3] < 1.0f) continue;
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(img.rgba[p * 4 + c], (*m.base_color)[c], 1e-5f) << "pixel " << p;
  }
}

// --materials look: the file's BRDF is set aside, every surface gets the look's shading (the same
// pixels as the material without metallic-roughness).
TEST(Material, TheLooksMaterialsReplaceTheFilesOnRequest) {
  RenderOptions options = furnace_options(uniform_white(), 4);
  options.shading.lights = look_preset("studio").lights;
  MeshMaterial plain;
  plain.base_color = Eigen::Vector3f(0.9f, 0.5f, 0.2f);
  const MeshMaterial shiny = metal(1.0f, 0.2f, *plain.base_color);
  RenderOptions look = options;
  look.shading.material.use_file_material = false;
  const Image by_look = Renderer(sphere_of(shiny), look).render(kSphereCamera), plain_img = Renderer(sphere_of(plain), options).render(kSphereCamera);
  EXPECT_EQ(by_look.rgba, plain_img.rgba);
  EXPECT_GT(test::mean_pixel_difference(Renderer(sphere_of(shiny), options).render(kSphereCamera), plain_img), 3.0);
}

// A unit quad in z = 0 facing +z (counter-clockwise seen from +z), UVs over [0, 1]^2, of one material.
TriangleMesh quad_of(const MeshMaterial& m) {
  TriangleMesh q;
  q.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  q.triangles = {{0, 1, 2}, {0, 2, 3}};
  q.corner_uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 0}, {1, 1}, {0, 1}};
  q.materials = {m};
  return q;
}
// The quad's coverage (alpha) at pixel (x, y) of a transparent 64 x 64 frame from +z (or from -z).
Image quad_frame(const MeshMaterial& m, bool from_behind = false, int spp = 16) {
  RenderOptions options = furnace_options(nullptr, spp);
  options.shading.background = BackgroundKind::transparent;
  options.shading.lights = look_preset("studio").lights;
  const Camera camera{{0, 0, from_behind ? -3.0 : 3.0}, {0, 0, 0}, {0, 1, 0}, 60.0};
  return Renderer(quad_of(m), options).render(camera);
}
float alpha_at(const Image& img, int x, int y) { return img.rgba[(static_cast<std::size_t>(y) * img.width + x) * 4 + 3]; }

// doubleSided false: a face is not seen from behind (back-face culling); true, and for OBJ or
// PLY, it is.
TEST(Material, ASingleSidedFaceIsNotSeenFromBehind) {
  MeshMaterial m;
  m.base_color = Eigen::Vector3f(0.8f, 0.2f, 0.2f);
  EXPECT_EQ(alpha_at(quad_frame(m, true), 32, 32), 1.0f);
  m.double_sided = false;
  EXPECT_EQ(alpha_at(quad_frame(m, false), 32, 32), 1.0f);
  EXPECT_EQ(alpha_at(quad_frame(m, true), 32, 32), 0.0f);
}

// ... and for shadow rays: a single-sided face met from behind by a shadow ray casts no shadow.
// A light from the right (camera space +x, +z); a small quad in front of the big one, facing the
// camera and the light, whose shadow falls on the big quad left of it (pixel 23 of row 32, which
// the small quad does not cover). Two-sided it shades that pixel; single-sided the big quad's
// shadow rays meet its back and pass.
TEST(Material, ASingleSidedFaceCastsNoShadowFromBehind) {
  MeshMaterial m;
  m.base_color = Eigen::Vector3f(0.8f, 0.8f, 0.8f);
  m.double_sided = false;
  TriangleMesh alone = quad_of(m), with_blocker = quad_of(m);
  with_blocker.positions.insert(with_blocker.positions.end(), {{-0.25, -0.25, 0.5}, {0.25, -0.25, 0.5}, {0.25, 0.25, 0.5}, {-0.25, 0.25, 0.5}});
  with_blocker.triangles.insert(with_blocker.triangles.end(), {{4, 5, 6}, {4, 6, 7}});
  with_blocker.corner_uvs.resize(12, Eigen::Vector2f(0, 0));
  RenderOptions options = furnace_options(nullptr, 16);
  options.shading.lights = {Light{{1.0f, 0.0f, 1.0f}, {1.0f, 1.0f, 1.0f}, 1.0f, 2.0f}};
  options.shading.ambient = Eigen::Vector3f::Zero();
  options.shading.ambient_occlusion = false;
  const Camera camera{{0, 0, 3}, {0, 0, 0}, {0, 1, 0}, 60.0};
  const std::size_t pixel = (32 * 64 + 23) * 4;
  const float lit = Renderer(alone, options).render(camera).rgba[pixel];
  ASSERT_GT(lit, 0.1f);
  EXPECT_NEAR(Renderer(with_blocker, options).render(camera).rgba[pixel], lit, 1e-3f) << "single-sided";
  with_blocker.materials[0].double_sided = true;
  EXPECT_LT(Renderer(with_blocker, options).render(camera).rgba[pixel], 0.5f * lit) << "two-sided";
}

// alphaMode MASK: where the base colour map's alpha (times the factor's) is under the cutoff the
// surface is not there; OPAQUE ignores alpha; BLEND stops a share alpha of the rays.
TEST(Material, AlphaModesMaskBlendAndOpaque) {
  const fs::path dir = test::scratch_dir();
  // Left half alpha 0, right half 255; straight alpha, so the colour stays red where alpha is 0.
  OIIO::ImageBuf tex(OIIO::ImageSpec(4, 4, 4, OIIO::TypeDesc::UINT8));
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) {
      const float px[4] = {1.0f, 0.0f, 0.0f, x < 2 ? 0.0f : 1.0f};
      tex.setpixel(x, y, px);
    }
  ASSERT_TRUE(tex.write((dir / "cutout.png").string()));
  MeshMaterial m;
  m.texture.file = dir / "cutout.png";
  // The quad spans pixels 13.5 to 50.5: u = 0.25 is pixel 22, u = 0.75 pixel 41.
  EXPECT_EQ(alpha_at(quad_frame(m), 22, 32), 1.0f) << "opaque";
  m.alpha_mode = MeshMaterial::AlphaMode::mask;
  const Image masked = quad_frame(m);
  EXPECT_EQ(alpha_at(masked, 22, 32), 0.0f) << "mask, alpha 0";
  EXPECT_EQ(alpha_at(masked, 41, 32), 1.0f) << "mask, alpha 1";
  m.alpha = 0.3f;  // the factor multiplies the map: 0.3 < 0.5 everywhere
  EXPECT_EQ(alpha_at(quad_frame(m), 41, 32), 0.0f) << "mask, factor 0.3";
  m.alpha_mode = MeshMaterial::AlphaMode::blend;
  m.alpha = 0.25f;
  const Image blended = quad_frame(m, false, 256);
  double sum = 0.0;
  int n = 0;
  for (int y = 24; y < 40; ++y)
    for (int x = 36; x < 48; ++x) sum += alpha_at(blended, x, y), ++n;
  EXPECT_NEAR(sum / n, 0.25, 0.02) << "blend, alpha 0.25";
  for (int y = 24; y < 40; ++y) EXPECT_EQ(alpha_at(blended, 22, y), 0.0f) << "blend, alpha 0";
}

// The reader: metallic and roughness factors and map, emissive factor times
// KHR_materials_emissive_strength and its map, KHR_materials_unlit, alphaMode, alphaCutoff and
// the factor's alpha, doubleSided, and glTF's defaults (a material without pbrMetallicRoughness
// is a rough metal: factors 1; it is single-sided and opaque).
TEST(Material, GltfReaderTakesEveryFactorAndMap) {
  const fs::path dir = test::scratch_dir();
  OIIO::ImageBuf tex(OIIO::ImageSpec(2, 2, 3, OIIO::TypeDesc::UINT8));
  const float grey[3] = {0.5f, 0.5f, 0.5f};
  OIIO::ImageBufAlgo::fill(tex, grey);
  ASSERT_TRUE(tex.write((dir / "t.png").string()));
  test::GltfBuilder g;
  const int pos = g.floats({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0}, 3), uv = g.floats({0, 0, 1, 0, 0, 1, 1, 1}, 2);
  g.embedded_image(test::read_bytes(dir / "t.png"), "image/png");
  g.doc["textures"] = {{{"source", 0}}};
  g.doc["extensionsUsed"] = {"KHR_materials_emissive_strength", "KHR_materials_unlit"};
  g.doc["materials"] = {
      {{"name", "brass"},
       {"pbrMetallicRoughness", {{"metallicFactor", 0.25}, {"roughnessFactor", 0.75}, {"metallicRoughnessTexture", {{"index", 0}}}}},
       {"emissiveFactor", {1.0, 0.5, 0.0}},
       {"emissiveTexture", {{"index", 0}}},
       {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4.0}}}}}},
      {{"name", "flat"}, {"extensions", {{"KHR_materials_unlit", nlohmann::json::object()}}}},
      {{"name", "defaults"}}};
  g.doc["materials"][1]["alphaMode"] = "MASK";
  g.doc["materials"][1]["alphaCutoff"] = 0.25;
  g.doc["materials"][1]["doubleSided"] = true;
  g.doc["materials"][1]["pbrMetallicRoughness"] = {{"baseColorFactor", {1.0, 1.0, 1.0, 0.75}}};
  nlohmann::json prims = nlohmann::json::array();
  for (int m = 0; m < 3; ++m)
    prims.push_back({{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv}}}, {"indices", g.indices({0, 1, 2, 1, 3, 2})}, {"material", m}});
  g.doc["meshes"] = {{{"primitives", prims}}};
  g.doc["nodes"] = {{{"mesh", 0}}};
  g.doc["scenes"] = {{{"nodes", {0}}}};
  g.doc["scene"] = 0;
  g.write_glb(dir / "materials.glb");
  const TriangleMesh mesh = load_mesh(dir / "materials.glb");
  ASSERT_EQ(mesh.materials.size(), 3u);
  const MeshMaterial& brass = mesh.materials[0];
  ASSERT_TRUE(brass.metallic_roughness);
  EXPECT_FLOAT_EQ(brass.metallic_roughness->metallic, 0.25f);
  EXPECT_FLOAT_EQ(brass.metallic_roughness->roughness, 0.75f);
  EXPECT_TRUE(brass.metallic_roughness->texture.present());
  EXPECT_EQ(brass.emissive, Eigen::Vector3f(4.0f, 2.0f, 0.0f));
  EXPECT_TRUE(brass.emissive_texture.present());
  EXPECT_FALSE(brass.unlit);
  EXPECT_EQ(brass.named_maps().size(), 2u);
  EXPECT_TRUE(mesh.materials[1].unlit);
  EXPECT_EQ(mesh.materials[1].alpha_mode, MeshMaterial::AlphaMode::mask);
  EXPECT_FLOAT_EQ(mesh.materials[1].alpha_cutoff, 0.25f);
  EXPECT_FLOAT_EQ(mesh.materials[1].alpha, 0.75f);
  EXPECT_TRUE(mesh.materials[1].double_sided);
  EXPECT_FALSE(mesh.materials[1].metallic_roughness);
  EXPECT_FALSE(mesh.materials[2].double_sided);  // glTF's default
  EXPECT_EQ(mesh.materials[2].alpha_mode, MeshMaterial::AlphaMode::opaque);
  ASSERT_TRUE(mesh.materials[2].metallic_roughness);
  EXPECT_FLOAT_EQ(mesh.materials[2].metallic_roughness->metallic, 1.0f);
  EXPECT_FLOAT_EQ(mesh.materials[2].metallic_roughness->roughness, 1.0f);
}

// Every part of a glTF material on every tile kernel (every_kernel.h; the look's own shading is
// Renderer.SamePixelsWithEveryInstructionSet's). A textured, normal-mapped, partly metal, emissive, half-transparent sphere under an
// environment, the look's lights and its ground, at whole and partial packets per pixel.
TEST(Material, SamePixelsWithEveryInstructionSet) {
  const fs::path dir = test::scratch_dir();
  const auto write_map = [&](const char* name, auto texel) {
    OIIO::ImageBuf tex(OIIO::ImageSpec(8, 8, 3, OIIO::TypeDesc::UINT8));
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) {
        const Eigen::Vector3f v = texel(x, y);
        tex.setpixel(x, y, v.data());
      }
    EXPECT_TRUE(tex.write((dir / name).string())) << tex.geterror();
    MeshTexture t;
    t.file = dir / name;
    return t;
  };
  MeshMaterial m = metal(0.6f, 0.35f, Eigen::Vector3f(0.9f, 0.7f, 0.5f));
  m.texture = write_map("checker.png", [](int x, int y) { return (x + y) % 2 ? Eigen::Vector3f(1, 1, 1) : Eigen::Vector3f(0.2f, 0.5f, 0.3f); });
  m.normal_texture = write_map("bumps.png", [](int x, int y) {  // tangent-space normals leaning every way
    const Eigen::Vector3f n = Eigen::Vector3f(0.4f * std::sin(1.7f * x), 0.4f * std::cos(2.3f * y), 1.0f).normalized();
    return Eigen::Vector3f((n.array() * 0.5f + 0.5f).matrix());
  });
  m.metallic_roughness->texture = write_map("metal.png", [](int x, int y) { return Eigen::Vector3f(0, 0.3f + 0.08f * x, 0.2f + 0.1f * y); });
  m.emissive = Eigen::Vector3f(0.05f, 0.02f, 0.0f);
  m.alpha_mode = MeshMaterial::AlphaMode::blend;
  m.alpha = 0.8f;
  TriangleMesh sphere = uv_sphere(1.0, 48, 24);
  for (const auto& t : sphere.triangles)
    for (const std::uint32_t v : t) {
      const Eigen::Vector3d& p = sphere.positions[v];
      sphere.corner_uvs.emplace_back(static_cast<float>(std::atan2(p.z(), p.x()) / (2 * kPi) + 0.5), static_cast<float>(std::acos(std::clamp(p.y(), -1.0, 1.0)) / kPi));
    }
  sphere.materials = {m};
  const auto env = test::sky_and_floor({1.0f, 0.6f, 0.4f}, {0.1f, 0.2f, 0.6f});
  for (int spp : {16, 5}) {
    RenderOptions options;
    options.width = 64;
    options.height = 48;
    options.samples_per_pixel = spp;
    options.layers = {true, true, true};
    options.shading.environment = env;
    const std::vector<Image> images = test::expect_same_bits_on_every_kernel(
        [&] { return Renderer(sphere, options).render(Camera{{2.2, 1.4, 2.6}, {0, 0, 0}, {0, 1, 0}, 40.0}, 3); },
        "spp " + std::to_string(spp));
    ASSERT_FALSE(images.empty());
    // The sphere is in the frame and its maps show: the albedo layer takes several values.
    const std::set<float> values(images[0].albedo.begin(), images[0].albedo.end());
    EXPECT_GT(values.size(), 100u);
  }
}

}  // namespace
}  // namespace meshtour
