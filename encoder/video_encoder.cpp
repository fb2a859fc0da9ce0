#include "encoder/video_encoder.h"

#include "core/error.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/dict.h>
#include <libavutil/error.h>
#include <libavutil/log.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

#include <fcntl.h>
#include <unistd.h>

#include <array>
#include <mutex>
#include <string_view>
#include <system_error>
#include <utility>

namespace meshtour {
namespace {

namespace fs = std::filesystem;

// x264 output depends on its thread count (frame threads limit motion search to rows already
// encoded by the previous frame's thread). "auto" would use the number of CPUs, so the same frames
// would give different files on different machines; a fixed count keeps the bytes reproducible.
constexpr int kEncoderThreads = 4;

constexpr int kMaxSide = 16384;

// Presets libx264 accepts; checked here so a typo is reported as a bad option rather than as an
// opaque "Invalid argument" from avcodec_open2.
constexpr std::array<std::string_view, 10> kPresets = {
    "ultrafast", "superfast", "veryfast", "faster", "fast",
    "medium",    "slow",      "slower",   "veryslow", "placebo"};

std::string av_error_text(int code) {
  std::array<char, AV_ERROR_MAX_STRING_SIZE> buf{};
  if (av_strerror(code, buf.data(), buf.size()) < 0) return "libav error " + std::to_string(code);
  return buf.data();
}

std::string quoted(const fs::path& p) { return "'" + p.string() + "'"; }

// libav logs warnings and x264 statistics to stderr by default; the CLI reports errors itself.
void quiet_libav_logging() {
  static std::once_flag once;
  std::call_once(once, [] { av_log_set_level(AV_LOG_ERROR); });
}

struct CodecContextDeleter {
  void operator()(AVCodecContext* c) const { avcodec_free_context(&c); }
};
struct FrameDeleter {
  void operator()(AVFrame* f) const { av_frame_free(&f); }
};
struct PacketDeleter {
  void operator()(AVPacket* p) const { av_packet_free(&p); }
};
struct SwsDeleter {
  void operator()(SwsContext* s) const { sws_freeContext(s); }
};
// Closes the file (if one was opened) before freeing the muxer, without writing a trailer:
// a context destroyed this way belongs to a file that is about to be discarded.
struct FormatContextDeleter {
  void operator()(AVFormatContext* f) const {
    if (f->pb && !(f->oformat->flags & AVFMT_NOFILE)) avio_closep(&f->pb);
    avformat_free_context(f);
  }
};
// Option dictionaries are passed as AVDictionary** and may be replaced by the callee, so the
// owner holds the raw pointer rather than a unique_ptr.
struct Dictionary {
  AVDictionary* dict = nullptr;
  Dictionary() = default;
  Dictionary(const Dictionary&) = delete;
  Dictionary& operator=(const Dictionary&) = delete;
  ~Dictionary() { av_dict_free(&dict); }
};

using CodecContextPtr = std::unique_ptr<AVCodecContext, CodecContextDeleter>;
using FramePtr = std::unique_ptr<AVFrame, FrameDeleter>;
using PacketPtr = std::unique_ptr<AVPacket, PacketDeleter>;
using SwsPtr = std::unique_ptr<SwsContext, SwsDeleter>;
using FormatContextPtr = std::unique_ptr<AVFormatContext, FormatContextDeleter>;

/// The partially written file: removed on destruction unless commit() moved it to its final name.
/// Only a file this object created (created() was called) is ever removed, so a failure to
/// create it cannot delete something else that happens to have the same name.
class TempFile {
public:
  explicit TempFile(fs::path path) : path_(std::move(path)) {}
  ~TempFile() { discard(); }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;

  const fs::path& path() const { return path_; }
  void created() { owned_ = true; }

  void discard() noexcept {
    if (!owned_) return;
    std::error_code ec;  // best effort: nothing useful to do if removal fails during cleanup
    fs::remove(path_, ec);
    owned_ = false;
  }

  /// fsync, then rename: after a crash either the old file or the complete new one is visible.
  void commit(const fs::path& final_path) {
    const int fd = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0 || ::fsync(fd) != 0) {
      const std::error_code err(errno, std::generic_category());
      if (fd >= 0) ::close(fd);
      throw IoError("could not flush video file " + quoted(path_) + " to disk: " + err.message());
    }
    ::close(fd);
    std::error_code ec;
    fs::rename(path_, final_path, ec);
    if (ec)
      throw IoError("could not move finished video " + quoted(path_) + " to " + quoted(final_path) +
                    ": " + ec.message());
    owned_ = false;
  }

private:
  fs::path path_;
  bool owned_ = false;
};

void validate(const fs::path& output, const VideoOptions& o) {
  auto check_even = [](const char* what, int v) {
    if (v <= 0)
      throw InputError("video " + std::string(what) + " must be positive, got " + std::to_string(v));
    if (v % 2 != 0)
      throw InputError("video " + std::string(what) + " " + std::to_string(v) +
                       " is odd; H.264 in yuv420p stores colour at half resolution and needs even "
                       "sizes, use " + std::to_string(v - 1) + " or " + std::to_string(v + 1));
  };
  check_even("width", o.width);
  check_even("height", o.height);
  // H.264 levels stop at 8192x4320 (level 6.2); beyond 16384 a side players and x264 give up.
  if (o.width > kMaxSide || o.height > kMaxSide)
    throw InputError("video size " + std::to_string(o.width) + "x" + std::to_string(o.height) +
                     " is too large for H.264; use at most " + std::to_string(kMaxSide) +
                     " pixels a side (3840x2160 or less plays everywhere)");
  if (o.fps < 1 || o.fps > 240)
    throw InputError("video frame rate " + std::to_string(o.fps) + " is out of range; use 1..240 fps");
  if (o.crf < 0 || o.crf > 51)
    throw InputError("video crf " + std::to_string(o.crf) +
                     " is out of range; use 0 (lossless) .. 51 (worst), 18 is visually lossless");
  bool known = false;
  for (auto p : kPresets) known = known || p == o.preset;
  if (!known) {
    std::string list;
    for (auto p : kPresets) list += (list.empty() ? "" : ", ") + std::string(p);
    throw InputError("unknown x264 preset '" + o.preset + "'; use one of: " + list);
  }

  if (output.filename().empty() || output.filename() == "." || output.filename() == "..")
    throw InputError("video output " + quoted(output) + " is not a file name; give e.g. tour.mp4");
  std::error_code ec;
  if (fs::is_directory(output, ec))
    throw InputError("video output " + quoted(output) + " is a directory; give a file name such as " +
                     quoted(output / "tour.mp4"));
  const fs::path dir = output.parent_path().empty() ? fs::path(".") : output.parent_path();
  if (!fs::is_directory(dir, ec))
    throw IoError("output directory " + quoted(dir) + " does not exist; create it before writing " +
                  quoted(output));
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    throw IoError("output directory " + quoted(dir) + " is not writable; cannot write " + quoted(output));
}

const AVCodec* find_h264_encoder() {
  if (const AVCodec* c = avcodec_find_encoder_by_name("libx264")) return c;
  // Some FFmpeg builds leave out libx264 (GPL); any other H.264 encoder still gives a valid file.
  if (const AVCodec* c = avcodec_find_encoder(AV_CODEC_ID_H264)) return c;
  throw RuntimeFailure(
      "this FFmpeg build has no H.264 encoder; install libavcodec with libx264 support "
      "(Debian: apt install libavcodec59, see scripts/install-deps.sh)");
}

}  // namespace

struct VideoEncoder::Impl {
  enum class State { Open, Finished, Failed };

  fs::path output;
  VideoOptions options;
  // Declared before the muxer so the file is closed (muxer destroyed) before it is removed.
  TempFile temp;
  FormatContextPtr format;
  CodecContextPtr codec;
  FramePtr frame;
  PacketPtr packet;
  SwsPtr sws;
  AVStream* stream = nullptr;  // owned by `format`
  std::int64_t frames = 0;
  State state = State::Open;

  Impl(const fs::path& out, const VideoOptions& opts)
      : output(out), options(opts), temp(temp_name(out)) {
    quiet_libav_logging();
    open();
  }

  static fs::path temp_name(const fs::path& out) {
    // Same directory as the output so the final rename() stays on one filesystem (atomic); a
    // leading dot hides it, the pid keeps two concurrent runs apart.
    // Built with += : GCC 12 warns falsely (-Wrestrict, PR 105651) on "literal" + std::string&&.
    std::string name = ".";
    name += out.filename().string();
    name += ".partial-";
    name += std::to_string(::getpid());
    name += ".mp4";
    return out.parent_path() / name;
  }

  [[noreturn]] void fail_libav(const std::string& what, int code) {
    throw RuntimeFailure("video encoder for " + quoted(output) + ": " + what + " failed: " +
                         av_error_text(code));
  }

  void open() {
    // The "file:" prefix makes libav treat the path as a plain file even if it contains a ':'
    // (it would otherwise be parsed as a protocol name).
    const std::string url = "file:" + temp.path().string();

    AVFormatContext* raw_format = nullptr;
    // "mp4" given explicitly: the temporary name's extension must not decide the container.
    int ret = avformat_alloc_output_context2(&raw_format, nullptr, "mp4", url.c_str());
    if (ret < 0 || !raw_format) fail_libav("creating the MP4 muxer", ret);
    format.reset(raw_format);

    const AVCodec* encoder = find_h264_encoder();
    codec.reset(avcodec_alloc_context3(encoder));
    if (!codec) fail_libav("allocating the H.264 encoder", AVERROR(ENOMEM));
    codec->width = options.width;
    codec->height = options.height;
    codec->pix_fmt = AV_PIX_FMT_YUV420P;
    codec->time_base = AVRational{1, options.fps};  // pts counts frames
    codec->framerate = AVRational{options.fps, 1};
    codec->sample_aspect_ratio = AVRational{1, 1};
    // The renderer writes sRGB; tagging BT.709 (limited range) and converting with the same matrix
    // below makes players show the colours of the PNG frames (untagged video is guessed, often as
    // BT.601, which shifts hues).
    codec->color_primaries = AVCOL_PRI_BT709;
    codec->color_trc = AVCOL_TRC_BT709;
    codec->colorspace = AVCOL_SPC_BT709;
    codec->color_range = AVCOL_RANGE_MPEG;
    codec->thread_count = kEncoderThreads;
    codec->thread_type = FF_THREAD_FRAME;
    if (format->oformat->flags & AVFMT_GLOBALHEADER) codec->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;

    if (std::string_view(encoder->name) == "libx264") {
      ret = av_opt_set(codec->priv_data, "crf", std::to_string(options.crf).c_str(), 0);
      if (ret < 0) fail_libav("setting crf " + std::to_string(options.crf), ret);
      ret = av_opt_set(codec->priv_data, "preset", options.preset.c_str(), 0);
      if (ret < 0) fail_libav("setting preset '" + options.preset + "'", ret);
    }
    // Other H.264 encoders (fallback only) have their own rate control options; their defaults
    // are used rather than guessing at option names.

    ret = avcodec_open2(codec.get(), encoder, nullptr);
    if (ret < 0) fail_libav(std::string("opening the ") + encoder->name + " encoder", ret);

    stream = avformat_new_stream(format.get(), nullptr);
    if (!stream) fail_libav("adding the video stream", AVERROR(ENOMEM));
    ret = avcodec_parameters_from_context(stream->codecpar, codec.get());
    if (ret < 0) fail_libav("copying encoder parameters to the stream", ret);
    stream->time_base = codec->time_base;  // a hint; the MP4 muxer may pick a finer timescale
    stream->avg_frame_rate = codec->framerate;
    stream->r_frame_rate = codec->framerate;
    stream->sample_aspect_ratio = codec->sample_aspect_ratio;

    ret = avio_open(&format->pb, url.c_str(), AVIO_FLAG_WRITE);
    if (ret < 0)
      throw IoError("could not create temporary video file " + quoted(temp.path()) + ": " +
                    av_error_text(ret));
    temp.created();

    // faststart moves the index (moov) in front of the data when the trailer is written, so a
    // browser can start playing before the whole file has downloaded.
    Dictionary muxer_opts;
    av_dict_set(&muxer_opts.dict, "movflags", "+faststart", 0);
    ret = avformat_write_header(format.get(), &muxer_opts.dict);
    if (ret < 0) fail_libav("writing the MP4 header", ret);

    frame.reset(av_frame_alloc());
    packet.reset(av_packet_alloc());
    if (!frame || !packet) fail_libav("allocating frame buffers", AVERROR(ENOMEM));
    frame->format = codec->pix_fmt;
    frame->width = codec->width;
    frame->height = codec->height;
    frame->color_primaries = codec->color_primaries;
    frame->color_trc = codec->color_trc;
    frame->colorspace = codec->colorspace;
    frame->color_range = codec->color_range;
    ret = av_frame_get_buffer(frame.get(), 0);
    if (ret < 0) fail_libav("allocating the YUV frame", ret);

    // SWS_ACCURATE_RND | SWS_BITEXACT: exact rounding, and the same result with or without SIMD,
    // so the output bytes do not depend on the CPU.
    sws.reset(sws_getContext(options.width, options.height, AV_PIX_FMT_RGB24, options.width,
                             options.height, AV_PIX_FMT_YUV420P,
                             SWS_BICUBIC | SWS_ACCURATE_RND | SWS_BITEXACT | SWS_FULL_CHR_H_INP,
                             nullptr, nullptr, nullptr));
    if (!sws) fail_libav("creating the RGB to YUV converter", AVERROR(EINVAL));
    // swscale defaults to BT.601; the stream is tagged BT.709, so convert with BT.709 from
    // full-range RGB to limited-range YUV.
    const int* bt709 = sws_getCoefficients(SWS_CS_ITU709);
    if (sws_setColorspaceDetails(sws.get(), bt709, 1, bt709, 0, 0, 1 << 16, 1 << 16) < 0)
      fail_libav("setting the BT.709 colour conversion", AVERROR(ENOSYS));
  }

  void require_open(const char* call) const {
    if (state == State::Finished)
      throw RuntimeFailure(std::string("VideoEncoder::") + call + " called after finish() for " +
                           quoted(output));
    if (state == State::Failed)
      throw RuntimeFailure(std::string("VideoEncoder::") + call + " called after an earlier error "
                           "while writing " + quoted(output) + "; the file was discarded");
  }

  // Sends one frame (nullptr: flush) and writes every packet the encoder returns.
  void encode(const AVFrame* input) {
    int ret = avcodec_send_frame(codec.get(), input);
    if (ret < 0) fail_libav(input ? "encoding frame " + std::to_string(frames) : "flushing", ret);
    for (;;) {
      ret = avcodec_receive_packet(codec.get(), packet.get());
      if (ret == AVERROR(EAGAIN) || ret == AVERROR_EOF) return;
      if (ret < 0) fail_libav("encoding", ret);
      // Constant frame rate: every frame lasts one tick of 1/fps. Without a duration the MP4
      // muxer would give the last frame zero length and the file would be 1/fps too short.
      if (packet->duration <= 0) packet->duration = 1;
      av_packet_rescale_ts(packet.get(), codec->time_base, stream->time_base);
      packet->stream_index = stream->index;
      ret = av_interleaved_write_frame(format.get(), packet.get());
      av_packet_unref(packet.get());  // already blank on success; frees the data on failure
      if (ret < 0)
        throw IoError("could not write video data to " + quoted(temp.path()) + ": " +
                      av_error_text(ret));
    }
  }

  void add_frame(std::span<const std::uint8_t> rgb) {
    require_open("add_frame");
    const std::size_t expected = static_cast<std::size_t>(options.width) *
                                 static_cast<std::size_t>(options.height) * 3;
    if (rgb.size() != expected)
      throw InputError("video frame " + std::to_string(frames) + " for " + quoted(output) + " has " +
                       std::to_string(rgb.size()) + " bytes; a " + std::to_string(options.width) +
                       "x" + std::to_string(options.height) + " RGB frame needs " +
                       std::to_string(expected));
    try {
      // The encoder may still reference the previous frame's buffer.
      int ret = av_frame_make_writable(frame.get());
      if (ret < 0) fail_libav("preparing frame " + std::to_string(frames), ret);
      const std::uint8_t* src[1] = {rgb.data()};
      const int src_stride[1] = {options.width * 3};
      sws_scale(sws.get(), src, src_stride, 0, options.height, frame->data, frame->linesize);
      frame->pts = frames;
      encode(frame.get());
      ++frames;
    } catch (...) {
      abandon();
      throw;
    }
  }

  void finish() {
    require_open("finish");
    try {
      if (frames == 0)
        throw InputError("no frames were added to video " + quoted(output) + "; nothing to write");
      encode(nullptr);
      int ret = av_write_trailer(format.get());
      if (ret < 0)
        throw IoError("could not finish video file " + quoted(temp.path()) + ": " + av_error_text(ret));
      ret = avio_closep(&format->pb);  // reports write errors buffered until now (e.g. disk full)
      if (ret < 0)
        throw IoError("could not close video file " + quoted(temp.path()) + ": " + av_error_text(ret));
      temp.commit(output);
      state = State::Finished;
    } catch (...) {
      abandon();
      throw;
    }
  }

  // After an error the file is useless: close and delete it now rather than in the destructor,
  // so the caller sees no stray temporary while it handles the error.
  void abandon() noexcept {
    state = State::Failed;
    format.reset();
    temp.discard();
  }
};

VideoEncoder::VideoEncoder(const std::filesystem::path& output, const VideoOptions& options) {
  validate(output, options);
  impl_ = std::make_unique<Impl>(output, options);
}

VideoEncoder::~VideoEncoder() = default;

void VideoEncoder::add_frame(std::span<const std::uint8_t> rgb) { impl_->add_frame(rgb); }

void VideoEncoder::finish() { impl_->finish(); }

std::int64_t VideoEncoder::frames_written() const { return impl_->frames; }

}  // namespace meshtour
