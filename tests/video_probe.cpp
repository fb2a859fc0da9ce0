#include "video_probe.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/dict.h>
#include <libavutil/error.h>
#include <libavutil/pixdesc.h>
#include <libswscale/swscale.h>
}

#include <array>
#include <memory>
#include <stdexcept>

namespace meshtour::test {
namespace {

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
struct SwsDeleter {
  void operator()(SwsContext* s) const { sws_freeContext(s); }
};

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& what, int code) {
  std::array<char, AV_ERROR_MAX_STRING_SIZE> buf{};
  av_strerror(code, buf.data(), buf.size());
  throw std::runtime_error("probe_video('" + file.string() + "'): " + what + ": " + buf.data());
}

// Converts one decoded frame to packed RGB24, reading YUV as BT.709 limited range (what the encoder
// writes) and producing full-range RGB; RGB and palette frames are only repacked.
std::vector<std::uint8_t> to_rgb(const std::filesystem::path& file, const AVFrame& frame) {
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(frame.width) * frame.height * 3);
  if (frame.format == AV_PIX_FMT_BGR0 || frame.format == AV_PIX_FMT_GBRP) {
    // RGB from a lossless codec (FFV1): repacked by hand, so its pixels come back exactly.
    const bool planar = frame.format == AV_PIX_FMT_GBRP;
    for (int y = 0; y < frame.height; ++y)
      for (int x = 0; x < frame.width; ++x) {
        std::uint8_t* p = &rgb[(static_cast<std::size_t>(y) * frame.width + x) * 3];
        if (planar) {
          p[0] = frame.data[2][y * frame.linesize[2] + x];
          p[1] = frame.data[0][y * frame.linesize[0] + x];
          p[2] = frame.data[1][y * frame.linesize[1] + x];
        } else {
          const std::uint8_t* q = frame.data[0] + y * frame.linesize[0] + 4 * x;
          p[0] = q[2], p[1] = q[1], p[2] = q[0];
        }
      }
    return rgb;
  }
  std::unique_ptr<SwsContext, SwsDeleter> sws(sws_getContext(
      frame.width, frame.height, static_cast<AVPixelFormat>(frame.format), frame.width, frame.height,
      AV_PIX_FMT_RGB24, SWS_BICUBIC | SWS_ACCURATE_RND | SWS_BITEXACT | SWS_FULL_CHR_H_INT, nullptr,
      nullptr, nullptr));
  if (!sws) fail(file, "no converter from the decoded pixel format to RGB", AVERROR(EINVAL));
  const int* bt709 = sws_getCoefficients(SWS_CS_ITU709);
  const AVPixFmtDescriptor* desc = av_pix_fmt_desc_get(static_cast<AVPixelFormat>(frame.format));
  const bool yuv = desc && !(desc->flags & (AV_PIX_FMT_FLAG_RGB | AV_PIX_FMT_FLAG_PAL));
  if (yuv && sws_setColorspaceDetails(sws.get(), bt709, 0, bt709, 1, 0, 1 << 16, 1 << 16) < 0)
    fail(file, "BT.709 conversion unsupported", AVERROR(ENOSYS));
  std::uint8_t* dst[1] = {rgb.data()};
  const int dst_stride[1] = {frame.width * 3};
  sws_scale(sws.get(), frame.data, frame.linesize, 0, frame.height, dst, dst_stride);
  return rgb;
}

// Converts one decoded frame to packed RGBA with straight alpha (colour as to_rgb reads it; the
// alpha plane is carried over as it is; 255 where the frame has none).
std::vector<std::uint8_t> to_rgba(const std::filesystem::path& file, const AVFrame& frame) {
  const std::vector<std::uint8_t> rgb = to_rgb(file, frame);
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(frame.width) * frame.height * 4, 255);
  for (std::size_t p = 0, n = static_cast<std::size_t>(frame.width) * frame.height; p < n; ++p)
    for (int c = 0; c < 3; ++c) rgba[p * 4 + static_cast<std::size_t>(c)] = rgb[p * 3 + static_cast<std::size_t>(c)];
  const AVPixFmtDescriptor* desc = av_pix_fmt_desc_get(static_cast<AVPixelFormat>(frame.format));
  if (!desc || !(desc->flags & AV_PIX_FMT_FLAG_ALPHA)) return rgba;
  // Alpha by hand from its component: the plane (planar formats) or the byte (packed 8-bit RGBA
  // kinds), scaled from its bit depth to 8 bits with rounding.
  const AVComponentDescriptor& a = desc->comp[3];
  const int bits = a.depth;
  for (int y = 0; y < frame.height; ++y)
    for (int x = 0; x < frame.width; ++x) {
      const std::uint8_t* row = frame.data[a.plane] + static_cast<std::ptrdiff_t>(y) * frame.linesize[a.plane];
      unsigned v = 0;
      if (bits <= 8) {
        v = row[x * a.step + a.offset];
      } else {
        const std::uint8_t* q = row + x * a.step + a.offset;
        v = (static_cast<unsigned>(q[0]) | static_cast<unsigned>(q[1]) << 8) >> a.shift;  // little-endian
        v = (v * 255u + ((1u << bits) - 1u) / 2u) / ((1u << bits) - 1u);
      }
      rgba[(static_cast<std::size_t>(y) * frame.width + x) * 4 + 3] = static_cast<std::uint8_t>(v);
    }
  return rgba;
}

}  // namespace

VideoProbe probe_video(const std::filesystem::path& file, const std::vector<int>& keep, const std::string& decoder_name) {
  const std::string url = "file:" + file.string();
  AVFormatContext* raw = nullptr;
  int ret = avformat_open_input(&raw, url.c_str(), nullptr, nullptr);
  if (ret < 0) fail(file, "cannot open", ret);
  std::unique_ptr<AVFormatContext, InputDeleter> input(raw);
  ret = avformat_find_stream_info(input.get(), nullptr);
  if (ret < 0) fail(file, "cannot read stream info", ret);
  const int index = av_find_best_stream(input.get(), AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
  if (index < 0) fail(file, "no video stream", index);
  const AVStream* stream = input->streams[index];
  const AVCodecParameters* par = stream->codecpar;

  VideoProbe probe;
  probe.codec = avcodec_get_name(par->codec_id);
  const char* pix = av_get_pix_fmt_name(static_cast<AVPixelFormat>(par->format));
  probe.pixel_format = pix ? pix : "unknown";
  probe.width = par->width;
  probe.height = par->height;
  probe.fps = av_q2d(stream->avg_frame_rate);
  probe.duration_seconds = stream->duration != AV_NOPTS_VALUE
                               ? static_cast<double>(stream->duration) * av_q2d(stream->time_base)
                               : static_cast<double>(input->duration) / AV_TIME_BASE;
  probe.stream_frames = stream->nb_frames;
  // Matroska/WebM: the demuxer reports a track's AlphaMode element as this stream tag.
  if (const AVDictionaryEntry* tag = av_dict_get(stream->metadata, "alpha_mode", nullptr, 0)) probe.alpha_mode = tag->value;

  const AVCodec* decoder =
      decoder_name.empty() ? avcodec_find_decoder(par->codec_id) : avcodec_find_decoder_by_name(decoder_name.c_str());
  if (!decoder)
    fail(file, "no decoder " + (decoder_name.empty() ? "for " + probe.codec : decoder_name), AVERROR_DECODER_NOT_FOUND);
  std::unique_ptr<AVCodecContext, CodecDeleter> codec(avcodec_alloc_context3(decoder));
  if (!codec) fail(file, "allocating decoder", AVERROR(ENOMEM));
  ret = avcodec_parameters_to_context(codec.get(), par);
  if (ret < 0) fail(file, "configuring decoder", ret);
  codec->thread_count = 1;  // small test videos; one thread keeps frame output order trivial
  ret = avcodec_open2(codec.get(), decoder, nullptr);
  if (ret < 0) fail(file, "opening decoder", ret);

  std::unique_ptr<AVPacket, PacketDeleter> packet(av_packet_alloc());
  std::unique_ptr<AVFrame, FrameDeleter> frame(av_frame_alloc());
  if (!packet || !frame) fail(file, "allocating buffers", AVERROR(ENOMEM));
  probe.rgb_frames.resize(keep.size());
  probe.rgba_frames.resize(keep.size());

  // Decoded frames come out in display order, so the running count is the frame index.
  auto drain = [&] {
    for (;;) {
      const int r = avcodec_receive_frame(codec.get(), frame.get());
      if (r == AVERROR(EAGAIN) || r == AVERROR_EOF) return;
      if (r < 0) fail(file, "decoding", r);
      for (std::size_t k = 0; k < keep.size(); ++k)
        if (keep[k] == probe.decoded_frames) {
          probe.rgb_frames[k] = to_rgb(file, *frame);
          probe.rgba_frames[k] = to_rgba(file, *frame);
        }
      if (probe.decoded_frames == 0) {
        const char* name = av_get_pix_fmt_name(static_cast<AVPixelFormat>(frame->format));
        probe.decoded_pixel_format = name ? name : "unknown";
      }
      ++probe.decoded_frames;
      av_frame_unref(frame.get());
    }
  };
  while ((ret = av_read_frame(input.get(), packet.get())) >= 0) {
    if (packet->stream_index == index) {
      ret = avcodec_send_packet(codec.get(), packet.get());
      av_packet_unref(packet.get());
      if (ret < 0) fail(file, "sending packet to decoder", ret);
      drain();
    } else {
      av_packet_unref(packet.get());
    }
  }
  if (ret != AVERROR_EOF) fail(file, "reading packets", ret);
  ret = avcodec_send_packet(codec.get(), nullptr);  // flush: the decoder holds back B-frame delay
  if (ret < 0) fail(file, "flushing decoder", ret);
  drain();

  for (std::size_t k = 0; k < keep.size(); ++k)
    if (keep[k] < 0 || keep[k] >= probe.decoded_frames)
      throw std::runtime_error("probe_video('" + file.string() + "'): frame " +
                               std::to_string(keep[k]) + " requested but only " +
                               std::to_string(probe.decoded_frames) + " frames decoded");
  return probe;
}

}  // namespace meshtour::test
