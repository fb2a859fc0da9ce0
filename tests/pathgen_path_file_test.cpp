// The path file: write → read gives the same poses; bad files give errors naming file and key.
#include <gtest/gtest.h>

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
  EXPECT_EQ(j["format_version"], 1);
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
  v["format_version"] = 2;
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
