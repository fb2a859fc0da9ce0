// Scene files and the tour's settings: a file's keys become the Scene's typed fields (relative
// paths from the file's folder), absent keys keep the defaults, bad keys and values are refused
// naming the file and the key, and command-line values land on top of a file as the registry
// orders them.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "core/error.h"
#include "helpers.h"
#include "scenes/scene.h"
#include "scenes/scene_options.h"

namespace meshtour {
namespace {

std::filesystem::path write(const std::filesystem::path& file, const std::string& text) {
  std::ofstream(file) << text;
  return file;
}

const char* const kMinimal = R"({"format": "meshtour-scene/1", "model": {"procedural": "sculpture"}})";

// The InputError message of parsing `json`, or "" when it parses.
std::string parse_error(const std::string& json) {
  try {
    (void)parse_scene(json, "t.json", "/scenes");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(SceneFile, LoadsAFileWithPathsRelativeToIt) {
  const auto dir = test::scratch_dir();
  write(dir / "orbit.json", "{}");
  const auto file = write(dir / "vase.json", R"({"format": "meshtour-scene/1", "model": {"file": "models/vase.ply"},
      "camera": {"path": "turntable", "path_file": "orbit.json"}})");
  const Scene scene = load_scene(file);
  EXPECT_EQ(scene.source, file.string());
  ASSERT_TRUE(scene.mesh_file);
  EXPECT_EQ(*scene.mesh_file, dir / "models" / "vase.ply");
  ASSERT_TRUE(scene.path_file);
  EXPECT_EQ(*scene.path_file, dir / "orbit.json");
  EXPECT_EQ(scene.path_mode, PathMode::turntable);
  EXPECT_THROW(load_scene(dir / "missing.json"), IoError);
}

TEST(SceneFile, AbsentKeysKeepTheDefaults) {
  const Scene scene = parse_scene(kMinimal, "t.json", "/");
  const Scene defaults;
  EXPECT_FALSE(scene.mesh_file);
  EXPECT_EQ(scene.procedural, "sculpture");
  EXPECT_EQ(scene.path_mode, defaults.path_mode);
  EXPECT_EQ(scene.fps, defaults.fps);
  EXPECT_EQ(scene.frames, defaults.frames);
  EXPECT_EQ(scene.render.width, defaults.render.width);
  EXPECT_EQ(scene.render.samples_per_pixel, defaults.render.samples_per_pixel);
  EXPECT_EQ(scene.crf, defaults.crf);
  EXPECT_TRUE(scene.auto_fov);
  EXPECT_EQ(scene.path_search.rows, PaperPathOptions{}.rows);
  EXPECT_EQ(scene.path_search.surface.smoothing, SmoothingMethod::implicit);
  EXPECT_FALSE(scene.file_look);

  // The built-in scene (scenes/default.json): the sculpture on the feature orbit, 4 s at 30 fps.
  const Scene builtin = default_scene();
  EXPECT_EQ(builtin.path_mode, PathMode::feature_orbit);
  EXPECT_EQ(builtin.fps, 30);
  EXPECT_EQ(builtin.frames, 120);
  EXPECT_EQ(builtin.render.width, 1280);
  EXPECT_EQ(builtin.render.height, 720);
  EXPECT_EQ(builtin.elevation_deg, 18.0);
  EXPECT_EQ(builtin.render.shading.preset, "studio");
}

TEST(SceneFile, KeysBecomeTypedSettings) {
  const Scene s = parse_scene(R"({"format": "meshtour-scene/1", "model": {"procedural": "sculpture", "detail": 0.5},
      "up": "-z", "missing_textures": "grey",
      "camera": {"path": "paper", "fov": 40, "elevation": 10},
      "timing": {"fps": 24, "frames": 48},
      "output": {"width": 640, "height": 360, "spp": 4, "crf": 23, "denoise": "off", "filter_radius": 1,
                 "exr_layers": ["albedo", "depth"]},
      "patches": {"smoothing": "taubin", "tolerance": 0.002, "keep_inaccurate": true, "keep_duplicate_vertices": true},
      "paper": {"rows": 7, "columns": 12, "axis_point": "aabb-center", "gaze_radius": "scaled"},
      "look": {"preset": "plain", "exposure": 0.5, "tone_mapping": "clamp", "background": "transparent", "crease_angle": 30}})",
                              "t.json", "/");
  EXPECT_EQ(s.procedural_detail, 0.5);
  EXPECT_EQ(s.up.name(), "-z");
  EXPECT_FALSE(s.up_auto);
  EXPECT_TRUE(s.missing_textures_grey);
  EXPECT_EQ(s.path_mode, PathMode::paper);
  EXPECT_FALSE(s.auto_fov);
  EXPECT_EQ(s.vertical_fov_deg, 40.0);
  EXPECT_EQ(s.elevation_deg, 10.0);
  EXPECT_EQ(s.fps, 24);
  EXPECT_EQ(s.frames, 48);
  EXPECT_EQ(s.render.width, 640);
  EXPECT_EQ(s.render.height, 360);
  EXPECT_EQ(s.render.samples_per_pixel, 4);
  EXPECT_EQ(s.crf, 23);
  EXPECT_FALSE(s.render.denoise);
  EXPECT_EQ(s.render.filter_radius, 1.0f);
  EXPECT_TRUE(s.render.layers.albedo && s.render.layers.depth && !s.render.layers.normal);
  EXPECT_EQ(s.path_search.surface.smoothing, SmoothingMethod::taubin);
  EXPECT_EQ(s.path_search.surface.tolerance, 0.002);
  EXPECT_TRUE(s.path_search.surface.keep_inaccurate_patches);
  EXPECT_FALSE(s.path_search.surface.merge_duplicate_vertices);
  EXPECT_EQ(s.path_search.rows, 7);
  EXPECT_EQ(s.path_search.columns, 12);
  EXPECT_EQ(s.path_search.axis_point, AxisPointMode::aabb_center);
  EXPECT_EQ(s.path_search.gaze_radius, GazeRadiusMode::scaled);
  const Shading& sh = s.render.shading;
  EXPECT_EQ(sh.preset, "plain");
  EXPECT_EQ(sh.exposure, 0.5f);
  EXPECT_EQ(sh.tone_mapping, ToneMapping::clamp);
  EXPECT_EQ(sh.background, BackgroundKind::transparent);
  EXPECT_EQ(sh.material.crease_angle_deg, 30.0f);
  EXPECT_TRUE(s.file_look);

  const Scene automatic = parse_scene(R"({"model": {"procedural": "sculpture"}, "up": "auto", "camera": {"fov": "auto"}})", "t.json", "/");
  EXPECT_TRUE(automatic.up_auto);
  EXPECT_TRUE(automatic.auto_fov);
}

TEST(SceneFile, BadKeysAndValuesNameTheFileAndTheKey) {
  EXPECT_NE(parse_error(R"({"model": {"procedural": "sculpture"}, "camera": {"pth": "paper"}})").find("t.json: 'camera.pth' unknown key"),
            std::string::npos);
  EXPECT_NE(parse_error(R"({"model": {"procedural": "sculpture"}, "output": {"spp": 0}})").find("'output.spp' must be between 1 and 4096"),
            std::string::npos);
  EXPECT_NE(parse_error(R"({"model": {"procedural": "sculpture"}, "camera": {"path": "spiral"}})").find("'camera.path'"),
            std::string::npos);
  EXPECT_NE(parse_error(R"({"model": {"procedural": "sculpture"}, "look": {"tone_mapping": "aces"}})").find("'look.tone_mapping'"),
            std::string::npos);
  EXPECT_NE(parse_error(R"({"model": {"procedural": "sculpture"}, "output": {"crf": 60}})").find("'output.crf' must be between 0 and 51 for h264"),
            std::string::npos);
  EXPECT_NE(parse_error(R"({"model": {"procedural": "sculpture"}, "timing": {"fps": "fast"}})").find("'timing.fps'"), std::string::npos);
  EXPECT_NE(parse_error(R"({"format": "meshtour-scene/2", "model": {"procedural": "sculpture"}})").find("'format'"), std::string::npos);
  EXPECT_NE(parse_error(R"({"camera": {"path": "paper"}})").find("has no 'model'"), std::string::npos);
  EXPECT_NE(parse_error("{"), "");
}

TEST(SceneOptions, CommandLineValuesLandOnTheFileInRegistryOrder) {
  const auto dir = test::scratch_dir();
  const auto file = write(dir / "s.json", R"({"model": {"procedural": "sculpture"}, "timing": {"fps": 24},
      "look": {"preset": "plain", "exposure": 1.5}})");
  // --seconds is applied after --fps whatever order the values come in: 2 s at 10 fps.
  Scene s = resolve_scene(file.string(), {{"seconds", "2"}, {"fps", "10"}});
  EXPECT_EQ(s.fps, 10);
  EXPECT_EQ(s.frames, 20);
  // Without --fps, the file's rate: 2 s at 24 fps.
  EXPECT_EQ(resolve_scene(file.string(), {{"seconds", "2"}}).frames, 48);
  // --preset switches the preset and keeps the file's own look values.
  s = resolve_scene(file.string(), {{"preset", "studio"}});
  EXPECT_EQ(s.render.shading.preset, "studio");
  EXPECT_EQ(s.render.shading.exposure, 1.5f);
  EXPECT_TRUE(s.render.shading.shadows);
  // A value given on the command line wins over the file's, the preset's included.
  s = resolve_scene(file.string(), {{"preset", "studio"}, {"exposure", "-1"}});
  EXPECT_EQ(s.render.shading.exposure, -1.0f);
  // The ground lies under the up axis given.
  s = resolve_scene(file.string(), {{"up", "z"}, {"path", "turntable"}, {"rows", "5"}});
  EXPECT_EQ(s.render.world_up, Eigen::Vector3d::UnitZ());
  EXPECT_EQ(s.path_mode, PathMode::turntable);
  EXPECT_EQ(s.path_search.rows, 5);
  // A mesh file gets the built-in scene's settings; the crf is checked for the job's codec.
  s = resolve_scene("bunny.ply", {});
  EXPECT_EQ(s.mesh_file, std::filesystem::path("bunny.ply"));
  EXPECT_EQ(s.elevation_deg, default_scene().elevation_deg);
  EXPECT_THROW(resolve_scene("", {{"crf", "60"}}), InputError);
  EXPECT_EQ(resolve_scene("", {{"crf", "60"}}, "vp9").crf, 60);
  EXPECT_THROW(resolve_scene("", {{"seconds", "100000"}, {"fps", "240"}}), InputError);
}

TEST(SceneOptions, OnlyTheToursSettingsAreSceneSettings) {
  EXPECT_TRUE(is_scene_setting(options::option("spp")));
  EXPECT_TRUE(is_scene_setting(options::option("seconds")));
  EXPECT_TRUE(is_scene_setting(options::option("gaze-radius")));
  EXPECT_FALSE(is_scene_setting(options::option("threads")));
  EXPECT_FALSE(is_scene_setting(options::option("poster")));
  for (const options::Option& o : options::registry()) {
    const options::Target t = options::target(o);
    EXPECT_EQ(is_scene_setting(o), t == options::Target::scene || t == options::Target::path_search) << o.id;
  }
}

TEST(PathMode, NamesRoundTrip) {
  for (const PathMode m : {PathMode::feature_orbit, PathMode::paper, PathMode::turntable}) EXPECT_EQ(parse_path_mode(path_mode_name(m)), m);
  EXPECT_THROW(parse_path_mode("spiral"), InputError);
  // The registry's choices are the modes' names.
  const auto& choices = options::option("path").choices;
  for (const auto& c : choices) EXPECT_EQ(path_mode_name(parse_path_mode(c)), c);
}

}  // namespace
}  // namespace meshtour
