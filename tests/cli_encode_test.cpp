// Tests for `meshtour encode`: a frames directory written here (small PNG/EXR frames and the
// manifest) is encoded by the real executable and the video read back with the test decoder.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "helpers.h"
#include "jobs/frame_dir.h"
#include "tracer/color.h"
#include "tracer/tracer.h"
#include "video_probe.h"

namespace meshtour {
namespace {

namespace fs = std::filesystem;
using test::probe_video;
using test::run_meshtour;
using test::scratch_dir;

constexpr int kWidth = 64;
constexpr int kHeight = 48;
constexpr int kFrames = 10;
constexpr int kFps = 25;

// Distinct, smooth frames: a wave sliding 3 px per frame over vertical and diagonal ramps.
std::vector<std::uint8_t> make_frame(int index, int width = kWidth, int height = kHeight) {
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(width) * height * 3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      std::uint8_t* p = &rgb[(static_cast<std::size_t>(y) * width + x) * 3];
      p[0] = static_cast<std::uint8_t>(std::lround(120 + 80 * std::sin(2 * 3.14159265358979 * (x + 3.0 * index) / width)));
      p[1] = static_cast<std::uint8_t>(50 + 120 * y / height);
      p[2] = static_cast<std::uint8_t>(200 - 100 * (x + y) / (width + height));
    }
  return rgb;
}

void write_png(const fs::path& file, const std::vector<std::uint8_t>& rgb, int width = kWidth, int height = kHeight) {
  auto out = OIIO::ImageOutput::create(file.string());
  ASSERT_TRUE(out);
  const OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
  ASSERT_TRUE(out->open(file.string(), spec));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, rgb.data()));
  ASSERT_TRUE(out->close());
}

// The manifest `render` would write for `count` PNG frames of the test's size and rate.
void write_test_frames_manifest(const fs::path& dir, int count) {
  FrameDirInfo info;
  info.frame_count = count;
  info.fps = kFps;
  info.width = kWidth;
  info.height = kHeight;
  info.image_formats = {"png"};
  info.source = "test";
  write_frame_dir_info(dir, info);
}

// kFrames PNG frames and, unless `manifest` is false, the manifest `render` would write.
fs::path make_frames_dir(const fs::path& dir, bool manifest = true) {
  fs::create_directories(dir);
  for (int k = 0; k < kFrames; ++k) write_png(frame_file(dir, k, "png"), make_frame(k));
  if (manifest) write_test_frames_manifest(dir, kFrames);
  return dir;
}


std::vector<std::string> entries(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  return names;
}


TEST(CliEncode, EncodesTheManifestsRangeAtItsRate) {
  const fs::path root = scratch_dir();
  const fs::path frames = make_frames_dir(root / "frames");
  const fs::path out = root / "out";
  fs::create_directory(out);
  const auto r = run_meshtour("encode " + test::shell_quoted(frames) + " -o " + test::shell_quoted(out / "tour.mp4"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // Progress on stderr (JSON lines, since it is not a terminal): frames done of total, then a summary.
  EXPECT_NE(r.output.find(R"("event":"encoded frame","done":10,"total":10)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(R"("event":"summary","what":"encoded frame","done":10,"total":10)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("wrote"), std::string::npos) << r.output;
  const auto probe = probe_video(out / "tour.mp4");
  EXPECT_EQ(probe.codec, "h264");
  EXPECT_EQ(probe.decoded_frames, kFrames);
  EXPECT_EQ(probe.width, kWidth);
  EXPECT_EQ(probe.height, kHeight);
  EXPECT_NEAR(probe.fps, kFps, 1e-9);
  EXPECT_EQ(entries(out), std::vector<std::string>{"tour.mp4"});
}

TEST(CliEncode, LosslessArchiveHoldsTheFramesExactly) {
  const fs::path root = scratch_dir();
  const fs::path frames = make_frames_dir(root / "frames");
  // The codec follows from the extension; --frames picks a stepped sub-range.
  const auto r = run_meshtour("encode " + test::shell_quoted(frames) + " -o " + test::shell_quoted(root / "a.mkv") + " --frames 1-9:2 -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(r.output.empty()) << "-q printed: " << r.output;
  const auto probe = probe_video(root / "a.mkv", {0, 4});
  EXPECT_EQ(probe.codec, "ffv1");
  EXPECT_EQ(probe.decoded_frames, 5);
  EXPECT_TRUE(probe.rgb_frames[0] == make_frame(1));
  EXPECT_TRUE(probe.rgb_frames[1] == make_frame(9));
}

TEST(CliEncode, MissingFramesAreAllNamedAndNothingIsWritten) {
  const fs::path root = scratch_dir();
  const fs::path frames = make_frames_dir(root / "frames");
  for (int k : {3, 4, 7}) fs::remove(frame_file(frames, k, "png"));
  const fs::path out = root / "out";
  fs::create_directory(out);
  const auto r = run_meshtour("encode " + test::shell_quoted(frames) + " -o " + test::shell_quoted(out / "tour.mp4"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("3 of 10 missing (3-4,7"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("frame_000003.png"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--frames 3-4,7"), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << "one error line expected: " << r.output;
  EXPECT_TRUE(fs::is_empty(out));

  // A range without the missing frames encodes.
  const auto ok = run_meshtour("encode " + test::shell_quoted(frames) + " -o " + test::shell_quoted(out / "tour.mp4") + " --frames 0-2,5-6,8-9 -q");
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_EQ(probe_video(out / "tour.mp4").decoded_frames, 7);
}

TEST(CliEncode, CorruptAndWronglySizedFramesAreNamed) {
  const fs::path root = scratch_dir();
  const fs::path frames = make_frames_dir(root / "frames");
  std::ofstream(frame_file(frames, 5, "png"), std::ios::binary) << "this is not a PNG";
  write_png(frame_file(frames, 8, "png"), make_frame(8, 32, 24), 32, 24);
  const fs::path out = root / "out";
  fs::create_directory(out);
  const auto r = run_meshtour("encode " + test::shell_quoted(frames) + " -o " + test::shell_quoted(out / "tour.webm"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("1 unreadable (5; frame_000005.png"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("1 not 64x48 (8; frame_000008.png is 32x24)"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::is_empty(out));
}

TEST(CliEncode, ExtensionMustMatchTheCodec) {
  const fs::path root = scratch_dir();
  const fs::path frames = make_frames_dir(root / "frames");
  auto r = run_meshtour("encode " + test::shell_quoted(frames) + " -o " + test::shell_quoted(root / "tour.mp4") + " --codec ffv1");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("name the file *.mkv"), std::string::npos) << r.output;
  r = run_meshtour("encode " + test::shell_quoted(frames) + " -o " + test::shell_quoted(root / "tour.avi"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(".webm (vp9)"), std::string::npos) << r.output;
  r = run_meshtour("encode " + test::shell_quoted(frames) + " -o " + test::shell_quoted(root / "tour.gif") + " --crf 20");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("crf does not apply to gif"), std::string::npos) << r.output;
  EXPECT_EQ(entries(root), std::vector<std::string>{"frames"});
}

TEST(CliEncode, WithoutManifestTheRangeMustBeGiven) {
  const fs::path root = scratch_dir();
  const fs::path frames = make_frames_dir(root / "frames", /*manifest=*/false);
  auto r = run_meshtour("encode " + test::shell_quoted(frames) + " -o " + test::shell_quoted(root / "tour.mp4"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("give it with --frames"), std::string::npos) << r.output;
  r = run_meshtour("encode " + test::shell_quoted(frames) + " -o " + test::shell_quoted(root / "tour.mp4") + " --frames 0-9 -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto probe = probe_video(root / "tour.mp4");
  EXPECT_EQ(probe.decoded_frames, kFrames);
  EXPECT_NEAR(probe.fps, 30, 1e-9);  // the default rate without a manifest
  // A range past the frames on disk names them as missing.
  r = run_meshtour("encode " + test::shell_quoted(frames) + " -o " + test::shell_quoted(root / "tour.mp4") + " --frames 0-11");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("2 of 12 missing (10-11"), std::string::npos) << r.output;
}

// EXR frames get the tracer's display transform (from their header): the lossless video of the
// EXR frames matches that of the PNG frames of the same images to within half-float rounding,
// under each tone curve (one per frame).
TEST(CliEncode, ExrFramesLookLikeThePngFrames) {
  const fs::path root = scratch_dir();
  const fs::path frames = root / "frames";
  fs::create_directory(frames);
  const ToneMapping curves[] = {ToneMapping::filmic, ToneMapping::clamp, ToneMapping::pbr_neutral};
  for (int k = 0; k < 3; ++k) {
    Image image;
    image.width = kWidth;
    image.height = kHeight;
    image.exposure = 0.5f;
    image.tone_mapping = curves[k];
    image.rgba.resize(static_cast<std::size_t>(kWidth) * kHeight * 4);
    for (int p = 0; p < kWidth * kHeight; ++p) {
      const float x = static_cast<float>(p % kWidth) / kWidth, y = static_cast<float>(p / kWidth) / kHeight;
      image.rgba[p * 4 + 0] = 3.0f * x * x + 0.1f * k;  // up to 3: the filmic shoulder matters
      image.rgba[p * 4 + 1] = 0.5f * y;
      image.rgba[p * 4 + 2] = 0.02f + 0.2f * x * y;
      image.rgba[p * 4 + 3] = 1.0f;
    }
    write_image(image, frame_file(frames, k, "png"));
    write_image(image, frame_file(frames, k, "exr"));
  }
  FrameDirInfo info;
  info.frame_count = 3;
  info.fps = kFps;
  info.width = kWidth;
  info.height = kHeight;
  info.image_formats = {"png", "exr"};
  write_frame_dir_info(frames, info);

  ASSERT_EQ(run_meshtour("encode " + test::shell_quoted(frames) + " -o " + test::shell_quoted(root / "png.mkv") + " -q").exit_code, 0);
  const auto r = run_meshtour("encode " + test::shell_quoted(frames) + " -o " + test::shell_quoted(root / "exr.mkv") + " --input-format exr -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto png = probe_video(root / "png.mkv", {0, 1, 2});
  const auto exr = probe_video(root / "exr.mkv", {0, 1, 2});
  for (int f = 0; f < 3; ++f) {
    int max_diff = 0;
    std::size_t differing = 0;
    for (std::size_t i = 0; i < png.rgb_frames[f].size(); ++i) {
      const int d = std::abs(png.rgb_frames[f][i] - exr.rgb_frames[f][i]);
      max_diff = std::max(max_diff, d);
      differing += d != 0;
    }
    EXPECT_LE(max_diff, 1) << "frame " << f;
    EXPECT_LT(differing, png.rgb_frames[f].size() / 10) << "frame " << f;
  }
  // Overriding the header's exposure changes the picture, so the header was read.
  ASSERT_EQ(run_meshtour("encode " + test::shell_quoted(frames) + " -o " + test::shell_quoted(root / "dark.mkv") + " --input-format exr --exposure 0 -q").exit_code, 0);
  EXPECT_FALSE(probe_video(root / "dark.mkv", {0}).rgb_frames[0] == exr.rgb_frames[0]);
}

// What `tour` encodes as it renders and what `encode` makes of the frames `tour` kept are the
// same file: a farm's frames give the single machine's video. (This caught x264's AVX-512 code
// reading memory it never wrote: the bytes then depended on the process's heap. 160x120 and 10
// frames were needed to show it; 64x48 did not.)
TEST(CliEncode, SameBytesAsTheTourThatRenderedTheFrames) {
  const fs::path root = scratch_dir();
  const auto tour = run_meshtour("tour -q --frames 10 --width 160 --height 120 --spp 1 --path turntable --frames-dir " +
                                 test::shell_quoted(root / "frames") + " -o " + test::shell_quoted(root / "tour.mp4"));
  ASSERT_EQ(tour.exit_code, 0) << tour.output;
  const auto r = run_meshtour("encode " + test::shell_quoted(root / "frames") + " --frames 0-9 -o " + test::shell_quoted(root / "encode.mp4") + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto a = test::file_bytes(root / "tour.mp4"), b = test::file_bytes(root / "encode.mp4");
  ASSERT_FALSE(a.empty());
  EXPECT_TRUE(a == b) << "tour and encode of the same frames differ (" << a.size() << " vs " << b.size() << " bytes)";
}

TEST(CliEncode, SigtermRemovesThePartialVideo) {
  const fs::path root = scratch_dir();
  const fs::path frames = root / "frames";
  fs::create_directory(frames);
  // Enough work (VP9, 256x192) that the signal arrives while frames are being encoded.
  constexpr int kMany = 150;
  for (int k = 0; k < kMany; ++k) write_png(frame_file(frames, k, "png"), make_frame(k, 256, 192), 256, 192);
  const fs::path out = root / "out";
  fs::create_directory(out);
  // Starts the encode in the background, waits for its temporary file, sends SIGTERM.
  const auto r = run_meshtour("encode " + test::shell_quoted(frames) + " --frames 0-" + std::to_string(kMany - 1) + " -o " +
                              test::shell_quoted(out / "tour.webm") + " -q & pid=$!; for i in $(seq 400); do ls " + test::shell_quoted(out) +
                              "/.tour.webm.partial-* >/dev/null 2>&1 && break; sleep 0.02; done; kill -TERM $pid; wait $pid; "
                              "echo exit=$?");
  EXPECT_NE(r.output.find("exit=130"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::is_empty(out)) << "left behind: " << (fs::is_empty(out) ? "" : entries(out).front());
}


// ---- --alpha: a transparent tour's video keeps its alpha, straight, as its PNG frames have it.

// A frame's straight colour and alpha as rendered (Image::to_srgba8), read as encode reads it
// (OpenImageIO's default read undoes the division by alpha its PNG writer applies).
std::vector<std::uint8_t> read_rgba_png(const fs::path& file) {
  auto in = OIIO::ImageInput::open(file.string());
  EXPECT_TRUE(in) << file;
  if (!in) return {};
  EXPECT_EQ(in->spec().nchannels, 4) << file;
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(in->spec().width) * in->spec().height * 4);
  EXPECT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::UINT8, rgba.data()));
  return rgba;
}

struct AlphaDifference {
  double alpha_mean = 0;   ///< mean |alpha difference| over all pixels
  double colour_mean = 0;  ///< mean |colour difference| over pixels the frame has fully opaque
  double partial = 0;      ///< fraction of pixels with 0 < alpha < 255 in the frame (the shadows, edges)
  double clear = 0;        ///< fraction with alpha 0
};

AlphaDifference alpha_difference(const std::vector<std::uint8_t>& video, const std::vector<std::uint8_t>& frame) {
  AlphaDifference d;
  EXPECT_EQ(video.size(), frame.size());
  double opaque = 0;
  const std::size_t n = std::min(video.size(), frame.size()) / 4;
  for (std::size_t p = 0; p < n; ++p) {
    const int a = frame[p * 4 + 3];
    d.alpha_mean += std::abs(video[p * 4 + 3] - a);
    d.partial += a > 0 && a < 255;
    d.clear += a == 0;
    if (a == 255) {
      ++opaque;
      for (int c = 0; c < 3; ++c) d.colour_mean += std::abs(video[p * 4 + c] - frame[p * 4 + c]) / 3.0;
    }
  }
  d.alpha_mean /= static_cast<double>(n);
  d.colour_mean /= std::max(opaque, 1.0);
  d.partial /= static_cast<double>(n);
  d.clear /= static_cast<double>(n);
  return d;
}

// Measured (the default scene, 96x64, spp 1), against the PNG frames: ProRes 4444 alpha mean
// error 0.000, colour (opaque pixels) 0.10; VP9 (crf 31) alpha 0.39 and 1.52, colour 2.6 and 6.7
// (4:2:0 chroma at the model's edges on a frame this small). Alpha lost (frames over black, or
// VP9 read with the native decoder) gives an alpha error above 100 here: half the frame is clear.
TEST(CliEncode, TransparentTourKeepsItsAlphaInProResAndVp9) {
  const fs::path root = scratch_dir();
  const std::string common = " -q --frames 4 --fps 24 --width 96 --height 64 --spp 1 --path turntable --background transparent";
  auto r = run_meshtour("tour" + common + " --alpha --frames-dir " + test::shell_quoted(root / "frames") + " -o " + test::shell_quoted(root / "tour.webm"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_meshtour("tour" + common + " --alpha -o " + test::shell_quoted(root / "tour.mov"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_meshtour("encode " + test::shell_quoted(root / "frames") + " --alpha -o " + test::shell_quoted(root / "encode.mov") + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;

  const auto webm = probe_video(root / "tour.webm", {0, 3}, "libvpx-vp9");
  const auto tour_mov = probe_video(root / "tour.mov", {0, 3});
  const auto encode_mov = probe_video(root / "encode.mov", {0, 3});
  EXPECT_EQ(webm.decoded_pixel_format, "yuva420p");
  EXPECT_NE(tour_mov.decoded_pixel_format.find("yuva444p"), std::string::npos) << tour_mov.decoded_pixel_format;
  for (const std::size_t k : {0u, 1u}) {
    const auto frame = read_rgba_png(frame_file(root / "frames", k == 0 ? 0 : 3, "png"));
    for (const auto* mov : {&tour_mov, &encode_mov}) {
      const AlphaDifference p = alpha_difference(mov->rgba_frames[k], frame);
      EXPECT_GT(p.clear, 0.4);  // the frame has clear background and partial shadows to keep
      EXPECT_GT(p.partial, 0.01);
      EXPECT_LT(p.alpha_mean, 0.5);
      EXPECT_LT(p.colour_mean, 1.5);
    }
    const AlphaDifference v = alpha_difference(webm.rgba_frames[k], frame);
    EXPECT_LT(v.alpha_mean, 2.0);
    EXPECT_LT(v.colour_mean, 10.0);
  }
}

TEST(CliEncode, AlphaIsRefusedWhereItCannotBeKept) {
  const fs::path root = scratch_dir();
  const fs::path frames = make_frames_dir(root / "opaque");
  struct Case {
    std::string args, expected;
  };
  const std::vector<Case> cases = {
      {"encode " + test::shell_quoted(frames) + " --alpha -o " + test::shell_quoted(root / "x.mp4"), "h264 (.mp4) cannot carry alpha; for video with alpha use prores (.mov)"},
      {"encode " + test::shell_quoted(frames) + " --alpha -o " + test::shell_quoted(root / "x.mov"), "frames 0-9 have no alpha"},
      {"tour --alpha -o " + test::shell_quoted(root / "x.mov") + " --frames 2 --width 64 --height 48", "--alpha needs a transparent background"},
      {"tour --alpha --background transparent -o " + test::shell_quoted(root / "x.mp4") + " --frames 2 --width 64 --height 48",
       "cannot carry alpha"},
      {"tour --alpha --background transparent --caption Hi -o " + test::shell_quoted(root / "x.webm") + " --frames 2 --width 64 --height 48",
       "--caption and --title-card are not drawn into video with alpha"},
  };
  for (const Case& c : cases) {
    const auto r = run_meshtour(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << c.args << "\n" << r.output;
  }
  EXPECT_FALSE(fs::exists(root / "x.mp4") || fs::exists(root / "x.mov") || fs::exists(root / "x.webm"));
}

// ---- One pixel value: over black in linear light; with --alpha, straight colour.

// `count` RGBA frames as `render --background transparent` writes them (tracer write_image, no tone
// curve): columns 0..15 clear, 16..47 sRGB grey 128 at alpha 128/255, 48..63 opaque grey 128.
fs::path make_half_alpha_frames(const fs::path& dir, int count) {
  fs::create_directories(dir);
  const float grey = srgb_to_linear(128.0f / 255.0f), half = 128.0f / 255.0f;
  for (int k = 0; k < count; ++k) {
    Image image;
    image.width = kWidth;
    image.height = kHeight;
    image.transparent = true;
    image.tone_mapping = ToneMapping::clamp;
    image.rgba.resize(static_cast<std::size_t>(kWidth) * kHeight * 4);
    for (int p = 0; p < kWidth * kHeight; ++p) {
      const int x = p % kWidth;
      const float a = x < 16 ? 0.0f : x < 48 ? half : 1.0f;
      for (int c = 0; c < 3; ++c) image.rgba[static_cast<std::size_t>(p) * 4 + c] = a * grey;  // premultiplied, linear
      image.rgba[static_cast<std::size_t>(p) * 4 + 3] = a;
    }
    write_image(image, frame_file(dir, k, "png"));
  }
  write_test_frames_manifest(dir, count);
  return dir;
}

// The mean of channel `c` over columns [x0, x1) of an interleaved frame with `n` channels.
double column_mean(const std::vector<std::uint8_t>& frame, int n, int c, int x0, int x1) {
  double sum = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = x0; x < x1; ++x) sum += frame[(static_cast<std::size_t>(y) * kWidth + x) * n + c];
  return sum / ((x1 - x0) * kHeight);
}

// Grey 128 at half alpha over black, in linear light as the tour's own video shows it:
// srgb(0.502 * linear(128)) = 92.5 -> 93. Multiplying the sRGB values gives 64 (what encode did);
// applying the alpha twice 32.
TEST(CliEncode, HalfAlphaGreyOverBlackIsComposedInLinearLight) {
  const fs::path root = scratch_dir();
  const fs::path frames = make_half_alpha_frames(root / "frames", 2);
  const auto r = run_meshtour("encode " + test::shell_quoted(frames) + " -o " + test::shell_quoted(root / "over.mkv") + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto video = probe_video(root / "over.mkv", {1});  // FFV1: lossless, so the values are exact
  ASSERT_EQ(video.rgb_frames.size(), 1u);
  const auto& rgb = video.rgb_frames[0];
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(column_mean(rgb, 3, c, 0, 16), 0.0) << "clear";
    EXPECT_EQ(column_mean(rgb, 3, c, 16, 48), 93.0) << "half alpha: 64 = sRGB values multiplied, 32 = alpha twice";
    EXPECT_EQ(column_mean(rgb, 3, c, 48, kWidth), 128.0) << "opaque";
  }
}

// --alpha keeps the colour straight (128 where alpha is 128; premultiplied would be 64) in all
// three codecs that carry alpha. VP9's alpha is a second VP9 stream beside the colour (WebM
// BlockAdditional, AlphaMode 1); libavcodec's native vp9 decoder ignores it, so the file is read
// with the libvpx-vp9 decoder. Measured (means over the region): FFV1 and ProRes 4444 colour 128,
// alpha 0, 128 and 255 exactly; VP9 (crf 31) the same but half alpha 129. encode before this
// read the frames' bytes (colour / alpha, see tour/encode_frames.cpp): colour 255.
TEST(CliEncode, AlphaVideoKeepsStraightColourInEveryAlphaCodec) {
  const fs::path root = scratch_dir();
  const fs::path frames = make_half_alpha_frames(root / "frames", 3);
  struct Case {
    std::string file, decoder, pixel_format;
    double tolerance;
  };
  for (const Case& c : {Case{"a.mkv", "", "bgra", 0.0}, Case{"a.mov", "", "yuva444p", 1.0}, Case{"a.webm", "libvpx-vp9", "yuva420p", 3.0}}) {
    const auto r = run_meshtour("encode " + test::shell_quoted(frames) + " --alpha -o " + test::shell_quoted(root / c.file) + " -q");
    ASSERT_EQ(r.exit_code, 0) << c.file << ": " << r.output;
    const auto video = probe_video(root / c.file, {2}, c.decoder);
    EXPECT_EQ(video.decoded_frames, 3) << c.file;
    EXPECT_NE(video.decoded_pixel_format.find(c.pixel_format), std::string::npos) << c.file << ": " << video.decoded_pixel_format;
    const auto& rgba = video.rgba_frames.at(0);
    EXPECT_NEAR(column_mean(rgba, 4, 3, 0, 12), 0.0, c.tolerance) << c.file << " clear alpha";
    EXPECT_NEAR(column_mean(rgba, 4, 3, 20, 44), 128.0, c.tolerance) << c.file << " half alpha";
    EXPECT_NEAR(column_mean(rgba, 4, 3, 52, kWidth), 255.0, c.tolerance) << c.file << " opaque alpha";
    for (int ch = 0; ch < 3; ++ch) {
      EXPECT_NEAR(column_mean(rgba, 4, ch, 20, 44), 128.0, c.tolerance) << c.file << " half-alpha colour (64: premultiplied)";
      EXPECT_NEAR(column_mean(rgba, 4, ch, 52, kWidth), 128.0, c.tolerance) << c.file << " opaque colour";
    }
    if (c.file == "a.webm") {
      EXPECT_EQ(video.alpha_mode, "1");
    }
  }
}

}  // namespace
}  // namespace meshtour
