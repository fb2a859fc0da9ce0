// meshtour info: what a mesh file holds, as text and as JSON, without rendering.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <fstream>
#include <vector>

#include "gltf_writer.h"
#include "helpers.h"
#include "textured_cube.h"

namespace meshtour {
namespace {

TEST(InfoCommand, JsonReportsCountsTopologyMaterialsAndMemory) {
  const auto dir = test::scratch_dir();
  const auto cube = test::write_textured_cube(dir);
  // A second, open part: one triangle (3 boundary edges, a second component).
  std::ofstream(cube, std::ios::app) << "v 5 0 0\nv 6 0 0\nv 5 1 0\nf 9/1 10/2 11/3\n";
  const auto r = test::run_meshtour("info '" + cube.string() + "' --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output.substr(r.output.find('{')));
  EXPECT_EQ(j["triangles"], 13);
  EXPECT_EQ(j["components"], 2);
  EXPECT_EQ(j["boundary_edges"], 3);
  EXPECT_EQ(j["texture_coordinates"], true);
  ASSERT_EQ(j["materials"].size(), 1u);
  EXPECT_EQ(j["materials"][0]["texture_size"][0], 64);
  EXPECT_GT(j["memory_estimate_bytes"]["peak"].get<double>(), 1e8);
  // The up-axis rule (mesh/up_axis.h): the triangle off the cube's +x side makes the hull a wedge
  // whose only whole, low-centred rest is the cube's -x face, so +x is up.
  EXPECT_EQ(j["up_axis"]["auto"], "+x") << j["up_axis"];
  EXPECT_EQ(j["up_axis"]["confident"], true);
  EXPECT_NE(j["up_axis"]["reason"].get<std::string>().find("rests on its -x side"), std::string::npos) << j["up_axis"];
}

// A tower on a wide plinth as a GLB, with the plinth under -`up` (mesh/up_axis.h: glTF is +y up
// by its specification; --up auto keeps that unless the shape clearly disagrees, then warns).
void write_plinth_glb(const std::filesystem::path& file, int up) {  // up: 1 (y) or 2 (z)
  std::vector<float> positions;
  std::vector<std::uint32_t> indices;
  const auto box = [&](std::array<float, 3> lo, std::array<float, 3> hi) {
    const auto base = static_cast<std::uint32_t>(positions.size() / 3);
    for (int i = 0; i < 8; ++i) {
      const std::array<float, 3> p{i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1], i & 4 ? hi[2] : lo[2]};
      // Built y-up; for up = 2 turned a quarter about x (y goes to z), a rotation, so the
      // triangles keep facing out.
      const std::array<float, 3> q = up == 2 ? std::array<float, 3>{p[0], -p[2], p[1]} : p;
      positions.insert(positions.end(), q.begin(), q.end());
    }
    const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& f : quads)
      for (const int k : {0, 1, 2, 0, 2, 3}) indices.push_back(base + static_cast<std::uint32_t>(f[k]));
  };
  box({-1.0f, 0.0f, -1.0f}, {1.0f, 0.3f, 1.0f});
  box({-0.4f, 0.3f, -0.4f}, {0.4f, 2.0f, 0.4f});
  test::GltfBuilder b;
  const int position_accessor = b.floats(positions, 3);
  const int index_accessor = b.indices(indices);
  const nlohmann::json primitive = {{"attributes", {{"POSITION", position_accessor}}}, {"indices", index_accessor}};
  b.doc["meshes"] = {{{"primitives", {primitive}}}};
  b.doc["nodes"] = {{{"mesh", 0}}};
  b.doc["scenes"] = {{{"nodes", {0}}}};
  b.doc["scene"] = 0;
  b.write_glb(file);
}

// An OBJ's MTL statements, as the renderer will take them (docs/FORMATS.md, OBJ materials).
TEST(InfoCommand, ShowsWhatAnObjMaterialBecame) {
  const auto dir = test::scratch_dir();
  std::ofstream(dir / "two.mtl") << "newmtl red\nKd 0.8 0.1 0.1\nNs 250\nKs 0.5 0.5 0.5\nnewmtl glass\nKd 0.2 0.4 0.9\nd 0.4\n";
  std::ofstream(dir / "two.obj") << "mtllib two.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nusemtl red\nf 1 2 3\nusemtl glass\nf 1 3 4\n";
  auto r = test::run_meshtour("info '" + (dir / "two.obj").string() + "' --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output.substr(r.output.find('{')));
  ASSERT_EQ(j["materials"].size(), 2u);
  EXPECT_NEAR(j["materials"][0]["base_color"][1].get<double>(), 0.1, 1e-6);
  EXPECT_NEAR(j["materials"][0]["roughness"].get<double>(), 0.5, 1e-6);
  EXPECT_FALSE(j["materials"][0].contains("alpha_mode"));
  EXPECT_EQ(j["materials"][1]["alpha_mode"], "blend");
  EXPECT_NEAR(j["materials"][1]["alpha"].get<double>(), 0.4, 1e-6);
  r = test::run_meshtour("info '" + (dir / "two.obj").string() + "'");
  EXPECT_NE(r.output.find("material 'red': 1 triangles, colour (0.8 0.1 0.1), metallic 0, roughness 0.5"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("material 'glass': 1 triangles, colour (0.2 0.4 0.9), blend, alpha 0.4"), std::string::npos) << r.output;
}

TEST(InfoCommand, GltfKeepsItsUpUnlessTheShapeClearlyDisagrees) {
  const auto dir = test::scratch_dir();
  write_plinth_glb(dir / "upright.glb", 1);
  write_plinth_glb(dir / "z_up.glb", 2);  // exported z-up: the spec says +y, the plinth says +z
  auto r = test::run_meshtour("info '" + (dir / "upright.glb").string() + "' --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  auto j = nlohmann::json::parse(r.output.substr(r.output.find('{')));
  EXPECT_EQ(j["up_axis"]["auto"], "+y") << j["up_axis"];
  EXPECT_FALSE(j["up_axis"].contains("warning")) << j["up_axis"];
  r = test::run_meshtour("info '" + (dir / "z_up.glb").string() + "' --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  j = nlohmann::json::parse(r.output.substr(r.output.find('{')));
  EXPECT_EQ(j["up_axis"]["auto"], "+z") << j["up_axis"];
  ASSERT_TRUE(j["up_axis"].contains("warning")) << j["up_axis"];
  EXPECT_NE(j["up_axis"]["warning"].get<std::string>().find("glTF"), std::string::npos) << j["up_axis"];
  r = test::run_meshtour("info '" + (dir / "z_up.glb").string() + "'");
  EXPECT_NE(r.output.find("warning: z_up.glb is glTF"), std::string::npos) << r.output;
}

TEST(InfoCommand, MissingTextureIsAWarningAndAMissingFileAnError) {
  const auto dir = test::scratch_dir();
  const auto cube = test::write_textured_cube(dir);
  std::filesystem::remove(dir / "checker.png");
  auto r = test::run_meshtour("info '" + cube.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warning:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("checker.png"), std::string::npos) << r.output;
  r = test::run_meshtour("info '" + (dir / "nothing.glb").string() + "'");
  EXPECT_EQ(r.exit_code, 3) << r.output;
}

}  // namespace
}  // namespace meshtour
