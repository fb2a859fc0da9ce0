#include "encoder/video_encoder.h"

#include "core/atomic_file.h"
#include "core/error.h"
#include "encoder/libav_support.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavfilter/avfilter.h>
#include <libavfilter/buffersink.h>
#include <libavfilter/buffersrc.h>
#include <libavformat/avformat.h>
#include <libavutil/cpu.h>
#include <libavutil/dict.h>
#include <libavutil/error.h>
#include <libavutil/log.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstring>
#include <mutex>
#include <string_view>
#include <system_error>
#include <utility>

namespace meshtour {
namespace {

namespace fs = std::filesystem;

// Muxers that write random or run-dependent fields (Matroska's segment UID) or version strings
// unless told to be bit-exact. MP4 (H.264) keeps the bytes it always had: it writes no random
// fields, only the library version, which is the same for every run of the same binary.
bool muxer_needs_bitexact(VideoCodec codec) { return codec != VideoCodec::h264; }

const char* muxer_name(VideoCodec codec) {
  switch (codec) {
    case VideoCodec::h264: return "mp4";
    case VideoCodec::prores: return "mov";
    case VideoCodec::ffv1: return "matroska";
    case VideoCodec::vp9: return "webm";
    case VideoCodec::gif: return "gif";
  }
  return "mp4";
}

// GIF palette: computed over the whole clip (no flicker between frames) by libavfilter's
// palettegen, applied with error-diffusion dithering (sequential, so deterministic); one
// palette entry stays transparent so the GIF encoder can store only what changed between frames.
constexpr const char* kGifFilter =
    "split[a][b];[a]palettegen=stats_mode=full[p];[b][p]paletteuse=dither=sierra2_4a";

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

using libav::FilterGraphPtr;
using libav::FramePtr;

std::string quoted(const fs::path& p) { return "'" + p.string() + "'"; }


struct CodecContextDeleter {
  void operator()(AVCodecContext* c) const { avcodec_free_context(&c); }
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
using PacketPtr = std::unique_ptr<AVPacket, PacketDeleter>;
using SwsPtr = std::unique_ptr<SwsContext, SwsDeleter>;
using FormatContextPtr = std::unique_ptr<AVFormatContext, FormatContextDeleter>;
struct FilterInOut {
  AVFilterInOut* list = nullptr;
  FilterInOut() = default;
  FilterInOut(const FilterInOut&) = delete;
  FilterInOut& operator=(const FilterInOut&) = delete;
  ~FilterInOut() { avfilter_inout_free(&list); }
};

std::string lowercase(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

void validate(const fs::path& output, const VideoOptions& o) {
  const VideoCodecInfo& info = video_codec_info(o.codec);
  const std::string codec(info.name);
  auto check_size = [&](const char* what, int v) {
    if (v <= 0)
      throw InputError("video " + std::string(what) + " must be positive, got " + std::to_string(v));
    if (info.needs_even_size && v % 2 != 0)
      throw InputError("video " + std::string(what) + " " + std::to_string(v) + " is odd; " + codec +
                       " stores colour at half resolution and needs even sizes, use " +
                       std::to_string(v - 1) + " or " + std::to_string(v + 1));
  };
  if (o.alpha) require_alpha_codec(o.codec);
  check_size("width", o.width);
  check_size("height", o.height);
  // H.264 levels stop at 8192x4320 (level 6.2); beyond 16384 a side players and encoders give up.
  if (o.width > kMaxSide || o.height > kMaxSide)
    throw InputError("video size " + std::to_string(o.width) + "x" + std::to_string(o.height) +
                     " is too large for " + codec + "; use at most " + std::to_string(kMaxSide) +
                     " pixels a side (3840x2160 or less plays everywhere)");
  if (o.fps < 1 || o.fps > 240)
    throw InputError("video frame rate " + std::to_string(o.fps) + " is out of range; use 1..240 fps");
  const std::optional<CrfRange> crf = crf_range(o.codec);
  if (o.crf && !crf)
    throw InputError(std::string("crf does not apply to ") + codec +
                     (info.lossless ? " (it is lossless)" : o.codec == VideoCodec::prores
                                                                ? " (ProRes 422 HQ has a fixed quality)"
                                                                : " (its quality is set by the 256-colour palette)") +
                     "; leave it out, or use h264 or vp9 for a crf");
  if (o.crf && (*o.crf < crf->lo || *o.crf > crf->hi))
    throw InputError("video crf " + std::to_string(*o.crf) + " is out of range for " + codec + "; use " +
                     std::to_string(crf->lo) + " (best) .. " + std::to_string(crf->hi) +
                     " (worst), default " + std::to_string(crf->fallback) +
                     (o.codec == VideoCodec::h264 ? " (visually lossless)" : ""));
  bool known = false;
  for (auto p : kPresets) known = known || p == o.preset;
  if (!known) {
    std::string list;
    for (auto p : kPresets) list += (list.empty() ? "" : ", ") + std::string(p);
    throw InputError("unknown x264 preset '" + o.preset + "'; use one of: " + list);
  }

  const std::string example = "tour" + std::string(info.extension);
  if (output.filename().empty() || output.filename() == "." || output.filename() == "..")
    throw InputError("video output " + quoted(output) + " is not a file name; give e.g. " + example);
  std::error_code ec;
  if (fs::is_directory(output, ec))
    throw InputError("video output " + quoted(output) + " is a directory; give a file name such as " +
                     quoted(output / example));
  if (lowercase(output.extension().string()) != info.extension) {
    std::string hint;
    for (const auto& other : video_codecs())
      if (other.extension == lowercase(output.extension().string()))
        hint = " (" + std::string(other.extension) + " is for codec " + std::string(other.name) + ")";
    throw InputError("video output " + quoted(output) + ": codec " + codec + " is written as " +
                     std::string(info.container) + "; name the file *" + std::string(info.extension) + hint);
  }
  const fs::path dir = output.parent_path().empty() ? fs::path(".") : output.parent_path();
  if (!fs::is_directory(dir, ec))
    throw IoError("output directory " + quoted(dir) + " does not exist; create it before writing " +
                  quoted(output));
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    throw IoError("output directory " + quoted(dir) + " is not writable; cannot write " + quoted(output));
}

// The SIMD code x264 may use, named as its "asm" option expects. Left to itself x264 picks every
// extension the CPU has, and its output is not the same for all of them: measured with x264
// 0.164 (Debian 12), plain SSE2 gives other bytes than SSSE3 .. AVX2 (which all agree), and its
// AVX-512 code reads memory it never wrote, so on an AVX-512 CPU the same frames gave different
// files from run to run (MALLOC_PERTURB_ changed them). Capping at AVX2 gives the same bytes on
// every x86-64 CPU with SSSE3 (all since about 2011). Empty on other architectures: x264 decides.
std::string x264_cpu_features() {
#if defined(__x86_64__) || defined(__i386__)
  const int cpu = av_get_cpu_flags();
  std::string list = "MMX2,SSE2,SSE2Fast";
  const std::pair<int, const char*> extensions[] = {
      {AV_CPU_FLAG_SSE3, "SSE3"}, {AV_CPU_FLAG_SSSE3, "SSSE3"}, {AV_CPU_FLAG_SSE4, "SSE4.1"},
      {AV_CPU_FLAG_SSE42, "SSE4.2"}, {AV_CPU_FLAG_AVX, "AVX"}, {AV_CPU_FLAG_FMA3, "FMA3"},
      {AV_CPU_FLAG_AVX2, "AVX2"}, {AV_CPU_FLAG_BMI1, "BMI1"}, {AV_CPU_FLAG_BMI2, "BMI2"}};
  for (const auto& [flag, name] : extensions)
    if (cpu & flag) (list += ",") += name;
  return list;
#else
  return {};
#endif
}

const AVCodec* find_h264_encoder() {
  if (const AVCodec* c = avcodec_find_encoder_by_name("libx264")) return c;
  // Some FFmpeg builds leave out libx264 (GPL); any other H.264 encoder still gives a valid file.
  if (const AVCodec* c = avcodec_find_encoder(AV_CODEC_ID_H264)) return c;
  throw RuntimeFailure(
      "this FFmpeg build has no H.264 encoder; install libavcodec with libx264 support "
      "(Debian: apt install libavcodec59, see scripts/install-deps.sh)");
}

const AVCodec* find_encoder(VideoCodec codec) {
  const char* name = nullptr;
  switch (codec) {
    case VideoCodec::h264: return find_h264_encoder();
    case VideoCodec::prores: name = "prores_ks"; break;  // the encoder with profiles and 10-bit 4:2:2
    case VideoCodec::ffv1: name = "ffv1"; break;
    case VideoCodec::vp9: name = "libvpx-vp9"; break;
    case VideoCodec::gif: name = "gif"; break;
  }
  if (const AVCodec* c = avcodec_find_encoder_by_name(name)) return c;
  throw RuntimeFailure(std::string("this FFmpeg build has no ") + name +
                       " encoder; install Debian's libavcodec59 (see scripts/install-deps.sh)");
}

AVPixelFormat encoder_pixel_format(VideoCodec codec, bool alpha) {
  if (alpha) {
    switch (codec) {
      case VideoCodec::prores: return AV_PIX_FMT_YUVA444P10LE;  // ProRes 4444: full-resolution colour
      case VideoCodec::ffv1: return AV_PIX_FMT_BGRA;             // bytes B, G, R, A: lossless
      case VideoCodec::vp9: return AV_PIX_FMT_YUVA420P;          // libvpx codes the alpha as a second plane
      case VideoCodec::h264:
      case VideoCodec::gif: break;                                // refused by validate()
    }
  }
  switch (codec) {
    case VideoCodec::h264: return AV_PIX_FMT_YUV420P;
    case VideoCodec::prores: return AV_PIX_FMT_YUV422P10LE;
    // Packed 8-bit RGB (bytes B, G, R, unused): FFV1's only 8-bit RGB layout. No colour
    // conversion, so the archive is lossless.
    case VideoCodec::ffv1: return AV_PIX_FMT_BGR0;
    case VideoCodec::vp9: return AV_PIX_FMT_YUV420P;
    case VideoCodec::gif: return AV_PIX_FMT_PAL8;
  }
  return AV_PIX_FMT_YUV420P;
}

}  // namespace

struct VideoEncoder::Impl {
  enum class State { Open, Finished, Failed };

  fs::path output;
  VideoOptions options;
  // Declared before the muxer so the file is closed (muxer destroyed) before it is removed.
  PendingFile temp;
  FormatContextPtr format;
  CodecContextPtr codec;
  FramePtr frame;
  PacketPtr packet;
  SwsPtr sws;
  FramePtr rgb_input;  // padded copy of the caller's RGB, what swscale reads
  // GIF only: RGB frames -> palettegen/paletteuse -> PAL8 frames for the encoder.
  FilterGraphPtr graph;
  AVFilterContext* source = nullptr;  // owned by `graph`
  AVFilterContext* sink = nullptr;    // owned by `graph`
  FramePtr filtered;
  std::int64_t frames_to_encoder = 0;
  AVStream* stream = nullptr;  // owned by `format`
  std::int64_t frames = 0;
  State state = State::Open;

  Impl(const fs::path& out, const VideoOptions& opts)
      // The temporary's extension is the codec's, whatever the output is called.
      : output(out), options(opts), temp(out, std::string(video_codec_info(opts.codec).extension)) {
    libav::quiet_logging();
    open();
  }


  [[noreturn]] void fail_libav(const std::string& what, int code) {
    throw RuntimeFailure("video encoder for " + quoted(output) + ": " + what + " failed: " +
                         libav::error_text(code));
  }

  void set_private(const char* key, const std::string& value) {
    const int ret = av_opt_set(codec->priv_data, key, value.c_str(), 0);
    if (ret < 0) fail_libav(std::string("setting ") + key + "=" + value, ret);
  }

  // Codec-specific settings. Thread counts are fixed constants, never "auto": the bytes must not
  // depend on the machine's core count.
  void configure_codec(const AVCodec* encoder) {
    const std::optional<CrfRange> range = crf_range(options.codec);
    const int crf = options.crf.value_or(range ? range->fallback : 0);
    const bool yuv = options.codec != VideoCodec::ffv1 && options.codec != VideoCodec::gif;
    if (yuv) {
      // The renderer writes sRGB; tagging BT.709 (limited range) and converting with the same
      // matrix makes players show the colours of the PNG frames (untagged video is guessed, often
      // as BT.601, which shifts hues).
      codec->color_primaries = AVCOL_PRI_BT709;
      codec->color_trc = AVCOL_TRC_BT709;
      codec->colorspace = AVCOL_SPC_BT709;
      codec->color_range = AVCOL_RANGE_MPEG;
    } else if (options.codec == VideoCodec::ffv1) {
      codec->color_primaries = AVCOL_PRI_BT709;  // sRGB primaries
      codec->color_trc = AVCOL_TRC_IEC61966_2_1;
      codec->colorspace = AVCOL_SPC_RGB;
      codec->color_range = AVCOL_RANGE_JPEG;
    }
    switch (options.codec) {
      case VideoCodec::h264:
        codec->thread_count = kEncoderThreads;
        codec->thread_type = FF_THREAD_FRAME;
        if (std::string_view(encoder->name) == "libx264") {
          set_private("crf", std::to_string(crf));
          set_private("preset", options.preset);
          if (const std::string features = x264_cpu_features(); !features.empty())
            set_private("x264-params", "asm=" + features);
        }
        // Other H.264 encoders (fallback only) have their own rate control options; their
        // defaults are used rather than guessing at option names.
        break;
      case VideoCodec::prores:
        // Slices are coded independently, so the thread count only changes the speed.
        codec->thread_count = kEncoderThreads;
        codec->thread_type = FF_THREAD_SLICE;
        set_private("profile", options.alpha ? "4444" : "hq");
        break;
      case VideoCodec::ffv1:
        // Level 3 (slices with CRCs, the archival standard), every frame a key frame so any
        // frame can be cut out; a fixed slice count, since that shapes the bitstream.
        codec->thread_count = kEncoderThreads;
        codec->thread_type = FF_THREAD_SLICE;
        codec->level = 3;
        codec->slices = 4;
        codec->gop_size = 1;
        set_private("slicecrc", "1");
        set_private("context", "1");  // the large context model: smaller files, same pixels
        break;
      case VideoCodec::vp9:
        // Constant quality (crf with zero target bit rate). Tiles are coded independently, so
        // threads only share out the tile columns; row-based multithreading stays off.
        codec->bit_rate = 0;
        codec->thread_count = kEncoderThreads;
        set_private("crf", std::to_string(crf));
        set_private("deadline", "good");
        set_private("cpu-used", "4");
        set_private("row-mt", "0");
        set_private("tile-columns", "2");  // log2: up to 4 columns, fewer on narrow frames
        set_private("frame-parallel", "0");
        break;
      case VideoCodec::gif:
        codec->thread_count = 1;
        break;
    }
    if (options.codec != VideoCodec::h264) codec->flags |= AV_CODEC_FLAG_BITEXACT;
  }

  void open() {
    const VideoCodecInfo& info = video_codec_info(options.codec);
    // The "file:" prefix makes libav treat the path as a plain file even if it contains a ':'
    // (it would otherwise be parsed as a protocol name).
    const std::string url = "file:" + temp.temporary().string();

    AVFormatContext* raw_format = nullptr;
    // Named explicitly: the temporary name's extension must not decide the container.
    int ret = avformat_alloc_output_context2(&raw_format, nullptr, muxer_name(options.codec), url.c_str());
    if (ret < 0 || !raw_format) fail_libav(std::string("creating the ") + std::string(info.container) + " muxer", ret);
    format.reset(raw_format);
    if (muxer_needs_bitexact(options.codec)) format->flags |= AVFMT_FLAG_BITEXACT;

    const AVCodec* encoder = find_encoder(options.codec);
    codec.reset(avcodec_alloc_context3(encoder));
    if (!codec) fail_libav(std::string("allocating the ") + encoder->name + " encoder", AVERROR(ENOMEM));
    codec->width = options.width;
    codec->height = options.height;
    codec->pix_fmt = encoder_pixel_format(options.codec, options.alpha);
    codec->time_base = AVRational{1, options.fps};  // pts counts frames
    codec->framerate = AVRational{options.fps, 1};
    codec->sample_aspect_ratio = AVRational{1, 1};
    if (format->oformat->flags & AVFMT_GLOBALHEADER) codec->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
    configure_codec(encoder);

    ret = avcodec_open2(codec.get(), encoder, nullptr);
    if (ret < 0) fail_libav(std::string("opening the ") + encoder->name + " encoder", ret);

    stream = avformat_new_stream(format.get(), nullptr);
    if (!stream) fail_libav("adding the video stream", AVERROR(ENOMEM));
    ret = avcodec_parameters_from_context(stream->codecpar, codec.get());
    if (ret < 0) fail_libav("copying encoder parameters to the stream", ret);
    stream->time_base = codec->time_base;  // a hint; the muxer may pick its own timescale
    stream->avg_frame_rate = codec->framerate;
    stream->r_frame_rate = codec->framerate;
    stream->sample_aspect_ratio = codec->sample_aspect_ratio;
    // (VP9 with alpha: the Matroska muxer writes the track's AlphaMode, which tells players to
    // decode the alpha plane libvpx stores beside each frame, from the yuva420p pixel format.)

    ret = avio_open(&format->pb, url.c_str(), AVIO_FLAG_WRITE);
    if (ret < 0)
      throw IoError("could not create temporary video file " + quoted(temp.temporary()) + ": " +
                    libav::error_text(ret));

    Dictionary muxer_opts;
    // faststart moves the index (moov) in front of the data when the trailer is written, so a
    // browser can start playing before the whole file has downloaded.
    if (options.codec == VideoCodec::h264) av_dict_set(&muxer_opts.dict, "movflags", "+faststart", 0);
    ret = avformat_write_header(format.get(), &muxer_opts.dict);
    if (ret < 0) fail_libav(std::string("writing the ") + std::string(info.container) + " header", ret);

    frame.reset(av_frame_alloc());
    packet.reset(av_packet_alloc());
    if (!frame || !packet) fail_libav("allocating frame buffers", AVERROR(ENOMEM));

    if (options.codec == VideoCodec::gif) {
      open_palette_filter();
      return;
    }
    frame->format = codec->pix_fmt;
    frame->width = codec->width;
    frame->height = codec->height;
    frame->color_primaries = codec->color_primaries;
    frame->color_trc = codec->color_trc;
    frame->colorspace = codec->colorspace;
    frame->color_range = codec->color_range;
    ret = av_frame_get_buffer(frame.get(), 0);
    if (ret < 0) fail_libav("allocating the encoder's frame", ret);
    zero_buffers(*frame);
    if (options.codec == VideoCodec::ffv1) return;  // RGB is copied into planes, no conversion

    // swscale's SIMD code reads up to 16 bytes past the end of its input rows (valgrind shows
    // it). Reading past the caller's vector would make the output depend on whatever lies
    // there, so frames are copied into a padded, zeroed buffer first.
    rgb_input.reset(av_frame_alloc());
    if (!rgb_input) fail_libav("allocating frame buffers", AVERROR(ENOMEM));
    rgb_input->format = options.alpha ? AV_PIX_FMT_RGBA : AV_PIX_FMT_RGB24;
    rgb_input->width = options.width;
    rgb_input->height = options.height;
    ret = av_frame_get_buffer(rgb_input.get(), 64);
    if (ret < 0) fail_libav("allocating the RGB input frame", ret);
    zero_buffers(*rgb_input);

    // SWS_ACCURATE_RND | SWS_BITEXACT: exact rounding, and the same result with or without SIMD,
    // so the output bytes do not depend on the CPU.
    // With alpha, swscale carries the alpha plane over unchanged: colour stays straight.
    sws.reset(sws_getContext(options.width, options.height, static_cast<AVPixelFormat>(rgb_input->format), options.width,
                             options.height, codec->pix_fmt,
                             SWS_BICUBIC | SWS_ACCURATE_RND | SWS_BITEXACT | SWS_FULL_CHR_H_INP,
                             nullptr, nullptr, nullptr));
    if (!sws) fail_libav("creating the RGB to YUV converter", AVERROR(EINVAL));
    // swscale defaults to BT.601; the stream is tagged BT.709, so convert with BT.709 from
    // full-range RGB to limited-range YUV.
    const int* bt709 = sws_getCoefficients(SWS_CS_ITU709);
    if (sws_setColorspaceDetails(sws.get(), bt709, 1, bt709, 0, 0, 1 << 16, 1 << 16) < 0)
      fail_libav("setting the BT.709 colour conversion", AVERROR(ENOSYS));
  }

  void open_palette_filter() {
    graph.reset(avfilter_graph_alloc());
    if (!graph) fail_libav("allocating the GIF palette filter", AVERROR(ENOMEM));
    graph->nb_threads = 1;  // filters run in sequence: same result on every machine
    const std::string source_args = "video_size=" + std::to_string(options.width) + "x" +
                                    std::to_string(options.height) + ":pix_fmt=" +
                                    std::to_string(AV_PIX_FMT_RGB24) + ":time_base=1/" +
                                    std::to_string(options.fps) + ":pixel_aspect=1/1";
    int ret = avfilter_graph_create_filter(&source, avfilter_get_by_name("buffer"), "frames",
                                           source_args.c_str(), nullptr, graph.get());
    if (ret < 0) fail_libav("creating the GIF filter input", ret);
    ret = avfilter_graph_create_filter(&sink, avfilter_get_by_name("buffersink"), "gif", nullptr, nullptr,
                                       graph.get());
    if (ret < 0) fail_libav("creating the GIF filter output", ret);
    const AVPixelFormat pal8[] = {AV_PIX_FMT_PAL8, AV_PIX_FMT_NONE};
    ret = av_opt_set_int_list(sink, "pix_fmts", pal8, AV_PIX_FMT_NONE, AV_OPT_SEARCH_CHILDREN);
    if (ret < 0) fail_libav("restricting the GIF filter output to 8-bit palette", ret);

    // The graph text's open ends: its input is fed by `source`, its output drains into `sink`.
    FilterInOut graph_input, graph_output;
    graph_input.list = avfilter_inout_alloc();
    graph_output.list = avfilter_inout_alloc();
    if (!graph_input.list || !graph_output.list) fail_libav("allocating the GIF filter", AVERROR(ENOMEM));
    graph_input.list->name = av_strdup("in");
    graph_input.list->filter_ctx = source;
    graph_input.list->pad_idx = 0;
    graph_output.list->name = av_strdup("out");
    graph_output.list->filter_ctx = sink;
    graph_output.list->pad_idx = 0;
    ret = avfilter_graph_parse_ptr(graph.get(), kGifFilter, &graph_output.list, &graph_input.list, nullptr);
    if (ret < 0) fail_libav("building the GIF palette filter", ret);
    ret = avfilter_graph_config(graph.get(), nullptr);
    if (ret < 0) fail_libav("configuring the GIF palette filter", ret);
    filtered.reset(av_frame_alloc());
    if (!filtered) fail_libav("allocating frame buffers", AVERROR(ENOMEM));
  }

  int bytes_per_pixel() const { return options.alpha ? 4 : 3; }

  // Packed RGB(A) rows into a frame whose rows may be longer (aligned).
  void copy_rows(std::span<const std::uint8_t> rgb, AVFrame& dst) const {
    const std::size_t row = static_cast<std::size_t>(options.width) * static_cast<std::size_t>(bytes_per_pixel());
    for (int y = 0; y < options.height; ++y)
      std::memcpy(dst.data[0] + static_cast<std::ptrdiff_t>(y) * dst.linesize[0], rgb.data() + y * row, row);
  }

  static void zero_buffers(AVFrame& f) {
    for (int plane = 0; plane < AV_NUM_DATA_POINTERS && f.buf[plane]; ++plane)
      std::memset(f.buf[plane]->data, 0, f.buf[plane]->size);
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
    if (ret < 0) fail_libav(input ? "encoding frame " + std::to_string(input->pts) : "flushing", ret);
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
        throw IoError("could not write video data to " + quoted(temp.temporary()) + ": " +
                      libav::error_text(ret));
    }
  }

  // GIF: encodes every frame the palette filter has ready (all of them only once it saw the end).
  void drain_palette_filter() {
    for (;;) {
      const int ret = av_buffersink_get_frame(sink, filtered.get());
      if (ret == AVERROR(EAGAIN) || ret == AVERROR_EOF) return;
      if (ret < 0) fail_libav("applying the GIF palette", ret);
      filtered->pts = frames_to_encoder++;
      try {
        encode(filtered.get());
      } catch (...) {
        av_frame_unref(filtered.get());
        throw;
      }
      av_frame_unref(filtered.get());
    }
  }

  void add_gif_frame(std::span<const std::uint8_t> rgb) {
    // Each frame needs a buffer of its own: the palette filter keeps them all until the end.
    FramePtr input(av_frame_alloc());
    if (!input) fail_libav("allocating frame " + std::to_string(frames), AVERROR(ENOMEM));
    input->format = AV_PIX_FMT_RGB24;
    input->width = options.width;
    input->height = options.height;
    int ret = av_frame_get_buffer(input.get(), 0);
    if (ret < 0) fail_libav("allocating frame " + std::to_string(frames), ret);
    zero_buffers(*input);  // the filters' own pixel conversion reads into the row padding too
    copy_rows(rgb, *input);
    input->pts = frames;
    ret = av_buffersrc_add_frame_flags(source, input.get(), 0);  // takes over the buffer
    if (ret < 0) fail_libav("sending frame " + std::to_string(frames) + " to the GIF palette filter", ret);
    drain_palette_filter();
  }

  void convert_into_frame(std::span<const std::uint8_t> rgb) {
    // The encoder may still reference the previous frame's buffer.
    int ret = av_frame_make_writable(frame.get());
    if (ret < 0) fail_libav("preparing frame " + std::to_string(frames), ret);
    if (options.codec == VideoCodec::ffv1) {
      // A plain copy into B, G, R, 0 (or A) order, so the archive holds exactly the given pixels.
      const std::size_t width = static_cast<std::size_t>(options.width);
      const std::size_t n = static_cast<std::size_t>(bytes_per_pixel());
      for (int y = 0; y < options.height; ++y) {
        const std::uint8_t* src = rgb.data() + y * width * n;
        std::uint8_t* dst = frame->data[0] + static_cast<std::ptrdiff_t>(y) * frame->linesize[0];
        for (std::size_t x = 0; x < width; ++x) {
          dst[4 * x] = src[n * x + 2];
          dst[4 * x + 1] = src[n * x + 1];
          dst[4 * x + 2] = src[n * x];
          dst[4 * x + 3] = n == 4 ? src[n * x + 3] : 0;
        }
      }
      return;
    }
    copy_rows(rgb, *rgb_input);
    sws_scale(sws.get(), rgb_input->data, rgb_input->linesize, 0, options.height, frame->data, frame->linesize);
  }

  void add_frame(std::span<const std::uint8_t> rgb) {
    require_open("add_frame");
    const std::size_t expected = static_cast<std::size_t>(options.width) *
                                 static_cast<std::size_t>(options.height) * static_cast<std::size_t>(bytes_per_pixel());
    if (rgb.size() != expected)
      throw InputError("video frame " + std::to_string(frames) + " for " + quoted(output) + " has " +
                       std::to_string(rgb.size()) + " bytes; a " + std::to_string(options.width) +
                       "x" + std::to_string(options.height) + (options.alpha ? " RGBA" : " RGB") + " frame needs " +
                       std::to_string(expected));
    try {
      if (graph) {
        add_gif_frame(rgb);
      } else {
        convert_into_frame(rgb);
        frame->pts = frames;
        encode(frame.get());
      }
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
      if (graph) {
        const int ret = av_buffersrc_add_frame_flags(source, nullptr, 0);  // end of stream
        if (ret < 0) fail_libav("ending the GIF palette filter", ret);
        drain_palette_filter();
      }
      encode(nullptr);
      int ret = av_write_trailer(format.get());
      if (ret < 0)
        throw IoError("could not finish video file " + quoted(temp.temporary()) + ": " + libav::error_text(ret));
      ret = avio_closep(&format->pb);  // reports write errors buffered until now (e.g. disk full)
      if (ret < 0)
        throw IoError("could not close video file " + quoted(temp.temporary()) + ": " + libav::error_text(ret));
      temp.commit();
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
