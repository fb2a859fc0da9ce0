// glTF 2.0 / GLB input: files written by the test itself (tests/gltf_writer.h), the Draco case
// encoded with Debian's draco_encoder when it is installed.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>

#include "core/error.h"
#include "gltf_writer.h"
#include "helpers.h"
#include "mesh/mesh.h"
#include "textured_cube.h"

namespace meshtour {
namespace {

using test::GltfBuilder;

// A unit square in the XY plane (z = 0) with UVs, as one triangle list; material 0 when
// `material` is set.
GltfBuilder square(bool material = true) {
  GltfBuilder b;
  const int pos = b.floats({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, 3);
  const int uv = b.floats({0, 1, 1, 1, 1, 0, 0, 0}, 2);  // glTF: v runs down the image
  const int idx = b.indices({0, 1, 2, 0, 2, 3});
  nlohmann::json prim = {{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv}}}, {"indices", idx}};
  if (material) prim["material"] = 0;
  b.doc["meshes"] = {{{"primitives", {prim}}}};
  b.doc["nodes"] = {{{"mesh", 0}}};
  b.doc["scenes"] = {{{"nodes", {0}}}};
  b.doc["scene"] = 0;
  return b;
}

void add_textured_material(GltfBuilder& b, int image, nlohmann::json texture_info = {}) {
  texture_info["index"] = 0;
  b.doc["samplers"] = {{{"wrapS", 33071}, {"wrapT", 33648}}};  // clamp, mirror
  b.doc["textures"] = {{{"source", image}, {"sampler", 0}}};
  b.doc["materials"] = {{{"name", "paint"},
                         {"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 1.0, 1.0, 1.0}}, {"baseColorTexture", texture_info}}}}};
}

std::vector<unsigned char> checker_png(const std::filesystem::path& dir) {
  test::write_textured_cube(dir);
  return test::read_bytes(dir / "checker.png");
}

TEST(MeshGltf, NodeTransformsMaterialsAndExternalFiles) {
  const auto dir = test::scratch_dir();
  checker_png(dir);
  GltfBuilder b = square();
  b.doc["images"] = {{{"uri", "checker.png"}}};
  add_textured_material(b, 0);
  // Two instances: translated by +2 in x, and scaled by 3 under a parent rotated about y.
  b.doc["nodes"] = {{{"mesh", 0}, {"translation", {2, 0, 0}}},
                    {{"children", {2}}, {"rotation", {0, 0.7071067811865476, 0, 0.7071067811865476}}},
                    {{"mesh", 0}, {"scale", {3, 3, 3}}}};
  b.doc["scenes"] = {{{"nodes", {0, 1}}}};
  b.write_gltf(dir / "square.gltf");
  const MeshFileSummary summary = check_mesh_file(dir / "square.gltf");
  EXPECT_EQ(summary.vertices, 8u);
  EXPECT_EQ(summary.triangles(), 4u);

  const TriangleMesh mesh = load_mesh(dir / "square.gltf");
  ASSERT_EQ(mesh.triangles.size(), 4u);
  ASSERT_EQ(mesh.positions.size(), 8u);
  EXPECT_NEAR((mesh.positions[1] - Eigen::Vector3d(3, 0, 0)).norm(), 0.0, 1e-12);
  // Rotated +90 degrees about y: x goes to -z.
  EXPECT_NEAR((mesh.positions[5] - Eigen::Vector3d(0, 0, -3)).norm(), 0.0, 1e-9);
  ASSERT_EQ(mesh.materials.size(), 1u);
  const MeshMaterial& m = mesh.materials[0];
  EXPECT_EQ(m.name, "paint");
  EXPECT_EQ(m.texture_file, dir / "checker.png");
  EXPECT_EQ(m.wrap_s, TextureWrap::clamp);
  EXPECT_EQ(m.wrap_t, TextureWrap::mirror);
  ASSERT_TRUE(m.base_color);
  EXPECT_FLOAT_EQ(m.base_color->x(), 0.5f);
  ASSERT_TRUE(mesh.has_texture());
  // Corner 1 of triangle 0 is vertex 1 at glTF uv (1, 1): v flipped to meshtour's (1, 0).
  EXPECT_NEAR((mesh.corner_uvs[1] - Eigen::Vector2f(1, 0)).norm(), 0.0f, 1e-6f);
}

TEST(MeshGltf, GlbWithEmbeddedImageColoursStripsAndTextureTransform) {
  const auto dir = test::scratch_dir();
  GltfBuilder b;
  // A strip of 4 vertices (2 triangles) with linear vertex colours.
  const int pos = b.floats({0, 0, 0, 0, 1, 0, 1, 0, 0, 1, 1, 0}, 3);
  const int col = b.floats({1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1}, 3);
  const int uv = b.floats({0, 0, 0, 1, 1, 0, 1, 1}, 2);
  b.doc["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", pos}, {"COLOR_0", col}, {"TEXCOORD_1", uv}}}, {"mode", 5}, {"material", 0}}}}}};
  b.doc["nodes"] = {{{"mesh", 0}}};
  const int image = b.embedded_image(checker_png(dir), "image/png");
  add_textured_material(b, image, {{"texCoord", 1}, {"extensions", {{"KHR_texture_transform", {{"offset", {0.5, 0}}, {"scale", {0.5, 0.5}}}}}}});
  b.doc["extensionsUsed"] = {"KHR_texture_transform"};
  b.doc["extensionsRequired"] = {"KHR_texture_transform"};
  b.write_glb(dir / "strip.glb");
  const TriangleMesh mesh = load_mesh(dir / "strip.glb");
  ASSERT_EQ(mesh.triangles.size(), 2u);
  EXPECT_EQ(mesh.triangles[0], (std::array<std::uint32_t, 3>{0, 1, 2}));
  EXPECT_EQ(mesh.triangles[1], (std::array<std::uint32_t, 3>{2, 1, 3}));  // strip: every other one flipped
  ASSERT_TRUE(mesh.has_colors());
  EXPECT_FLOAT_EQ(mesh.colors[0].x(), 1.0f);  // stored sRGB-encoded, like PLY colours
  ASSERT_EQ(mesh.materials.size(), 1u);
  ASSERT_TRUE(mesh.materials[0].texture_bytes);
  EXPECT_TRUE(mesh.materials[0].texture_times_vertex_colors);
  const TextureSize size = probe_texture(mesh.materials[0]);
  EXPECT_EQ(size.width, 64);
  // Vertex 1 (uv 0, 1) -> transform (0.5, 0.5) -> meshtour's v = 1 - 0.5.
  EXPECT_NEAR((mesh.corner_uvs[1] - Eigen::Vector2f(0.5f, 0.5f)).norm(), 0.0f, 1e-6f);
}

std::string error_of(const std::filesystem::path& file) {
  try {
    load_mesh(file);
  } catch (const Error& e) {
    return e.what();
  }
  return "(loaded)";
}

TEST(MeshGltf, BadFilesGetClearErrors) {
  const auto dir = test::scratch_dir();
  {
    GltfBuilder b = square(false);
    b.write_glb(dir / "truncated.glb", 20);
    EXPECT_NE(error_of(dir / "truncated.glb").find("truncated.glb"), std::string::npos) << error_of(dir / "truncated.glb");
    EXPECT_THROW(check_mesh_file(dir / "truncated.glb"), InputError);
  }
  {
    GltfBuilder b = square();
    b.doc["images"] = {{{"uri", "no such image.png"}}};
    add_textured_material(b, 0);
    b.write_gltf(dir / "missing_image.gltf");
    const std::string e = error_of(dir / "missing_image.gltf");
    EXPECT_NE(e.find("no such image.png"), std::string::npos) << e;
    EXPECT_NE(e.find("'paint'"), std::string::npos) << e;
    LoadReport report;
    EXPECT_NO_THROW(load_mesh(dir / "missing_image.gltf", &report, LoadOptions{.missing_textures_grey = true}));
    EXPECT_EQ(report.warnings.size(), 1u);
  }
  {
    GltfBuilder b = square(false);
    b.doc["extensionsRequired"] = {"KHR_materials_volume", "EXT_fancy"};
    b.write_gltf(dir / "extension.gltf");
    const std::string e = error_of(dir / "extension.gltf");
    EXPECT_NE(e.find("KHR_materials_volume, EXT_fancy"), std::string::npos) << e;
  }
  {
    // gltfpack's output: the geometry's views point into a fallback buffer with no data, which
    // the reader refuses with a complaint about its length. The extension is what to name.
    GltfBuilder b = square(false);
    b.doc["extensionsUsed"] = b.doc["extensionsRequired"] = {"EXT_meshopt_compression"};
    b.doc["buffers"].push_back({{"byteLength", 4096}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}});
    b.doc["bufferViews"][0]["buffer"] = 1;
    b.write_glb(dir / "meshopt.glb");
    const std::string e = error_of(dir / "meshopt.glb");
    EXPECT_NE(e.find("requires the glTF extension EXT_meshopt_compression"), std::string::npos) << e;
  }
  {
    GltfBuilder b = square();
    b.doc["materials"] = nlohmann::json::array();
    b.write_gltf(dir / "material.gltf");
    const std::string e = error_of(dir / "material.gltf");
    EXPECT_NE(e.find("names material 0, but the file has 0"), std::string::npos) << e;
  }
  {
    GltfBuilder b = square(false);
    b.doc["accessors"][2]["count"] = 600;  // indices past the end of their view
    b.write_gltf(dir / "overrun.gltf");
    const std::string e = error_of(dir / "overrun.gltf");
    EXPECT_NE(e.find("reach past the end"), std::string::npos) << e;
  }
  {
    GltfBuilder b = square(false);
    const std::vector<unsigned char> junk = {'D', 'R', 'A', 'C', 'O', 2, 2, 1, 1, 0, 0, 0, 7, 7, 7, 7, 7, 7};
    const int view = b.view(junk.data(), junk.size());
    b.doc["meshes"][0]["primitives"][0]["extensions"] = {{"KHR_draco_mesh_compression", {{"bufferView", view}, {"attributes", {{"POSITION", 0}}}}}};
    b.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
    b.write_glb(dir / "corrupt_draco.glb");
    const std::string e = error_of(dir / "corrupt_draco.glb");
    EXPECT_NE(e.find("corrupt Draco data"), std::string::npos) << e;
  }
}

// A Draco-compressed primitive as exporters write it: the .drc bytes in a buffer view, the
// attributes' unique ids in the extension. draco_encoder (Debian's `draco` package) makes the
// bytes from a PLY; its first attribute (id 0) is the position.
TEST(MeshGltf, DracoPrimitiveDecodesWithinItsQuantization) {
  const auto dir = test::scratch_dir();
  if (std::system("command -v draco_encoder >/dev/null 2>&1") != 0) {
    if (std::getenv("MESHTOUR_REQUIRE_SHARED")) FAIL() << "draco_encoder is not installed (scripts/install-deps.sh)";
    GTEST_SKIP() << "draco_encoder is not installed (Debian package draco); skipping the Draco case";
  }
  TriangleMesh source;
  for (int i = 0; i < 4; ++i) source.positions.emplace_back(i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i == 3 ? 0.5 : 0.0);
  source.triangles = {{0, 1, 2}, {2, 1, 3}};
  save_mesh(source, dir / "quad.ply");
  const std::string command = "draco_encoder -i '" + (dir / "quad.ply").string() + "' -o '" + (dir / "quad.drc").string() +
                              "' -qp 14 >/dev/null 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  const std::vector<unsigned char> drc = test::read_bytes(dir / "quad.drc");
  ASSERT_FALSE(drc.empty());

  GltfBuilder b;
  const int view = b.view(drc.data(), drc.size());
  b.doc["accessors"] = {{{"componentType", 5126}, {"count", 4}, {"type", "VEC3"}, {"min", {-1, -1, 0}}, {"max", {1, 1, 0.5}}},
                        {{"componentType", 5125}, {"count", 6}, {"type", "SCALAR"}}};
  b.doc["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1},
                                       {"extensions", {{"KHR_draco_mesh_compression", {{"bufferView", view}, {"attributes", {{"POSITION", 0}}}}}}}}}}}};
  b.doc["nodes"] = {{{"mesh", 0}}};
  b.doc["extensionsUsed"] = b.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  b.write_glb(dir / "draco.glb");
  EXPECT_EQ(check_mesh_file(dir / "draco.glb").triangles(), 2u);
  const TriangleMesh mesh = load_mesh(dir / "draco.glb");
  ASSERT_EQ(mesh.triangles.size(), 2u);
  // Every source vertex is found within the 14-bit quantization of the 2-unit box.
  for (const auto& p : source.positions) {
    double best = 1e9;
    for (const auto& q : mesh.positions) best = std::min(best, (p - q).norm());
    EXPECT_LT(best, 2.0 / (1 << 13)) << p.transpose();
  }
}

}  // namespace
}  // namespace meshtour
