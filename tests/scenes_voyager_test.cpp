// Voyager scene documents (scenes/voyager.h), written here from the SVX schema: the model's pose
// and units, the derivative of the highest quality on disk or the one asked for, the opening
// view's direction as Voyager composes it, the collection title, and errors that name the key.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <set>
#include <string>

#include "core/error.h"
#include "helpers.h"
#include "scenes/scene.h"
#include "scenes/scene_options.h"
#include "scenes/voyager.h"

// A namespace of its own: the unity build puts this file beside the scene-file tests.
namespace meshtour::voyager_test {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// A document for one model stored Z-up in millimetres, in a centimetre scene: the model's
// rotation (-90 degrees about x) stands it up in Voyager's Y-up world. `derivatives`, `orbit`
// and `extra` replace their parts.
std::string document(const std::string& derivatives = "", const std::string& orbit = R"("orbit": [-20, 30, 0], "offset": [0, 0, 150])",
                     const std::string& meta = R"("metas": [{"collection": {"title": "Bronze bell"}}],)") {
  const std::string d = !derivatives.empty() ? derivatives : R"([
      {"usage": "Web3D", "quality": "Low", "assets": [{"uri": "bell-low.glb", "type": "Model"}]},
      {"usage": "Web3D", "quality": "High", "assets": [{"uri": "bell-high.glb", "type": "Model"}, {"uri": "t.jpg", "type": "Texture"}]},
      {"usage": "Web3D", "quality": "Highest", "assets": [{"uri": "bell-highest.glb", "type": "Model"}]},
      {"usage": "App3D", "quality": "Highest", "assets": [{"uri": "bell-app.glb", "type": "Model"}]},
      {"usage": "Web3D", "quality": "AR", "assets": [{"uri": "bell-ar.glb", "type": "Model"}]}])";
  return R"({"asset": {"type": "application/si-dpo-3d.document+json", "version": "1.0"},
    "scene": 0, "scenes": [{"nodes": [0, 1], "setup": 0}],
    "nodes": [{"name": "Camera", "camera": 0}, {"name": "Bell", "model": 0, "meta": 0}],
    "cameras": [{"type": "perspective", "perspective": {"yfov": 52, "znear": 0.1}}],
    "setups": [{"units": "cm", "navigation": {"type": "Orbit", "orbit": {)" +
         orbit + R"(}}}],
    )" + meta + R"(
    "models": [{"units": "mm", "rotation": [-0.70710678, 0, 0, 0.70710678], "translation": [0, 0, -50],
                "derivatives": )" + d + R"(}]})";
}

// `text` with its first `from` replaced by `to`.
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// Files on disk, by name.
auto on_disk(std::set<std::string> names) {
  return [names](const std::filesystem::path& p) { return names.contains(p.filename().string()); };
}

std::string parse_error(const std::string& json, std::string_view quality = "") {
  try {
    (void)parse_voyager_document(json, "bell.svx.json", "/scans", quality, on_disk({"bell-low.glb", "bell-high.glb", "bell-ar.glb"}));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(VoyagerDocument, StandsTheModelUpInTheScenesUnits) {
  const VoyagerDocument doc = parse_voyager_document(document(), "bell.svx.json", "/scans", "", on_disk({"bell-low.glb"}));
  EXPECT_EQ(doc.model_units, "mm");
  EXPECT_EQ(doc.scene_units, "cm");
  // The model's +z (its height, 300 mm) becomes the world's +y, in centimetres.
  const Eigen::Vector4d top = doc.transform * Eigen::Vector4d(0, 0, 300, 1);
  const Eigen::Vector4d base = doc.transform * Eigen::Vector4d(0, 0, 0, 1);
  EXPECT_NEAR(top.y() - base.y(), 30.0, 1e-6);
  EXPECT_NEAR(top.x() - base.x(), 0.0, 1e-6);
  EXPECT_NEAR(top.z() - base.z(), 0.0, 1e-6);
  // The translation (in model units) is applied after the rotation, scaled to the scene's units.
  EXPECT_NEAR(base.z(), -5.0, 1e-6);
}

TEST(VoyagerDocument, ChoosesTheHighestWeb3DDerivativeOnDisk) {
  // Highest is listed but not on disk; App3D is another usage; AR only when asked for.
  const VoyagerDocument doc =
      parse_voyager_document(document(), "bell.svx.json", "/scans", "", on_disk({"bell-low.glb", "bell-high.glb", "bell-ar.glb", "bell-app.glb"}));
  EXPECT_EQ(doc.quality, "High");
  EXPECT_EQ(doc.model_file, std::filesystem::path("/scans/bell-high.glb"));
  const VoyagerDocument all = parse_voyager_document(document(), "bell.svx.json", "/scans", "",
                                                     on_disk({"bell-low.glb", "bell-high.glb", "bell-highest.glb"}));
  EXPECT_EQ(all.quality, "Highest");
}

TEST(VoyagerDocument, QualityChoosesTheDerivative) {
  const auto disk = on_disk({"bell-low.glb", "bell-high.glb", "bell-ar.glb"});
  EXPECT_EQ(parse_voyager_document(document(), "bell.svx.json", "/scans", "low", disk).model_file, std::filesystem::path("/scans/bell-low.glb"));
  EXPECT_EQ(parse_voyager_document(document(), "bell.svx.json", "/scans", "AR", disk).quality, "AR");
  // Listed but not on disk: the message names the file; not listed: says what is.
  EXPECT_NE(parse_error(document(), "Highest").find("bell-highest.glb"), std::string::npos) << parse_error(document(), "Highest");
  EXPECT_NE(parse_error(document(), "Medium").find("no Web3D derivative of quality Medium"), std::string::npos);
  EXPECT_NE(parse_error(document(), "best").find("--quality best"), std::string::npos);
}

TEST(VoyagerDocument, OpeningViewAsVoyagerComposesIt) {
  const VoyagerDocument doc = parse_voyager_document(document(), "bell.svx.json", "/scans", "", on_disk({"bell-low.glb"}));
  const Eigen::Vector3d d = doc.view_direction();
  // Pitch -20 looks down from 20 degrees above; head 30 turns the eye from +z towards +x.
  EXPECT_NEAR(std::asin(d.y()) / kDeg, 20.0, 1e-9);
  EXPECT_NEAR(std::atan2(d.x(), d.z()) / kDeg, 30.0, 1e-9);
  EXPECT_TRUE(doc.orbit_given);
  // No orbit: Voyager's own default (-25, -25, 0), said.
  const std::string plain = replaced(document(), R"(, "orbit": {"orbit": [-20, 30, 0], "offset": [0, 0, 150]})", "");
  const VoyagerDocument none = parse_voyager_document(plain, "bell.svx.json", "/scans", "", on_disk({"bell-low.glb"}));
  EXPECT_FALSE(none.orbit_given);
  EXPECT_NEAR(std::asin(none.view_direction().y()) / kDeg, 25.0, 1e-9);
}

TEST(VoyagerDocument, TitleFromTheCollection) {
  EXPECT_EQ(parse_voyager_document(document(), "b.svx.json", "/scans", "", on_disk({"bell-low.glb"})).title, "Bronze bell");
  const std::string titles = document("", R"("orbit": [0, 0, 0])", R"("metas": [{"collection": {"titles": {"DE": "Glocke", "EN": "Bell"}}}],)");
  EXPECT_EQ(parse_voyager_document(titles, "b.svx.json", "/scans", "", on_disk({"bell-low.glb"})).title, "Bell");
  const std::string none = document("", R"("orbit": [0, 0, 0])", "");
  EXPECT_NE(parse_error(none).find("metas"), std::string::npos);  // the node's meta refers to a missing array
}

TEST(VoyagerDocument, ErrorsNameTheKey) {
  const auto expect = [](const std::string& json, const std::string& words) {
    const std::string e = parse_error(json);
    EXPECT_NE(e.find(words), std::string::npos) << "'" << words << "' not in: " << e;
    EXPECT_NE(e.find("bell.svx.json"), std::string::npos) << e;
  };
  expect(document("", R"("orbit": [-20, 30], "offset": [0, 0, 1])"), "'setups[0].navigation.orbit.orbit' must be an array of 3 numbers");
  expect(document("", R"("orbit": [-20, "up", 0])"), "'setups[0].navigation.orbit.orbit' must be an array of 3 numbers");
  expect(document("", R"("orbit": [0, 0, 0], "offset": [1, 2])"), "'setups[0].navigation.orbit.offset' must be an array of 3 numbers");
  expect(document(R"([{"usage": "Web3D", "quality": "Best", "assets": []}])"), "'models[0].derivatives[0].quality' must be one of");
  expect(document(R"([{"usage": "Web3D", "quality": "High", "assets": [{"uri": "", "type": "Model"}]}])"),
         "'models[0].derivatives[0].assets[0].uri' must name");
  expect(document(R"([{"usage": "Web3D", "quality": "High", "assets": [{"uri": "https://3d-api.si.edu/x.glb", "type": "Model"}]}])"),
         "is a URL");
  expect(document(R"([{"usage": "Image2D", "quality": "High", "assets": [{"uri": "x.jpg", "type": "Image"}]}])"),
         "'models[0].derivatives' has no Web3D derivative");
  expect(document(R"([{"usage": "Web3D", "quality": "Highest", "assets": [{"uri": "gone.glb", "type": "Model"}]}])"),
         "no Web3D derivative's model is on disk (looked for Highest (/scans/gone.glb))");
  expect(replaced(document(), R"("units": "mm")", R"("units": "furlong")"), "'models[0].units' must be one of");
  expect(replaced(document(), R"("units": "mm", )", ""), "'models[0].units' is missing");
  expect(replaced(document(), "[-0.70710678, 0, 0, 0.70710678]", "[0, 0, 0]"), "'models[0].rotation' must be an array of 4 numbers");
  expect(replaced(document(), R"({"name": "Camera", "camera": 0})", R"({"name": "Camera", "children": [0]})"),
         "'nodes[0].children[0]' names node 0, which is already in the scene's tree");
  expect(replaced(document(), R"("model": 0,)", R"("model": 3,)"), "'nodes[1].model' must be between 0 and 0, got 3");
  expect(replaced(document(), R"("model": 0,)", ""), "'scenes[0]' has no node with a model");
  expect(replaced(document(), R"("units": "cm")", R"("units": 3)"), "'setups[0].units' must be a string");
  expect(R"({"asset": {"type": "model/gltf+json"}, "scene": 0, "scenes": []})", "'asset.type' must be \"application/si-dpo-3d.document+json\"");
  expect(R"({"asset": {"type": "application/si-dpo-3d.document+json"}, "scene": 0})", "'scenes' is missing");
  expect("[1, 2]", "must be a JSON object");
  expect("{\"asset\": ", "not valid JSON");
}

// resolve_scene: a .svx.json input is a Voyager scene, and --quality (a registry row) reaches it.
TEST(VoyagerDocument, ResolvesAsATourScene) {
  const auto dir = test::scratch_dir();
  std::ofstream(dir / "bell-low.glb") << "x";
  std::ofstream(dir / "bell-high.glb") << "x";
  std::ofstream(dir / "bell.svx.json") << document();
  const Scene scene = resolve_scene((dir / "bell.svx.json").string(), {});
  EXPECT_EQ(scene.mesh_file->filename(), "bell-high.glb");
  EXPECT_EQ(scene.up, (Axis{1, false}));
  EXPECT_FALSE(scene.up_auto);
  ASSERT_TRUE(scene.opening_view && scene.model_transform);
  EXPECT_EQ(scene.title, "Bronze bell");
  EXPECT_EQ(resolve_scene((dir / "bell.svx.json").string(), {{"quality", "low"}}).mesh_file->filename(), "bell-low.glb");
  // A scene file may name the document as its model.
  std::ofstream(dir / "tour.json") << R"({"format": "meshtour-scene/1", "model": {"file": "bell.svx.json"}, "quality": "low"})";
  EXPECT_EQ(resolve_scene((dir / "tour.json").string(), {}).mesh_file->filename(), "bell-low.glb");
}

// Without --up, a mesh file's up is chosen by its shape (issue 37); given, it is kept.
TEST(UpDefault, MeshFilesDefaultToUpByShape) {
  const auto dir = test::scratch_dir();
  for (const char* name : {"m.ply", "m.obj", "m.stl", "m.off", "m.glb"}) {
    std::ofstream(dir / name) << "x";
    EXPECT_TRUE(resolve_scene((dir / name).string(), {}).up_auto) << name;
    EXPECT_FALSE(resolve_scene((dir / name).string(), {{"up", "z"}}).up_auto) << name;
  }
  EXPECT_FALSE(resolve_scene("", {}).up_auto);  // the built-in model is +y
}

}  // namespace
}  // namespace meshtour::voyager_test
