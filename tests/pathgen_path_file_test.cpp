// The path file: write → read gives the same poses; bad files give errors naming file and key.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "core/error.h"
#include "helpers.h"
#include "pathgen/debug_output.h"
#include "pathgen/path_file.h"

namespace meshtour {
namespace {

// A sphere-like UV surface with a band of heavier faces, already "analysed" (synthetic).
SurfaceAnalysis make_surface(const Eigen::Vector3d& up_tilt = Eigen::Vector3d::Zero()) {
  SurfaceAnalysis s;
  const int around = 48, along = 24;
  for (int i = 0; i <= along; ++i)
    for (int k = 0; k < around; ++k) {
      const double polar = std::numbers::pi * (i + 0.5) / (along + 1);
      const double a = 2 * std::numbers::pi * k / around;
      s.positions.push_back(Eigen::Vector3d(0.3 * std::sin(polar) * std::sin(a), 0.4 * std::cos(polar),
                                            0.3 * std::sin(polar) * std::cos(a)) + up_tilt);
    }
  for (int i = 0; i < along; ++i)
    for (int k = 0; k < around; ++k) {
      const auto v = [&](int ii, int kk) { return static_cast<std::uint32_t>(ii * around + (kk % around)); };
      s.triangles.push_back({v(i, k), v(i + 1, k + 1), v(i, k + 1)});
      s.triangles.push_back({v(i, k), v(i + 1, k), v(i + 1, k + 1)});
    }
  for (std::size_t f = 0; f < s.triangles.size(); ++f) {
    s.face_weight.push_back(1.0 + static_cast<double>((f * 7919) % 13));
    s.face_patch.push_back(static_cast<int>(f % 97));
  }
  s.patch_count = 97;
  s.grown_patches = 90;
  s.single_face_patches = 7;
  s.scale = 3.25;
  s.offset = Eigen::Vector3d(-1.5, 10.0, 0.25);
  s.cleanup_notes = {"synthetic surface"};
  s.stage_seconds = {{"normalize", 0.001}, {"smooth", 0.002}};
  return s;
}

void expect_same_poses(const CameraPath& a, const CameraPath& b) {
  for (int k = 0; k <= 1000; ++k) {
    const double t = k / 1000.0 - 0.3;
    const CameraPose p = a.pose(t), q = b.pose(t);
    EXPECT_LE((p.eye - q.eye).norm(), 1e-12) << t;
    EXPECT_LE((p.target - q.target).norm(), 1e-12) << t;
    EXPECT_LE((p.up - q.up).norm(), 1e-12) << t;
  }
}

TEST(PathgenPathFile, RoundTripGivesTheSamePoses) {
  const auto dir = test::scratch_dir();
  for (int variant = 0; variant < 3; ++variant) {
    PaperPathOptions o;
    if (variant == 1) {
      o.degree = 2;
      o.gaze_radius = GazeRadiusMode::scaled;
      o.height_reference = HeightReference::curve_mean;
      o.up = UpDirection::parse("0.1,1,0.2");
    }
    if (variant == 2) {
      o.up = UpDirection::parse("-z");
      o.rows = 7;
      o.columns = 13;
    }
    const PaperPathResult r = compute_paper_path(make_surface(), o);
    const auto file = dir / ("path" + std::to_string(variant) + ".json");
    write_path_file(r, file, "synthetic");
    const std::unique_ptr<CameraPath> read = read_path_file(file);
    expect_same_poses(r.camera_path(), *read);
    // Written twice, the file is identical (no time stamps or addresses in it).
    const std::string first = path_file_text(r, "synthetic");
    EXPECT_EQ(first, path_file_text(r, "synthetic"));
  }
  // No temporary files left behind.
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    EXPECT_EQ(entry.path().filename().string().rfind(".", 0), std::string::npos) << entry.path();
}

TEST(PathgenPathFile, HoldsTheDocumentedKeys) {
  const PaperPathResult r = compute_paper_path(make_surface(), PaperPathOptions{});
  const auto j = nlohmann::json::parse(path_file_text(r));
  EXPECT_EQ(j["format_version"], kPathFormatVersion);
  EXPECT_EQ(j["mode"], "paper");
  EXPECT_EQ(j["faces"], r.surface.triangles.size());
  EXPECT_EQ(j["vertices"], r.surface.positions.size());
  EXPECT_EQ(j["patches"]["count"], 97);
  EXPECT_DOUBLE_EQ(j["patches"]["ratio"].get<double>(), 97.0 / r.surface.triangles.size());
  EXPECT_EQ(j["patches"]["orphans"], 0);
  EXPECT_DOUBLE_EQ(j["cylinder"]["radius"].get<double>(), r.cylinder.radius);
  EXPECT_DOUBLE_EQ(j["cylinder"]["height"].get<double>(), r.cylinder.height);
  const double a = j["metrics"]["amplitude_ratio"];
  EXPECT_GE(a, 0.0);
  EXPECT_LE(a, 1.0);  // a fraction, not a percentage
  EXPECT_EQ(j["metrics"]["extreme_points"].get<int>() % 2, 0);
  EXPECT_DOUBLE_EQ(j["metrics"]["weight_max"].get<double>(), r.metrics.weight_max);
  EXPECT_TRUE(j["metrics"]["weight_avg"].is_number());
  EXPECT_TRUE(j["metrics"]["weight_avg_nonempty"].is_number());
  ASSERT_EQ(j["grid"]["weights"].size(), 11u);
  for (const auto& row : j["grid"]["weights"]) EXPECT_EQ(row.size(), 20u);
  EXPECT_TRUE(j["grid"]["empty_cells"].is_number_integer());
  EXPECT_EQ(j["grid"]["control_rows"].size(), 20u);
  EXPECT_EQ(j["curve"]["control_points"].size(), 20u);
  EXPECT_EQ(j["curve"]["knots"].size(), 20u);
  EXPECT_TRUE(j["curve"]["start_parameter"].is_number());
  EXPECT_TRUE(j["options"]["surface"]["tolerance"].is_number());
  EXPECT_TRUE(j["timings_s"]["smooth"].is_number());
  EXPECT_TRUE(j["timings_s"]["grid"].is_number());
  EXPECT_TRUE(j["transform"]["scale"].is_number());
}

void expect_input_error(const std::filesystem::path& file, const std::string& text, const std::string& key) {
  {
    std::ofstream out(file);
    out << text;
  }
  try {
    read_path_file(file);
    FAIL() << "expected InputError for " << text.substr(0, 60);
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(file.string()), std::string::npos) << what;
    EXPECT_NE(what.find(key), std::string::npos) << what;
  }
}

TEST(PathgenPathFile, BadFilesGiveErrorsNamingFileAndKey) {
  const auto dir = test::scratch_dir();
  EXPECT_THROW(read_path_file(dir / "missing.json"), IoError);
  const PaperPathResult r = compute_paper_path(make_surface(), PaperPathOptions{});
  auto j = nlohmann::json::parse(path_file_text(r));
  const auto file = dir / "bad.json";
  expect_input_error(file, "{ not json", "JSON");
  auto v = j;
  v["format_version"] = kPathFormatVersion + 1;
  expect_input_error(file, v.dump(), "format_version");
  v["format_version"] = 0;
  expect_input_error(file, v.dump(), "format_version");
  v = j;
  v.erase("format_version");
  expect_input_error(file, v.dump(), "format_version");
  v = j;
  v["curve"].erase("control_heights");
  expect_input_error(file, v.dump(), "curve.control_heights");
  v = j;
  v["cylinder"]["radius"] = "wide";
  expect_input_error(file, v.dump(), "cylinder.radius");
  v = j;
  v["transform"]["offset"] = {1, 2};
  expect_input_error(file, v.dump(), "transform.offset");
  v = j;
  v["curve"]["degree"] = 5;
  expect_input_error(file, v.dump(), "curve.degree");
}

// Poses equal to the last bit: a render from the file must give the frames of the path it was
// written from, not merely close ones.
void expect_identical_poses(const CameraPath& a, const CameraPath& b) {
  for (int k = 0; k < 97; ++k) {
    const CameraPose p = frame_pose(a, k, 97), q = frame_pose(b, k, 97);
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(p.eye[i], q.eye[i]) << "frame " << k;
      EXPECT_EQ(p.target[i], q.target[i]) << "frame " << k;
      EXPECT_EQ(p.up[i], q.up[i]) << "frame " << k;
    }
  }
}

FeatureOrbitGeometry odd_orbit() {
  FeatureOrbitGeometry g;
  g.center = Eigen::Vector3d(0.1, -2.0 / 3.0, 1e-7);
  g.up = Eigen::Vector3d(0, 0, 1);
  g.front = Eigen::Vector3d(0, -1, 0);
  g.side = g.up.cross(g.front);
  g.start = 0.3141592653589793;
  g.distance = {2.5, 0.1 / 3.0, -0.2, 1.0 / 7.0, 0.01};
  g.elevation = ElevationCurve{0.31, -0.2 / 3.0, 0.125, 0.0701, 0.9};
  return g;
}

TEST(PathgenPathFile, FeatureOrbitAndTurntableRoundTripBitForBit) {
  const auto dir = test::scratch_dir();
  PathRecord record;
  record.source = "model.obj";
  record.made_for = {{"up", "z"}, {"aspect", setting_text(16.0 / 9.0)}, {"fov", "auto"}, {"frames", "5"}};
  record.frames = 5;
  record.frame_scores = {0.5, 1.0 / 3.0, 0.25, 0.125, 0.0625};
  const FeatureOrbitPath orbit(odd_orbit());
  std::ofstream(dir / "orbit.json") << path_file_text(orbit.geometry(), record);
  const PathFile read = load_path_file(dir / "orbit.json");
  EXPECT_EQ(read.mode, "feature-orbit");
  EXPECT_EQ(read.format_version, kPathFormatVersion);
  PathSettings sorted = record.made_for;  // read back by name, in the JSON object's key order
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(read.record.made_for, sorted);
  EXPECT_EQ(read.record.frames, 5);
  EXPECT_EQ(read.record.frame_scores, record.frame_scores);
  EXPECT_EQ(read.record.source, "model.obj");
  ASSERT_TRUE(dynamic_cast<const FeatureOrbitPath*>(read.path.get()));
  expect_identical_poses(orbit, *read.path);

  // A turntable fitted to a small irregular point set, rebuilt from its geometry alone.
  const std::vector<Eigen::Vector3d> points = {{0, 0, 0}, {1, 0.2, 0}, {0.3, 1.7, 0.1}, {0.2, 0.4, 0.9}, {-0.5, 0.1, 0.3}};
  TurntableOptions options;
  options.up = Axis::parse("y");
  options.elevation_deg = 23.0;
  options.lens.vertical_fov_deg = 31.0;
  const TurntablePath turntable(points, options);
  PathRecord plain;
  plain.made_for = {{"up", "y"}};
  std::ofstream(dir / "turntable.json") << path_file_text(turntable.geometry(), plain);
  const PathFile t = load_path_file(dir / "turntable.json");
  EXPECT_EQ(t.mode, "turntable");
  EXPECT_EQ(t.record.frames, 0);
  expect_identical_poses(turntable, *t.path);
  EXPECT_EQ(read_path_file(dir / "turntable.json")->pose(0.25).eye, turntable.pose(0.25).eye);
  // The paper-only reader names what the file holds instead.
  try {
    read_paper_path_file(dir / "turntable.json");
    FAIL() << "a turntable file read as the paper path";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("holds a turntable path"), std::string::npos) << e.what();
  }
}

// Files of format 1 (before modes and made_for) are still read: the paper path, no settings.
TEST(PathgenPathFile, FormatOneIsStillRead) {
  const auto dir = test::scratch_dir();
  const PaperPathResult r = compute_paper_path(make_surface(), PaperPathOptions{});
  auto j = nlohmann::json::parse(path_file_text(r, "old"));
  j["format_version"] = 1;
  j.erase("mode");
  j.erase("made_for");
  std::ofstream(dir / "v1.json") << j.dump(2);
  const PathFile f = load_path_file(dir / "v1.json");
  EXPECT_EQ(f.format_version, 1);
  EXPECT_EQ(f.mode, "paper");
  EXPECT_TRUE(f.record.made_for.empty());
  expect_identical_poses(r.camera_path(), *f.path);
  check_path_settings(f, {{"up", "z"}, {"aspect", "1"}}, dir / "v1.json");  // nothing recorded, nothing refused
}

TEST(PathgenPathFile, SettingsThePathWasMadeForAreCompared) {
  PathFile f;
  f.mode = "feature-orbit";
  f.record.made_for = {{"up", "y"}, {"aspect", setting_text(16.0 / 9.0)}, {"fov", "auto"}};
  EXPECT_NO_THROW(check_path_settings(f, {{"up", "y"}, {"aspect", setting_text(1280.0 / 720.0)}, {"elevation", "18"}}, "p.json"));
  try {
    check_path_settings(f, {{"up", "y"}, {"aspect", setting_text(4.0 / 3.0)}}, "p.json");
    FAIL() << "another aspect was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("p.json"), std::string::npos) << what;
    EXPECT_NE(what.find("aspect 1.7777777777777777"), std::string::npos) << what;
    EXPECT_NE(what.find("aspect 1.3333333333333333"), std::string::npos) << what;
  }
  EXPECT_THROW(check_path_settings(f, {{"fov", "35"}}, "p.json"), InputError);
}

TEST(PathgenPathFile, BadOrbitAndTurntableFilesGiveErrorsNamingTheKey) {
  const auto dir = test::scratch_dir();
  const auto file = dir / "bad.json";
  const auto orbit = nlohmann::json::parse(path_file_text(odd_orbit(), PathRecord{}));
  auto v = orbit;
  v["mode"] = "spiral";
  expect_input_error(file, v.dump(), "mode");
  v = orbit;
  v.erase("mode");
  expect_input_error(file, v.dump(), "mode");
  v = orbit;
  v.erase("made_for");
  expect_input_error(file, v.dump(), "made_for");
  v = orbit;
  v["made_for"]["up"] = 1;
  expect_input_error(file, v.dump(), "made_for.up");
  v = orbit;
  v["orbit"]["up"] = {0, 0, 2};
  expect_input_error(file, v.dump(), "orbit.up");
  v = orbit;
  v["orbit"]["distance"] = {1, 0.5, 0.5, 0, 0};  // reaches the centre
  expect_input_error(file, v.dump(), "orbit.distance");
  v = orbit;
  v["orbit"]["distance"] = {1, 0};
  expect_input_error(file, v.dump(), "orbit.distance");
  v = orbit;
  v["orbit"]["center"] = {1e300, 0, 0};
  expect_input_error(file, v.dump(), "orbit.center");
  v = orbit;
  v["orbit"]["elevation"]["base"] = 2.0;
  expect_input_error(file, v.dump(), "orbit.elevation.base");
  v = orbit;
  v["frames"] = 3;
  v["frame_scores"] = {1, 2};
  expect_input_error(file, v.dump(), "frame_scores");
  TurntableGeometry g;
  auto t = nlohmann::json::parse(path_file_text(g, PathRecord{}));
  t["turntable"]["elevation_deg"] = 95;
  expect_input_error(file, t.dump(), "turntable.elevation_deg");
  t["turntable"]["elevation_deg"] = 10;
  t["turntable"]["radius"] = 0;
  expect_input_error(file, t.dump(), "turntable.radius");
}

TEST(PathgenPathFile, DebugOutputsAreWritten) {
  const auto dir = test::scratch_dir() / "debug";
  PaperPathOptions o;
  o.samples = 36;
  const PaperPathResult r = compute_paper_path(make_surface(), o);
  const auto files = write_debug_outputs(r, dir);
  ASSERT_EQ(files.size(), 4u);
  for (const auto& f : files) EXPECT_GT(std::filesystem::file_size(f), 100u) << f;
  // Binary PLY: header + 12 bytes per vertex + 16 bytes per face.
  std::ifstream ply(dir / "patches.ply", std::ios::binary);
  std::string header, line;
  while (std::getline(ply, line) && line != "end_header") header += line + "\n";
  EXPECT_NE(header.find("property uchar red"), std::string::npos);
  const auto size = std::filesystem::file_size(dir / "patches.ply");
  EXPECT_EQ(size, header.size() + std::string("end_header\n").size() + 12 * r.surface.positions.size() +
                      16 * r.surface.triangles.size());
  std::ifstream csv(dir / "samples.csv");
  int lines = 0;
  while (std::getline(csv, line)) ++lines;
  EXPECT_EQ(lines, 37);
}

}  // namespace
}  // namespace meshtour
