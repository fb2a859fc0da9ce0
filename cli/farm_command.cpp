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
#include "jobs/batch_manifest.h"
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
  add_scene_options(*cmd, args->scene, options::farm);
  cmd->add_option("--manifest", args->manifest, "A batch manifest (CSV or JSON, see 'meshtour batch --help'): one array task per item")
      ->check(CLI::ExistingFile);
  cmd->add_option("--out-dir", args->out_dir, "Directory for the scripts, the path, the frames, logs and the video (shared by all nodes)")
      ->required();
  cmd->add_option("-o,--output", args->output, "Video file name inside --out-dir (default <input name> + the codec's extension)");
  cmd->add_option("--chunk-size", args->chunk_size, "Frames per array task (default 10)")->check(CLI::Range(1, 1000000));
  cmd->add_option("--partition", args->partition, "Slurm partition (sbatch --partition; default: the cluster's default)");
  cmd->add_option("--time", args->time_limit, "Time limit of each task (sbatch --time, e.g. 30 or 2:00:00)");
  cmd->add_option("--cpus-per-task", args->cpus_per_task, "CPUs per task (sbatch --cpus-per-task); render uses that many threads (default 1)")
      ->check(CLI::Range(1, 1024));
  cmd->add_option("--executable", args->executable, "The meshtour executable the jobs run (default: this one)");
  cmd->add_flag("--submit", args->submit, "Submit the jobs with sbatch and print their ids");
  cmd->add_flag("-q,--quiet", args->quiet, "Print nothing but errors and the job ids");
  cmd->callback([args] { run_farm_slurm(*args); });
}

}  // namespace meshtour::cli
