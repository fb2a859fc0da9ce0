// End-to-end tests of `meshtour tour`: the real executable, the real files, an independent decoder.
#include <gtest/gtest.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "helpers.h"
#include "video_probe.h"

namespace meshtour {
namespace {

using test::run_meshtour;


std::size_t count_files(const std::filesystem::path& dir) {
  std::size_t n = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) n += e.is_regular_file();
  return n;
}

// Mean absolute difference (0..255) between a decoded frame and the PNG the same run wrote.
double mean_abs_diff(const std::vector<std::uint8_t>& rgb, const std::filesystem::path& png) {
  OIIO::ImageBuf image(png.string());
  EXPECT_TRUE(image.read(0, 0, true, OIIO::TypeDesc::UINT8));
  const auto& spec = image.spec();
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(spec.width) * spec.height * 3);
  image.get_pixels(OIIO::ROI(0, spec.width, 0, spec.height, 0, 1, 0, 3), OIIO::TypeDesc::UINT8, pixels.data());
  EXPECT_EQ(pixels.size(), rgb.size());
  double sum = 0;
  for (std::size_t i = 0; i < std::min(pixels.size(), rgb.size()); ++i) sum += std::abs(int(pixels[i]) - int(rgb[i]));
  return sum / static_cast<double>(rgb.size());
}

TEST(TourCommand, DefaultSceneVideoHasEveryFrameAndMatchesThePngs) {
  const auto dir = test::scratch_dir();
  const auto video = dir / "default.mp4";
  const auto frames = dir / "frames";
  const auto r = run_meshtour("tour -o " + test::shell_quoted(video) + " --frames 12 --fps 24 --width 160 --height 120 --spp 4 --frames-dir " +
                              test::shell_quoted(frames) + " --format png+exr --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(count_files(frames), 25u);  // 12 PNG + 12 EXR + the manifest (meshtour-frames.json)
  const auto probe = test::probe_video(video, {0, 7});
  EXPECT_EQ(probe.codec, "h264");
  EXPECT_EQ(probe.pixel_format, "yuv420p");
  EXPECT_EQ(probe.width, 160);
  EXPECT_EQ(probe.height, 120);
  EXPECT_EQ(probe.stream_frames, 12);
  EXPECT_EQ(probe.decoded_frames, 12);
  EXPECT_NEAR(probe.fps, 24.0, 1e-9);
  EXPECT_NEAR(probe.duration_seconds, 0.5, 1e-3);
  // A decoded frame matches its own PNG closely (chroma subsampling and CRF 18 only; 4 spp, so
  // the frame is not mostly 1-spp grain, which H.264 keeps least faithfully), and clearly
  // does not match another frame of the turntable: the check can tell frames apart.
  const double same = mean_abs_diff(probe.rgb_frames[0], frames / "frame_000000.png");
  const double other = mean_abs_diff(probe.rgb_frames[1], frames / "frame_000000.png");
  EXPECT_LT(same, 2.5);
  EXPECT_GT(other, 2.0 * same + 1.0);
  EXPECT_LT(mean_abs_diff(probe.rgb_frames[1], frames / "frame_000007.png"), 2.5);
}

TEST(TourCommand, SecondsAndFpsGiveTheFrameCount) {
  const auto dir = test::scratch_dir();
  const auto r = run_meshtour("tour -o " + test::shell_quoted(dir / "t.mp4") + " --seconds 0.5 --fps 10 --width 64 --height 48 --spp 1 -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(test::probe_video(dir / "t.mp4").decoded_frames, 5);
}

TEST(TourCommand, BunnyTourShowsTheWholeModel) {
  MESHTOUR_SKIP_UNDER_SANITIZERS("a 70k-face tour measured for framing; the same pipeline runs under the sanitizers on small meshes");
  MESHTOUR_SHARED_MESH(bunny, "bunny.ply");
  const auto dir = test::scratch_dir();
  const auto video = dir / "bunny.mp4";
  // The plain preset has no ground plane, so the EXR alpha channel is exactly the model's coverage.
  const auto r = run_meshtour("tour " + test::shell_quoted(bunny) + " -o " + test::shell_quoted(video) + " --frames 48 --width 192 --height 108 --spp 1 --up y" +
                              " --preset plain --frames-dir " + test::shell_quoted(dir / "frames") + " --format exr -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto probe = test::probe_video(video);
  EXPECT_EQ(probe.stream_frames, 48);
  EXPECT_EQ(probe.decoded_frames, 48);
  // Every sixth frame: the model covers a real part of the image, and no model pixel touches the
  // border (the whole model is in view).
  for (int k = 0; k < 48; k += 6) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06d.exr", k);
    OIIO::ImageBuf image((dir / "frames" / name).string());
    ASSERT_TRUE(image.read(0, 0, true, OIIO::TypeDesc::FLOAT)) << name;
    ASSERT_GE(image.spec().nchannels, 4) << name;
    const int w = image.spec().width, h = image.spec().height;
    int model = 0, border = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const bool covered = image.getchannel(x, y, 0, 3) > 0.0f;
        model += covered;
        border += covered && (x == 0 || y == 0 || x == w - 1 || y == h - 1);
      }
    EXPECT_GT(model, w * h / 20) << name << ": the model covers too little of the frame";
    EXPECT_EQ(border, 0) << name << ": the model touches the frame border";
  }
}

TEST(TourCommand, PathFileAndTurntableModes) {
  MESHTOUR_SHARED_MESH(bunny, "bunny.ply");
  const auto dir = test::scratch_dir();
  // A path computed once and rendered elsewhere gives the same frames as the path computed in place.
  ASSERT_EQ(run_meshtour("path " + test::shell_quoted(bunny) + " --up y -o " + test::shell_quoted(dir / "bunny.path.json")).exit_code, 0);
  const std::string common = " --frames 6 --width 96 --height 54 --spp 1 --preset plain --frames-dir ";
  auto r = run_meshtour("tour " + test::shell_quoted(bunny) + " -o " + test::shell_quoted(dir / "a.mp4") + " --path-file " + test::shell_quoted(dir / "bunny.path.json") + common +
                        test::shell_quoted(dir / "from_file") + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_meshtour("tour " + test::shell_quoted(bunny) + " -o " + test::shell_quoted(dir / "b.mp4") + " --path paper --up y" + common + test::shell_quoted(dir / "in_place") + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_meshtour("tour " + test::shell_quoted(bunny) + " -o " + test::shell_quoted(dir / "c.mp4") + " --path turntable" + common + test::shell_quoted(dir / "turntable") + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (int k = 0; k < 6; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06d.png", k);
    OIIO::ImageBuf a((dir / "from_file" / name).string()), b((dir / "in_place" / name).string()),
        c((dir / "turntable" / name).string());
    const auto same = OIIO::ImageBufAlgo::compare(a, b, 1.0f / 255, 1.0f / 255);
    EXPECT_EQ(same.nfail, 0u) << name << ": path file and in-place path differ";
    const auto other = OIIO::ImageBufAlgo::compare(a, c, 1.0f / 255, 1.0f / 255);
    EXPECT_GT(other.nfail, 100u) << name << ": the turntable should not look like the paper path";
  }
}

struct BadInput {
  const char* name;
  std::string args;      // arguments after "tour"
  int exit_code;
  std::string message;   // must appear in the one-line error
};

TEST(TourCommand, BadInputGivesOneClearLineAndNoVideo) {
  const auto dir = test::scratch_dir();
  std::ofstream(dir / "garbage.ply") << "ply\nformat binary_little_endian 1.0\nelement vertex 99999999\n";
  std::ofstream(dir / "garbage.off") << "OFF\nthis is not a number\n\x01\x02";
  std::ofstream(dir / "empty.obj") << "# nothing here\n";
  std::ofstream(dir / "points.obj") << "v 0 0 0\nv 1 0 0\n";
  {
    OIIO::ImageBuf square(OIIO::ImageSpec(16, 16, 3, OIIO::TypeDesc::FLOAT));
    ASSERT_TRUE(square.write((dir / "square.exr").string()));
  }
  const std::vector<BadInput> cases = {
      {"missing file", test::shell_quoted(dir / "nope.ply"), 3, "no such file"},
      {"corrupt PLY", test::shell_quoted(dir / "garbage.ply"), 2, "corrupt PLY"},
      {"unreadable mesh", test::shell_quoted(dir / "garbage.off"), 2, "garbage.off"},
      {"empty mesh", test::shell_quoted(dir / "empty.obj"), 2, "no faces"},
      {"points only", test::shell_quoted(dir / "points.obj"), 2, "no faces"},
      {"unwritable output", "-o /proc/forbidden/x.mp4", 3, "x.mp4"},
      {"odd size", "--width 161 --height 121", 2, "even"},
      {"bad axis", "--up w", 2, "--up"},
      {"missing environment", "--environment " + test::shell_quoted(dir / "sky.hdr"), 3, "sky.hdr"},
      {"square environment", "--environment " + test::shell_quoted(dir / "square.exr"), 2, "twice as wide as high"},
  };
  for (const auto& c : cases) {
    const auto video = dir / (std::string(c.name) + ".mp4");
    std::string args = c.args;
    if (args.find("-o ") == std::string::npos) args += " -o " + test::shell_quoted(video);
    if (args.find("--width") == std::string::npos) args += " --width 64 --height 48";
    const auto r = run_meshtour("tour " + args + " --frames 2 -q");
    EXPECT_EQ(r.exit_code, c.exit_code) << c.name << ": " << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << c.name << ": " << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << c.name << ": " << r.output;
    EXPECT_FALSE(std::filesystem::exists(video)) << c.name;
  }
  // Nothing half-written anywhere: only the inputs remain.
  EXPECT_EQ(count_files(dir), 5u);
}

// --environment neutral lights the model with the built-in studio (brighter than the look's sky),
// in a tour and from a scene file's look.environment alike.
TEST(TourCommand, EnvironmentLightsTheModel) {
  const auto dir = test::scratch_dir();
  const auto poster_mean = [&](const std::string& name, const std::string& args) {
    const auto poster = dir / (name + ".png");
    const auto r = run_meshtour("tour " + args + " --frames 1 --width 96 --height 64 --spp 2 --path turntable -q --poster " +
                                test::shell_quoted(poster) + " -o " + test::shell_quoted(dir / (name + ".mp4")));
    EXPECT_EQ(r.exit_code, 0) << r.output;
    OIIO::ImageBuf image(poster.string());
    const auto stats = OIIO::ImageBufAlgo::computePixelStats(image);
    return stats.avg.empty() ? 0.0f : stats.avg[0];
  };
  const float none = poster_mean("none", ""), neutral = poster_mean("neutral", "--environment neutral");
  EXPECT_GT(neutral, none + 0.01f) << none << " vs " << neutral;
  std::ofstream(dir / "plain.json") << R"({"model": {"procedural": "sculpture"}})";
  std::ofstream(dir / "lit.json") << R"({"model": {"procedural": "sculpture"}, "look": {"environment": "neutral"}})";
  EXPECT_GT(poster_mean("lit", test::shell_quoted(dir / "lit.json")), poster_mean("plain", test::shell_quoted(dir / "plain.json")) + 0.01f);
}

// --size NAME: an unknown name is one line listing every name; a name with --width is refused;
// a named size reaches the path (planned for its aspect) without rendering a frame that large.
TEST(TourCommand, SizeByNameRefusesUnknownNamesWithTheList) {
  const auto dir = test::scratch_dir();
  auto r = run_meshtour("tour --size tall --frames 2 -q -o " + test::shell_quoted(dir / "x.mp4"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  for (const char* name : {"tall", "720p", "1080p", "1440p", "4k", "vertical", "vertical-720", "square", "portrait"})
    EXPECT_NE(r.output.find(name), std::string::npos) << name << ": " << r.output;
  r = run_meshtour("tour --size square --width 640 --frames 2 -q -o " + test::shell_quoted(dir / "x.mp4"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_NE(r.output.find("--width"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "x.mp4"));
  std::ofstream(dir / "tetra.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  r = run_meshtour("path " + test::shell_quoted(dir / "tetra.obj") + " --path turntable --size vertical --frames 2 -q -o " +
                   test::shell_quoted(dir / "p.json"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(test::file_bytes(dir / "p.json").find("\"aspect\": \"0.5625\""), std::string::npos) << test::file_bytes(dir / "p.json");
}

TEST(Cli, HelpAndVersion) {
  const auto help = run_meshtour("--help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.output.find("tour"), std::string::npos);
  EXPECT_NE(help.output.find("Exit codes"), std::string::npos);
  const auto tour_help = run_meshtour("tour --help");
  EXPECT_EQ(tour_help.exit_code, 0);
  for (const char* option : {"--width", "--height", "--fps", "--frames", "--seconds", "--up", "--frames-dir", "--format", "--threads", "--path"})
    EXPECT_NE(tour_help.output.find(option), std::string::npos) << option;
  const auto version = run_meshtour("--version");
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_NE(version.output.find("meshtour "), std::string::npos);
  EXPECT_NE(run_meshtour("").exit_code, 0);
  EXPECT_NE(run_meshtour("frobnicate").exit_code, 0);
}

}  // namespace
}  // namespace meshtour

namespace meshtour {
namespace {

// docs/OPTIONS.md is generated from the option registry; a stale copy fails here.
TEST(OptionsDoc, IsWhatTheRegistrySays) {
  const auto r = test::run_meshtour("options");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(test::source_dir() / "docs" / "OPTIONS.md", std::ios::binary);
  std::stringstream committed;
  committed << in.rdbuf();
  EXPECT_TRUE(r.output == committed.str())
      << "docs/OPTIONS.md is stale; regenerate it with: build-test/cli/meshtour options > docs/OPTIONS.md";
}

}  // namespace
}  // namespace meshtour
