// `meshtour evaluate --compare`, the camera exports of `path` and `tour` (validated with the
// Khronos glTF validator through Node.js) and the --overview picture, on a small generated mesh.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "helpers.h"
#include "test_meshes.h"

namespace {

namespace fs = std::filesystem;
using meshtour::test::run_meshtour;


fs::path small_mesh(const fs::path& dir) {
  const fs::path file = dir / "bumpy.ply";
  meshtour::save_mesh(meshtour::test_meshes::bumpy_sphere(3), file);
  return file;
}

std::string read_file(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Runs the Khronos validator (tests/gltf/validate.js); returns its exit code and report.
meshtour::test::CommandResult validate_gltf(const fs::path& file) {
  const std::string cmd = "cd '" + meshtour::test::source_dir().string() + "' && node tests/gltf/validate.js " + meshtour::test::shell_quoted(file) + " 2>&1";
  meshtour::test::CommandResult result;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return result;
  char buf[4096];
  while (std::size_t n = fread(buf, 1, sizeof buf, pipe)) result.output.append(buf, n);
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

TEST(CliEvaluate, CompareWritesOneTableAndTheJsonShape) {
  const fs::path dir = meshtour::test::scratch_dir();
  const fs::path mesh = small_mesh(dir);
  const auto r = run_meshtour("evaluate " + meshtour::test::shell_quoted(mesh) + " --compare --frames 24 --samples 32768 --first-view preferred --json " +
                              meshtour::test::shell_quoted(dir / "e.json"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* mode : {"turntable ", "paper ", "feature-orbit "}) EXPECT_NE(r.output.find(mode), std::string::npos) << r.output;
  std::ifstream in(dir / "e.json");
  const nlohmann::json doc = nlohmann::json::parse(in);
  ASSERT_EQ(doc.size(), 1u);
  ASSERT_EQ(doc["modes"].size(), 3u);
  for (const char* mode : {"turntable", "paper", "feature-orbit"}) {
    const auto& m = doc["modes"].at(mode);
    EXPECT_EQ(m.size(), 15u) << mode;  // 10 figures, objective, frame_scores, preference, frame_preferences, definitions
    ASSERT_EQ(m.at("frame_preferences").size(), 24u) << mode;
    EXPECT_EQ(m["preference"]["score"], m["frame_preferences"][0]) << mode;  // the poster's, frame 0's
    EXPECT_GE(m.at("min_edge_margin").get<double>(), 0.05) << mode;  // action-safe framing
    EXPECT_EQ(m.at("frames_below_floor").get<int>(), 0) << mode;
    ASSERT_EQ(m.at("frame_scores").size(), 24u) << mode;
    ASSERT_EQ(m.at("definitions").size(), 8u) << mode;
    // The default definition's figures are today's top-level keys.
    EXPECT_EQ(m["definitions"]["patch-density-75deg"]["feature_coverage"], m["feature_coverage"]) << mode;
    for (const auto& [key, d] : m["definitions"].items()) {
      EXPECT_GT(d.at("feature_coverage").get<double>(), 0.2) << mode << " " << key;
      EXPECT_LE(d.at("feature_coverage").get<double>(), 1.0) << mode << " " << key;
    }
    const double features = m.at("feature_coverage"), surface = m.at("surface_coverage");
    EXPECT_GT(features, 0.3) << mode;
    EXPECT_LE(features, 1.0) << mode;
    EXPECT_GT(surface, 0.3) << mode;
    EXPECT_LE(surface, 1.0) << mode;
    EXPECT_GE(m.at("feature_median_frames").get<double>(), m.at("feature_min_frames").get<double>());
    EXPECT_LE(m.at("feature_median_frames").get<double>(), 24.0);
    // 24 frames around a loop: about 2π/24 rad per frame.
    EXPECT_GT(m.at("camera_max_angular_speed").get<double>(), 0.2);
    EXPECT_LT(m.at("camera_max_angular_speed").get<double>(), 0.4);
    EXPECT_EQ(m.at("frames_out_of_frame").get<int>(), 0) << mode;
  }
  // With --first-view preferred the feature orbit starts at its preferred view: frame 0's preference is the highest, or within
  // the tie band and the frames' spacing of it (measured here by evaluate on the tour's own cameras).
  const auto& preferences = doc["modes"]["feature-orbit"]["frame_preferences"];
  for (std::size_t k = 1; k < preferences.size(); ++k)
    EXPECT_GE(preferences[0].get<double>(), preferences[k].get<double>() - 0.02) << "frame " << k;
  // The path modes see the same mesh: a fixed evaluation gives the same numbers again.
  const auto again = run_meshtour("evaluate " + meshtour::test::shell_quoted(mesh) + " --path turntable --frames 24 --samples 32768 -q --json " + meshtour::test::shell_quoted(dir / "t.json"));
  ASSERT_EQ(again.exit_code, 0) << again.output;
  std::ifstream in2(dir / "t.json");
  const nlohmann::json single = nlohmann::json::parse(in2);
  EXPECT_EQ(single["modes"]["turntable"], doc["modes"]["turntable"]);
}

TEST(CliEvaluate, PathFileGivesTheSameNumbersAsThePaperMode) {
  const fs::path dir = meshtour::test::scratch_dir();
  const fs::path mesh = small_mesh(dir);
  auto r = run_meshtour("path " + meshtour::test::shell_quoted(mesh) + " -q -o " + meshtour::test::shell_quoted(dir / "p.json"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_meshtour("evaluate " + meshtour::test::shell_quoted(mesh) + " --path-file " + meshtour::test::shell_quoted(dir / "p.json") + " --frames 12 --samples 16384 -q --json " + meshtour::test::shell_quoted(dir / "f.json"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_meshtour("evaluate " + meshtour::test::shell_quoted(mesh) + " --path paper --frames 12 --samples 16384 -q --json " + meshtour::test::shell_quoted(dir / "m.json"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream f(dir / "f.json"), m(dir / "m.json");
  const nlohmann::json from_file = nlohmann::json::parse(f), from_mode = nlohmann::json::parse(m);
  EXPECT_EQ(from_file["modes"]["path-file"], from_mode["modes"]["paper"]);
  // --compare judges the built-in modes only.
  r = run_meshtour("evaluate " + meshtour::test::shell_quoted(mesh) + " --compare --path-file " + meshtour::test::shell_quoted(dir / "p.json"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  // Two definitions under one name: a one-line error naming the options, no JSON.
  r = run_meshtour("evaluate " + meshtour::test::shell_quoted(mesh) + " --strict-angle 45 --json " + meshtour::test::shell_quoted(dir / "same.json"));  // --stricter-angle is 45
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("both 45 degrees"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "same.json"));
}

// The default path must win however "seen well" is judged, not only at the angles its search
// uses. The rocker arm is where a raised orbit, chosen by the mean over 75 and 60 degrees, fell
// 5.0 points behind the paper's path at 45 degrees and 7.8 at 30: its features include the inner
// faces of the arm's holes, seen squarely only from a level camera.
TEST(CliEvaluate, TheFeatureOrbitKeepsUpUnderEveryDefinitionOnTheRocker) {
  MESHTOUR_SKIP_UNDER_SANITIZERS("a score of eight coverage definitions; the search runs under the sanitizers in lighter tests");
  MESHTOUR_SHARED_MESH(mesh, "rocker.ply");
  const fs::path dir = meshtour::test::scratch_dir();
  // The default angles (those the search uses), and others it never sees.
  for (const std::string angles : {"", " --seen-angle 80 --strict-angle 50 --stricter-angle 40 --strictest-angle 20"}) {
    // --up y: the rocker as stored (it has no natural up; --up auto, the default, lays it on its flank).
    const auto r = run_meshtour("evaluate " + meshtour::test::shell_quoted(mesh) + " --up y --compare --json " +
                                meshtour::test::shell_quoted(dir / "e.json") + angles);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    std::ifstream in(dir / "e.json");
    const nlohmann::json modes = nlohmann::json::parse(in).at("modes");
    ASSERT_EQ(modes.at("feature-orbit").at("definitions").size(), 8u);
    for (const auto& [key, orbit] : modes["feature-orbit"]["definitions"].items()) {
      const double mine = orbit.at("feature_coverage");
      for (const char* other : {"turntable", "paper"})
        EXPECT_GE(mine, modes.at(other)["definitions"].at(key)["feature_coverage"].get<double>() - 0.01)
            << key << ": the feature orbit more than a point behind the " << other << (angles.empty() ? "" : " at" + angles);
    }
  }
}

TEST(CliEvaluate, GltfFromPathAndTourIsValidAndIdentical) {
  MESHTOUR_SKIP_UNDER_SANITIZERS("the same camera export from two commands, bytes compared; the Release pass checks them");
  const fs::path dir = meshtour::test::scratch_dir();
  const fs::path mesh = small_mesh(dir);
  auto r = run_meshtour("path " + meshtour::test::shell_quoted(mesh) + " --path feature-orbit --frames 8 -q --gltf " + meshtour::test::shell_quoted(dir / "path.gltf") +
                        " --camera-frames " + meshtour::test::shell_quoted(dir / "frames.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_meshtour("tour " + meshtour::test::shell_quoted(mesh) + " --path feature-orbit --frames 8 --width 64 --height 36 --spp 1 -q -o " +
                   meshtour::test::shell_quoted(dir / "t.mp4") + " --gltf " + meshtour::test::shell_quoted(dir / "tour.gltf"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // The same cameras whichever command exports them (the tour's 64x36 has the default 16:9 aspect).
  EXPECT_EQ(read_file(dir / "path.bin"), read_file(dir / "tour.bin"));
  // Each names its own buffer: compare the texts with the two buffer names taken out.
  const auto without_buffer_name = [](std::string text, const std::string& name) {
    const std::size_t at = text.find(name);
    return at == std::string::npos ? text : text.erase(at, name.size());
  };
  EXPECT_EQ(without_buffer_name(read_file(dir / "path.gltf"), "path.bin"), without_buffer_name(read_file(dir / "tour.gltf"), "tour.bin"));
  for (const char* name : {"path.gltf", "tour.gltf"}) {
    const auto v = validate_gltf(dir / name);
    EXPECT_EQ(v.exit_code, 0) << name << ": " << v.output;
    EXPECT_NE(v.output.find("\"numErrors\": 0"), std::string::npos) << v.output;
  }
  // The validator does catch a broken file: a buffer that is too short.
  std::string text = read_file(dir / "path.gltf");
  const std::string key = "\"byteLength\": ";
  const auto at = text.find(key);
  ASSERT_NE(at, std::string::npos);
  text.insert(at + key.size(), 1, '9');
  std::ofstream(dir / "broken.gltf") << text;
  fs::copy_file(dir / "path.bin", dir / "broken.bin");
  const auto broken = validate_gltf(dir / "broken.gltf");
  EXPECT_EQ(broken.exit_code, 1) << broken.output;
}

// `path` describes the turntable a tour renders with its camera options (--elevation, --fov, the
// frame size and rate), not only the default one.
TEST(CliEvaluate, PathTakesTheTurntablesCameraOptionsAsTourDoes) {
  const fs::path dir = meshtour::test::scratch_dir();
  const fs::path mesh = small_mesh(dir);
  const std::string camera = meshtour::test::shell_quoted(mesh) + " --path turntable --elevation 35 --fov 25 --frames 6 --fps 24";
  std::string path_command = "path ", tour_command = "tour ";
  path_command += camera;
  path_command += " --width 640 --height 480 -q --gltf " + meshtour::test::shell_quoted(dir / "path.gltf");
  path_command += " --camera-frames " + meshtour::test::shell_quoted(dir / "frames.json");
  tour_command += camera;
  tour_command += " --width 64 --height 48 --spp 1 -q -o " + meshtour::test::shell_quoted(dir / "t.mp4");
  tour_command += " --gltf " + meshtour::test::shell_quoted(dir / "tour.gltf");
  auto r = run_meshtour(path_command);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_meshtour(tour_command);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(read_file(dir / "path.bin"), read_file(dir / "tour.bin"));  // the same cameras (both 4:3)
  std::ifstream in(dir / "frames.json");
  const nlohmann::json frames = nlohmann::json::parse(in);  // one object per frame
  ASSERT_EQ(frames.size(), 6u);
  for (const auto& f : frames) {
    Eigen::Vector3d d;
    for (int k = 0; k < 3; ++k) d[k] = f["eye"][k].get<double>() - f["target"][k].get<double>();
    EXPECT_NEAR(std::asin(d.normalized().y()) * 180.0 / EIGEN_PI, 35.0, 1e-6);
    EXPECT_NEAR(f["vertical_fov_deg"].get<double>(), 25.0, 1e-9);
  }
  // The elevation changes what evaluate measures of the turntable.
  r = run_meshtour("evaluate " + meshtour::test::shell_quoted(mesh) + " --path turntable --frames 12 --samples 16384 -q --json " + meshtour::test::shell_quoted(dir / "e18.json"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_meshtour("evaluate " + meshtour::test::shell_quoted(mesh) + " --path turntable --elevation 70 --frames 12 --samples 16384 -q --json " +
                   meshtour::test::shell_quoted(dir / "e70.json"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream a(dir / "e18.json"), b(dir / "e70.json");
  EXPECT_NE(nlohmann::json::parse(a)["modes"]["turntable"]["surface_coverage"],
            nlohmann::json::parse(b)["modes"]["turntable"]["surface_coverage"]);
}

TEST(CliEvaluate, OverviewShowsTheModelAndThePath) {
  const fs::path dir = meshtour::test::scratch_dir();
  const fs::path mesh = small_mesh(dir);
  const auto r = run_meshtour("path " + meshtour::test::shell_quoted(mesh) + " --path turntable -q --overview " + meshtour::test::shell_quoted(dir / "o.png") + " --overview-size 160x120");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  auto in = OIIO::ImageInput::open((dir / "o.png").string());
  ASSERT_TRUE(in);
  const OIIO::ImageSpec& spec = in->spec();
  EXPECT_EQ(spec.width, 160);
  EXPECT_EQ(spec.height, 120);
  std::vector<unsigned char> pixels(static_cast<std::size_t>(spec.width) * spec.height * spec.nchannels);
  ASSERT_TRUE(in->read_image(0, 0, 0, -1, OIIO::TypeDesc::UINT8, pixels.data()));
  // The position path is drawn magenta: strong red and blue, little green.
  int magenta = 0;
  for (std::size_t p = 0; p + 2 < pixels.size(); p += spec.nchannels)
    magenta += pixels[p] > 150 && pixels[p + 2] > 150 && pixels[p + 1] < 100;
  EXPECT_GT(magenta, 50);
  // Options of the paper path only: refused for another mode, with a message.
  const auto refused = run_meshtour("path " + meshtour::test::shell_quoted(mesh) + " --path turntable --plot " + meshtour::test::shell_quoted(dir / "p.png"));
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_FALSE(fs::exists(dir / "p.png"));
}

}  // namespace
