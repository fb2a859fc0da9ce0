// Posters, captions and title cards (tour, render + encode): the poster is frame 0 (the preferred
// view) byte for byte, captions exist only in the video, land where asked, render UTF-8, and a caption
// that does not fit is refused with the limit named.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "golden.h"
#include "helpers.h"
#include "video_probe.h"

namespace meshtour {
namespace {

namespace fs = std::filesystem;
using test::probe_video;
using test::run_meshtour;
using test::scratch_dir;

constexpr int kTourWidth = 192, kTourHeight = 108, kTourFrames = 6;
const std::string kCaption = "Nefertiti — ÄM 21300";  // an em dash and an umlaut


std::string tour_size() {
  return " --frames " + std::to_string(kTourFrames) + " --width " + std::to_string(kTourWidth) + " --height " +
         std::to_string(kTourHeight) + " --spp 1";
}

int best_view_frame(const fs::path& frames_dir) {
  std::ifstream in(frames_dir / "meshtour-frames.json");
  const auto j = nlohmann::json::parse(in);
  return j.value("best_view_frame", -1);
}

fs::path frame_png(const fs::path& dir, int k) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%06d.png", k);
  return dir / name;
}

// The rendered frames of the default scene, once per test (render writes what tour would). The
// caption tests take the turntable: no path search, so they stay quick under the sanitizers.
fs::path render_frames(const fs::path& root, const std::string& path = "turntable") {
  const auto r = run_meshtour("render -q --frame-count " + std::to_string(kTourFrames) + " --width " + std::to_string(kTourWidth) +
                              " --height " + std::to_string(kTourHeight) + " --spp 1 --path " + path + " --out-dir " + test::shell_quoted(root / "frames"));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return root / "frames";
}

TEST(CliPoster, IsTheFirstFrameByteForByteFromTourAndFromEncode) {
  MESHTOUR_SKIP_UNDER_SANITIZERS("the poster of two commands compared byte for byte; the Release pass checks it");
  const fs::path root = scratch_dir();
  const auto tour = run_meshtour("tour -q" + tour_size() + " --frames-dir " + test::shell_quoted(root / "tour-frames") + " -o " +
                                 test::shell_quoted(root / "tour.mp4") + " --poster " + test::shell_quoted(root / "tour-poster.png"));
  ASSERT_EQ(tour.exit_code, 0) << tour.output;
  ASSERT_GE(best_view_frame(root / "tour-frames"), 0) << "the feature orbit scores every frame";
  const std::string poster = test::file_bytes(root / "tour-poster.png");
  ASSERT_FALSE(poster.empty());
  // Frame 0: the feature orbit starts at its preferred view, whichever frame covers most.
  EXPECT_TRUE(poster == test::file_bytes(frame_png(root / "tour-frames", 0))) << "tour's poster is not frame 0";

  // A farm: render writes the frames, encode writes the poster.
  const fs::path frames = render_frames(root, "feature-orbit");
  const auto enc = run_meshtour("encode -q " + test::shell_quoted(frames) + " -o " + test::shell_quoted(root / "farm.mp4") + " --poster " +
                                test::shell_quoted(root / "farm-poster.png"));
  ASSERT_EQ(enc.exit_code, 0) << enc.output;
  EXPECT_TRUE(test::file_bytes(root / "farm-poster.png") == poster) << "encode's poster differs from tour's";

  // Another size: cropped and resampled, the same from both.
  const auto sized = run_meshtour("encode -q " + test::shell_quoted(frames) + " -o " + test::shell_quoted(root / "farm2.mp4") + " --poster " +
                                  test::shell_quoted(root / "square.png") + " --poster-size 64x64");
  ASSERT_EQ(sized.exit_code, 0) << sized.output;
  OIIO::ImageBuf square((root / "square.png").string());
  ASSERT_TRUE(square.read());
  EXPECT_EQ(square.spec().width, 64);
  EXPECT_EQ(square.spec().height, 64);
}

TEST(CliPoster, BadSizeAndNameAreRefused) {
  const fs::path root = scratch_dir();
  auto r = run_meshtour("tour -q" + tour_size() + " -o " + test::shell_quoted(root / "t.mp4") + " --poster " + test::shell_quoted(root / "p.png") +
                        " --poster-size 65x64");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("even"), std::string::npos) << r.output;
  r = run_meshtour("tour -q" + tour_size() + " -o " + test::shell_quoted(root / "t.mp4") + " --poster " + test::shell_quoted(root / "p.jpg"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("*.png"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(root / "t.mp4"));
}

// FFV1 is lossless: the decoded frames are exactly what the caption filter drew.
std::vector<std::uint8_t> first_frame(const fs::path& video) {
  const auto p = probe_video(video, {0});
  return p.rgb_frames.at(0);
}

// Pixels of `rgb` that differ from `clean`, counted inside and outside the box [x0, x1) x [y0, y1).
std::pair<int, int> changed(const std::vector<std::uint8_t>& rgb, const std::vector<std::uint8_t>& clean, int x0, int y0,
                            int x1, int y1) {
  int inside = 0, outside = 0;
  for (int y = 0; y < kTourHeight; ++y)
    for (int x = 0; x < kTourWidth; ++x) {
      const std::size_t i = (static_cast<std::size_t>(y) * kTourWidth + x) * 3;
      const bool differs = rgb[i] != clean[i] || rgb[i + 1] != clean[i + 1] || rgb[i + 2] != clean[i + 2];
      const bool in = x >= x0 && x < x1 && y >= y0 && y < y1;
      (in ? inside : outside) += differs;
    }
  return {inside, outside};
}

TEST(CliCaption, IsBurnedWhereAskedIntoTheVideoOnlyAndMatchesTheGolden) {
  const fs::path root = scratch_dir();
  const fs::path frames = render_frames(root);
  const std::string before = test::file_bytes(frame_png(frames, 0));
  auto r = run_meshtour("encode -q " + test::shell_quoted(frames) + " -o " + test::shell_quoted(root / "clean.mkv"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_meshtour("encode -q " + test::shell_quoted(frames) + " -o " + test::shell_quoted(root / "bottom-left.mkv") + " --caption '" + kCaption + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_meshtour("encode -q " + test::shell_quoted(frames) + " -o " + test::shell_quoted(root / "top-right.mkv") + " --caption '" + kCaption +
                   "' --caption-position top-right");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(test::file_bytes(frame_png(frames, 0)) == before) << "encode changed a frame file";

  const auto clean = first_frame(root / "clean.mkv");
  const auto bottom_left = first_frame(root / "bottom-left.mkv");
  const auto top_right = first_frame(root / "top-right.mkv");
  // The lower-left quarter-height band holds the caption; nothing else changes.
  const auto [bl_in, bl_out] = changed(bottom_left, clean, 0, kTourHeight * 3 / 4, kTourWidth * 7 / 8, kTourHeight);
  EXPECT_GT(bl_in, 300) << "the bottom-left caption is missing";
  EXPECT_EQ(bl_out, 0) << "the bottom-left caption spills outside its corner";
  const auto [tr_in, tr_out] = changed(top_right, clean, kTourWidth / 8, 0, kTourWidth, kTourHeight / 4);
  EXPECT_GT(tr_in, 300) << "the top-right caption is missing";
  EXPECT_EQ(tr_out, 0) << "the top-right caption spills outside its corner";

  // The caption's band against the golden crop (text raster by FreeType: stable across CPUs; the
  // tolerance absorbs a renderer pixel flipping behind the half-transparent box).
  const fs::path out_dir = fs::path(MESHTOUR_BINARY_DIR) / "golden-results";
  fs::create_directories(out_dir);
  const int band = kTourHeight / 4;
  OIIO::ImageBuf crop(OIIO::ImageSpec(kTourWidth, band, 3, OIIO::TypeDesc::UINT8));
  crop.set_pixels(crop.roi(), OIIO::TypeDesc::UINT8, bottom_left.data() + static_cast<std::size_t>(kTourHeight - band) * kTourWidth * 3);
  const fs::path actual = out_dir / "caption_bottom_left.actual.png";
  ASSERT_TRUE(crop.write(actual.string()));
  test::compare_png_with_golden(actual, "caption_bottom_left", 0.02);
}

TEST(CliCaption, TooLongIsAnErrorNamingTheLimit) {
  const fs::path root = scratch_dir();
  const fs::path frames = render_frames(root);
  const auto r = run_meshtour("encode -q " + test::shell_quoted(frames) + " -o " + test::shell_quoted(root / "long.mp4") +
                              " --caption 'The Bust of Nefertiti, painted limestone, Amarna, about 1345 BC — ÄM 21300'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("holds at most"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--caption-size"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(root / "long.mp4"));
  // tour refuses it before rendering anything.
  const auto t = run_meshtour("tour -q" + tour_size() + " -o " + test::shell_quoted(root / "t.mp4") +
                              " --caption 'The Bust of Nefertiti, painted limestone, Amarna, about 1345 BC'");
  EXPECT_EQ(t.exit_code, 2) << t.output;
  EXPECT_NE(t.output.find("holds at most"), std::string::npos) << t.output;
  EXPECT_FALSE(fs::exists(root / "t.mp4"));
}

TEST(CliCaption, InvalidUtf8AndStrayOptionsAreRefused) {
  const fs::path root = scratch_dir();
  const fs::path frames = render_frames(root);
  auto r = run_meshtour("encode -q " + test::shell_quoted(frames) + " -o " + test::shell_quoted(root / "a.mp4") + " --caption \"$(printf 'bad \\377 byte')\"");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("UTF-8"), std::string::npos) << r.output;
  r = run_meshtour("encode -q " + test::shell_quoted(frames) + " -o " + test::shell_quoted(root / "a.mp4") + " --caption-size 20");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("without --caption"), std::string::npos) << r.output;
}

TEST(CliCaption, TitleCardOpensOnThePosterAndFadesIntoTheTour) {
  const fs::path root = scratch_dir();
  const fs::path frames = render_frames(root);
  // 1 s at 10 fps: 7 card frames, then the fade (3 frames) into the 6 tour frames.
  const auto r = run_meshtour("encode -q " + test::shell_quoted(frames) + " --fps 10 -o " + test::shell_quoted(root / "card.mkv") + " --caption '" + kCaption +
                              "' --title-card 1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto clean = run_meshtour("encode -q " + test::shell_quoted(frames) + " --fps 10 -o " + test::shell_quoted(root / "clean.mkv"));
  ASSERT_EQ(clean.exit_code, 0) << clean.output;
  const auto card = probe_video(root / "card.mkv", {0, 6});
  EXPECT_EQ(card.decoded_frames, 7 + kTourFrames);
  EXPECT_TRUE(card.rgb_frames[0] == card.rgb_frames[1]) << "the card holds still until the fade";
  const auto tour = probe_video(root / "clean.mkv", {0});
  EXPECT_FALSE(card.rgb_frames[0] == tour.rgb_frames[0]) << "the card shows no caption";
}

// tour with a title card: the same clip length as encode's, the poster still the clean first frame.
TEST(CliCaption, TourTitleCardAndPosterTogether) {
  const fs::path root = scratch_dir();
  const auto r = run_meshtour("tour -q" + tour_size() + " --path turntable --fps 10 --frames-dir " + test::shell_quoted(root / "frames") + " -o " +
                              test::shell_quoted(root / "t.mp4") + " --caption '" + kCaption + "' --title-card 1 --poster " + test::shell_quoted(root / "p.png"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(probe_video(root / "t.mp4").decoded_frames, 7 + kTourFrames);
  EXPECT_TRUE(test::file_bytes(root / "p.png") == test::file_bytes(frame_png(root / "frames", 0))) << "the poster has a caption";
}

}  // namespace
}  // namespace meshtour
