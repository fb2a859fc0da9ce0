// Encoding a frames directory (tour/encode_frames.h): every frame in order at the manifest's size
// and rate, the poster as the best frame's own PNG, and a damaged directory refused before any
// output exists, naming the frames at fault. Frames are tiny solid PNGs written here.
#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "helpers.h"
#include "jobs/frame_dir.h"
#include "tour/encode_frames.h"
#include "video_probe.h"

namespace {

using namespace meshtour;
namespace fs = std::filesystem;
using testing::internal::CaptureStderr;
using testing::internal::GetCapturedStderr;

constexpr int kFrames = 6, kWidth = 32, kHeight = 24, kFps = 12, kBestFrame = 4;

// The grey level of frame k: far enough apart to tell frames apart after lossy coding.
std::uint8_t grey_of(int k) { return static_cast<std::uint8_t>(30 + 40 * k); }

// A frames directory as `render` leaves it: the manifest and frame_00000k.png for every k.
fs::path make_frames_dir() {
  const fs::path dir = test::scratch_dir() / "frames";
  fs::create_directories(dir);
  FrameDirInfo info;
  info.frame_count = kFrames;
  info.fps = kFps;
  info.width = kWidth;
  info.height = kHeight;
  info.image_formats = {"png"};
  info.view_scores = {0.1, 0.2, 0.3, 0.2, 0.9, 0.5};
  info.best_view_frame = kBestFrame;
  write_frame_dir_info(dir, info);
  for (int k = 0; k < kFrames; ++k) {
    const std::vector<std::uint8_t> rgb(static_cast<std::size_t>(kWidth) * kHeight * 3, grey_of(k));
    OIIO::ImageBuf image(OIIO::ImageSpec(kWidth, kHeight, 3, OIIO::TypeDesc::UINT8));
    image.set_pixels(image.roi(), OIIO::TypeDesc::UINT8, rgb.data());
    EXPECT_TRUE(image.write(frame_file(dir, k, "png").string())) << image.geterror();
  }
  return dir;
}

double mean_of(const std::vector<std::uint8_t>& rgb) {
  double sum = 0.0;
  for (const std::uint8_t v : rgb) sum += v;
  return rgb.empty() ? 0.0 : sum / static_cast<double>(rgb.size());
}

// Runs the job with its progress lines kept out of the test's log; returns what it printed.
std::string encode_quietly(const EncodeJob& job) {
  CaptureStderr();
  try {
    encode_frames(job);
  } catch (...) {
    GetCapturedStderr();
    throw;
  }
  return GetCapturedStderr();
}

TEST(TourEncodeFrames, EveryFrameInOrderAtTheManifestsSizeAndRateAndTheBestFrameAsPoster) {
  const fs::path dir = make_frames_dir();
  const fs::path video = dir.parent_path() / "tour.mp4", poster = dir.parent_path() / "poster.png";
  EncodeJob job;
  job.dir = dir.string();
  job.output = video.string();
  job.poster.file = poster;
  encode_quietly(job);

  const test::VideoProbe probe = test::probe_video(video, {0, kFrames - 1});
  EXPECT_EQ(probe.codec, "h264");
  EXPECT_EQ(probe.width, kWidth);
  EXPECT_EQ(probe.height, kHeight);
  EXPECT_NEAR(probe.fps, kFps, 1e-6);
  EXPECT_EQ(probe.decoded_frames, kFrames);
  ASSERT_EQ(probe.rgb_frames.size(), 2u);
  EXPECT_NEAR(mean_of(probe.rgb_frames[0]), grey_of(0), 6.0);
  EXPECT_NEAR(mean_of(probe.rgb_frames[1]), grey_of(kFrames - 1), 6.0);
  // The poster is frame 0's PNG (the preferred view), byte for byte, not the best-covering frame's.
  EXPECT_EQ(test::file_bytes(poster), test::file_bytes(frame_file(dir, 0, "png")));
  EXPECT_NE(test::file_bytes(poster), test::file_bytes(frame_file(dir, kBestFrame, "png")));
}

TEST(TourEncodeFrames, TheOutputsExtensionChoosesTheCodec) {
  const fs::path dir = make_frames_dir();
  EncodeJob job;
  job.dir = dir.string();
  job.output = (dir.parent_path() / "tour.webm").string();
  encode_quietly(job);
  const test::VideoProbe probe = test::probe_video(job.output);
  EXPECT_EQ(probe.codec, "vp9");
  EXPECT_EQ(probe.decoded_frames, kFrames);

  job.output = (dir.parent_path() / "tour.avi").string();
  try {
    encode_quietly(job);
    FAIL() << "an .avi output was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not a video type meshtour writes"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(job.output));
}

TEST(TourEncodeFrames, DamagedFramesAreAllNamedBeforeAnyOutputExists) {
  const fs::path dir = make_frames_dir();
  fs::remove(frame_file(dir, 2, "png"));
  fs::remove(frame_file(dir, 3, "png"));
  std::ofstream(frame_file(dir, 5, "png")) << "not a png";
  EncodeJob job;
  job.dir = dir.string();
  job.output = (dir.parent_path() / "tour.mp4").string();
  job.poster.file = dir.parent_path() / "poster.png";
  try {
    encode_quietly(job);
    FAIL() << "a directory with missing and damaged frames was encoded";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("2 of 6 missing (2-3, e.g. frame_000002.png)"), std::string::npos) << message;
    EXPECT_NE(message.find("1 unreadable (5; frame_000005.png"), std::string::npos) << message;
    EXPECT_NE(message.find("meshtour render --frames 2-3,5"), std::string::npos) << message;
  }
  EXPECT_FALSE(fs::exists(job.output));
  EXPECT_FALSE(fs::exists(job.poster.file));

  // Not a directory at all.
  job.dir = (dir.parent_path() / "nowhere").string();
  EXPECT_THROW(encode_quietly(job), InputError);
}

}  // namespace
