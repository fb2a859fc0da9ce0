#include "encoder/caption.h"

#include "core/error.h"
#include "encoder/libav_support.h"

extern "C" {
#include <libavfilter/avfilter.h>
#include <libavfilter/buffersink.h>
#include <libavfilter/buffersrc.h>
#include <libavutil/error.h>
#include <libavutil/frame.h>
#include <libavutil/log.h>
#include <libavutil/opt.h>
}

#include <fontconfig/fontconfig.h>
#include <ft2build.h>
#include FT_FREETYPE_H

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <mutex>

namespace meshtour {
namespace {

namespace fs = std::filesystem;


[[noreturn]] void fail_libav(const std::string& what, int code) {
  throw RuntimeFailure("caption filter: " + what + " failed: " + libav::error_text(code));
}


// ---- RAII around the C APIs
struct FtLibraryDeleter {
  void operator()(FT_Library l) const { FT_Done_FreeType(l); }
};
struct FtFaceDeleter {
  void operator()(FT_Face f) const { FT_Done_Face(f); }
};
struct FcConfigDeleter {
  void operator()(FcConfig* c) const { FcConfigDestroy(c); }
};
struct FcPatternDeleter {
  void operator()(FcPattern* p) const { FcPatternDestroy(p); }
};
using FtLibraryPtr = std::unique_ptr<std::remove_pointer_t<FT_Library>, FtLibraryDeleter>;
using FtFacePtr = std::unique_ptr<std::remove_pointer_t<FT_Face>, FtFaceDeleter>;
using FcConfigPtr = std::unique_ptr<FcConfig, FcConfigDeleter>;
using FcPatternPtr = std::unique_ptr<FcPattern, FcPatternDeleter>;
using libav::FilterGraphPtr;
using libav::FramePtr;

constexpr std::array<std::pair<std::string_view, CaptionPosition>, 6> kPositions = {{
    {"bottom-left", CaptionPosition::bottom_left}, {"bottom", CaptionPosition::bottom},
    {"bottom-right", CaptionPosition::bottom_right}, {"top-left", CaptionPosition::top_left},
    {"top", CaptionPosition::top}, {"top-right", CaptionPosition::top_right}}};

// The box behind the text (legible on any background) and the space between it and the frame edge.
int box_border(int size) { return std::max(2, size / 4); }
int edge_margin(int size) { return size / 2 + box_border(size); }

// The font the caption uses, and its pixel size: shared by the measurement and the filter.
struct ResolvedFont {
  fs::path file;
  int size = 0;
};

ResolvedFont resolve_font(const CaptionStyle& style, int height) {
  ResolvedFont f;
  f.file = style.font.empty() ? default_caption_font() : style.font;
  f.size = style.size > 0 ? style.size : default_caption_size(height);
  return f;
}

// A filter of the graph with its options set through the options API (never a filter string).
AVFilterContext* add_filter(AVFilterGraph* graph, const char* filter, const char* name,
                            std::initializer_list<std::pair<const char*, std::string>> options) {
  const AVFilter* f = avfilter_get_by_name(filter);
  if (!f)
    throw RuntimeFailure(std::string("this FFmpeg build has no '") + filter +
                         "' filter; install Debian's libavfilter8 (see scripts/install-deps.sh)");
  AVFilterContext* ctx = avfilter_graph_alloc_filter(graph, f, name);
  if (!ctx) fail_libav(std::string("creating the ") + filter + " filter", AVERROR(ENOMEM));
  for (const auto& [key, value] : options) {
    const int ret = av_opt_set(ctx, key, value.c_str(), AV_OPT_SEARCH_CHILDREN);
    if (ret < 0) fail_libav(std::string("setting ") + filter + " option " + key, ret);
  }
  const int ret = avfilter_init_str(ctx, nullptr);
  if (ret < 0) fail_libav(std::string("initialising the ") + filter + " filter", ret);
  return ctx;
}

void link(AVFilterContext* from, unsigned from_pad, AVFilterContext* to, unsigned to_pad) {
  const int ret = avfilter_link(from, from_pad, to, to_pad);
  if (ret < 0) fail_libav("linking the caption filters", ret);
}

AVFilterContext* add_source(AVFilterGraph* graph, const char* name, int width, int height, int fps) {
  return add_filter(graph, "buffer", name,
                    {{"width", std::to_string(width)},
                     {"height", std::to_string(height)},
                     {"pix_fmt", std::to_string(AV_PIX_FMT_RGB24)},
                     {"time_base", "1/" + std::to_string(fps)},
                     {"frame_rate", std::to_string(fps) + "/1"},
                     {"pixel_aspect", "1/1"}});
}

AVFilterContext* add_rgb_sink(AVFilterGraph* graph) {
  AVFilterContext* sink = add_filter(graph, "buffersink", "out", {});
  const AVPixelFormat rgb[] = {AV_PIX_FMT_RGB24, AV_PIX_FMT_NONE};
  const int ret = av_opt_set_int_list(sink, "pix_fmts", rgb, AV_PIX_FMT_NONE, AV_OPT_SEARCH_CHILDREN);
  if (ret < 0) fail_libav("restricting the caption output to RGB", ret);
  return sink;
}

FilterGraphPtr new_graph() {
  libav::quiet_logging();
  FilterGraphPtr graph(avfilter_graph_alloc());
  if (!graph) fail_libav("allocating the filter graph", AVERROR(ENOMEM));
  graph->nb_threads = 1;  // filters run in sequence: the same pixels on every machine
  // Pixel-format conversions the graph inserts (xfade works on planar RGB): exact rounding.
  graph->scale_sws_opts = av_strdup("flags=bicubic+accurate_rnd+bitexact");
  return graph;
}

// The drawtext filter for `style`, checked to fit a width x height frame (InputError otherwise).
AVFilterContext* add_drawtext(AVFilterGraph* graph, int width, int height, const CaptionStyle& style) {
  if (style.text.empty()) throw InputError("--caption is empty; give the text to show, or leave the option out");
  const ResolvedFont font = resolve_font(style, height);
  const int text_width = caption_text_width(font.file, font.size, style.text);
  const int margin = edge_margin(font.size);
  const int room = width - 2 * margin;
  if (text_width > room) {
    // The largest size that fits, found by measuring (glyph widths do not scale exactly linearly).
    int fits = 0;
    for (int s = std::min(font.size - 1, static_cast<int>(font.size * static_cast<double>(room) / text_width) + 1); s >= 6; --s)
      if (caption_text_width(font.file, s, style.text) <= width - 2 * edge_margin(s)) {
        fits = s;
        break;
      }
    throw InputError("caption \"" + style.text + "\" is " + std::to_string(text_width) + " pixels wide at --caption-size " +
                     std::to_string(font.size) + ", but a " + std::to_string(width) + "-pixel frame holds at most " +
                     std::to_string(room) + " pixels of text (" + std::to_string(margin) + "-pixel margins); " +
                     (fits > 0 ? "use --caption-size " + std::to_string(fits) + " or less, or shorten the caption"
                               : "shorten the caption"));
  }
  if (font.size * 3 / 2 + 2 * margin > height)
    throw InputError("--caption-size " + std::to_string(font.size) + " is too large for a " + std::to_string(height) +
                     "-pixel-high frame; use at most " + std::to_string(std::max(6, height / 3)));
  const std::string m = std::to_string(margin);
  std::string x = m, y = "h-lh-" + m;
  switch (style.position) {
    case CaptionPosition::bottom_left: break;
    case CaptionPosition::bottom: x = "(w-tw)/2"; break;
    case CaptionPosition::bottom_right: x = "w-tw-" + m; break;
    case CaptionPosition::top_left: y = m; break;
    case CaptionPosition::top: x = "(w-tw)/2", y = m; break;
    case CaptionPosition::top_right: x = "w-tw-" + m, y = m; break;
  }
  return add_filter(graph, "drawtext", "caption",
                    {{"fontfile", font.file.string()},
                     {"text", style.text},
                     {"expansion", "none"},  // '%' is a character, not a placeholder
                     {"fontsize", std::to_string(font.size)},
                     {"fontcolor", "white"},
                     {"box", "1"},
                     {"boxcolor", "black@0.6"},
                     {"boxborderw", std::to_string(box_border(font.size))},
                     {"x", x},
                     {"y", y}});
}

void configure(AVFilterGraph* graph) {
  const int ret = avfilter_graph_config(graph, nullptr);
  if (ret < 0) fail_libav("configuring the caption filter graph", ret);
}

FramePtr rgb_frame(std::span<const std::uint8_t> rgb, int width, int height, std::int64_t pts) {
  FramePtr f(av_frame_alloc());
  if (!f) fail_libav("allocating a frame", AVERROR(ENOMEM));
  f->format = AV_PIX_FMT_RGB24;
  f->width = width;
  f->height = height;
  int ret = av_frame_get_buffer(f.get(), 0);
  if (ret < 0) fail_libav("allocating a frame", ret);
  for (int plane = 0; plane < AV_NUM_DATA_POINTERS && f->buf[plane]; ++plane)
    std::memset(f->buf[plane]->data, 0, f->buf[plane]->size);  // row padding is read by SIMD code
  const std::size_t row = static_cast<std::size_t>(width) * 3;
  for (int y = 0; y < height; ++y)
    std::memcpy(f->data[0] + static_cast<std::ptrdiff_t>(y) * f->linesize[0], rgb.data() + y * row, row);
  f->pts = pts;
  return f;
}

void push(AVFilterContext* source, std::span<const std::uint8_t> rgb, int width, int height, std::int64_t pts) {
  const std::size_t expected = static_cast<std::size_t>(width) * height * 3;
  if (rgb.size() != expected)
    throw InputError("caption: frame has " + std::to_string(rgb.size()) + " bytes, a " + std::to_string(width) + "x" +
                     std::to_string(height) + " RGB frame " + std::to_string(expected));
  FramePtr f = rgb_frame(rgb, width, height, pts);
  const int ret = av_buffersrc_add_frame_flags(source, f.get(), 0);
  if (ret < 0) fail_libav("sending a frame to the caption filter", ret);
}

void end_input(AVFilterContext* source) {
  const int ret = av_buffersrc_add_frame_flags(source, nullptr, 0);
  if (ret < 0) fail_libav("ending the caption filter's input", ret);
}

// Every frame the sink has ready, as packed RGB.
std::vector<std::vector<std::uint8_t>> drain(AVFilterContext* sink, int width, int height) {
  std::vector<std::vector<std::uint8_t>> out;
  FramePtr f(av_frame_alloc());
  if (!f) fail_libav("allocating a frame", AVERROR(ENOMEM));
  for (;;) {
    const int ret = av_buffersink_get_frame(sink, f.get());
    if (ret == AVERROR(EAGAIN) || ret == AVERROR_EOF) return out;
    if (ret < 0) fail_libav("drawing the caption", ret);
    std::vector<std::uint8_t> rgb(static_cast<std::size_t>(width) * height * 3);
    const std::size_t row = static_cast<std::size_t>(width) * 3;
    for (int y = 0; y < height; ++y)
      std::memcpy(rgb.data() + y * row, f->data[0] + static_cast<std::ptrdiff_t>(y) * f->linesize[0], row);
    av_frame_unref(f.get());
    out.push_back(std::move(rgb));
  }
}

}  // namespace

CaptionPosition parse_caption_position(std::string_view name) {
  std::string list;
  for (const auto& [n, p] : kPositions) {
    if (n == name) return p;
    list += (list.empty() ? "" : ", ") + std::string(n);
  }
  throw InputError("unknown caption position '" + std::string(name) + "'; use one of: " + list);
}

int default_caption_size(int height) { return std::max(10, height / 18); }

fs::path default_caption_font() {
  static std::mutex mutex;  // fontconfig's configuration objects are not thread-safe
  const std::lock_guard lock(mutex);
  const FcConfigPtr config(FcInitLoadConfigAndFonts());
  if (!config) throw RuntimeFailure("fontconfig could not load its configuration; give the caption font with --font FILE");
  const FcPatternPtr pattern(FcNameParse(reinterpret_cast<const FcChar8*>("DejaVu Sans:style=Book")));
  if (!pattern) throw RuntimeFailure("fontconfig: cannot build the font query");
  FcConfigSubstitute(config.get(), pattern.get(), FcMatchPattern);
  FcDefaultSubstitute(pattern.get());
  FcResult result = FcResultNoMatch;
  const FcPatternPtr match(FcFontMatch(config.get(), pattern.get(), &result));
  FcChar8* family = nullptr;
  FcChar8* file = nullptr;
  if (match && FcPatternGetString(match.get(), FC_FAMILY, 0, &family) == FcResultMatch &&
      FcPatternGetString(match.get(), FC_FILE, 0, &file) == FcResultMatch &&
      std::string_view(reinterpret_cast<const char*>(family)) == "DejaVu Sans")
    return fs::path(reinterpret_cast<const char*>(file));
  throw InputError("the caption font DejaVu Sans is not installed (Debian: apt install fonts-dejavu-core, see "
                   "scripts/install-deps.sh); or give a TrueType/OpenType font with --font FILE");
}

int caption_text_width(const fs::path& font, int size, std::string_view text) {
  const std::vector<char32_t> chars = decode_caption_text(text);
  FT_Library raw_library = nullptr;
  if (FT_Init_FreeType(&raw_library) != 0) throw RuntimeFailure("FreeType could not start");
  const FtLibraryPtr library(raw_library);
  FT_Face raw_face = nullptr;
  if (FT_New_Face(library.get(), font.c_str(), 0, &raw_face) != 0)
    throw InputError(font.string() + ": not a font FreeType can read; give a TrueType or OpenType file with --font");
  const FtFacePtr face(raw_face);
  if (FT_Set_Pixel_Sizes(face.get(), 0, static_cast<FT_UInt>(size)) != 0)
    throw InputError(font.string() + ": cannot be set at " + std::to_string(size) + " pixels");
  // As drawtext lays out one line: pen advances plus kerning; the width is the right edge of the
  // last glyph's box or the pen, whichever is further.
  long pen = 0, right = 0;
  FT_UInt previous = 0;
  for (const char32_t c : chars) {
    const FT_UInt glyph = FT_Get_Char_Index(face.get(), c);
    if (glyph == 0)
      throw InputError("caption: the font " + font.filename().string() + " has no glyph for " + code_point_name(c) +
                       "; choose a font that has it with --font");
    if (previous && FT_HAS_KERNING(face.get())) {
      FT_Vector delta{};
      FT_Get_Kerning(face.get(), previous, glyph, FT_KERNING_DEFAULT, &delta);
      pen += delta.x >> 6;
    }
    if (FT_Load_Glyph(face.get(), glyph, FT_LOAD_DEFAULT) != 0)
      throw InputError("caption: the font " + font.filename().string() + " cannot load the glyph of " + code_point_name(c));
    const FT_GlyphSlot slot = face->glyph;
    right = std::max(right, pen + static_cast<long>((slot->metrics.horiBearingX + slot->metrics.width) >> 6));
    pen += slot->advance.x >> 6;
    previous = glyph;
  }
  return static_cast<int>(std::max(pen, right));
}

struct CaptionBurner::Impl {
  int width, height;
  FilterGraphPtr graph;
  AVFilterContext* source = nullptr;  // owned by graph
  AVFilterContext* sink = nullptr;    // owned by graph
  std::int64_t pts = 0;
};

CaptionBurner::CaptionBurner(int width, int height, const CaptionStyle& style) : impl_(std::make_unique<Impl>()) {
  impl_->width = width;
  impl_->height = height;
  impl_->graph = new_graph();
  AVFilterGraph* g = impl_->graph.get();
  AVFilterContext* text = add_drawtext(g, width, height, style);
  impl_->source = add_source(g, "frames", width, height, 30);
  impl_->sink = add_rgb_sink(g);
  link(impl_->source, 0, text, 0);
  link(text, 0, impl_->sink, 0);
  configure(g);
}

CaptionBurner::~CaptionBurner() = default;

std::vector<std::uint8_t> CaptionBurner::burn(std::span<const std::uint8_t> rgb) {
  push(impl_->source, rgb, impl_->width, impl_->height, impl_->pts++);
  auto frames = drain(impl_->sink, impl_->width, impl_->height);
  if (frames.size() != 1) throw RuntimeFailure("caption filter returned " + std::to_string(frames.size()) + " frames for one");
  return std::move(frames.front());
}

struct TitleCard::Impl {
  int width, height;
  FilterGraphPtr graph;
  AVFilterContext* card = nullptr;  // the poster with the large caption (owned by graph)
  AVFilterContext* tour = nullptr;  // the tour's frames (owned by graph)
  AVFilterContext* sink = nullptr;
  std::vector<std::uint8_t> poster;
  std::int64_t card_frames = 0, card_sent = 0, fade_start = 0, tour_sent = 0;
  bool card_ended = false, ended = false;

  void send_card_until(std::int64_t n, std::vector<std::vector<std::uint8_t>>& out) {
    for (; card_sent < std::min(n, card_frames); ++card_sent) {
      push(card, poster, width, height, card_sent);
      auto ready = drain(sink, width, height);
      std::move(ready.begin(), ready.end(), std::back_inserter(out));
    }
    if (card_sent == card_frames && !card_ended) {
      end_input(card);
      card_ended = true;
    }
  }
};

TitleCard::TitleCard(int width, int height, int fps, double seconds, std::span<const std::uint8_t> poster_rgb,
                     const CaptionStyle& style)
    : impl_(std::make_unique<Impl>()) {
  Impl& t = *impl_;
  t.width = width;
  t.height = height;
  t.poster.assign(poster_rgb.begin(), poster_rgb.end());
  const double fade = std::min(1.0, seconds / 3.0);
  t.fade_start = std::max<std::int64_t>(1, std::llround((seconds - fade) * fps));
  const std::int64_t fade_frames = std::max<std::int64_t>(1, std::llround(fade * fps));
  // A few frames more than the fade needs: xfade ends the fade before the card's input ends.
  t.card_frames = t.fade_start + fade_frames + 2;
  t.graph = new_graph();
  AVFilterGraph* g = t.graph.get();
  t.card = add_source(g, "card", width, height, fps);
  t.tour = add_source(g, "tour", width, height, fps);
  AVFilterContext* card_out = t.card;
  if (!style.text.empty()) {
    CaptionStyle large = style;
    large.position = CaptionPosition::bottom;
    const ResolvedFont normal = resolve_font(style, height);
    large.font = normal.file;
    // Twice the caption's size, or the largest that fits, but never smaller than the caption itself.
    large.size = std::max(normal.size, std::min(2 * normal.size, height / 6));
    while (large.size > normal.size &&
           caption_text_width(large.font, large.size, large.text) > width - 2 * edge_margin(large.size))
      --large.size;
    AVFilterContext* text = add_drawtext(g, width, height, large);
    link(t.card, 0, text, 0);
    card_out = text;
  }
  char offset[32], duration[32];
  std::snprintf(offset, sizeof offset, "%.6f", static_cast<double>(t.fade_start) / fps);
  std::snprintf(duration, sizeof duration, "%.6f", static_cast<double>(fade_frames) / fps);
  AVFilterContext* xfade =
      add_filter(g, "xfade", "title_card", {{"transition", "fade"}, {"duration", duration}, {"offset", offset}});
  t.sink = add_rgb_sink(g);
  link(card_out, 0, xfade, 0);
  link(t.tour, 0, xfade, 1);
  link(xfade, 0, t.sink, 0);
  configure(g);
}

TitleCard::~TitleCard() = default;

std::vector<std::vector<std::uint8_t>> TitleCard::add(std::span<const std::uint8_t> tour_rgb) {
  Impl& t = *impl_;
  if (t.ended) throw RuntimeFailure("TitleCard::add called after end()");
  std::vector<std::vector<std::uint8_t>> out;
  // The card up to the fade, then one card frame beside each tour frame while they blend.
  t.send_card_until(t.fade_start + t.tour_sent + 1, out);
  push(t.tour, tour_rgb, t.width, t.height, t.tour_sent++);
  auto ready = drain(t.sink, t.width, t.height);
  std::move(ready.begin(), ready.end(), std::back_inserter(out));
  return out;
}

std::vector<std::vector<std::uint8_t>> TitleCard::end() {
  Impl& t = *impl_;
  std::vector<std::vector<std::uint8_t>> out;
  if (t.ended) return out;
  t.send_card_until(t.card_frames, out);
  end_input(t.tour);
  t.ended = true;
  auto ready = drain(t.sink, t.width, t.height);
  std::move(ready.begin(), ready.end(), std::back_inserter(out));
  return out;
}

}  // namespace meshtour
