// Normal maps and the file's own normals, seen through the normal layer (the world-space shading
// normal the denoiser is guided by) of a square quad facing the camera: a map of one tilted
// normal must tilt the whole quad along the frame its UVs and tangents give, the way the glTF
// specification reads it (+x along increasing u, +y along increasing v up the image, w turning
// the bitangent), and a file's NORMAL must be the shading normal.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <numbers>
#include <optional>

#include "gltf_writer.h"
#include "helpers.h"
#include "core/error.h"
#include "tracer/tracer.h"

namespace meshtour {
namespace {

namespace fs = std::filesystem;

struct QuadSpec {
  std::optional<Eigen::Vector3f> normal;   // NORMAL of every vertex, or none
  std::optional<Eigen::Vector4f> tangent;  // TANGENT of every vertex, or none
  std::optional<Eigen::Vector3f> mapped;   // the normal map's one tangent-space normal, or no map
  bool mirrored_u = false;                 // u runs right to left
  double scale = 1.0;                      // normalTexture.scale
  QuadSpec with_normal(Eigen::Vector3f n) const { QuadSpec q = *this; q.normal = n; return q; }
  QuadSpec with_tangent(Eigen::Vector4f t) const { QuadSpec q = *this; q.tangent = t; return q; }
  QuadSpec with_map(Eigen::Vector3f m) const { QuadSpec q = *this; q.mapped = m; return q; }
  QuadSpec mirrored() const { QuadSpec q = *this; q.mirrored_u = true; return q; }
  QuadSpec scaled(double k) const { QuadSpec q = *this; q.scale = k; return q; }
};

// A one-colour 8x8 PNG holding the tangent-space normal `m` as glTF stores it (m * 0.5 + 0.5).
std::vector<unsigned char> normal_map_png(const fs::path& dir, const Eigen::Vector3f& m) {
  OIIO::ImageBuf tex(OIIO::ImageSpec(8, 8, 3, OIIO::TypeDesc::UINT8));
  const Eigen::Vector3f v = (m.normalized() * 0.5f).array() + 0.5f;
  OIIO::ImageBufAlgo::fill(tex, v.data());
  const fs::path file = dir / "normal.png";
  EXPECT_TRUE(tex.write(file.string())) << tex.geterror();
  return test::read_bytes(file);
}

fs::path write_quad(const fs::path& dir, const QuadSpec& q) {
  test::GltfBuilder g;
  const float corners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  std::vector<float> positions, uvs, normals, tangents;
  for (const auto& c : corners) {
    positions.insert(positions.end(), {c[0], c[1], 0.0f});
    const float u = (c[0] + 1) / 2, v = (c[1] + 1) / 2;  // v up the image
    uvs.insert(uvs.end(), {q.mirrored_u ? 1 - u : u, 1 - v});  // glTF's v runs down
    if (q.normal) normals.insert(normals.end(), {q.normal->x(), q.normal->y(), q.normal->z()});
    if (q.tangent) tangents.insert(tangents.end(), {q.tangent->x(), q.tangent->y(), q.tangent->z(), q.tangent->w()});
  }
  nlohmann::json attributes = {{"POSITION", g.floats(positions, 3)}, {"TEXCOORD_0", g.floats(uvs, 2)}};
  if (q.normal) attributes["NORMAL"] = g.floats(normals, 3);
  if (q.tangent) attributes["TANGENT"] = g.floats(tangents, 4);
  const int idx = g.indices({0, 1, 2, 0, 2, 3});
  g.doc["meshes"] = {{{"primitives", {{{"attributes", attributes}, {"indices", idx}, {"material", 0}}}}}};
  g.doc["nodes"] = {{{"mesh", 0}}};
  g.doc["scenes"] = {{{"nodes", {0}}}};
  g.doc["scene"] = 0;
  nlohmann::json material = {{"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.8, 0.8, 1.0}}}}};
  if (q.mapped) {
    g.embedded_image(normal_map_png(dir, *q.mapped), "image/png");
    g.doc["textures"] = {{{"source", 0}}};
    material["normalTexture"] = {{"index", 0}, {"scale", q.scale}};
  }
  g.doc["materials"] = nlohmann::json::array({material});
  g.write_glb(dir / "quad.glb");
  return dir / "quad.glb";
}

// The mean shading normal over the middle of the frame (the quad fills it).
Eigen::Vector3f shading_normal(const fs::path& model) {
  RenderOptions options;
  options.width = options.height = 32;
  options.samples_per_pixel = 4;
  options.shading = look_preset("plain");
  options.layers.normal = true;
  options.denoise = false;
  const double fov = 2.0 * std::atan(0.2) * 180.0 / std::numbers::pi;
  const Image img = Renderer(load_mesh(model), options).render(Camera{{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, fov});
  Eigen::Vector3f sum = Eigen::Vector3f::Zero();
  for (int y = 8; y < 24; ++y)
    for (int x = 8; x < 24; ++x) sum += Eigen::Map<const Eigen::Vector3f>(&img.normal[(static_cast<std::size_t>(y) * 32 + x) * 3]);
  return sum.normalized();
}

void expect_near(const Eigen::Vector3f& got, const Eigen::Vector3f& want, const char* what) {
  EXPECT_LT((got - want.normalized()).norm(), 0.01f) << what << ": got " << got.transpose() << ", want " << want.normalized().transpose();
}

const Eigen::Vector3f kUp(0, 0, 1);
const float kSin = 0.5f, kCos = 0.8660254f;  // 30 degrees

TEST(NormalMap, TiltsTheShadingNormalAlongTheFrameOfTheUvs) {
  const fs::path dir = test::scratch_dir();
  expect_near(shading_normal(write_quad(dir, QuadSpec{}.with_normal(kUp))), kUp, "no map");
  // +x of the map is increasing u (right), +y is increasing v (up the image).
  expect_near(shading_normal(write_quad(dir, QuadSpec{}.with_normal(kUp).with_map(Eigen::Vector3f(kSin, 0, kCos)))), {kSin, 0, kCos}, "tilt along u");
  expect_near(shading_normal(write_quad(dir, QuadSpec{}.with_normal(kUp).with_map(Eigen::Vector3f(0, kSin, kCos)))), {0, kSin, kCos}, "tilt along v");
  // Mirrored UVs: u runs left, so +x of the map does too; the generated tangent's w keeps +y up.
  expect_near(shading_normal(write_quad(dir, QuadSpec{}.with_normal(kUp).with_map(Eigen::Vector3f(kSin, 0, kCos)).mirrored())),
              {-kSin, 0, kCos}, "mirrored, along u");
  expect_near(shading_normal(write_quad(dir, QuadSpec{}.with_normal(kUp).with_map(Eigen::Vector3f(0, kSin, kCos)).mirrored())),
              {0, kSin, kCos}, "mirrored, along v");
  // Without NORMAL in the file the map works on the computed normals.
  expect_near(shading_normal(write_quad(dir, QuadSpec{}.with_map(Eigen::Vector3f(kSin, 0, kCos)))), {kSin, 0, kCos}, "computed normals");
  // The scale multiplies x and y: 0 leaves the surface's own normal.
  expect_near(shading_normal(write_quad(dir, QuadSpec{}.with_normal(kUp).with_map(Eigen::Vector3f(kSin, 0, kCos)).scaled(0.0))), kUp, "scale 0");
}

TEST(NormalMap, TheFilesTangentsAreUsed) {
  const fs::path dir = test::scratch_dir();
  // TANGENT +y (w +1): the bitangent is cross(n, t) = -x, so +x of the map points up the frame.
  expect_near(shading_normal(write_quad(dir, QuadSpec{}.with_normal(kUp).with_tangent(Eigen::Vector4f(0, 1, 0, 1)).with_map(Eigen::Vector3f(kSin, 0, kCos)))),
              {0, kSin, kCos}, "tangent +y");
  // w -1 turns the bitangent: +y of the map points right.
  expect_near(shading_normal(write_quad(dir, QuadSpec{}.with_normal(kUp).with_tangent(Eigen::Vector4f(0, 1, 0, -1)).with_map(Eigen::Vector3f(0, kSin, kCos)))),
              {kSin, 0, kCos}, "tangent +y, w -1");
}

// A damaged normal map is refused naming it, or with --missing-textures grey left out with a
// warning (the faces keep their colour and their own normals).
TEST(NormalMap, ADamagedMapIsNamedOrLeftOut) {
  const fs::path dir = test::scratch_dir();
  // The PNG's bytes cut short inside the GLB: rewrite the file with half an image.
  test::GltfBuilder g;
  std::vector<unsigned char> png = normal_map_png(dir, Eigen::Vector3f(kSin, 0, kCos));
  png.resize(png.size() / 2);
  const std::vector<float> positions = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0}, uvs = {0, 1, 1, 1, 1, 0, 0, 0};
  const nlohmann::json attributes = {{"POSITION", g.floats(positions, 3)}, {"TEXCOORD_0", g.floats(uvs, 2)}};
  const int idx = g.indices({0, 1, 2, 0, 2, 3});
  g.doc["meshes"] = {{{"primitives", {{{"attributes", attributes}, {"indices", idx}, {"material", 0}}}}}};
  g.doc["nodes"] = {{{"mesh", 0}}};
  g.embedded_image(png, "image/png");
  g.doc["textures"] = {{{"source", 0}}};
  g.doc["materials"] = {{{"name", "stone"}, {"normalTexture", {{"index", 0}}}}};
  g.write_glb(dir / "damaged.glb");
  try {
    load_mesh(dir / "damaged.glb");
    ADD_FAILURE() << "a damaged normal map was accepted";
  } catch (const IoError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("the normal texture of material 'stone'"), std::string::npos) << message;
    EXPECT_NE(message.find("--missing-textures grey"), std::string::npos) << message;
  }
  LoadReport report;
  const TriangleMesh grey = load_mesh(dir / "damaged.glb", &report, LoadOptions{.missing_textures_grey = true});
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_NE(report.warnings[0].find("without their normal map"), std::string::npos) << report.warnings[0];
  EXPECT_FALSE(grey.materials[0].normal_texture.present());
}

// Relief from a normal map survives denoising at 16 spp: a map of vertical stripes, 4 texels wide,
// leaning 30 degrees left and right in turn, lit by the studio look's key light from the left,
// shows bright and dark stripes; the denoised frame keeps their contrast (the denoiser divides by
// the unshadowed light, which the mapped normal shades, and its normal guide is the mapped one).
TEST(NormalMap, ReliefSurvivesDenoising) {
  const fs::path dir = test::scratch_dir();
  OIIO::ImageBuf tex(OIIO::ImageSpec(64, 8, 3, OIIO::TypeDesc::UINT8));
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 64; ++x) {
      const Eigen::Vector3f m = (x / 4) % 2 ? Eigen::Vector3f(kSin, 0, kCos) : Eigen::Vector3f(-kSin, 0, kCos);
      const Eigen::Vector3f v = (m * 0.5f).array() + 0.5f;
      tex.setpixel(x, y, v.data());
    }
  ASSERT_TRUE(tex.write((dir / "stripes.png").string()));
  test::GltfBuilder g;
  const std::vector<float> positions = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0}, uvs = {0, 1, 1, 1, 1, 0, 0, 0}, normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  const nlohmann::json attributes = {{"POSITION", g.floats(positions, 3)}, {"TEXCOORD_0", g.floats(uvs, 2)}, {"NORMAL", g.floats(normals, 3)}};
  const int idx = g.indices({0, 1, 2, 0, 2, 3});
  g.doc["meshes"] = {{{"primitives", {{{"attributes", attributes}, {"indices", idx}, {"material", 0}}}}}};
  g.doc["nodes"] = {{{"mesh", 0}}};
  g.embedded_image(test::read_bytes(dir / "stripes.png"), "image/png");
  g.doc["samplers"] = {{{"magFilter", 9728}, {"minFilter", 9728}}};  // sharp stripes
  g.doc["textures"] = {{{"source", 0}, {"sampler", 0}}};
  g.doc["materials"] = {{{"normalTexture", {{"index", 0}}}}};
  g.write_glb(dir / "stripes.glb");
  RenderOptions options;
  options.width = options.height = 128;
  options.samples_per_pixel = 16;
  options.shading.ground = false;
  const double fov = 2.0 * std::atan(0.2) * 180.0 / std::numbers::pi;
  const Image img = Renderer(load_mesh(dir / "stripes.glb"), options).render(Camera{{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, fov});
  ASSERT_FALSE(img.denoised.empty());
  // 16 stripes across 128 pixels, 8 pixels each: the middle 4 columns of each, rows 16-111.
  const auto contrast = [&](const std::vector<float>& rgba) {
    double lit = 0, dark = 0;
    for (int y = 16; y < 112; ++y)
      for (int x = 0; x < 128; ++x) {
        if (x % 8 < 2 || x % 8 > 5) continue;
        const double v = rgba[(static_cast<std::size_t>(y) * 128 + x) * 4 + 1];
        ((x / 8) % 2 ? dark : lit) += v;  // which of the two is brighter is the key light's side; the contrast is what counts
      }
    return (lit - dark) / (lit + dark);
  };
  const double raw = contrast(img.rgba), denoised = contrast(img.denoised);
  std::cout << "[ contrast ] raw " << raw << ", denoised " << denoised << "\n";
  EXPECT_GT(std::abs(raw), 0.1) << "the map makes no relief";
  EXPECT_NEAR(denoised, raw, 0.1 * std::abs(raw));
}

TEST(FileNormals, AreTheShadingNormals) {
  const fs::path dir = test::scratch_dir();
  // A flat quad whose file says its normals lean 37 degrees to the right: computed normals would
  // be (0, 0, 1).
  expect_near(shading_normal(write_quad(dir, QuadSpec{}.with_normal(Eigen::Vector3f(0.6f, 0, 0.8f)))), {0.6f, 0, 0.8f}, "file normals");
}

// The same through KHR_draco_mesh_compression (Voyager's deliveries are Draco GLBs): the decoded
// NORMAL is the shading normal, to Draco's quantisation.
TEST(FileNormals, AreReadFromDracoData) {
  if (std::system("command -v draco_transcoder >/dev/null 2>&1") != 0) {
    if (std::getenv("MESHTOUR_REQUIRE_SHARED")) FAIL() << "draco_transcoder is not installed (scripts/install-deps.sh --tests)";
    GTEST_SKIP() << "draco_transcoder is not installed (Debian package draco)";
  }
  const fs::path dir = test::scratch_dir();
  const fs::path plain = write_quad(dir, QuadSpec{}.with_normal(Eigen::Vector3f(0.6f, 0, 0.8f))), draco = dir / "draco.glb";
  const std::string command = "draco_transcoder -i '" + plain.string() + "' -o '" + draco.string() + "' >/dev/null 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  ASSERT_NE(test::read_bytes(draco), test::read_bytes(plain));
  const TriangleMesh mesh = load_mesh(draco);
  ASSERT_EQ(mesh.corner_normals.size(), 6u);
  for (const Eigen::Vector3f& n : mesh.corner_normals) EXPECT_LT((n - Eigen::Vector3f(0.6f, 0, 0.8f)).norm(), 0.02f) << n.transpose();
  expect_near(shading_normal(draco), {0.6f, 0, 0.8f}, "Draco normals");
}

}  // namespace
}  // namespace meshtour
