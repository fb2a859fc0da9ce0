// meshtour info: what a mesh file holds, as text and as JSON, without rendering.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>

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
