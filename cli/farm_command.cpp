// meshtour farm slurm: splits a tour over a Slurm cluster. The camera path is computed once here
// (a path file beside the frames), a job array renders the frames in chunks (`meshtour render
// --frames A-B --path-file ...`, the chunk derived from SLURM_ARRAY_TASK_ID), and a job that
// depends on the whole array (afterok) encodes them (`meshtour encode`). With a batch manifest,
// one array task per item instead (`meshtour batch --item`). Everything is written as sbatch
// scripts with absolute paths (the cluster shares the filesystem), submitted with --submit.
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "tour/farm_job.h"
#include "cli/scene_args.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "options/batch_manifest.h"
#include "jobs/frame_dir.h"
#include "pathgen/path_file.h"

namespace meshtour::cli {
namespace {

struct FarmArgs {
  SceneArgs scene;  // the input and every value given: the tour's settings, and what the tasks are given again
  FarmJob job;
};

// The settings of the farm's tasks, resolved here: the tour's scene (without a manifest), the
// manifest's item count, and the options each task is given again.
void run_farm(FarmArgs& args) {
  FarmJob& job = args.job;
  const options::Values& given = args.scene.values;
  if (!job.manifest.empty() && !args.scene.input.empty()) throw InputError("give either a SCENE|MESH or --manifest, not both");
  const std::string codec(video_codec_info(job.codec).name);
  if (const auto crf = given.find("crf"); crf != given.end())
    if (const std::string problem = options::check_value_for_codec(options::option("crf"), crf->second, codec); !problem.empty())
      throw InputError("--crf " + problem);
  job.input = args.scene.input;
  const bool alpha = job.alpha;
  if (job.manifest.empty()) {
    job.scene = resolve_scene(args.scene, codec);
    // What the encode job would refuse, refused now, before anything is rendered.
    if (alpha) {
      require_alpha_codec(job.codec);
      if (job.scene->render.shading.background != BackgroundKind::transparent)
        throw InputError("--alpha needs a transparent background: add --background transparent (over the gradient the "
                         "frames have no alpha to keep)");
      if (job.format == FrameFormats::exr)
        throw InputError("--alpha encodes the PNG frames (RGBA); give --format png or png+exr, not exr");
    }
  } else {
    if (alpha)
      throw InputError("--alpha is for one tour; the items of a batch (--manifest) are H.264 MP4, which cannot carry alpha");
    job.manifest_items = static_cast<int>(read_batch_manifest(std::filesystem::absolute(job.manifest)).size());
  }
  job.render_args = options::forwarded_args(given, options::render_tasks, options::render);
  job.batch_args = options::forwarded_args(given, options::batch_tasks, options::batch);
  const std::vector<std::string> to_encode = options::forwarded_args(given, options::encode_job, options::encode);
  // (--flag value pairs, and flags alone: --alpha.)
  const auto takes_value = [](const std::string& flag) {
    for (const options::Option& o : options::registry())
      if (o.flag_in(options::encode) == flag) return o.kind != options::Kind::flag;
    return true;
  };
  for (std::size_t i = 0; i < to_encode.size(); ++i) {
    const std::string& flag = to_encode[i];
    if (!takes_value(flag)) {
      job.encode_args.push_back(flag);
      continue;
    }
    if (flag == options::option("codec").flag) {  // the farm gives it, with its default
      ++i;
      continue;
    }
    // Files named here are found from the job's own directory too.
    const bool file = flag == options::option("poster").flag || flag == options::option("font").flag;
    const std::string& value = to_encode.at(++i);
    job.encode_args.insert(job.encode_args.end(), {flag, file ? std::filesystem::absolute(value).string() : value});
  }
  run_farm_slurm(job);
}

}  // namespace

void add_farm_command(CLI::App& app) {
  CLI::App* farm = app.add_subcommand("farm", "Split a tour (or a batch) over a render farm's job engine.");
  farm->require_subcommand(1);
  auto args = std::make_shared<FarmArgs>();
  FarmJob& job = args->job;
  CLI::App* cmd = farm->add_subcommand("slurm", "Write (and with --submit, submit) Slurm jobs: a job array of frame chunks and a dependent encode.");
  cmd->description(
      "Computes the camera path once, for every path mode (DIR/path.json: the job's one path search; the\n"
      "tasks read it and never search), writes DIR/render.sbatch (a job array: task i runs\n"
      "'meshtour render --frames A-B --path-file ...' for its chunk of frames into DIR/frames),\n"
      "DIR/encode.sbatch ('meshtour encode', to run after the whole array succeeded) and DIR/submit.sh.\n"
      "With --submit, submits them (sbatch --parsable) and prints render_job=ID and encode_job=ID.\n"
      "With --manifest, one array task per batch item instead ('meshtour batch --item i'), printing\n"
      "batch_job=ID. Paths in the scripts are absolute: DIR must be on a filesystem every node shares.\n"
      "Re-submitting resumes: frames and videos that exist are skipped.");
  options::Values& given = args->scene.values;  // what the tasks are given again (forwarded_args)
  add_scene_options(*cmd, args->scene, options::farm,
                    {{"codec", options::recorded(given, "codec", options::to(job.codec, parse_video_codec))},
                     {"format", options::to(job.format, parse_frame_formats)},
                     {"web", options::recorded(given, "web", options::to(job.web))},
                     {"alpha", options::recorded(given, "alpha", options::to(job.alpha))},
                     {"manifest", options::to(job.manifest)},
                     {"out-dir", options::to(job.out_dir)},
                     {"output", options::to(job.output)},
                     {"chunk-size", options::to(job.chunk_size)},
                     {"partition", options::to(job.partition)},
                     {"time", options::to(job.time_limit)},
                     {"cpus-per-task", options::to(job.cpus_per_task)},
                     {"max-memory", options::recorded(given, "max-memory", options::to(job.max_memory))},
                     {"executable", options::to(job.executable)},
                     {"submit", options::to(job.submit)},
                     {"quiet", options::to(job.quiet)}});
  cmd->callback([args] { run_farm(*args); });
}

}  // namespace meshtour::cli
