// `meshtour path` end to end: the JSON it writes on real meshes, the plot and debug outputs, the
// help text, and one-line errors without partial outputs.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <optional>
#include <nlohmann/json.hpp>

#include "helpers.h"
#include "mesh/mesh.h"
#include "test_meshes.h"
#include "tour/bitmap_text.h"
#include "tour/path_plot.h"

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
  EXPECT_EQ(j["format_version"], 2);
  EXPECT_EQ(j["mode"], "paper");
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

// Where `text` is drawn in `image` with `color` inside `region` (its top-left corner), or nothing:
// every ink pixel of the glyphs must have that colour and every other pixel of their box must not.
std::optional<std::pair<int, int>> find_text(const meshtour::PlotImage& image, const meshtour::PlotRect& region,
                                             const std::string& text, std::array<std::uint8_t, 3> color, int scale) {
  meshtour::PlotImage glyphs{meshtour::text_width(text, scale), meshtour::text_height(scale), {}};
  glyphs.rgb.assign(static_cast<std::size_t>(glyphs.width) * glyphs.height * 3, 0);
  const std::array<std::uint8_t, 3> ink{255, 255, 255};
  meshtour::draw_text(glyphs, 0, 0, text, ink, scale);
  const auto pixel = [](const meshtour::PlotImage& im, int x, int y) {
    const auto* p = &im.rgb[(static_cast<std::size_t>(y) * im.width + x) * 3];
    return std::array<std::uint8_t, 3>{p[0], p[1], p[2]};
  };
  for (int y0 = std::max(0, region.y0); y0 + glyphs.height <= std::min(image.height, region.y1); ++y0)
    for (int x0 = std::max(0, region.x0); x0 + glyphs.width <= std::min(image.width, region.x1); ++x0) {
      bool match = true;
      for (int y = 0; match && y < glyphs.height; ++y)
        for (int x = 0; match && x < glyphs.width; ++x)
          match = (pixel(glyphs, x, y) == ink) == (pixel(image, x0 + x, y0 + y) == color);
      if (match) return std::pair{x0, y0};
    }
  return std::nullopt;
}

TEST(CliPath, PlotHasAxesAColourBarAndALegend) {
  const fs::path dir = meshtour::test::scratch_dir();
  meshtour::save_mesh(meshtour::test_meshes::bumpy_sphere(3), dir / "ball.ply");
  // The specification's ε (diagonal units): under I-34's tighter default this small ball's path
  // stays so close to its base curve that the gaze and position curves hide under it.
  const auto result = run_meshtour("path '" + (dir / "ball.ply").string() + "' --up y --tolerance-unit diagonal -q -o '" +
                                   (dir / "p.json").string() + "' --plot '" + (dir / "plot.png").string() + "'");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  auto in = OIIO::ImageInput::open((dir / "plot.png").string());
  ASSERT_TRUE(in);
  const meshtour::PathPlotLayout layout = meshtour::path_plot_layout();
  ASSERT_EQ(in->spec().width, layout.width);
  ASSERT_EQ(in->spec().height, layout.height);
  ASSERT_EQ(in->spec().nchannels, 3);
  meshtour::PlotImage image{layout.width, layout.height, std::vector<std::uint8_t>(static_cast<std::size_t>(layout.width) * layout.height * 3)};
  ASSERT_TRUE(in->read_image(0, 0, 0, -1, OIIO::TypeDesc::UINT8, image.rgb.data()));
  const auto pixel = [&](int x, int y) {
    const auto* p = &image.rgb[(static_cast<std::size_t>(y) * image.width + x) * 3];
    return std::array<std::uint8_t, 3>{p[0], p[1], p[2]};
  };
  const auto count = [&](const meshtour::PlotRect& r, std::array<std::uint8_t, 3> c) {
    int n = 0;
    for (int y = r.y0; y < r.y1; ++y)
      for (int x = r.x0; x < r.x1; ++x) n += pixel(x, y) == c;
    return n;
  };

  // The colour bar is the heat map's ramp, 0 at the bottom row and Wmax at the top row.
  const meshtour::PlotRect& bar = layout.colour_bar;
  const int column = (bar.x0 + bar.x1) / 2;
  for (int y = bar.y0; y < bar.y1; ++y)
    ASSERT_EQ(pixel(column, y), meshtour::weight_color(static_cast<double>(bar.y1 - 1 - y) / (bar.y1 - 1 - bar.y0))) << y;
  EXPECT_NE(pixel(column, bar.y0), pixel(column, bar.y1 - 1));

  // Labels, by their exact glyphs: the colour bar's ends, the axes' ticks and titles.
  const int s = layout.text_scale;
  namespace color = meshtour::plot_colors;
  const meshtour::PlotRect right{bar.x1, 0, layout.width, layout.height};
  char w_max[32];
  std::snprintf(w_max, sizeof w_max, "%.3g", read_json(dir / "p.json")["metrics"]["weight_max"].get<double>());
  const auto top = find_text(image, right, w_max, color::text, s);
  ASSERT_TRUE(top) << w_max;
  EXPECT_LT(std::abs(top->second - bar.y0), 12);  // level with the top of the bar
  const auto bottom = find_text(image, {bar.x1, (bar.y0 + bar.y1) / 2 + 20, layout.width, layout.height}, "0", color::text, s);
  ASSERT_TRUE(bottom);
  EXPECT_LT(std::abs(bottom->second - bar.y1), 12);
  const meshtour::PlotRect& map = layout.heat_map;
  const meshtour::PlotRect below{0, map.y1, layout.width, layout.legend.y0};
  for (const char* label : {"0°", "90°", "180°", "270°", "360°", "angle around the up axis (degrees)"})
    EXPECT_TRUE(find_text(image, below, label, color::text, s)) << label;
  const meshtour::PlotRect left{0, map.y0 - 10, map.x0, map.y1 + 10};
  for (const char* label : {"0.25", "0.5", "0.75", "1"}) EXPECT_TRUE(find_text(image, left, label, color::text, s)) << label;
  EXPECT_TRUE(find_text(image, {0, 0, layout.width, map.y0}, "height (fraction of the bounding cylinder", color::text, s));
  // 360° is right of 0°, 1 above 0.25.
  EXPECT_GT(find_text(image, below, "360°", color::text, s)->first, find_text(image, below, "0°", color::text, s)->first + 1000);
  EXPECT_LT(find_text(image, left, "1", color::text, s)->second, find_text(image, left, "0.25", color::text, s)->second - 300);

  // The legend names every mark and shows a sample of it in its colour.
  const meshtour::PlotRect& legend = layout.legend;
  for (const char* label : {"base curve", "gaze", "position", "control point", "start", "empty cell"})
    EXPECT_TRUE(find_text(image, legend, label, color::legend_text, s)) << label;
  for (const auto& c : {color::base, color::gaze, color::position, color::start, color::empty_cell, color::control_ring})
    EXPECT_GT(count(legend, c), 20) << int(c[0]) << "," << int(c[1]) << "," << int(c[2]);
  // The curves themselves are on the heat map.
  EXPECT_GT(count(map, color::gaze), 500);
  EXPECT_GT(count(map, color::position), 500);
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

// --up auto (mesh/up_axis.h) on a tower standing on a wide plinth with +z up: the path says the
// choice and why, and circles +z.
TEST(CliPath, UpAutoFindsThePlinth) {
  const fs::path dir = meshtour::test::scratch_dir();
  std::ofstream obj(dir / "plinth.obj");
  const auto box = [&](int base, double x, double y, double z0, double z1) {
    for (int i = 0; i < 8; ++i) obj << "v " << (i & 1 ? x : -x) << ' ' << (i & 2 ? y : -y) << ' ' << (i & 4 ? z1 : z0) << "\n";
    for (const auto& q : {std::array{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}})
      obj << "f " << base + q[0] << ' ' << base + q[1] << ' ' << base + q[2] << ' ' << base + q[3] << "\n";
  };
  box(1, 1.0, 1.0, 0.0, 0.3);
  box(9, 0.4, 0.4, 0.3, 2.0);
  obj.close();
  const auto result = run_meshtour("path '" + (dir / "plinth.obj").string() + "' --up auto --path turntable --camera-frames '" +
                                   (dir / "cameras.json").string() + "'");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("--up auto: +z (rests on its -z side"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("up +z)"), std::string::npos) << result.output;
}

// Occurrences of `word` in `text`.
int count_of(const std::string& text, const std::string& word) {
  int n = 0;
  for (auto at = text.find(word); at != std::string::npos; at = text.find(word, at + word.size())) ++n;
  return n;
}

// Every path mode writes a path file (`path -o`), from which `tour --path-file` renders, without
// a search, the very frames and video `tour --path MODE` renders; a tour whose settings differ
// from those the path was made for is refused with the setting named.
TEST(CliPath, EveryModeWritesAPathFileThatRendersTheModesOwnFrames) {
  MESHTOUR_SKIP_UNDER_SANITIZERS("renders every path mode from its file and compares bytes; the Release pass checks them, the path-file reader runs under the sanitizers in BadInputCorpus.PathFiles and the fuzz target");
  const fs::path dir = meshtour::test::scratch_dir();
  meshtour::save_mesh(meshtour::test_meshes::bumpy_sphere(3), dir / "bumpy.obj");
  const std::string mesh = meshtour::test::shell_quoted(dir / "bumpy.obj");
  const std::string settings = " --up y --frames 4 --width 64 --height 36";
  for (const std::string mode : {"feature-orbit", "turntable", "paper"}) {
    const fs::path file = dir / (mode + ".path.json");
    auto r = run_meshtour("path " + mesh + " --path " + mode + settings + " -o " + meshtour::test::shell_quoted(file));
    ASSERT_EQ(r.exit_code, 0) << mode << ": " << r.output;
    const nlohmann::json j = read_json(file);
    EXPECT_EQ(j["format_version"], 2) << mode;
    EXPECT_EQ(j["mode"], mode);
    EXPECT_EQ(j["made_for"]["up"], "+y") << mode;
    if (mode != "paper") {
      EXPECT_EQ(j["made_for"]["aspect"], "1.7777777777777777") << mode;
    }
    if (mode == "feature-orbit") {
      EXPECT_EQ(j["frames"], 4);
      EXPECT_EQ(j["frame_scores"].size(), 4u);
    }
    const std::string tour = "tour " + mesh + settings + " --spp 1 --preset plain --crf 18";
    const fs::path a = dir / (mode + "-file"), b = dir / (mode + "-mode");
    r = run_meshtour(tour + " --path-file " + meshtour::test::shell_quoted(file) + " --frames-dir " + meshtour::test::shell_quoted(a) +
                     " -o " + meshtour::test::shell_quoted(a.string() + ".mp4") + " --progress none");
    ASSERT_EQ(r.exit_code, 0) << mode << ": " << r.output;
    EXPECT_EQ(count_of(r.output, "path search:"), 0) << mode << ": the tour searched although it was given the path: " << r.output;
    r = run_meshtour(tour + " --path " + mode + " --frames-dir " + meshtour::test::shell_quoted(b) + " -o " +
                     meshtour::test::shell_quoted(b.string() + ".mp4") + " --progress none");
    ASSERT_EQ(r.exit_code, 0) << mode << ": " << r.output;
    EXPECT_EQ(count_of(r.output, "path search:"), mode == "turntable" ? 0 : 1) << mode << ": " << r.output;
    for (int k = 0; k < 4; ++k) {
      const std::string frame = "frame_00000" + std::to_string(k) + ".png";
      EXPECT_TRUE(meshtour::test::file_bytes(a / frame) == meshtour::test::file_bytes(b / frame)) << mode << " " << frame;
    }
    EXPECT_TRUE(meshtour::test::file_bytes(a.string() + ".mp4") == meshtour::test::file_bytes(b.string() + ".mp4")) << mode;
  }
  // Other settings than the path was made for: exit 2, one line naming the setting and both values
  // (`render` calls the tour's length --frame-count).
  const std::string orbit = " --path-file " + meshtour::test::shell_quoted(dir / "feature-orbit.path.json");
  const std::pair<std::string, std::string> mismatches[] = {
      {" --up y --frame-count 4 --width 64 --height 48", "aspect 1.7777777777777777, but this render has aspect 1.3333333333333333"},
      {" --up y --frame-count 6 --width 64 --height 36", "frames 4, but this render has frames 6"},
      {" --up z --frame-count 4 --width 64 --height 36", "up +y, but this render has up +z"},
      {" --up y --frame-count 4 --width 64 --height 36 --fov 30", "fov auto, but this render has fov 30"},
      {" --up y --frame-count 4 --width 64 --height 36 --tolerance 0.004", "path-search"}};
  for (const auto& [other, words] : mismatches) {
    const auto r = run_meshtour("render " + mesh + orbit + other + " --spp 1 --out-dir " + meshtour::test::shell_quoted(dir / "refused") + " -q");
    EXPECT_EQ(r.exit_code, 2) << other << ": " << r.output;
    EXPECT_EQ(count_lines(r.output), 1) << other << ": " << r.output;
    EXPECT_NE(r.output.find(words), std::string::npos) << other << ": " << r.output;
  }
  EXPECT_FALSE(fs::exists(dir / "refused"));
  // The turntable was fitted to its elevation.
  const auto r = run_meshtour("render " + mesh + " --path-file " + meshtour::test::shell_quoted(dir / "turntable.path.json") +
                              " --up y --frame-count 4 --width 64 --height 36 --elevation 40 --out-dir " + meshtour::test::shell_quoted(dir / "refused") + " -q");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("made for elevation 18, but this render has elevation 40"), std::string::npos) << r.output;
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
  // A flag of another command, or another command's name for the same setting, says where it belongs.
  const std::pair<std::string, std::string> misplaced[] = {
      {"tour '" + mesh.string() + "' --frame-count 12 -o '" + (dir / "t.mp4").string() + "'", "tour takes it as --frames"},
      {"path '" + mesh.string() + "' --crf 18" + out, "--crf is an option of tour, batch, farm slurm and encode, not of path"}};
  for (const auto& [command, hint] : misplaced) {
    const auto result = run_meshtour(command);
    EXPECT_EQ(result.exit_code, 2) << result.output;
    EXPECT_EQ(count_lines(result.output), 1) << result.output;
    EXPECT_NE(result.output.find(hint), std::string::npos) << result.output;
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

TEST(CliPath, MemoryEstimateIsTheModesOwn) {
  // `path` estimates what the chosen mode holds, as `tour` does: the paper path's stages (about
  // 1.8 kB a face), or the coverage model and the ray-tracing scene of the feature orbit. It once
  // estimated the paper's stages for every mode and refused the 17.8M-face bunny's orbit (38 GiB
  // estimated) that a whole tour runs in 2.9 GB.
  const fs::path dir = meshtour::test::scratch_dir();
  meshtour::save_mesh(meshtour::test_meshes::icosphere(5), dir / "ball.ply");
  const auto estimate_of = [&](const std::string& mode) {
    const auto r = run_meshtour("path " + meshtour::test::shell_quoted(dir / "ball.ply") + " --up y --path " + mode + " -q --max-memory 1M -o " +
                                meshtour::test::shell_quoted(dir / (mode + ".json")));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("needs an estimated"), std::string::npos) << r.output;
    return r.output;
  };
  const std::string paper = estimate_of("paper"), orbit = estimate_of("feature-orbit"), turntable = estimate_of("turntable");
  // The parts are listed as "(runtime …, mesh …, <part> …)".
  EXPECT_EQ(paper.find("ray-tracing scene"), std::string::npos) << paper;
  EXPECT_NE(paper.find(", camera path "), std::string::npos) << paper;
  EXPECT_NE(orbit.find(", ray-tracing scene "), std::string::npos) << orbit;
  EXPECT_NE(orbit.find(", camera path "), std::string::npos) << orbit;
  EXPECT_EQ(turntable.find(", camera path "), std::string::npos) << turntable;
  EXPECT_EQ(turntable.find("ray-tracing scene"), std::string::npos) << turntable;
  EXPECT_NE(paper, orbit);
}

}  // namespace
