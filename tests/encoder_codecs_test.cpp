// Tests for every codec of encoder/video_encoder: each file is decoded by an independent reader
// (video_probe) and checked for codec, size, frame count and pixels (exact for FFV1, a PSNR floor
// for the lossy codecs), and two encodes of the same frames must give the same bytes.
#include "core/error.h"
#include "encoder/video_encoder.h"
#include "helpers.h"
#include "video_probe.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace meshtour {
namespace {

namespace fs = std::filesystem;
using test::probe_video;
using test::scratch_dir;

constexpr int kWidth = 64;
constexpr int kHeight = 48;
constexpr int kFps = 25;  // a whole number of GIF ticks (1/100 s) per frame
constexpr int kFrames = 10;

// A rendered-looking frame: a smooth wave that slides 3 px per frame under a shaded disc moving
// 4 px per frame, its edge anti-aliased like a rendered one. Every channel differs, so swapped
// channels or frames show up. (Hard coloured edges would measure 4:2:0 chroma subsampling, not
// the encoder: ~33 dB even for H.264 at crf 0.)
std::vector<std::uint8_t> make_frame(int index, int width = kWidth, int height = kHeight) {
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(width) * height * 3);
  const double cx = 12 + 4.0 * index, cy = height / 2.0, r = 10;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      std::uint8_t* p = &rgb[(static_cast<std::size_t>(y) * width + x) * 3];
      const double wave = std::sin(2 * 3.14159265358979 * (x + 3.0 * index) / width);
      const double bg[3] = {100 + 60 * wave, 60 + 100.0 * y / height, 180 - 60.0 * (x + y) / (width + height)};
      const double d = std::hypot(x - cx, y - cy);
      const double cover = std::clamp((r - d) / 3.0 + 0.5, 0.0, 1.0);  // 3 px soft edge
      const double shade = 1.0 - 0.5 * std::min(d, r) / r;
      const double disc[3] = {220 * shade, 150 * shade, 60 * shade};
      for (int c = 0; c < 3; ++c)
        p[c] = static_cast<std::uint8_t>(std::lround(cover * disc[c] + (1 - cover) * bg[c]));
    }
  return rgb;
}

double psnr(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
  EXPECT_EQ(a.size(), b.size());
  double sq = 0;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
    const double d = static_cast<double>(a[i]) - b[i];
    sq += d * d;
  }
  const double mse = sq / static_cast<double>(a.size());
  return mse == 0 ? 99.0 : 10 * std::log10(255.0 * 255.0 / mse);
}


VideoOptions options_for(VideoCodec codec) {
  VideoOptions o;
  o.width = kWidth;
  o.height = kHeight;
  o.fps = kFps;
  o.codec = codec;
  return o;
}

fs::path encode(const fs::path& dir, const std::string& stem, const VideoOptions& o, int frames = kFrames) {
  const fs::path file = dir / (stem + std::string(video_codec_info(o.codec).extension));
  VideoEncoder encoder(file, o);
  for (int i = 0; i < frames; ++i) encoder.add_frame(make_frame(i, o.width, o.height));
  encoder.finish();
  return file;
}

struct Expected {
  VideoCodec codec;
  const char* decoder_name;
  const char* pixel_format;
  double min_psnr;  ///< dB over the whole frame; 99 = exact
};

// PSNR floors, 3-4 dB under what was measured on these frames (h264 crf 18: 39.5-40.4 dB,
// prores: 50-52, vp9 crf 31: 35.1-42.8, gif: 34.1-36.2), and all above the PSNR against the
// neighbouring frame (23-25 dB), which the test checks so that the floor is known to bite.
const Expected kExpected[] = {
    {VideoCodec::h264, "h264", "yuv420p", 36.0},
    {VideoCodec::prores, "prores", "yuv422p10le", 46.0},
    {VideoCodec::ffv1, "ffv1", "bgr0", 99.0},
    {VideoCodec::vp9, "vp9", "yuv420p", 32.0},
    {VideoCodec::gif, "gif", "bgra", 31.0},
};

class EncoderCodecs : public ::testing::TestWithParam<Expected> {};

TEST_P(EncoderCodecs, RoundTripsFramesAndSize) {
  const Expected& expected = GetParam();
  const fs::path file = encode(scratch_dir(), "clip", options_for(expected.codec));
  const std::vector<int> keep = {0, 5, kFrames - 1};
  const auto probe = probe_video(file, keep);
  EXPECT_EQ(probe.codec, expected.decoder_name);
  EXPECT_EQ(probe.pixel_format, expected.pixel_format);
  EXPECT_EQ(probe.width, kWidth);
  EXPECT_EQ(probe.height, kHeight);
  EXPECT_EQ(probe.decoded_frames, kFrames);
  EXPECT_NEAR(probe.duration_seconds, static_cast<double>(kFrames) / kFps, 1.01 / kFps);
  ASSERT_EQ(probe.rgb_frames.size(), keep.size());
  for (std::size_t k = 0; k < keep.size(); ++k) {
    const auto source = make_frame(keep[k]);
    const double same = psnr(probe.rgb_frames[k], source);
    std::printf("%s frame %d: PSNR %.1f dB, file %ju bytes\n", expected.decoder_name, keep[k], same,
                static_cast<std::uintmax_t>(fs::file_size(file)));
    if (expected.min_psnr >= 99.0) {
      EXPECT_TRUE(probe.rgb_frames[k] == source) << "lossless codec changed pixels of frame " << keep[k];
    } else {
      EXPECT_GT(same, expected.min_psnr) << "frame " << keep[k];
    }
    const double neighbour = psnr(probe.rgb_frames[k], make_frame(keep[k] == 0 ? 1 : keep[k] - 1));
    std::printf("  against the neighbouring frame: %.1f dB\n", neighbour);
    EXPECT_LT(neighbour, std::min(expected.min_psnr, 31.0)) << "frame " << keep[k] << " looks like its neighbour";
  }
  // Only the finished file remains: the temporary was renamed.
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(file.parent_path())) ++entries;
  EXPECT_EQ(entries, 1);
}

TEST_P(EncoderCodecs, SameFramesGiveSameBytes) {
  const Expected& expected = GetParam();
  const fs::path dir = scratch_dir();
  const auto a = test::file_bytes(encode(dir, "a", options_for(expected.codec)));
  const auto b = test::file_bytes(encode(dir, "b", options_for(expected.codec)));
  ASSERT_FALSE(a.empty());
  EXPECT_TRUE(a == b) << expected.decoder_name << ": two encodes of the same frames differ (" << a.size()
                      << " vs " << b.size() << " bytes)";
}

INSTANTIATE_TEST_SUITE_P(AllCodecs, EncoderCodecs, ::testing::ValuesIn(kExpected),
                         [](const auto& info) { return std::string(info.param.decoder_name); });

TEST(EncoderCodecOptions, ExtensionMustMatchTheCodec) {
  const fs::path dir = scratch_dir();
  VideoOptions o = options_for(VideoCodec::ffv1);
  try {
    VideoEncoder encoder(dir / "archive.mp4", o);
    FAIL() << "ffv1 into .mp4 accepted";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("*.mkv"), std::string::npos) << message;
    EXPECT_NE(message.find(".mp4 is for codec h264"), std::string::npos) << message;
  }
  o.codec = VideoCodec::h264;
  EXPECT_THROW(VideoEncoder(dir / "tour.webm", o), InputError);
  EXPECT_THROW(VideoEncoder(dir / "tour", o), InputError);
  EXPECT_TRUE(fs::is_empty(dir));
  // Case does not matter.
  encode(dir, "upper", options_for(VideoCodec::gif), 2);
  fs::rename(dir / "upper.gif", dir / "UPPER.GIF");
  VideoEncoder upper(dir / "again.GIF", options_for(VideoCodec::gif));
}

TEST(EncoderCodecOptions, CrfIsCheckedPerCodec) {
  const fs::path dir = scratch_dir();
  for (VideoCodec lossless_or_fixed : {VideoCodec::prores, VideoCodec::ffv1, VideoCodec::gif}) {
    VideoOptions o = options_for(lossless_or_fixed);
    o.crf = 20;
    const fs::path file = dir / ("x" + std::string(video_codec_info(o.codec).extension));
    try {
      VideoEncoder encoder(file, o);
      FAIL() << "crf accepted for " << video_codec_info(o.codec).name;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("crf does not apply"), std::string::npos) << e.what();
    }
  }
  VideoOptions vp9 = options_for(VideoCodec::vp9);
  vp9.crf = 64;
  EXPECT_THROW(VideoEncoder(dir / "x.webm", vp9), InputError);
  VideoOptions h264 = options_for(VideoCodec::h264);
  h264.crf = 52;
  EXPECT_THROW(VideoEncoder(dir / "x.mp4", h264), InputError);
  EXPECT_TRUE(fs::is_empty(dir));

  // A higher crf gives a smaller VP9 file: the option reaches the encoder.
  vp9.crf = 10;
  const auto fine = fs::file_size(encode(dir, "fine", vp9));
  vp9.crf = 60;
  const auto coarse = fs::file_size(encode(dir, "coarse", vp9));
  EXPECT_LT(coarse, fine);
}

TEST(EncoderCodecOptions, OddSizesOnlyForRgbAndPaletteCodecs) {
  const fs::path dir = scratch_dir();
  for (VideoCodec codec : {VideoCodec::ffv1, VideoCodec::gif}) {
    VideoOptions o = options_for(codec);
    o.width = 33;
    o.height = 21;
    const auto probe = probe_video(encode(dir, "odd", o, 3), {2});
    EXPECT_EQ(probe.width, 33);
    EXPECT_EQ(probe.height, 21);
    EXPECT_EQ(probe.decoded_frames, 3);
    if (codec == VideoCodec::ffv1) {
      EXPECT_TRUE(probe.rgb_frames[0] == make_frame(2, 33, 21));
    }
  }
  for (VideoCodec codec : {VideoCodec::prores, VideoCodec::vp9}) {
    VideoOptions o = options_for(codec);
    o.width = 33;
    EXPECT_THROW(VideoEncoder(dir / ("odd" + std::string(video_codec_info(codec).extension)), o), InputError);
  }
}

TEST(EncoderCodecOptions, NamesParse) {
  for (const auto& info : video_codecs()) EXPECT_EQ(parse_video_codec(info.name), info.codec);
  try {
    parse_video_codec("av1");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("h264, prores, ffv1, vp9, gif"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace meshtour

namespace meshtour {
namespace {

// The frames of a farm encode or a tour arrive slowly (each one is read or rendered first), those
// of the tests above all at once; encoder threads must not make the bytes depend on that timing.
TEST(EncoderCodecThreads, SlowlyFedFramesGiveSameBytes) {
  // The codecs encoded on several threads (gif runs on one, so timing cannot matter to it).
  for (VideoCodec codec : {VideoCodec::h264, VideoCodec::prores, VideoCodec::ffv1, VideoCodec::vp9}) {
    const fs::path dir = scratch_dir();
    // Large enough for x264 to use all its threads (it drops to fewer on frames a few macroblock rows high).
    VideoOptions o = options_for(codec);
    o.width = 320;
    o.height = 240;
    const auto fast = test::file_bytes(encode(dir, "fast", o, 16));
    const fs::path slow = dir / ("slow" + std::string(video_codec_info(codec).extension));
    {
      VideoEncoder encoder(slow, o);
      for (int i = 0; i < 16; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(i % 3 == 0 ? 40 : 1));
        encoder.add_frame(make_frame(i, o.width, o.height));
      }
      encoder.finish();
    }
    EXPECT_TRUE(fast == test::file_bytes(slow)) << video_codec_info(codec).name << ": bytes depend on how fast frames arrive";
  }
}

}  // namespace
}  // namespace meshtour
