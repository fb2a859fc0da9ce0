// `meshtour tour|path scene.svx.json` on a Voyager scene written here from the SVX schema: a
// figure stored Z-up in millimetres whose document stands it up (its rotation) in a centimetre
// scene. The tour is upright (+y, the figure's height along it), frame 0 looks from the opening
// view (orbit angles) within 2 degrees of azimuth and elevation in every path mode, the highest
// Web3D derivative on disk is the one toured unless --quality says otherwise, and the collection
// title is the caption unless --caption is given.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "helpers.h"

// A namespace of its own: the unity build puts this file beside the other CLI tests.
namespace voyager_cli_test {
namespace {

namespace fs = std::filesystem;
using meshtour::test::run_meshtour;
using meshtour::test::shell_quoted;

constexpr double kDeg = std::numbers::pi / 180.0;

// A figure standing along +z (millimetres): a 40 x 30 plinth 10 high, a body 20 x 14 up to 90, a
// head 12 wide up to 110, and an arm out along +x; no mirror plane across x, so the shape has a
// front. `scale` shrinks it for a low-quality derivative.
std::string figure_obj(double scale = 1.0) {
  std::ostringstream s;
  int base = 0;
  const auto box = [&](double x0, double y0, double z0, double x1, double y1, double z1) {
    for (int k = 0; k < 8; ++k)
      s << "v " << scale * (k & 1 ? x1 : x0) << ' ' << scale * (k & 2 ? y1 : y0) << ' ' << scale * (k & 4 ? z1 : z0) << "\n";
    static const int q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& f : q) s << "f " << base + f[0] + 1 << ' ' << base + f[1] + 1 << ' ' << base + f[2] + 1 << ' ' << base + f[3] + 1 << "\n";
    base += 8;
  };
  box(-20, -15, 0, 20, 15, 10);
  box(-10, -7, 10, 10, 7, 90);
  box(-6, -6, 90, 6, 6, 110);
  box(10, -3, 60, 28, 3, 66);
  return s.str();
}

struct Written {
  fs::path dir, document;
};

// The scene: Low and High derivatives on disk, Highest listed but absent; orbit (-20, 30, 0).
Written write_scene(const std::string& orbit = "[-20, 30, 0]") {
  Written w;
  w.dir = meshtour::test::scratch_dir();
  std::ofstream(w.dir / "figure-high.obj") << figure_obj();
  std::ofstream(w.dir / "figure-low.obj") << figure_obj(0.5);
  w.document = w.dir / "figure.svx.json";
  std::ofstream(w.document) << R"({"asset": {"type": "application/si-dpo-3d.document+json", "version": "1.0"},
    "scene": 0, "scenes": [{"nodes": [0, 1], "setup": 0, "meta": 0}],
    "nodes": [{"name": "Camera", "camera": 0}, {"name": "Figure", "model": 0}],
    "cameras": [{"type": "perspective", "perspective": {"yfov": 52, "znear": 0.1}}],
    "setups": [{"units": "cm", "navigation": {"type": "Orbit", "autoZoom": true,
                "orbit": {"orbit": )" + orbit + R"(, "offset": [0, 0, 150]}}}],
    "metas": [{"collection": {"title": "Figure on a plinth"}}],
    "models": [{"units": "mm", "rotation": [-0.70710678, 0, 0, 0.70710678],
      "derivatives": [
        {"usage": "Web3D", "quality": "Low", "assets": [{"uri": "figure-low.obj", "type": "Model"}]},
        {"usage": "Web3D", "quality": "High", "assets": [{"uri": "figure-high.obj", "type": "Model"}]},
        {"usage": "Web3D", "quality": "Highest", "assets": [{"uri": "figure-highest.glb", "type": "Model"}]}]}]})";
  return w;
}

struct View {
  double azimuth_deg, elevation_deg;  // of the eye about the target; azimuth from +z towards +x, around +y
  double up_y;
};

// Frame `k`'s view from a --camera-frames CSV.
View frame_view(const fs::path& csv, int k = 0) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);  // header
  for (int i = 0; i <= k; ++i) std::getline(in, line);
  std::vector<double> v;
  std::stringstream ss(line);
  for (std::string cell; std::getline(ss, cell, ',');) v.push_back(std::stod(cell));
  EXPECT_GE(v.size(), 11u) << line;
  if (v.size() < 11) return {};
  const double dx = v[2] - v[5], dy = v[3] - v[6], dz = v[4] - v[7];
  const double r = std::sqrt(dx * dx + dy * dy + dz * dz);
  return {std::atan2(dx, dz) / kDeg, std::asin(dy / r) / kDeg, v[9]};
}

double angle_apart(double a, double b) { return std::abs(std::remainder(a - b, 360.0)); }

TEST(VoyagerScene, FrameZeroIsTheOpeningViewInEveryPathMode) {
  const Written w = write_scene();
  for (const char* mode : {"feature-orbit", "turntable", "paper"}) {
    SCOPED_TRACE(mode);
    const fs::path csv = w.dir / (std::string(mode) + ".csv");
    const auto r = run_meshtour("path " + shell_quoted(w.document) + " --path " + mode + " --frames 24 --threads 1 -o " +
                                shell_quoted(w.dir / (std::string(mode) + ".path.json")) + " --camera-frames " + shell_quoted(csv));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const View v = frame_view(csv);
    // Voyager: pitch -20 is 20 degrees above, head 30 is 30 degrees round from +z towards +x.
    EXPECT_LT(angle_apart(v.azimuth_deg, 30.0), 2.0) << v.azimuth_deg;
    EXPECT_LT(std::abs(v.elevation_deg - 20.0), 2.0) << v.elevation_deg;
    EXPECT_GT(v.up_y, 0.99);  // upright: the camera's up is Voyager's +y
  }
}

TEST(VoyagerScene, TourIsUprightWithTheHighestDerivativeAndTheTitleAsCaption) {
  const Written w = write_scene();
  const fs::path out = w.dir / "figure.mp4", csv = w.dir / "tour.csv";
  const auto r = run_meshtour("tour " + shell_quoted(w.document) + " --width 160 --height 120 --frames 2 --spp 1 --threads 1 -o " +
                              shell_quoted(out) + " --camera-frames " + shell_quoted(csv));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(out));
  EXPECT_NE(r.output.find("the High Web3D derivative"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("figure-high.obj"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("caption: \"Figure on a plinth\""), std::string::npos) << r.output;
  // Upright: up +y, and the figure's 11 cm (110 mm in a cm scene) of height along it.
  EXPECT_NE(r.output.find("up +y"), std::string::npos) << r.output;
  const auto bounds = r.output.find("bounds (");
  ASSERT_NE(bounds, std::string::npos) << r.output;
  double lo[3], hi[3];
  ASSERT_EQ(std::sscanf(r.output.c_str() + bounds, "bounds (%lf %lf %lf) - (%lf %lf %lf)", &lo[0], &lo[1], &lo[2], &hi[0], &hi[1], &hi[2]), 6)
      << r.output.substr(bounds, 80);
  EXPECT_NEAR(hi[1] - lo[1], 11.0, 1e-3);
  EXPECT_NEAR(hi[0] - lo[0], 4.8, 1e-3);  // plinth's -2 cm to the arm's 2.8 cm
  EXPECT_NEAR(hi[2] - lo[2], 3.0, 1e-3);
  const View v = frame_view(csv);
  EXPECT_LT(angle_apart(v.azimuth_deg, 30.0), 2.0) << v.azimuth_deg;
  EXPECT_LT(std::abs(v.elevation_deg - 20.0), 2.0) << v.elevation_deg;

  // --quality and --caption.
  const auto low = run_meshtour("tour " + shell_quoted(w.document) + " --quality low --caption Mine --width 160 --height 120 --frames 2 "
                                "--spp 1 --threads 1 -o " + shell_quoted(w.dir / "low.mp4"));
  ASSERT_EQ(low.exit_code, 0) << low.output;
  EXPECT_NE(low.output.find("figure-low.obj"), std::string::npos) << low.output;
  EXPECT_EQ(low.output.find("caption: \"Figure"), std::string::npos) << low.output;
  // With alpha a caption cannot be drawn: the title is left out, saying so, where --caption would fail.
  const auto alpha = run_meshtour("tour " + shell_quoted(w.document) + " --background transparent --alpha --width 160 --height 120 "
                                  "--frames 2 --spp 1 --threads 1 -o " + shell_quoted(w.dir / "alpha.mov"));
  EXPECT_EQ(alpha.exit_code, 0) << alpha.output;
  EXPECT_NE(alpha.output.find("the document's title is not captioned"), std::string::npos) << alpha.output;
}

// info describes the derivative a tour would load, posed: upright (+y by shape too) in centimetres.
TEST(VoyagerScene, InfoDescribesThePosedDerivative) {
  const Written w = write_scene();
  const auto r = run_meshtour("info " + shell_quoted(w.document));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("the High derivative"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("units mm in a cm scene"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("title \"Figure on a plinth\""), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("up axis (--up auto): +y"), std::string::npos) << r.output;
}

// A batch manifest's mesh may be a Voyager document: the video is named after it (figure.mp4, not
// figure.svx.mp4) and captioned with its title.
TEST(VoyagerScene, BatchItemsTakeDocuments) {
  const Written w = write_scene();
  std::ofstream(w.dir / "m.csv") << "mesh\nfigure.svx.json\n";
  const auto r = run_meshtour("batch " + shell_quoted(w.dir / "m.csv") + " --out-dir " + shell_quoted(w.dir / "v") +
                              " --frames 2 --width 160 --height 120 --spp 1 --progress none");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(w.dir / "v" / "figure.mp4")) << r.output;
  std::ifstream in(w.dir / "v" / "batch-summary.json");
  const std::string summary((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(summary.find("Figure on a plinth"), std::string::npos) << summary;
}

TEST(VoyagerScene, OpeningViewFromBelowIsRaisedToTheFloor) {
  // Pitch +30 looks up from below the model's centre: the floor rule raises it to level.
  const Written w = write_scene("[30, -60, 0]");
  const fs::path csv = w.dir / "below.csv";
  const auto r = run_meshtour("path " + shell_quoted(w.document) + " --path turntable --frames 24 -o " + shell_quoted(w.dir / "p.path.json") +
                              " --camera-frames " + shell_quoted(csv));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (int k = 0; k < 24; ++k) EXPECT_GE(frame_view(csv, k).elevation_deg, -1e-6) << "frame " << k;
  EXPECT_LT(angle_apart(frame_view(csv).azimuth_deg, -60.0), 2.0);
}

}  // namespace
}  // namespace voyager_cli_test
