// A frames directory in, one video out: the last step of a farm job, where the chunks rendered by
// separate processes (render) become the same video a single `tour` run would have written. Every
// frame of the range is checked before the first one is encoded, so a missing or damaged frame is
// reported in seconds, not after a long encode. EXR frames are read back (the inverse of
// tracer/image.cpp's writer) and shown through the display transform their header records.
#include "tour/encode_frames.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/interrupt.h"
#include "encoder/video_encoder.h"
#include "jobs/frame_dir.h"
#include "jobs/frame_range.h"
#include "tour/progress.h"
#include "tracer/color.h"
#include "tracer/tracer.h"

namespace meshtour {
namespace {

namespace fs = std::filesystem;

// What to encode, settled before any frame is read.
struct EncodePlan {
  fs::path dir;
  std::vector<int> frames;
  std::string extension;  // "png" or "exr"
  int fps = 30;
  int width = 0, height = 0;  // 0: take it from the first frame (no manifest)
  int poster = kPosterFrame;  // the frame the poster and the title card show
};

std::string lowercase(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// --codec, or the codec whose extension the output has (tour.webm -> vp9), or h264.
VideoCodec choose_codec(const EncodeJob& a) {
  const std::string ext = lowercase(fs::path(a.output).extension().string());
  if (a.codec) {
    // Checked here too (the encoder does as well) so that the mistake is reported before the frames are.
    const VideoCodecInfo& info = video_codec_info(*a.codec);
    if (ext != info.extension)
      throw InputError(a.output + ": codec " + std::string(info.name) + " is written as " + std::string(info.container) +
                       "; name the file *" + std::string(info.extension));
    return info.codec;
  }
  if (const std::optional<VideoCodec> codec = codec_for_extension(ext)) return *codec;
  std::string list;
  for (const auto& info : video_codecs())
    list += (list.empty() ? "" : ", ") + std::string(info.extension) + " (" + std::string(info.name) + ")";
  throw InputError(a.output + ": '" + ext + "' is not a video type meshtour writes; name the output " + list +
                   ", or give --codec");
}

EncodePlan make_plan(const EncodeJob& a) {
  EncodePlan plan;
  plan.dir = a.dir;
  int frame_count = 0;
  std::error_code ec;
  if (!fs::is_directory(plan.dir, ec)) throw InputError(a.dir + ": no such frames directory");
  if (has_frame_dir_info(plan.dir)) {
    const FrameDirInfo info = read_frame_dir_info(plan.dir);
    frame_count = info.frame_count;
    plan.frames = parse_frame_range(a.frames.value_or("all"), info.frame_count);
    plan.fps = a.fps.value_or(info.fps);
    plan.width = info.width;
    plan.height = info.height;
    const auto has = [&](const std::string& f) {
      return std::find(info.image_formats.begin(), info.image_formats.end(), f) != info.image_formats.end();
    };
    if (a.input_format && !has(*a.input_format))
      throw InputError(a.dir + ": the frames were rendered as " + info.image_formats.front() + ", not " +
                       *a.input_format + " (see " + std::string(kFrameDirManifestName) + "); leave out --input-format");
    // PNG when there is a choice: it is already the display image, no tone mapping needed.
    plan.extension = a.input_format.value_or(has("png") ? "png" : "exr");
  } else {
    if (!a.frames || a.frames->empty() || *a.frames == "all")
      throw InputError(a.dir + ": no " + std::string(kFrameDirManifestName) +
                       " (written by 'meshtour render'), so the frame range is unknown; give it with --frames, e.g. --frames 0-119");
    // Without a manifest the tour's length is unknown: the range is taken as given.
    plan.frames = parse_frame_range(*a.frames, 1'000'000'000);
    plan.fps = a.fps.value_or(30);
    plan.extension = a.input_format.value_or("png");
  }
  if (plan.frames.empty())
    throw InputError("--frames '" + a.frames.value_or("") + "' selects no frame of the " +
                     std::to_string(frame_count) + "-frame tour in " + a.dir + " (frames 0-" +
                     std::to_string(frame_count - 1) + ")");
  if ((a.exposure || a.tone_mapping) && plan.extension != "exr")
    throw InputError("--exposure and --tone-mapping apply to EXR frames only; PNG frames are already display images");
  return plan;
}

// What a frame file holds, from its header only.
struct FrameHeader {
  int width = 0, height = 0, channels = 0;
  bool alpha = false;  // an alpha channel (PNG: grey+alpha or RGBA; EXR: "A")
  std::string error;  // empty when the file could be opened as an image
};

FrameHeader read_header(const fs::path& file) {
  FrameHeader h;
  auto in = OIIO::ImageInput::open(file.string());
  if (!in) {
    h.error = OIIO::geterror();
    if (h.error.empty()) h.error = "not an image";
    return h;
  }
  const OIIO::ImageSpec& spec = in->spec();
  h.width = spec.width;
  h.height = spec.height;
  h.channels = spec.nchannels;
  h.alpha = spec.alpha_channel >= 0 || h.channels == 2 || h.channels == 4;
  in->close();
  return h;
}

// OpenImageIO's messages can span lines; the CLI reports errors on one.
std::string one_line(std::string text) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

// Checks that every frame exists, opens as an image and has the tour's size; throws one
// InputError naming all the frames at fault. Fills in the size when there is no manifest.
void check_frames(EncodePlan& plan, bool alpha) {
  const std::vector<int> missing = missing_frames(plan.dir, plan.frames, plan.extension);
  std::vector<int> unreadable, wrong_size, opaque;
  std::string first_unreadable, first_wrong;
  for (const int k : plan.frames) {
    throw_if_interrupted();
    if (std::binary_search(missing.begin(), missing.end(), k)) continue;
    const fs::path file = frame_file(plan.dir, k, plan.extension);
    const FrameHeader h = read_header(file);
    if (!h.error.empty()) {
      if (unreadable.empty()) first_unreadable = file.filename().string() + ": " + one_line(h.error);
      unreadable.push_back(k);
      continue;
    }
    if (plan.width == 0) plan.width = h.width, plan.height = h.height;
    if (h.width != plan.width || h.height != plan.height) {
      if (wrong_size.empty())
        first_wrong = file.filename().string() + " is " + std::to_string(h.width) + "x" + std::to_string(h.height);
      wrong_size.push_back(k);
    }
    if (alpha && !h.alpha) opaque.push_back(k);
  }
  if (missing.empty() && unreadable.empty() && wrong_size.empty() && !opaque.empty())
    throw InputError(plan.dir.string() + ": --alpha, but frames " + format_frame_range(opaque) + " have no alpha (e.g. " +
                     frame_file(plan.dir, opaque.front(), plan.extension).filename().string() +
                     "); render them with --background transparent, or leave out --alpha");
  if (missing.empty() && unreadable.empty() && wrong_size.empty()) return;

  const std::string total = std::to_string(plan.frames.size());
  std::string message = plan.dir.string() + ": cannot encode frames " + format_frame_range(plan.frames) + ":";
  const char* sep = " ";
  if (!missing.empty()) {
    message += sep + std::to_string(missing.size()) + " of " + total + " missing (" + format_frame_range(missing) +
               ", e.g. " + frame_file(plan.dir, missing.front(), plan.extension).filename().string() + ")";
    sep = "; ";
  }
  if (!unreadable.empty()) {
    message += sep + std::to_string(unreadable.size()) + " unreadable (" + format_frame_range(unreadable) + "; " +
               first_unreadable + ")";
    sep = "; ";
  }
  if (!wrong_size.empty())
    message += sep + std::to_string(wrong_size.size()) + " not " + std::to_string(plan.width) + "x" +
               std::to_string(plan.height) + " (" + format_frame_range(wrong_size) + "; " + first_wrong + ")";
  message += "; render them again (meshtour render --frames " +
             format_frame_range([&] {
               std::vector<int> all = missing;
               all.insert(all.end(), unreadable.begin(), unreadable.end());
               all.insert(all.end(), wrong_size.begin(), wrong_size.end());
               std::sort(all.begin(), all.end());
               return all;
             }()) +
             ") or choose other frames with --frames";
  throw InputError(message);
}

// The display transform for EXR frames: what the tracer applied to the PNG of the same frame.
struct DisplayTransform {
  std::optional<float> exposure;  // unset: from the EXR header, else 0
  std::optional<ToneMapping> tone_mapping;  // unset: from the EXR header, else filmic
};

// Reads one frame as 8-bit sRGB RGB, the encoder's input; with `alpha`, as RGBA with straight alpha.
std::vector<std::uint8_t> read_frame(const fs::path& file, const EncodePlan& plan, const DisplayTransform& display,
                                     bool alpha) {
  // PNG frames with alpha hold straight colour (tracer/image_writer.cpp), and the encoder takes
  // straight colour: read them as they are, not premultiplied (OpenImageIO's default).
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(file.string(), &config);
  if (!in) throw IoError(file.string() + ": cannot read frame: " + one_line(OIIO::geterror()));
  const OIIO::ImageSpec spec = in->spec();
  if (spec.width != plan.width || spec.height != plan.height)
    throw InputError(file.string() + ": frame is " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                     ", the others " + std::to_string(plan.width) + "x" + std::to_string(plan.height));
  const int channels = spec.nchannels;
  const std::size_t pixels = static_cast<std::size_t>(spec.width) * spec.height;
  std::vector<std::uint8_t> rgb(pixels * 3);

  if (plan.extension == "exr") {  // (never with `alpha`: encode_frames refuses it)
    // Linear light: the same Image::to_srgb8 (exposure, tone curve, sRGB) the tracer uses for
    // its PNGs and the tour's video. Channels are found by name; a missing alpha is opaque.
    Image image;
    image.width = spec.width;
    image.height = spec.height;
    const auto channel = [&](const char* name) {
      for (int c = 0; c < channels; ++c)
        if (spec.channelnames[static_cast<std::size_t>(c)] == name) return c;
      return -1;
    };
    // The denoised layer when the frame has one: it is what the PNG frames and the tour's video
    // show, so a video made from EXR frames matches them instead of showing the raw grain.
    const bool denoised = channel("denoised.R") >= 0 && channel("denoised.G") >= 0 && channel("denoised.B") >= 0;
    const char* const prefix = denoised ? "denoised." : "";
    const auto layer_channel = [&](const char* name) { return channel((std::string(prefix) + name).c_str()); };
    const int r = layer_channel("R"), g = layer_channel("G"), b = layer_channel("B"), a = layer_channel("A");
    if (r < 0 || g < 0 || b < 0) throw InputError(file.string() + ": EXR frame has no R, G, B channels");
    std::vector<float> all(pixels * static_cast<std::size_t>(channels));
    if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, all.data()))
      throw IoError(file.string() + ": cannot read frame: " + one_line(in->geterror()));
    image.rgba.resize(pixels * 4);
    for (std::size_t p = 0; p < pixels; ++p) {
      const float* src = &all[p * static_cast<std::size_t>(channels)];
      image.rgba[p * 4] = src[r], image.rgba[p * 4 + 1] = src[g], image.rgba[p * 4 + 2] = src[b];
      image.rgba[p * 4 + 3] = a >= 0 ? src[a] : 1.0f;
    }
    image.exposure = display.exposure.value_or(spec.get_float_attribute("meshtour:exposure", 0.0f));
    // A header written by another version may name a curve this one does not have: filmic then.
    const std::string tone = spec.get_string_attribute("meshtour:toneMapping", "filmic");
    image.tone_mapping = display.tone_mapping.value_or(tone_mapping_from_name(tone).value_or(ToneMapping::filmic));
    return image.to_srgb8();
  }

  // PNG: already 8-bit sRGB, colour straight (read as above). Grey is spread to RGB; a frame with
  // alpha (transparent background) is shown over black, as the video of a transparent tour is,
  // unless the video keeps the alpha: then the frame's pixels go in as they are.
  std::vector<std::uint8_t> all(pixels * static_cast<std::size_t>(channels));
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::UINT8, all.data()))
    throw IoError(file.string() + ": cannot read frame: " + one_line(in->geterror()));
  const bool has_alpha = channels == 2 || channels >= 4;
  const int colour = channels >= 3 ? 3 : 1;
  if (alpha) {
    std::vector<std::uint8_t> rgba(pixels * 4);
    for (std::size_t p = 0; p < pixels; ++p) {
      const std::uint8_t* src = &all[p * static_cast<std::size_t>(channels)];
      for (int c = 0; c < 3; ++c) rgba[p * 4 + static_cast<std::size_t>(c)] = src[colour == 3 ? c : 0];
      rgba[p * 4 + 3] = has_alpha ? src[colour] : 255;
    }
    return rgba;
  }
  // Over black in linear light, as the tour's own video shows a transparent render (its colour is
  // premultiplied in linear light before the sRGB curve): 50 % alpha on sRGB grey 128 gives 93
  // (multiplying the sRGB values gives 64).
  std::array<float, 256> linear{};
  for (int v = 0; v < 256; ++v) linear[static_cast<std::size_t>(v)] = srgb_to_linear(static_cast<float>(v) / 255.0f);
  for (std::size_t p = 0; p < pixels; ++p) {
    const std::uint8_t* src = &all[p * static_cast<std::size_t>(channels)];
    const unsigned a = has_alpha ? src[colour] : 255u;
    for (int c = 0; c < 3; ++c) {
      const std::uint8_t v = src[colour == 3 ? c : 0];
      rgb[p * 3 + static_cast<std::size_t>(c)] =
          a == 255u ? v
          : a == 0u ? 0
                    : static_cast<std::uint8_t>(std::lround(
                          std::clamp(linear_to_srgb(linear[v] * static_cast<float>(a) / 255.0f), 0.0f, 1.0f) * 255.0f));
    }
  }
  return rgb;
}

}  // namespace

void encode_frames(const EncodeJob& args) {
  VideoOptions video;
  video.codec = choose_codec(args);
  video.crf = args.crf;
  video.alpha = args.alpha;
  if (args.alpha) require_alpha_codec(video.codec);  // before the frames are read
  EncodePlan plan = make_plan(args);
  // An EXR frame always has alpha (the model's coverage), also over the gradient: only PNG frames
  // tell a transparent render (RGBA) from an opaque one (RGB).
  if (args.alpha && plan.extension != "png")
    throw InputError(args.dir + ": --alpha reads PNG frames (RGBA, as render --background transparent writes them), not " +
                     plan.extension + "; give --input-format png");
  video.fps = plan.fps;
  check_frames(plan, args.alpha);
  video.width = plan.width;
  video.height = plan.height;

  DisplayTransform display;
  if (args.exposure) display.exposure = static_cast<float>(*args.exposure);
  display.tone_mapping = args.tone_mapping;

  const fs::path output = args.output;
  VideoEncoder encoder(output, video);  // validates the options and the output before any work
  CaptionedVideo captioned(encoder, video, args.caption);  // a caption that does not fit fails now
  check_poster_output(args.poster);
  const fs::path poster_file = frame_file(plan.dir, plan.poster, plan.extension);
  if ((captioned.needs_poster() || !args.poster.file.empty()) && !fs::exists(poster_file))
    throw InputError(plan.dir.string() + ": the poster frame " + poster_file.filename().string() +
                     " is missing; render it (meshtour render --frames " + std::to_string(plan.poster) + ")");
  if (captioned.needs_poster()) captioned.start(read_frame(poster_file, plan, display, args.alpha));
  const int total = static_cast<int>(plan.frames.size());
  Progress progress("encoded frame", total, args.quiet);
  for (int i = 0; i < total; ++i) {
    throw_if_interrupted();
    captioned.add(read_frame(frame_file(plan.dir, plan.frames[static_cast<std::size_t>(i)], plan.extension), plan, display, args.alpha));
    progress.update(i + 1);
  }
  throw_if_interrupted();
  captioned.finish();
  progress.finish();
  if (!args.poster.file.empty()) {
    // A PNG frame is the poster as it is (byte for byte the frame `tour` would write); EXR frames
    // go through the same display transform as the video.
    if (plan.extension == "png") write_poster_from_png(poster_file, args.poster);
    else write_poster_pixels(read_frame(poster_file, plan, display, false), plan.width, plan.height, 3, args.poster);
    if (!args.quiet) std::fprintf(stderr, "wrote %s (poster: frame %d)\n", args.poster.file.string().c_str(), plan.poster);
  }
  if (!args.quiet) {
    std::error_code ec;
    const auto bytes = fs::file_size(output, ec);
    std::fprintf(stderr, "wrote %s (%s%s, %d frames %s, %dx%d, %d fps, %.2f MB)\n", output.string().c_str(),
                 std::string(video_codec_info(video.codec).name).c_str(), args.alpha ? " with alpha" : "", total, format_frame_range(plan.frames).c_str(),
                 plan.width, plan.height, plan.fps, ec ? 0.0 : static_cast<double>(bytes) / 1e6);
  }
}

}  // namespace meshtour
