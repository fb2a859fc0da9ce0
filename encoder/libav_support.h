#pragma once
// What the encoder's libav users share (video_encoder.cpp, caption.cpp): error text, the log level,
// and owners of libav's frames and filter graphs. Internal to encoder/.
extern "C" {
#include <libavfilter/avfilter.h>
#include <libavutil/error.h>
#include <libavutil/frame.h>
#include <libavutil/log.h>
}

#include <array>
#include <memory>
#include <mutex>
#include <string>

namespace meshtour::libav {

inline std::string error_text(int code) {
  std::array<char, AV_ERROR_MAX_STRING_SIZE> buf{};
  if (av_strerror(code, buf.data(), buf.size()) < 0) return "libav error " + std::to_string(code);
  return buf.data();
}

/// libav logs warnings and x264 statistics to stderr by default; meshtour reports errors itself.
inline void quiet_logging() {
  static std::once_flag once;
  std::call_once(once, [] { av_log_set_level(AV_LOG_ERROR); });
}

struct FrameDeleter {
  void operator()(AVFrame* f) const { av_frame_free(&f); }
};
struct FilterGraphDeleter {
  void operator()(AVFilterGraph* g) const { avfilter_graph_free(&g); }
};
using FramePtr = std::unique_ptr<AVFrame, FrameDeleter>;
using FilterGraphPtr = std::unique_ptr<AVFilterGraph, FilterGraphDeleter>;

}  // namespace meshtour::libav
