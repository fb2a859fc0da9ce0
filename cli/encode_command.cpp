// meshtour encode: a frames directory in, one video out. The last step of a farm job: the chunks
// rendered by separate processes (meshtour render) become the same video a single `tour` run
// would have written. Every frame of the range is checked before the first one is encoded, so a
// missing or damaged frame is reported in seconds, not after a long encode.
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "cli/video_settings.h"
#include "scenes/scene_options.h"
#include "options/cli_options.h"
#include "core/error.h"
#include "encoder/video_encoder.h"
#include "jobs/frame_dir.h"
#include "jobs/frame_range.h"
#include "tour/encode_frames.h"
#include "tracer/tracer.h"

namespace meshtour::cli {
namespace {

namespace fs = std::filesystem;

struct EncodeArgs {
  EncodeJob job;
  options::Values values;  // the video's registry rows: poster, caption, title card
};

void run_encode(EncodeArgs& args) {
  install_interrupt_handlers();
  args.job.poster = poster_job(args.values);
  args.job.caption = caption_args(args.values);
  encode_frames(args.job);
}

std::string codec_table() {
  std::string table =
      "Codecs (--codec; without it, the output's extension picks one, and .mp4 is H.264):\n"
      "  codec   file    lossless  stored as / use\n";
  for (const auto& c : video_codecs()) {
    char line[400];
    std::snprintf(line, sizeof line, "  %-7s %-7s %-9s %s\n  %-7s %-7s %-9s   %s\n", std::string(c.name).c_str(),
                  std::string(c.extension).c_str(), c.lossless ? "yes" : "no", std::string(c.format).c_str(), "", "", "",
                  std::string(c.use).c_str());
    table += line;
  }
  return table;
}

}  // namespace

void add_encode_command(CLI::App& app) {
  auto args = std::make_shared<EncodeArgs>();
  CLI::App* cmd = app.add_subcommand("encode", "Encode a directory of rendered frames into a video (the farm's last step).");
  cmd->description(
      "Encode the frames in DIR (frame_000000.png or .exr, as 'meshtour render' and 'meshtour tour --frames-dir'\n"
      "write them) into one video. The frame range, rate and size come from DIR/meshtour-frames.json, written\n"
      "by 'meshtour render'; without it, give the range with --frames (the rate is then 30 fps unless --fps).\n"
      "Every frame of the range is checked before encoding starts: missing, unreadable or wrongly sized\n"
      "frames are all named in one error (exit 2) and no video is written. The video appears under its\n"
      "name only when complete; Ctrl-C or SIGTERM removes the partial file (exit 130). The same frames and\n"
      "options always give the same file, byte for byte: the encoders' settings and thread counts are fixed.\n\n" +
      codec_table() +
      "\n--crf (lower is better, bigger files): " + options::codec_ranges_text(options::option("crf")) + ".\n"
      "prores (fixed 422 HQ quality), ffv1 (lossless) and gif (256 colours) refuse --crf.\n\n"
      "EXR frames are linear light: they get the display transform of the PNG frames (exposure and tone\n"
      "curve, recorded in each EXR's header by meshtour; --exposure and --tone-mapping override it), so a\n"
      "video from EXR frames looks like one from the PNG frames. PNG frames with alpha are shown over black,\n"
      "unless --alpha keeps their alpha (straight) in the video: prores becomes ProRes 4444, vp9 stores an\n"
      "alpha plane (WebM AlphaMode; browsers play it transparent), ffv1 stores RGBA; h264 and gif cannot.\n\n"
      "Examples:\n"
      "  meshtour encode frames/ -o tour.mp4                   # the whole tour, H.264\n"
      "  meshtour encode frames/ -o tour.mkv                   # lossless FFV1 archive (codec from the name)\n"
      "  meshtour encode frames/ -o web.webm --crf 36          # smaller VP9 for a web page\n"
      "  meshtour encode frames/ -o preview.gif --frames 0-119:2 --fps 15\n"
      "  meshtour encode frames/ -o overlay.mov --alpha         # ProRes 4444 from RGBA PNG frames\n"
      "  meshtour encode shots/ -o clip.mov --frames 0-47 --fps 24   # frames from elsewhere, no manifest");
  cmd->add_option("dir", args->job.dir, "Directory holding the frames (frame_000000.png ...)")->required();
  EncodeJob& job = args->job;
  options::add_command_options(*cmd, options::encode, args->values,
                               {{"fps", options::to(job.fps)},
                                {"exposure", options::to(job.exposure)},
                                {"crf", options::to(job.crf)},
                                {"codec", options::to(job.codec, parse_video_codec)},
                                {"frame-selection", options::to(job.frames)},
                                {"output", options::to(job.output)},
                                {"quiet", options::to(job.quiet)},
                                {"alpha", options::to(job.alpha)},
                                {"input-format", options::to(job.input_format)},
                                {"tone-mapping", options::to(job.tone_mapping, parse_tone_mapping)}});
  cmd->callback([args] { run_encode(*args); });
}

}  // namespace meshtour::cli
