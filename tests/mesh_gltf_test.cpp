// glTF 2.0 / GLB input: files written by the test itself (tests/gltf_writer.h), the Draco case
// encoded with Debian's draco_encoder when it is installed, the EXT_meshopt_compression cases with
// libmeshoptimizer's encoders (as gltfpack writes them).
#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <meshoptimizer.h>
#include <OpenImageIO/imagebuf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <numbers>

#include "core/error.h"
#include "gltf_writer.h"
#include "helpers.h"
#include "mesh/mesh.h"
#include "textured_cube.h"

namespace meshtour {
namespace {

using test::GltfBuilder;

// `b` with one mesh of one primitive, in one node of the default scene.
GltfBuilder one_mesh(GltfBuilder b, const nlohmann::json& prim) {
  b.doc["meshes"] = {{{"primitives", {prim}}}};
  b.doc["nodes"] = {{{"mesh", 0}}};
  b.doc["scenes"] = {{{"nodes", {0}}}};
  b.doc["scene"] = 0;
  return b;
}

// A unit square in the XY plane (z = 0) with UVs, as one triangle list; material 0 when
// `material` is set.
GltfBuilder square(bool material = true) {
  GltfBuilder b;
  const int pos = b.floats({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, 3);
  const int uv = b.floats({0, 1, 1, 1, 1, 0, 0, 0}, 2);  // glTF: v runs down the image
  const int idx = b.indices({0, 1, 2, 0, 2, 3});
  nlohmann::json prim = {{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv}}}, {"indices", idx}};
  if (material) prim["material"] = 0;
  return one_mesh(std::move(b), prim);
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
  {  // The check reads no buffer, but finds one that is shorter than the JSON says.
    GltfBuilder cut = b;
    cut.write_gltf(dir / "cut.gltf");
    const std::string bin = "cut.bin";  // the writer's buffer file: the .gltf's name
    std::filesystem::resize_file(dir / bin, std::filesystem::file_size(dir / bin) - 4);
    try {
      check_mesh_file(dir / "cut.gltf");
      ADD_FAILURE() << "a truncated buffer file passed the check";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("buffer 0's file '" + bin + "' holds"), std::string::npos) << e.what();
    }
  }

  const TriangleMesh mesh = load_mesh(dir / "square.gltf");
  ASSERT_EQ(mesh.triangles.size(), 4u);
  ASSERT_EQ(mesh.positions.size(), 8u);
  EXPECT_NEAR((mesh.positions[1] - Eigen::Vector3d(3, 0, 0)).norm(), 0.0, 1e-12);
  // Rotated +90 degrees about y: x goes to -z.
  EXPECT_NEAR((mesh.positions[5] - Eigen::Vector3d(0, 0, -3)).norm(), 0.0, 1e-9);
  ASSERT_EQ(mesh.materials.size(), 1u);
  const MeshMaterial& m = mesh.materials[0];
  EXPECT_EQ(m.name, "paint");
  EXPECT_EQ(m.texture.file, dir / "checker.png");
  EXPECT_EQ(m.texture.wrap_s, TextureWrap::clamp);
  EXPECT_EQ(m.texture.wrap_t, TextureWrap::mirror);
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
  ASSERT_TRUE(mesh.materials[0].texture.bytes);
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

// Two base-colour sources of older and web-optimised exports:
//  * KHR_materials_pbrSpecularGlossiness (older Sketchfab and Blender files): its diffuse factor
//    and texture (with its own KHR_texture_transform) take precedence over pbrMetallicRoughness;
//  * EXT_texture_webp (glTF-Transform's `webp`): the WebP image the texture's extension names is
//    used in place of its PNG source, and a texture with the WebP image alone works too.
TEST(MeshGltf, SpecularGlossinessDiffuseAndWebpTextures) {
  const auto dir = test::scratch_dir();
  {
    GltfBuilder b = square();
    const int image = b.embedded_image(checker_png(dir), "image/png");
    b.doc["textures"] = {{{"source", image}}};
    b.doc["materials"] = {
        {{"name", "old"},
         {"pbrMetallicRoughness", {{"baseColorFactor", {1.0, 0.0, 0.0, 1.0}}}},
         {"extensions",
          {{"KHR_materials_pbrSpecularGlossiness",
            {{"diffuseFactor", {0.25, 0.5, 1.0, 1.0}},
             {"specularFactor", {0.1, 0.1, 0.1}},
             {"diffuseTexture", {{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"scale", {0.5, 0.5}}}}}}}}}}}}}};
    b.doc["extensionsUsed"] = {"KHR_materials_pbrSpecularGlossiness", "KHR_texture_transform"};
    b.doc["extensionsRequired"] = {"KHR_materials_pbrSpecularGlossiness"};
    b.write_glb(dir / "specgloss.glb");
    const TriangleMesh mesh = load_mesh(dir / "specgloss.glb");
    ASSERT_EQ(mesh.materials.size(), 1u);
    ASSERT_TRUE(mesh.materials[0].base_color);
    EXPECT_FLOAT_EQ(mesh.materials[0].base_color->x(), 0.25f);
    EXPECT_FLOAT_EQ(mesh.materials[0].base_color->y(), 0.5f);
    ASSERT_TRUE(mesh.materials[0].texture.bytes);
    EXPECT_EQ(probe_texture(mesh.materials[0]).width, 64);
    // Vertex 1 at glTF uv (1, 1), scaled by 0.5: meshtour's (0.5, 1 - 0.5).
    EXPECT_NEAR((mesh.corner_uvs[1] - Eigen::Vector2f(0.5f, 0.5f)).norm(), 0.0f, 1e-6f);
  }
  // The checker as WebP (lossless, 64 x 64) beside a 4 x 4 PNG fallback.
  OIIO::ImageBuf checker((dir / "checker.png").string());
  ASSERT_TRUE(checker.write((dir / "checker.webp").string())) << checker.geterror();
  OIIO::ImageBuf small(OIIO::ImageSpec(4, 4, 3, OIIO::TypeDesc::UINT8));
  ASSERT_TRUE(small.write((dir / "small.png").string()));
  for (const bool with_fallback : {true, false}) {
    GltfBuilder b = square();
    const int png = b.embedded_image(test::read_bytes(dir / "small.png"), "image/png");
    const int webp = b.embedded_image(test::read_bytes(dir / "checker.webp"), "image/webp");
    nlohmann::json texture = {{"extensions", {{"EXT_texture_webp", {{"source", webp}}}}}};
    if (with_fallback) texture["source"] = png;
    b.doc["textures"] = nlohmann::json::array({texture});
    b.doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
    b.doc["extensionsUsed"] = {"EXT_texture_webp"};
    if (!with_fallback) b.doc["extensionsRequired"] = {"EXT_texture_webp"};
    b.write_glb(dir / "webp.glb");
    const TriangleMesh mesh = load_mesh(dir / "webp.glb");
    ASSERT_EQ(mesh.materials.size(), 1u);
    const TextureSize size = probe_texture(mesh.materials[0]);
    EXPECT_EQ(size.width, 64) << "with a PNG fallback: " << with_fallback;
    EXPECT_EQ(size.height, 64);
    EXPECT_TRUE(mesh.materials[0].texture.file.string().ends_with(".webp"));
  }
  // A .gltf with the WebP image as a data URI (tinygltf decodes only PNG, JPEG, BMP and GIF ones).
  const auto base64 = [](const std::vector<unsigned char>& bytes) {
    static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
      const std::uint32_t n = (std::uint32_t{bytes[i]} << 16) | (i + 1 < bytes.size() ? std::uint32_t{bytes[i + 1]} << 8 : 0u) |
                              (i + 2 < bytes.size() ? std::uint32_t{bytes[i + 2]} : 0u);
      const std::size_t digits_used = std::min<std::size_t>(3, bytes.size() - i) + 1;  // the rest is padding
      for (std::size_t k = 0; k < 4; ++k) out += k < digits_used ? digits[(n >> (18 - 6 * k)) & 63] : '=';
    }
    return out;
  };
  for (const std::string& payload : {base64(test::read_bytes(dir / "checker.webp")), std::string("not*base64")}) {
    GltfBuilder b = square();
    b.doc["images"] = {{{"uri", "data:image/webp;base64," + payload}}};
    b.doc["textures"] = {{{"extensions", {{"EXT_texture_webp", {{"source", 0}}}}}}};
    b.doc["materials"] = {{{"name", "inline"}, {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
    b.doc["extensionsUsed"] = b.doc["extensionsRequired"] = {"EXT_texture_webp"};
    b.write_gltf(dir / "webp_uri.gltf");
    if (payload.starts_with("not")) {
      const std::string e = error_of(dir / "webp_uri.gltf");
      EXPECT_NE(e.find("material 'inline': its image's data URI has a character that is not base64"), std::string::npos) << e;
      continue;
    }
    const TriangleMesh mesh = load_mesh(dir / "webp_uri.gltf");
    ASSERT_EQ(mesh.materials.size(), 1u);
    EXPECT_EQ(probe_texture(mesh.materials[0]).width, 64);
  }
}

// Skinning: a skinned mesh is placed by its joints (global joint matrix x inverse bind matrix,
// blended by the weights), and its own node's transform is not applied. The square's vertices
// 0-3 sit at (0,0,0) (1,0,0) (1,1,0) (0,1,0).
TEST(MeshGltf, SkinnedMeshesArePlacedByTheirJoints) {
  const auto dir = test::scratch_dir();
  // Two joints: node 1 (the armature's bone, posed by `pose`) and node 2 (at rest). Vertex 0 is
  // half on each, the others all on joint `main_joint`.
  const auto skinned = [&](const Eigen::Affine3d& pose, const Eigen::Affine3d& bind, int main_joint) {
    GltfBuilder b = square(false);
    const std::vector<unsigned char> joints = {0, 1, 0, 0, static_cast<unsigned char>(main_joint), 0, 0, 0,
                                               static_cast<unsigned char>(main_joint), 0, 0, 0, static_cast<unsigned char>(main_joint), 0, 0, 0};
    b.doc["accessors"].push_back({{"bufferView", b.view(joints.data(), joints.size())}, {"componentType", 5121}, {"count", 4}, {"type", "VEC4"}});
    const int joint_accessor = static_cast<int>(b.doc["accessors"].size()) - 1;
    const int weights = b.floats({0.5f, 0.5f, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, 4);
    std::vector<float> inverse_bind;
    for (const Eigen::Matrix4d& m : {Eigen::Matrix4d(bind.inverse().matrix()), Eigen::Matrix4d::Identity().eval()})
      for (int k = 0; k < 16; ++k) inverse_bind.push_back(static_cast<float>(m(k % 4, k / 4)));  // column-major
    const int ibm = b.view(inverse_bind.data(), inverse_bind.size() * sizeof(float));
    b.doc["accessors"].push_back({{"bufferView", ibm}, {"componentType", 5126}, {"count", 2}, {"type", "MAT4"}});
    b.doc["meshes"][0]["primitives"][0]["attributes"]["JOINTS_0"] = joint_accessor;
    b.doc["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_0"] = weights;
    std::vector<double> matrix;
    for (int k = 0; k < 16; ++k) matrix.push_back(pose.matrix()(k % 4, k / 4));
    b.doc["nodes"] = {{{"mesh", 0}, {"skin", 0}, {"translation", {100, 0, 0}}},  // ignored: the joints place a skinned mesh
                      {{"matrix", matrix}},
                      {{"name", "rest"}}};
    b.doc["skins"] = {{{"joints", {1, 2}}, {"inverseBindMatrices", static_cast<int>(b.doc["accessors"].size()) - 1}}};
    b.doc["scenes"] = {{{"nodes", {0, 1, 2}}}};
    return b;
  };
  const Eigen::Affine3d bind(Eigen::Translation3d(0, 5, 0));
  const std::array<Eigen::Vector3d, 4> square_at = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(1, 1, 0), Eigen::Vector3d(0, 1, 0)};
  {
    // In its bind pose the skin leaves the mesh where it is: the node's +100 is not applied.
    skinned(bind, bind, 0).write_glb(dir / "bind.glb");
    const TriangleMesh mesh = load_mesh(dir / "bind.glb");
    ASSERT_EQ(mesh.positions.size(), 4u);
    for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR((mesh.positions[i] - square_at[i]).norm(), 0.0, 1e-6) << i;
  }
  {
    // The bone turned 90 degrees about z at its bind place: vertices on it turn about (0, 5, 0);
    // vertex 0, half on the resting joint, lands halfway.
    const Eigen::Affine3d pose = bind * Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ());
    skinned(pose, bind, 0).write_glb(dir / "posed.glb");
    const TriangleMesh mesh = load_mesh(dir / "posed.glb");
    const Eigen::Affine3d moved = pose * bind.inverse();
    for (std::size_t i = 1; i < 4; ++i) EXPECT_NEAR((mesh.positions[i] - moved * square_at[i]).norm(), 0.0, 1e-6) << i;
    EXPECT_NEAR((mesh.positions[0] - 0.5 * (moved * square_at[0] + square_at[0])).norm(), 0.0, 1e-6);
    // The same file through Debian's draco_transcoder: the joints and weights come out of the
    // Draco data, the vertices land within its quantization.
    if (std::system("command -v draco_transcoder >/dev/null 2>&1") == 0) {
      const std::string command = "draco_transcoder -i '" + (dir / "posed.glb").string() + "' -o '" + (dir / "posed_draco.glb").string() + "' >/dev/null 2>&1";
      ASSERT_EQ(std::system(command.c_str()), 0) << command;
      const TriangleMesh draco = load_mesh(dir / "posed_draco.glb");
      ASSERT_EQ(draco.positions.size(), 4u);
      for (const auto& p : mesh.positions) {
        double best = 1e9;
        for (const auto& q : draco.positions) best = std::min(best, (p - q).norm());
        EXPECT_LT(best, 1e-3) << p.transpose();
      }
    } else if (std::getenv("MESHTOUR_REQUIRE_SHARED")) {
      FAIL() << "draco_transcoder is not installed (scripts/install-deps.sh --tests)";
    }
  }
  {
    GltfBuilder b = skinned(bind, bind, 7);  // joint 7 of a two-joint skin
    b.write_glb(dir / "bad_joint.glb");
    const std::string e = error_of(dir / "bad_joint.glb");
    EXPECT_NE(e.find("vertex 1 names joint 7, but its skin has 2"), std::string::npos) << e;
    b = skinned(bind, bind, 0);
    b.doc["meshes"][0]["primitives"][0]["attributes"].erase("WEIGHTS_0");
    b.write_glb(dir / "no_weights.glb");
    EXPECT_NE(error_of(dir / "no_weights.glb").find("has no JOINTS_0 and WEIGHTS_0"), std::string::npos) << error_of(dir / "no_weights.glb");
  }
}

// EXT_mesh_gpu_instancing: the node's mesh once per instance (TRANSLATION, ROTATION, SCALE under
// the node's transform). KHR_lights_punctual, even when required, only adds lights, which the
// look replaces: the model loads, with a warning saying so.
TEST(MeshGltf, GpuInstancesAndIgnoredLights) {
  const auto dir = test::scratch_dir();
  GltfBuilder b = square(false);
  const int translation = b.floats({0, 0, 0, 5, 0, 0}, 3);
  const int rotation = b.floats({0, 0, 0, 1, 0, 0, 0.7071067811865476f, 0.7071067811865476f}, 4);  // none; 90 degrees about z
  const int scale = b.floats({1, 1, 1, 2, 2, 2}, 3);
  b.doc["nodes"][0]["translation"] = {0, 10, 0};
  b.doc["nodes"][0]["extensions"] = {
      {"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", translation}, {"ROTATION", rotation}, {"SCALE", scale}}}}},
      {"KHR_lights_punctual", {{"light", 0}}}};
  b.doc["extensions"] = {{"KHR_lights_punctual", {{"lights", {{{"type", "point"}, {"intensity", 10}}}}}}};
  b.doc["extensionsUsed"] = b.doc["extensionsRequired"] = {"EXT_mesh_gpu_instancing", "KHR_lights_punctual"};
  b.write_glb(dir / "instances.glb");
  LoadReport report;
  const TriangleMesh mesh = load_mesh(dir / "instances.glb", &report);
  ASSERT_EQ(mesh.triangles.size(), 4u);
  ASSERT_EQ(mesh.positions.size(), 8u);
  // Instance 0: the square moved up by the node; instance 1: turned 90 degrees, doubled, at x = 5.
  EXPECT_NEAR((mesh.positions[2] - Eigen::Vector3d(1, 11, 0)).norm(), 0.0, 1e-6);
  EXPECT_NEAR((mesh.positions[4 + 1] - Eigen::Vector3d(5, 12, 0)).norm(), 0.0, 1e-6);  // (1,0,0) -> (0,2,0) + (5,10,0)
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_NE(report.warnings[0].find("KHR_lights_punctual"), std::string::npos) << report.warnings[0];
  // A second node drawing the same mesh, mirrored in x, after the instanced one: the primitive is
  // decoded once and serves all three draws, and the mirrored copy's triangles are turned so that
  // they still face +z (the square's side).
  {
    GltfBuilder shared = b;
    shared.doc["nodes"].push_back({{"mesh", 0}, {"scale", {-1, 1, 1}}, {"translation", {0, 0, 3}}});
    shared.doc["scenes"][0]["nodes"].push_back(1);
    shared.write_glb(dir / "shared.glb");
    const TriangleMesh three = load_mesh(dir / "shared.glb");
    ASSERT_EQ(three.triangles.size(), 6u);
    // The check counts the same draws from the JSON alone (two GPU instances, one node).
    const MeshFileSummary counted = check_mesh_file(dir / "shared.glb");
    EXPECT_EQ(counted.triangles(), 6u);
    EXPECT_EQ(counted.vertices, 12u);
    for (const auto& t : three.triangles) {
      const Eigen::Vector3d n = (three.positions[t[1]] - three.positions[t[0]]).cross(three.positions[t[2]] - three.positions[t[0]]);
      EXPECT_GT(n.z(), 0.0);
    }
    EXPECT_NEAR(three.bounds().lo.x(), -1.0, 1e-6);  // the mirrored copy spans x in [-1, 0] at z = 3
    EXPECT_NEAR(three.bounds().hi.z(), 3.0, 1e-6);
  }

  b.doc["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["SCALE"] = b.floats({1, 1, 1}, 3);  // one, for two instances
  b.write_glb(dir / "uneven.glb");
  const std::string e = error_of(dir / "uneven.glb");
  EXPECT_NE(e.find("EXT_mesh_gpu_instancing: its attributes differ in count"), std::string::npos) << e;
  // Two million instances from an accessor with no data (zeros): refused before it is read.
  b.doc["accessors"].push_back({{"componentType", 5126}, {"count", 2'000'000}, {"type", "VEC3"}});
  b.doc["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"] = {{"TRANSLATION", b.doc["accessors"].size() - 1}};
  b.write_glb(dir / "bomb.glb");
  const std::string bomb = error_of(dir / "bomb.glb");
  EXPECT_NE(bomb.find("announces 2000000 instances; meshtour draws at most 1000000"), std::string::npos) << bomb;
}

// A wavy height field of n x n vertices: positions and a triangle list.
struct Grid {
  std::vector<float> positions;
  std::vector<std::uint32_t> indices;
};
Grid wavy_grid(int n) {
  Grid g;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const float x = static_cast<float>(i) / (n - 1), z = static_cast<float>(j) / (n - 1);
      g.positions.insert(g.positions.end(), {x, 0.1f * std::sin(7.0f * x) * std::cos(5.0f * z), z});
    }
  for (int i = 0; i + 1 < n; ++i)
    for (int j = 0; j + 1 < n; ++j) {
      const auto v = static_cast<std::uint32_t>(i * n + j), n32 = static_cast<std::uint32_t>(n);
      g.indices.insert(g.indices.end(), {v, v + 1, v + n32, v + 1, v + n32 + 1, v + n32});
    }
  return g;
}

GltfBuilder plain_grid(const Grid& g) {
  GltfBuilder b;
  const int pos = b.floats(g.positions, 3);
  const int idx = b.indices(g.indices);
  return one_mesh(std::move(b), {{"attributes", {{"POSITION", pos}}}, {"indices", idx}});
}

// gltfpack's layout: the compressed bytes in buffer 0 (the GLB's), the views in buffer 1, a
// fallback with no data, which the decoder fills. `exponential`: positions through the
// EXPONENTIAL filter (15-bit mantissas), as gltfpack -vpf writes them.
GltfBuilder meshopt_grid(const Grid& g, bool exponential = false) {
  GltfBuilder b;
  const std::size_t vertices = g.positions.size() / 3, indices = g.indices.size();
  std::vector<unsigned char> raw(vertices * 12);
  if (exponential) meshopt_encodeFilterExp(raw.data(), vertices, 12, 15, g.positions.data());
  else std::memcpy(raw.data(), g.positions.data(), raw.size());
  std::vector<unsigned char> packed_vertices(meshopt_encodeVertexBufferBound(vertices, 12));
  packed_vertices.resize(meshopt_encodeVertexBuffer(packed_vertices.data(), packed_vertices.size(), raw.data(), vertices, 12));
  std::vector<unsigned char> packed_indices(meshopt_encodeIndexBufferBound(indices, vertices));
  packed_indices.resize(meshopt_encodeIndexBuffer(packed_indices.data(), packed_indices.size(), g.indices.data(), indices));
  const auto put = [&b](const std::vector<unsigned char>& bytes) {
    while (b.bin.size() % 4) b.bin.push_back(0);
    const std::size_t at = b.bin.size();
    b.bin.insert(b.bin.end(), bytes.begin(), bytes.end());
    return at;
  };
  const std::size_t at_vertices = put(packed_vertices), at_indices = put(packed_indices);
  nlohmann::json vertex_ext = {{"buffer", 0}, {"byteOffset", at_vertices}, {"byteLength", packed_vertices.size()}, {"byteStride", 12},
                               {"count", vertices}, {"mode", "ATTRIBUTES"}};
  if (exponential) vertex_ext["filter"] = "EXPONENTIAL";
  b.doc["bufferViews"] = {
      {{"buffer", 1}, {"byteOffset", 0}, {"byteLength", vertices * 12}, {"byteStride", 12}, {"extensions", {{"EXT_meshopt_compression", vertex_ext}}}},
      {{"buffer", 1},
       {"byteOffset", vertices * 12},
       {"byteLength", indices * 4},
       {"extensions",
        {{"EXT_meshopt_compression",
          {{"buffer", 0}, {"byteOffset", at_indices}, {"byteLength", packed_indices.size()}, {"byteStride", 4}, {"count", indices}, {"mode", "TRIANGLES"}}}}}}};
  std::vector<float> lo(3, 1e30f), hi(3, -1e30f);
  for (std::size_t i = 0; i < g.positions.size(); ++i) lo[i % 3] = std::min(lo[i % 3], g.positions[i]), hi[i % 3] = std::max(hi[i % 3], g.positions[i]);
  b.doc["accessors"] = {{{"bufferView", 0}, {"componentType", 5126}, {"count", vertices}, {"type", "VEC3"}, {"min", lo}, {"max", hi}},
                        {{"bufferView", 1}, {"componentType", 5125}, {"count", indices}, {"type", "SCALAR"}}};
  b.doc["buffers"] = {nlohmann::json::object(),
                      {{"byteLength", vertices * 12 + indices * 4}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}}};
  b.doc["extensionsUsed"] = b.doc["extensionsRequired"] = {"EXT_meshopt_compression"};
  return one_mesh(std::move(b), {{"attributes", {{"POSITION", 0}}}, {"indices", 1}});
}

// EXT_meshopt_compression (gltfpack's and glTF-Transform's output): the decoded views give the
// same model as the uncompressed file, bit for bit, as GLB and as .gltf with an external .bin;
// through the EXPONENTIAL filter, within its 15-bit mantissa.
TEST(MeshGltf, MeshoptCompressedViewsDecodeToTheSameModel) {
  const auto dir = test::scratch_dir();
  const Grid grid = wavy_grid(40);
  plain_grid(grid).write_glb(dir / "plain.glb");
  const TriangleMesh reference = load_mesh(dir / "plain.glb");
  ASSERT_EQ(reference.triangles.size(), grid.indices.size() / 3);
  meshopt_grid(grid).write_glb(dir / "meshopt.glb");
  meshopt_grid(grid).write_gltf(dir / "meshopt.gltf");
  // The index codec may start a triangle at another corner (same winding): compare each
  // triangle from its smallest index.
  const auto canonical = [](std::vector<std::array<std::uint32_t, 3>> triangles) {
    for (auto& t : triangles) std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    return triangles;
  };
  for (const char* file : {"meshopt.glb", "meshopt.gltf"}) {
    const TriangleMesh mesh = load_mesh(dir / file);
    EXPECT_EQ(canonical(mesh.triangles), canonical(reference.triangles)) << file;
    EXPECT_EQ(mesh.positions, reference.positions) << file;
  }
  meshopt_grid(grid, true).write_glb(dir / "meshopt_exp.glb");
  const TriangleMesh filtered = load_mesh(dir / "meshopt_exp.glb");
  EXPECT_EQ(canonical(filtered.triangles), canonical(reference.triangles));
  ASSERT_EQ(filtered.positions.size(), reference.positions.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < filtered.positions.size(); ++i) worst = std::max(worst, (filtered.positions[i] - reference.positions[i]).norm());
  EXPECT_LT(worst, 1e-4) << "positions through the EXPONENTIAL filter";
  EXPECT_GT(worst, 0.0) << "the filter is lossy: a zero error would mean the filter was not applied";
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
    // A buffer URI naming a folder (found by fuzz_gltf: a malformed URI decodes to the model's
    // own folder): refused as a missing file, not read with the size a directory reports.
    std::filesystem::create_directories(dir / "a folder");
    GltfBuilder b = square(false);
    b.write_gltf(dir / "folder_buffer.gltf");
    nlohmann::json doc = nlohmann::json::parse(std::ifstream(dir / "folder_buffer.gltf"));
    for (const char* uri : {"a%20folder", "."}) {
      doc["buffers"][0]["uri"] = uri;
      std::ofstream(dir / "folder_buffer.gltf") << doc.dump();
      const std::string e = error_of(dir / "folder_buffer.gltf");
      EXPECT_NE(e.find("File not found"), std::string::npos) << uri << ": " << e;
    }
  }
  {
    // Indices stored as floats (found by fuzz_gltf): refused, not converted to vertex numbers.
    GltfBuilder b = square(false);
    b.doc["accessors"][2]["componentType"] = 5126;
    b.write_gltf(dir / "float_indices.gltf");
    const std::string e = error_of(dir / "float_indices.gltf");
    EXPECT_NE(e.find("have component type 5126; glTF indices are unsigned"), std::string::npos) << e;
  }
  {
    GltfBuilder b = square(false);
    b.doc["extensionsRequired"] = {"KHR_materials_volume", "EXT_fancy"};
    b.write_gltf(dir / "extension.gltf");
    const std::string e = error_of(dir / "extension.gltf");
    EXPECT_NE(e.find("KHR_materials_volume, EXT_fancy"), std::string::npos) << e;
  }
  {
    // A view in an EXT_meshopt_compression fallback buffer (no data of its own) that has no
    // compressed data: it would read zeros.
    GltfBuilder b = square(false);
    b.doc["extensionsUsed"] = b.doc["extensionsRequired"] = {"EXT_meshopt_compression"};
    b.doc["buffers"] = {nlohmann::json::object(), {{"byteLength", 4096}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}}};
    b.doc["bufferViews"][0]["buffer"] = 1;
    b.write_glb(dir / "meshopt.glb");
    const std::string e = error_of(dir / "meshopt.glb");
    EXPECT_NE(e.find("buffer view 0 lies in buffer 1, an EXT_meshopt_compression fallback"), std::string::npos) << e;
  }
  {
    // Corrupt or impossible EXT_meshopt_compression views: each named, none handed to the decoder
    // with values it would assert on.
    const Grid grid = wavy_grid(8);
    struct Case {
      const char* file;
      std::function<void(GltfBuilder&)> damage;
      const char* says;
    };
    const std::vector<Case> cases = {
        {"meshopt_corrupt.glb", [](GltfBuilder& b) { std::fill(b.bin.begin(), b.bin.begin() + 16, static_cast<unsigned char>(0xFF)); },
         "compressed data is corrupt"},
        {"meshopt_stride.glb", [](GltfBuilder& b) { b.doc["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["byteStride"] = 6; },
         "byteStride 6 is not valid for mode ATTRIBUTES"},
        {"meshopt_triangles.glb", [](GltfBuilder& b) { b.doc["bufferViews"][1]["extensions"]["EXT_meshopt_compression"]["count"] = 7; },
         "not a multiple of 3"},
        {"meshopt_outside.glb", [](GltfBuilder& b) { b.doc["bufferViews"][1]["extensions"]["EXT_meshopt_compression"]["byteOffset"] = 1 << 30; },
         "lie outside buffer 0"},
        {"meshopt_huge.glb", [](GltfBuilder& b) { b.doc["buffers"][1]["byteLength"] = std::uint64_t{1} << 40; }, "far more than its"},
        {"meshopt_filter.glb", [](GltfBuilder& b) { b.doc["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["filter"] = "QUATERNION"; },
         "filter 'QUATERNION'"},
        {"meshopt_count.glb", [](GltfBuilder& b) { b.doc["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["count"] = -3; },
         "count is not a non-negative whole number"},
    };
    meshopt_grid(grid).write_glb(dir / "meshopt_valid.glb");  // undamaged, it loads
    EXPECT_EQ(load_mesh(dir / "meshopt_valid.glb").triangles.size(), 98u);
    for (const Case& c : cases) {
      GltfBuilder b = meshopt_grid(grid);
      c.damage(b);
      b.write_glb(dir / c.file);
      const std::string e = error_of(dir / c.file);
      EXPECT_NE(e.find(c.says), std::string::npos) << c.file << ": " << e;
      EXPECT_NE(e.find(c.file), std::string::npos) << e;
    }
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
    if (std::getenv("MESHTOUR_REQUIRE_SHARED")) FAIL() << "draco_encoder is not installed (scripts/install-deps.sh --tests)";
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
