#pragma once
// The video codecs meshtour writes, one row each: what the option value is called, how the file is
// stored, and the CRF range of the codecs that take one. Plain data (no libav), so that the option
// registry can show and check --codec and --crf from it without depending on the encoder.
#include <array>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "core/error.h"

namespace meshtour {

enum class VideoCodec { h264, prores, ffv1, vp9, gif };

/// A codec's constant rate factor: lower is better; `fallback` when none is given.
struct CrfRange {
  int lo, hi, fallback;
};

/// What a codec is for and how it is stored; one row per codec, for option checks and help texts.
struct VideoCodecInfo {
  VideoCodec codec;
  std::string_view name;         ///< option value: "h264", "prores", ...
  std::string_view extension;    ///< the output file's extension, with the dot: ".mp4"
  std::string_view container;    ///< for people: "MP4", "QuickTime MOV", ...
  std::string_view format;       ///< what is stored: "H.264 High, yuv420p BT.709, crf"
  std::string_view use;          ///< what it is good for
  bool lossless;                 ///< decodes to exactly the frames given
  bool needs_even_size;          ///< chroma subsampling: width and height must be even
  std::optional<CrfRange> crf;   ///< unset: the codec takes no CRF (fixed profile, lossless, palette)
  /// What is stored with --alpha (straight, not premultiplied, alpha); "" = the codec cannot carry alpha.
  std::string_view alpha_format = {};
};

/// The codecs, in help-text order (h264 first: the default).
inline constexpr std::array<VideoCodecInfo, 5> kVideoCodecs = {{
    {VideoCodec::h264, "h264", ".mp4", "MP4", "H.264 High, 8-bit 4:2:0, BT.709",
     "sharing, players, browsers (the default)", false, true, CrfRange{0, 51, 18}},
    {VideoCodec::prores, "prores", ".mov", "QuickTime MOV", "ProRes 422 HQ, 10-bit 4:2:2, BT.709",
     "editing (Final Cut, Resolve, Premiere); visually lossless, large", false, true, std::nullopt,
     "ProRes 4444, 10-bit 4:4:4 with 16-bit alpha, BT.709"},
    {VideoCodec::ffv1, "ffv1", ".mkv", "Matroska MKV", "FFV1 level 3, 8-bit RGB, intra only",
     "archives: decodes to exactly the frames given", true, false, std::nullopt,
     "FFV1 level 3, 8-bit RGBA, intra only"},
    {VideoCodec::vp9, "vp9", ".webm", "WebM", "VP9 profile 0, 8-bit 4:2:0, BT.709",
     "web pages (HTML5 <video>); smaller than H.264 at the same quality, slower", false, true, CrfRange{0, 63, 31},
     "VP9 profile 0, 8-bit 4:2:0 with a VP9-coded alpha plane (WebM AlphaMode)"},
    {VideoCodec::gif, "gif", ".gif", "GIF", "animated GIF, one 256-colour palette per clip, dithered",
     "previews where video cannot play (e-mail, READMEs); short, small clips only", false, false, std::nullopt},
}};

inline std::span<const VideoCodecInfo> video_codecs() { return kVideoCodecs; }

inline const VideoCodecInfo& video_codec_info(VideoCodec codec) {
  for (const auto& info : kVideoCodecs)
    if (info.codec == codec) return info;
  return kVideoCodecs[0];
}

/// The CRF range and default of `codec`, or nullopt when the codec takes no CRF.
inline std::optional<CrfRange> crf_range(VideoCodec codec) { return video_codec_info(codec).crf; }

/// "prores (.mov), ffv1 (.mkv) or vp9 (.webm)": the codecs that can carry alpha, for messages.
inline std::string alpha_codecs_text() {
  std::string list;
  std::size_t n = 0, total = 0;
  for (const auto& info : kVideoCodecs) total += info.alpha_format.empty() ? 0 : 1;
  for (const auto& info : kVideoCodecs) {
    if (info.alpha_format.empty()) continue;
    list += (n == 0 ? "" : n + 1 == total ? " or " : ", ") + std::string(info.name) + " (" + std::string(info.extension) + ")";
    ++n;
  }
  return list;
}

/// \throw InputError when `codec` cannot carry alpha (h264, gif), naming the codecs that can.
inline void require_alpha_codec(VideoCodec codec) {
  const VideoCodecInfo& info = video_codec_info(codec);
  if (info.alpha_format.empty())
    throw InputError("codec " + std::string(info.name) + " (" + std::string(info.extension) +
                     ") cannot carry alpha; for video with alpha use " + alpha_codecs_text() +
                     ", or leave out --alpha to show the frames over black");
}

/// The codec whose file extension `extension` is (".webm" -> vp9; case-insensitive), or nullopt.
inline std::optional<VideoCodec> codec_for_extension(std::string_view extension) {
  std::string lower(extension);
  for (char& c : lower) c = static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
  for (const auto& info : kVideoCodecs)
    if (info.extension == lower) return info.codec;
  return std::nullopt;
}

/// \throw InputError for an unknown name, listing the known ones.
inline VideoCodec parse_video_codec(std::string_view name) {
  std::string list;
  for (const auto& info : kVideoCodecs) {
    if (info.name == name) return info.codec;
    list += (list.empty() ? "" : ", ") + std::string(info.name);
  }
  throw InputError("unknown video codec '" + std::string(name) + "'; use one of: " + list);
}

}  // namespace meshtour
