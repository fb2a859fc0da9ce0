// Tests for encoder/video_encoder: the MP4 it writes is read back with an independent decoder
// (video_probe) and checked for frame count, timing, format, colour and byte-exact determinism.
#include "core/error.h"
#include "encoder/video_encoder.h"
#include "helpers.h"
#include "video_probe.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
}

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <memory>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

namespace meshtour {
namespace {

namespace fs = std::filesystem;
using test::probe_video;
using test::scratch_dir;

constexpr int kWidth = 96;
constexpr int kHeight = 64;
constexpr int kFps = 24;
constexpr int kFrames = 24;

VideoOptions small_options() {
  VideoOptions o;
  o.width = kWidth;
  o.height = kHeight;
  o.fps = kFps;
  return o;
}

// Top-left corner of the moving square in frame `index`.
int square_x(int index, int width = kWidth) { return 4 + 3 * index % (width - 20); }
int square_y(int index, int height = kHeight) { return 8 + index % (height - 24); }
constexpr int kSquare = 16;

// Smooth content (a sine band sliding 4 px per frame, fixed ramps in G and B) plus a 16x16 square
// moving 3 px per frame. Channels differ everywhere, so swapped channels show up; consecutive
// frames differ clearly, so an off-by-one frame index shows up too.
std::vector<std::uint8_t> make_frame(int index, int width = kWidth, int height = kHeight) {
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(width) * height * 3);
  const int sx = square_x(index, width), sy = square_y(index, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      std::uint8_t* p = &rgb[(static_cast<std::size_t>(y) * width + x) * 3];
      if (x >= sx && x < sx + kSquare && y >= sy && y < sy + kSquare) {
        p[0] = 230, p[1] = 200, p[2] = 40;
        continue;
      }
      const double phase = 2 * std::numbers::pi * (x + 4.0 * index) / width;
      p[0] = static_cast<std::uint8_t>(std::lround(128 + 90 * std::sin(phase)));
      p[1] = static_cast<std::uint8_t>(40 + 2 * y * 64 / height);
      p[2] = static_cast<std::uint8_t>(200 - x * 96 / width);
    }
  return rgb;
}

// Pixels away from the square in frames index-1..index+1 (3 px margin). The square's sharp
// coloured edges lose detail to yuv420p's half-resolution chroma whatever the encoder does
// (PSNR ~33 dB even at crf 0), so the quality thresholds are applied to the smooth part only.
std::vector<bool> smooth_mask(int index) {
  std::vector<bool> mask(static_cast<std::size_t>(kWidth) * kHeight, true);
  for (int i = index - 1; i <= index + 1; ++i)
    for (int y = square_y(i) - 3; y < square_y(i) + kSquare + 3; ++y)
      for (int x = square_x(i) - 3; x < square_x(i) + kSquare + 3; ++x)
        if (x >= 0 && x < kWidth && y >= 0 && y < kHeight)
          mask[static_cast<std::size_t>(y) * kWidth + x] = false;
  return mask;
}

void encode(const fs::path& file, const VideoOptions& options, int frames) {
  VideoEncoder encoder(file, options);
  for (int i = 0; i < frames; ++i) encoder.add_frame(make_frame(i, options.width, options.height));
  EXPECT_EQ(encoder.frames_written(), frames);
  encoder.finish();
}

struct Difference {
  double mean_abs;  ///< mean absolute error per channel, in 0..255 units
  double psnr;      ///< dB
};

Difference compare(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b,
                   const std::vector<bool>& mask) {
  EXPECT_EQ(a.size(), b.size());
  EXPECT_EQ(a.size(), mask.size() * 3);
  double abs_sum = 0, sq_sum = 0, n = 0;
  for (std::size_t i = 0; i < a.size() && i / 3 < mask.size(); ++i) {
    if (!mask[i / 3]) continue;
    const double d = static_cast<double>(a[i]) - b[i];
    abs_sum += std::abs(d);
    sq_sum += d * d;
    ++n;
  }
  const double mse = sq_sum / n;
  return {abs_sum / n, mse == 0 ? 99.0 : 10 * std::log10(255.0 * 255.0 / mse)};
}

// Measured on the smooth part at crf 18: mean error 1.0..1.2, PSNR 43..45 dB. The neighbouring
// frame, swapped channels, or decoding with BT.601 or full range instead of BT.709 limited range
// (mean error ~5.5, PSNR ~31 dB) all fall outside; the neighbour and swap cases are checked below
// so the thresholds are known to bite.
constexpr double kMaxMeanAbs = 2.0;
constexpr double kMinPsnr = 38.0;

std::vector<std::string> directory_entries(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  return names;
}


TEST(EncoderVideo, WritesExpectedStream) {
  const fs::path file = scratch_dir() / "tour.mp4";
  encode(file, small_options(), kFrames);

  const auto probe = probe_video(file);
  EXPECT_EQ(probe.codec, "h264");
  EXPECT_EQ(probe.pixel_format, "yuv420p");
  EXPECT_EQ(probe.width, kWidth);
  EXPECT_EQ(probe.height, kHeight);
  EXPECT_NEAR(probe.fps, kFps, 1e-9);
  EXPECT_EQ(probe.stream_frames, kFrames);
  EXPECT_EQ(probe.decoded_frames, kFrames);
  EXPECT_NEAR(probe.duration_seconds, static_cast<double>(kFrames) / kFps, 1e-3);
  // Only the final file remains: the temporary was renamed, not copied.
  EXPECT_EQ(directory_entries(file.parent_path()), std::vector<std::string>{"tour.mp4"});
}

TEST(EncoderVideo, DecodedFramesMatchSources) {
  const fs::path file = scratch_dir() / "tour.mp4";
  encode(file, small_options(), kFrames);
  // A middle frame (a B- or P-frame) and the last one (only emitted when the encoder is flushed).
  const auto probe = probe_video(file, {12, kFrames - 1});
  ASSERT_EQ(probe.rgb_frames.size(), 2u);

  for (const auto& [decoded, index] : {std::pair{&probe.rgb_frames[0], 12},
                                       std::pair{&probe.rgb_frames[1], kFrames - 1}}) {
    const std::vector<bool> mask = smooth_mask(index);
    const Difference same = compare(*decoded, make_frame(index), mask);
    EXPECT_LT(same.mean_abs, kMaxMeanAbs) << "frame " << index;
    EXPECT_GT(same.psnr, kMinPsnr) << "frame " << index;

    // The same thresholds must reject the neighbouring frame, or they would not catch an
    // off-by-one in the timestamps.
    const Difference neighbour = compare(*decoded, make_frame(index - 1), mask);
    EXPECT_GT(neighbour.mean_abs, kMaxMeanAbs) << "frame " << index;
    EXPECT_LT(neighbour.psnr, kMinPsnr) << "frame " << index;

    // ... and swapped red/blue channels.
    std::vector<std::uint8_t> bgr = make_frame(index);
    for (std::size_t i = 0; i < bgr.size(); i += 3) std::swap(bgr[i], bgr[i + 2]);
    const Difference swapped = compare(*decoded, bgr, mask);
    EXPECT_GT(swapped.mean_abs, kMaxMeanAbs) << "frame " << index;
    EXPECT_LT(swapped.psnr, kMinPsnr) << "frame " << index;
  }
}

// The Y'CbCr values actually stored, and the stream's colour tags, read without the probe's
// BT.709 conversion: a round trip through encoder and probe cannot tell BT.601 from BT.709 if
// both made the same mistake, but the stored values can.
struct StoredColour {
  int y = -1, cb = -1, cr = -1;
  AVColorSpace space = AVCOL_SPC_UNSPECIFIED;
  AVColorRange range = AVCOL_RANGE_UNSPECIFIED;
  AVColorPrimaries primaries = AVCOL_PRI_UNSPECIFIED;
  AVColorTransferCharacteristic trc = AVCOL_TRC_UNSPECIFIED;
};

StoredColour stored_centre_colour(const fs::path& file) {
  struct InputDeleter {
    void operator()(AVFormatContext* f) const { avformat_close_input(&f); }
  };
  struct CodecDeleter {
    void operator()(AVCodecContext* c) const { avcodec_free_context(&c); }
  };
  struct FrameDeleter {
    void operator()(AVFrame* f) const { av_frame_free(&f); }
  };
  struct PacketDeleter {
    void operator()(AVPacket* p) const { av_packet_free(&p); }
  };
  StoredColour out;
  AVFormatContext* raw = nullptr;
  if (avformat_open_input(&raw, file.c_str(), nullptr, nullptr) < 0) return out;
  std::unique_ptr<AVFormatContext, InputDeleter> input(raw);
  if (avformat_find_stream_info(input.get(), nullptr) < 0) return out;
  const int index = av_find_best_stream(input.get(), AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
  if (index < 0) return out;
  const AVCodecParameters* par = input->streams[index]->codecpar;
  out.space = par->color_space;
  out.range = par->color_range;
  out.primaries = par->color_primaries;
  out.trc = par->color_trc;

  const AVCodec* decoder = avcodec_find_decoder(par->codec_id);
  std::unique_ptr<AVCodecContext, CodecDeleter> codec(avcodec_alloc_context3(decoder));
  if (!codec || avcodec_parameters_to_context(codec.get(), par) < 0 ||
      avcodec_open2(codec.get(), decoder, nullptr) < 0)
    return out;
  std::unique_ptr<AVPacket, PacketDeleter> packet(av_packet_alloc());
  std::unique_ptr<AVFrame, FrameDeleter> frame(av_frame_alloc());
  bool flushed = false;
  while (!flushed) {
    if (av_read_frame(input.get(), packet.get()) < 0) {
      avcodec_send_packet(codec.get(), nullptr);
      flushed = true;
    } else {
      if (packet->stream_index == index) avcodec_send_packet(codec.get(), packet.get());
      av_packet_unref(packet.get());
    }
    if (avcodec_receive_frame(codec.get(), frame.get()) == 0) {
      const int x = frame->width / 2, y = frame->height / 2;
      out.y = frame->data[0][y * frame->linesize[0] + x];
      out.cb = frame->data[1][y / 2 * frame->linesize[1] + x / 2];
      out.cr = frame->data[2][y / 2 * frame->linesize[2] + x / 2];
      return out;
    }
  }
  return out;
}

TEST(EncoderVideo, StoresBt709LimitedRange) {
  const fs::path file = scratch_dir() / "red.mp4";
  {
    VideoEncoder encoder(file, small_options());
    std::vector<std::uint8_t> red(static_cast<std::size_t>(kWidth) * kHeight * 3, 0);
    for (std::size_t i = 0; i < red.size(); i += 3) red[i] = 255;
    encoder.add_frame(red);
    encoder.finish();
  }
  const StoredColour c = stored_centre_colour(file);
  EXPECT_EQ(c.space, AVCOL_SPC_BT709);
  EXPECT_EQ(c.range, AVCOL_RANGE_MPEG);
  EXPECT_EQ(c.primaries, AVCOL_PRI_BT709);
  EXPECT_EQ(c.trc, AVCOL_TRC_BT709);
  // Pure red in BT.709 limited range: Y' = 16 + 219 * 0.2126 = 63, Cb = 128 - 112 * 0.2126 / 0.9278
  // = 102, Cr = 240. (BT.601 would give Y' = 81, Cb = 90; full range Y' = 54.)
  EXPECT_NEAR(c.y, 63, 2);
  EXPECT_NEAR(c.cb, 102, 2);
  EXPECT_NEAR(c.cr, 240, 2);
}

TEST(EncoderVideo, IndexPrecedesDataForStreaming) {
  const fs::path file = scratch_dir() / "tour.mp4";
  encode(file, small_options(), 4);
  const std::string bytes = test::file_bytes(file);
  // Walk the top-level MP4 boxes: 32-bit big-endian size, 4-character type.
  std::vector<std::string> boxes;
  for (std::size_t pos = 0; pos + 8 <= bytes.size();) {
    std::uint64_t size = 0;
    for (int i = 0; i < 4; ++i) size = size << 8 | static_cast<std::uint8_t>(bytes[pos + i]);
    boxes.emplace_back(&bytes[pos + 4], 4);
    if (size == 1 && pos + 16 <= bytes.size()) {  // 64-bit size follows the type
      size = 0;
      for (int i = 8; i < 16; ++i) size = size << 8 | static_cast<std::uint8_t>(bytes[pos + i]);
    }
    if (size < 8) break;
    pos += size;
  }
  const auto moov = std::find(boxes.begin(), boxes.end(), "moov");
  const auto mdat = std::find(boxes.begin(), boxes.end(), "mdat");
  ASSERT_NE(moov, boxes.end());
  ASSERT_NE(mdat, boxes.end());
  EXPECT_LT(moov, mdat) << "moov must come before mdat (+faststart)";
}

TEST(EncoderVideo, SameFramesGiveSameBytes) {
  const fs::path dir = scratch_dir();
  encode(dir / "a.mp4", small_options(), kFrames);
  encode(dir / "b.mp4", small_options(), kFrames);
  const auto a = test::file_bytes(dir / "a.mp4");
  const auto b = test::file_bytes(dir / "b.mp4");
  ASSERT_FALSE(a.empty());
  EXPECT_TRUE(a == b) << "two encodes of the same frames differ (" << a.size() << " vs " << b.size()
                      << " bytes)";
}

TEST(EncoderVideo, OddSizeIsRejectedWithoutWritingAnything) {
  const fs::path dir = scratch_dir();
  VideoOptions o = small_options();
  o.width = 97;
  try {
    VideoEncoder encoder(dir / "tour.mp4", o);
    FAIL() << "odd width accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("96 or 98"), std::string::npos) << e.what();
  }
  o = small_options();
  o.height = 63;
  EXPECT_THROW(VideoEncoder(dir / "tour.mp4", o), InputError);
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(EncoderVideo, OutOfRangeOptionsAreRejected) {
  const fs::path dir = scratch_dir();
  for (auto change : std::vector<void (*)(VideoOptions&)>{
           [](VideoOptions& o) { o.width = 0; }, [](VideoOptions& o) { o.height = -2; },
           [](VideoOptions& o) { o.fps = 0; }, [](VideoOptions& o) { o.fps = 241; },
           [](VideoOptions& o) { o.crf = -1; }, [](VideoOptions& o) { o.crf = 52; },
           [](VideoOptions& o) { o.preset = "turbo"; }}) {
    VideoOptions o = small_options();
    change(o);
    EXPECT_THROW(VideoEncoder(dir / "tour.mp4", o), InputError);
  }
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(EncoderVideo, MissingDirectoryIsAnIoErrorNamingIt) {
  const fs::path missing = scratch_dir() / "no-such-dir";
  try {
    VideoEncoder encoder(missing / "tour.mp4", small_options());
    FAIL() << "missing directory accepted";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(missing));
}

TEST(EncoderVideo, UncreatableTemporaryIsAnIoErrorAndNothingIsRemoved) {
  // A directory squatting on the temporary's name makes creating it fail after the encoder is
  // already set up, exercising the cleanup of a half-constructed encoder.
  const fs::path dir = scratch_dir();
  const fs::path squatter = dir / (".tour.mp4.partial-" + std::to_string(::getpid()) + ".mp4");
  fs::create_directory(squatter);
  try {
    VideoEncoder encoder(dir / "tour.mp4", small_options());
    FAIL() << "temporary file created over a directory";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(squatter.string()), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_directory(squatter));
  EXPECT_FALSE(fs::exists(dir / "tour.mp4"));
}

TEST(EncoderVideo, UnfinishedEncoderLeavesNothingBehind) {
  const fs::path dir = scratch_dir();
  {
    VideoEncoder encoder(dir / "tour.mp4", small_options());
    for (int i = 0; i < 5; ++i) encoder.add_frame(make_frame(i));
    // While encoding, only a hidden temporary exists; the final name appears on finish().
    const auto names = directory_entries(dir);
    ASSERT_EQ(names.size(), 1u);
    EXPECT_EQ(names[0].rfind(".tour.mp4.partial-", 0), 0u) << names[0];
    EXPECT_FALSE(fs::exists(dir / "tour.mp4"));
  }
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(EncoderVideo, WrongFrameSizeIsAnInputErrorAndEncoderStaysUsable) {
  const fs::path file = scratch_dir() / "tour.mp4";
  VideoEncoder encoder(file, small_options());
  const std::vector<std::uint8_t> short_frame(kWidth * kHeight * 3 - 1);
  EXPECT_THROW(encoder.add_frame(short_frame), InputError);
  EXPECT_THROW(encoder.add_frame(make_frame(0, kWidth / 2, kHeight / 2)), InputError);
  EXPECT_EQ(encoder.frames_written(), 0);
  for (int i = 0; i < 3; ++i) encoder.add_frame(make_frame(i));
  encoder.finish();
  EXPECT_EQ(probe_video(file).decoded_frames, 3);
}

TEST(EncoderVideo, FinishWithoutFramesWritesNothing) {
  const fs::path dir = scratch_dir();
  VideoEncoder encoder(dir / "tour.mp4", small_options());
  EXPECT_THROW(encoder.finish(), InputError);
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(EncoderVideo, UseAfterFinishIsRejected) {
  const fs::path dir = scratch_dir();
  VideoEncoder encoder(dir / "tour.mp4", small_options());
  encoder.add_frame(make_frame(0));
  encoder.finish();
  EXPECT_THROW(encoder.add_frame(make_frame(1)), RuntimeFailure);
  EXPECT_THROW(encoder.finish(), RuntimeFailure);
  EXPECT_EQ(probe_video(dir / "tour.mp4").decoded_frames, 1);
}

TEST(EncoderVideo, ReplacesExistingFileAndAcceptsColonInName) {
  const fs::path file = scratch_dir() / "take:2.mp4";
  std::ofstream(file) << "old contents";
  encode(file, small_options(), 3);
  EXPECT_EQ(probe_video(file).decoded_frames, 3);
  EXPECT_EQ(directory_entries(file.parent_path()), std::vector<std::string>{"take:2.mp4"});
}


// ---- Video with alpha (VideoOptions::alpha): the alpha and the straight colour come back.

// Blocks of one colour each (so 4:2:0 chroma is exact inside them) at four alpha levels: opaque,
// half, a quarter and clear, in columns; the colour rows differ in every channel. Straight alpha:
// the colour stays the same whatever the alpha, so a premultiplying encoder (or reader) would
// darken the half and quarter columns by 2x and 4x, far outside the tolerance.
constexpr std::array<std::uint8_t, 4> kAlphaLevels = {255, 128, 64, 0};
constexpr std::array<std::array<std::uint8_t, 3>, 2> kAlphaColours = {{{200, 60, 30}, {40, 150, 220}}};

std::vector<std::uint8_t> make_alpha_frame() {
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(kWidth) * kHeight * 4);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      std::uint8_t* p = &rgba[(static_cast<std::size_t>(y) * kWidth + x) * 4];
      const auto& colour = kAlphaColours[static_cast<std::size_t>(y * 2 / kHeight)];
      p[0] = colour[0], p[1] = colour[1], p[2] = colour[2];
      p[3] = kAlphaLevels[static_cast<std::size_t>(x * 4 / kWidth)];
    }
  return rgba;
}

struct AlphaError {
  int alpha = 0;   ///< largest |alpha - expected| at the blocks' centres
  int colour = 0;  ///< largest |colour - expected| there, where alpha >= 64 (clear pixels have no colour)
};

// Compares the centre 8x8 of each block of decoded frame `rgba` with make_alpha_frame().
AlphaError alpha_error(const std::vector<std::uint8_t>& rgba) {
  AlphaError e;
  const std::vector<std::uint8_t> expected = make_alpha_frame();
  EXPECT_EQ(rgba.size(), expected.size());
  if (rgba.size() != expected.size()) return {255, 255};
  for (int by = 0; by < 2; ++by)
    for (int bx = 0; bx < 4; ++bx) {
      const int cx = bx * kWidth / 4 + kWidth / 8, cy = by * kHeight / 2 + kHeight / 4;
      for (int y = cy - 4; y < cy + 4; ++y)
        for (int x = cx - 4; x < cx + 4; ++x) {
          const std::size_t i = (static_cast<std::size_t>(y) * kWidth + x) * 4;
          e.alpha = std::max(e.alpha, std::abs(rgba[i + 3] - expected[i + 3]));
          if (expected[i + 3] >= 64)
            for (int c = 0; c < 3; ++c) e.colour = std::max(e.colour, std::abs(rgba[i + c] - expected[i + c]));
        }
    }
  return e;
}

test::VideoProbe encode_alpha(const fs::path& file, VideoCodec codec, const std::string& decoder = {}) {
  VideoOptions o = small_options();
  o.codec = codec;
  o.alpha = true;
  VideoEncoder encoder(file, o);
  for (int i = 0; i < 6; ++i) encoder.add_frame(make_alpha_frame());
  encoder.finish();
  return probe_video(file, {0, 5}, decoder);
}

// Measured at the blocks' centres: ProRes 4444 alpha and colour exact; VP9 (crf 31) alpha within 1,
// colour exact. Premultiplied colour would be off by 100 (half alpha), a dropped alpha by 127.
TEST(EncoderVideo, ProRes4444KeepsStraightAlpha) {
  const fs::path dir = scratch_dir();
  const test::VideoProbe p = encode_alpha(dir / "alpha.mov", VideoCodec::prores);
  EXPECT_EQ(p.codec, "prores");
  EXPECT_NE(p.decoded_pixel_format.find("yuva444p"), std::string::npos) << p.decoded_pixel_format;
  EXPECT_EQ(p.decoded_frames, 6);
  for (const auto& frame : p.rgba_frames) {
    const AlphaError e = alpha_error(frame);
    EXPECT_LE(e.alpha, 2);
    EXPECT_LE(e.colour, 3);
  }
}

TEST(EncoderVideo, Vp9KeepsStraightAlphaForTheLibvpxDecoder) {
  const fs::path dir = scratch_dir();
  // The native VP9 decoder ignores WebM's alpha; libvpx-vp9 decodes it (as browsers do).
  const test::VideoProbe p = encode_alpha(dir / "alpha.webm", VideoCodec::vp9, "libvpx-vp9");
  EXPECT_EQ(p.codec, "vp9");
  EXPECT_EQ(p.alpha_mode, "1");  // the track header browsers need to play the alpha
  EXPECT_EQ(p.decoded_pixel_format, "yuva420p");
  EXPECT_EQ(p.decoded_frames, 6);
  for (const auto& frame : p.rgba_frames) {
    const AlphaError e = alpha_error(frame);
    EXPECT_LE(e.alpha, 6);
    EXPECT_LE(e.colour, 6);
  }
}

TEST(EncoderVideo, Ffv1KeepsAlphaExactly) {
  const fs::path dir = scratch_dir();
  const test::VideoProbe p = encode_alpha(dir / "alpha.mkv", VideoCodec::ffv1);
  for (const auto& frame : p.rgba_frames) EXPECT_EQ(frame, make_alpha_frame());
}

TEST(EncoderVideo, AlphaWithACodecThatCannotCarryItIsRefused) {
  const fs::path dir = scratch_dir();
  for (const auto& [codec, name] : {std::pair{VideoCodec::h264, "x.mp4"}, std::pair{VideoCodec::gif, "x.gif"}}) {
    VideoOptions o = small_options();
    o.codec = codec;
    o.alpha = true;
    try {
      VideoEncoder encoder(dir / name, o);
      FAIL() << name << ": alpha accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("cannot carry alpha"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("prores (.mov)"), std::string::npos) << e.what();
    }
  }
  EXPECT_TRUE(fs::is_empty(dir));
  // An RGB frame given to an encoder that expects RGBA is the wrong size.
  VideoOptions o = small_options();
  o.codec = VideoCodec::prores;
  o.alpha = true;
  VideoEncoder encoder(dir / "x.mov", o);
  EXPECT_THROW(encoder.add_frame(make_frame(0)), InputError);
}

}  // namespace
}  // namespace meshtour
