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

void add_farm_command(CLI::App& app) {
  CLI::App* farm = app.add_subcommand("farm", "Split a tour (or a batch) over a render farm's job engine.");
  farm->require_subcommand(1);
  auto args = std::make_shared<FarmJob>();
  CLI::App* cmd = farm->add_subcommand("slurm", "Write (and with --submit, submit) Slurm jobs: a job array of frame chunks and a dependent encode.");
  cmd->description(
      "Computes the camera path once (DIR/path.json), writes DIR/render.sbatch (a job array: task i runs\n"
      "'meshtour render --frames A-B --path-file ...' for its chunk of frames into DIR/frames),\n"
      "DIR/encode.sbatch ('meshtour encode', to run after the whole array succeeded) and DIR/submit.sh.\n"
      "With --submit, submits them (sbatch --parsable) and prints render_job=ID and encode_job=ID.\n"
      "With --manifest, one array task per batch item instead ('meshtour batch --item i'), printing\n"
      "batch_job=ID. Paths in the scripts are absolute: DIR must be on a filesystem every node shares.\n"
      "Re-submitting resumes: frames and videos that exist are skipped.");
  options::Values& given = args->scene.values;  // what the tasks are given again (forwarded_args)
  add_scene_options(*cmd, args->scene, options::farm,
                    {{"codec", options::recorded(given, "codec", options::to(args->codec))},
                     {"format", options::to(args->format)},
                     {"web", options::recorded(given, "web", options::to(args->web))},
                     {"manifest", options::to(args->manifest)},
                     {"out-dir", options::to(args->out_dir)},
                     {"output", options::to(args->output)},
                     {"chunk-size", options::to(args->chunk_size)},
                     {"partition", options::to(args->partition)},
                     {"time", options::to(args->time_limit)},
                     {"cpus-per-task", options::to(args->cpus_per_task)},
                     {"executable", options::to(args->executable)},
                     {"submit", options::to(args->submit)},
                     {"quiet", options::to(args->quiet)}});
  cmd->callback([args] { run_farm_slurm(*args); });
}

}  // namespace meshtour::cli
