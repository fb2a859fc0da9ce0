// `meshtour path` end to end: the JSON it writes on real meshes, the plot and debug outputs, the
// help text, and one-line errors without partial outputs.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "helpers.h"

namespace {

namespace fs = std::filesystem;
using meshtour::test::run_meshtour;

nlohmann::json read_json(const fs::path& file) {
  std::ifstream in(file);
  return nlohmann::json::parse(in);
}

int count_lines(const std::string& text) {
  int lines = 0;
  for (char c : text) lines += c == '\n';
  return lines;
}

void expect_sane_path_file(const nlohmann::json& j, int faces) {
  EXPECT_EQ(j["format_version"], 1);
  EXPECT_EQ(j["faces"].get<int>(), faces);
  EXPECT_GT(j["vertices"].get<int>(), faces / 3);
  const int T = j["patches"]["count"];
  EXPECT_GT(T, 0);
  EXPECT_LT(T, faces);
  EXPECT_NEAR(j["patches"]["ratio"].get<double>(), static_cast<double>(T) / faces, 1e-12);
  EXPECT_GE(j["patches"]["orphans"].get<int>(), 0);
  // Normalized units: the diagonal of the bounding box is 1.
  const double r = j["cylinder"]["radius"], h = j["cylinder"]["height"];
  EXPECT_GT(r, 0.05);
  EXPECT_LT(r, 1.0);
  EXPECT_GT(h, 0.05);
  EXPECT_LE(h, 1.0 + 1e-9);
  const double a = j["metrics"]["amplitude_ratio"];
  EXPECT_GE(a, 0.0);
  EXPECT_LE(a, 0.5);  // a fraction of h; the gaze path spans at most half of the height
  EXPECT_DOUBLE_EQ(a, 0.5 * j["metrics"]["amplitude_ratio_curve"].get<double>());
  const int E = j["metrics"]["extreme_points"];
  EXPECT_EQ(E % 2, 0);
  EXPECT_LE(E, 20);
  const double w_max = j["metrics"]["weight_max"], w_avg = j["metrics"]["weight_avg"];
  EXPECT_GE(w_max, 1.0);
  EXPECT_LE(w_max, 200.0);
  EXPECT_GT(w_avg, 0.0);
  EXPECT_LE(w_avg, w_max);
  EXPECT_GE(j["metrics"]["weight_avg_nonempty"].get<double>(), w_avg);
  ASSERT_EQ(j["grid"]["weights"].size(), 11u);
  for (const auto& row : j["grid"]["weights"]) ASSERT_EQ(row.size(), 20u);
  ASSERT_EQ(j["grid"]["control_rows"].size(), 20u);
  for (const auto& row : j["grid"]["control_rows"]) {
    EXPECT_GE(row.get<int>(), 0);
    EXPECT_LE(row.get<int>(), 10);
  }
  EXPECT_GE(j["grid"]["empty_cells"].get<int>(), 0);
  EXPECT_EQ(j["curve"]["control_heights"].size(), 20u);
  EXPECT_EQ(j["curve"]["knots"].size(), 20u);
  const double t0 = j["curve"]["start_parameter"];
  EXPECT_GE(t0, 0.0);
  EXPECT_LT(t0, 1.0);
  EXPECT_GT(j["transform"]["scale"].get<double>(), 0.0);
  EXPECT_TRUE(j["options"].is_object());
  EXPECT_TRUE(j["timings_s"]["total"].is_number());
}

TEST(CliPath, BunnyWithYUpWritesAPathFilePlotAndDebugOutputs) {
  MESHTOUR_SHARED_MESH(mesh, "bunny.ply");
  const fs::path dir = meshtour::test::scratch_dir();
  const auto result = run_meshtour("path '" + mesh.string() + "' --up y -o '" + (dir / "bunny.json").string() +
                                   "' --plot '" + (dir / "bunny.png").string() + "' --debug-dir '" +
                                   (dir / "debug").string() + "'");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  for (const char* key : {"69630 faces", "T = ", "orphans", "r = ", "h = ", "k_r", "A = ", "E = ", "Wmax", "Wavg", "rows", "smooth"})
    EXPECT_NE(result.output.find(key), std::string::npos) << key << "\n" << result.output;
  const auto j = read_json(dir / "bunny.json");
  expect_sane_path_file(j, 69630);
  EXPECT_EQ(j["cylinder"]["up"], nlohmann::json::array({0.0, 1.0, 0.0}));
  EXPECT_GT(fs::file_size(dir / "bunny.png"), 1000u);
  for (const char* f : {"patches.ply", "face_weights.ply", "cell_weights.ply", "samples.csv"})
    EXPECT_TRUE(fs::exists(dir / "debug" / f)) << f;
}

TEST(CliPath, VenusWithZUp) {
  MESHTOUR_SHARED_MESH(mesh, "venus.ply");
  const fs::path dir = meshtour::test::scratch_dir();
  const auto result = run_meshtour("path '" + mesh.string() + "' --up z -q -o '" + (dir / "venus.json").string() + "'");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(result.output, "");  // --quiet
  const auto j = read_json(dir / "venus.json");
  expect_sane_path_file(j, 28602);
  EXPECT_EQ(j["cylinder"]["up"], nlohmann::json::array({0.0, 0.0, 1.0}));
  // A standing statue is taller than twice its radius: the camera circles at 6r.
  EXPECT_EQ(j["metrics"]["radius_factor"].get<double>(),
            j["metrics"]["height_over_radius"].get<double>() > 2.0 ? 6.0 : 4.0);
}

TEST(CliPath, MissingMeshIsOneLineErrorAndNoOutput) {
  const fs::path dir = meshtour::test::scratch_dir();
  const auto result = run_meshtour("path '" + (dir / "nope.ply").string() + "' -o '" + (dir / "out.json").string() + "'");
  EXPECT_NE(result.exit_code, 0);
  EXPECT_EQ(count_lines(result.output), 1) << result.output;
  EXPECT_NE(result.output.find("nope.ply"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(dir / "out.json"));
}

TEST(CliPath, BadOptionsAreOneLineErrorsAndNoOutput) {
  MESHTOUR_SHARED_MESH(mesh, "bunny.ply");
  const fs::path dir = meshtour::test::scratch_dir();
  const std::string out = " -o '" + (dir / "out.json").string() + "'";
  for (const std::string bad : {"--up w", "--rows 0", "--degree 4", "--smoothing gentle", "--tolerance -1",
                                "--gaze-scale 2", "--no-such-option"}) {
    const auto result = run_meshtour("path '" + mesh.string() + "' " + bad + out);
    EXPECT_EQ(result.exit_code, 2) << bad << ": " << result.output;
    EXPECT_EQ(count_lines(result.output), 1) << bad << ": " << result.output;
    EXPECT_FALSE(fs::exists(dir / "out.json")) << bad;
  }
  // A model that is flat across the chosen up axis cannot get a cylinder.
  {
    std::ofstream flat(dir / "flat.obj");
    flat << "v 0 0 0\nv 1 0 0\nv 0 0 1\nv 1 0 1\nf 1 2 3\nf 2 4 3\n";
  }
  const auto result = run_meshtour("path '" + (dir / "flat.obj").string() + "' --up y --smoothing none" + out);
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("--up"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(dir / "out.json"));
}

TEST(CliPath, UnwritableOutputLeavesNoPartialFiles) {
  MESHTOUR_SHARED_MESH(mesh, "bunny.ply");
  const fs::path dir = meshtour::test::scratch_dir();
  const auto result = run_meshtour("path '" + mesh.string() + "' --plot '" + (dir / "plot.png").string() +
                                   "' -o '" + (dir / "missing-folder" / "out.json").string() + "'");
  EXPECT_EQ(result.exit_code, 3) << result.output;
  EXPECT_EQ(count_lines(result.output), 1) << result.output;
  EXPECT_FALSE(fs::exists(dir / "plot.png"));
}

TEST(CliPath, HelpTeachesDefaultsAndInterpretations) {
  const auto result = run_meshtour("path --help");
  EXPECT_EQ(result.exit_code, 0);
  for (const char* text : {"--up", "--tolerance", "0.001", "--rows", "11", "--columns", "20", "--degree",
                           "--smoothing", "implicit", "--weight-neighbourhood", "vertex-3-ring", "I-15",
                           "--cell-averaging", "--axis-point", "--plot", "--debug-dir", "diagonal"})
    EXPECT_NE(result.output.find(text), std::string::npos) << text;
}

}  // namespace
