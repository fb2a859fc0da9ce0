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
#include "cli/scene_args.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "jobs/batch_manifest.h"
#include "jobs/frame_dir.h"
#include "pathgen/path_file.h"

namespace meshtour::cli {
namespace {

struct FarmArgs {
  SceneArgs scene;
  std::string manifest;
  std::string out_dir;
  std::string output;  // video name inside out_dir
  std::string executable;
  std::string partition, time_limit;
  int chunk_size = 10;
  int cpus_per_task = 1;
  bool submit = false;
  bool quiet = false;
};

/// The shell's single-quoted form of `s` (safe for any text).
std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (const char c : s) {
    if (c == '\'') q += "'\\''";
    else q += c;
  }
  return q + "'";
}

std::string join_quoted(const std::vector<std::string>& args) {
  std::string out;
  for (const auto& a : args) out.append(" ").append(shell_quote(a));  // (append: GCC 12 -Wrestrict false positive)
  return out;
}

std::string video_extension(const std::string& codec) {
  if (codec == "prores") return ".mov";
  if (codec == "ffv1") return ".mkv";
  if (codec == "vp9") return ".webm";
  if (codec == "gif") return ".gif";
  return ".mp4";
}

void write_text(const std::filesystem::path& file, const std::string& text, bool executable) {
  write_text_file_atomically(file, text, "farm script");
  if (executable) {
    std::error_code ec;
    std::filesystem::permissions(file, std::filesystem::perms::owner_exec | std::filesystem::perms::group_exec |
                                           std::filesystem::perms::others_exec,
                                 std::filesystem::perm_options::add, ec);
  }
}

std::string sbatch_header(const FarmArgs& a, const std::string& job_name, const std::string& log) {
  std::string h = "#!/bin/bash\n";
  h += "#SBATCH --job-name=" + job_name + "\n";
  h += "#SBATCH --output=" + log + "\n";
  h += "#SBATCH --cpus-per-task=" + std::to_string(a.cpus_per_task) + "\n";
  if (!a.partition.empty()) h += "#SBATCH --partition=" + a.partition + "\n";
  if (!a.time_limit.empty()) h += "#SBATCH --time=" + a.time_limit + "\n";
  return h;
}

// Runs `command` through the shell and returns its stdout; throws with `what` if it fails.
std::string run_capture(const std::string& command, const std::string& what) {
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) throw RuntimeFailure(what + ": cannot run sbatch");
  std::string out;
  std::array<char, 4096> buf{};
  while (const std::size_t n = std::fread(buf.data(), 1, buf.size(), pipe)) out.append(buf.data(), n);
  const int status = ::pclose(pipe);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw RuntimeFailure(what + " failed (sbatch exit status " + std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) +
                         "; see its message above)");
  return out;
}

// sbatch --parsable prints "jobid" or "jobid;cluster".
std::string submit(const std::string& sbatch_args, const std::string& what) {
  std::string out = run_capture("sbatch --parsable" + sbatch_args, what);
  const auto end = out.find_first_of(";\n");
  out = out.substr(0, end);
  if (out.empty() || out.find_first_not_of("0123456789") != std::string::npos)
    throw RuntimeFailure(what + ": sbatch printed no job id ('" + out + "')");
  return out;
}

std::filesystem::path this_executable(const FarmArgs& a) {
  if (!a.executable.empty()) return std::filesystem::absolute(a.executable);
  std::error_code ec;
  auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) throw RuntimeFailure("cannot find the meshtour executable's path (/proc/self/exe); give it with --executable");
  return self;
}

void run_farm_slurm(const FarmArgs& args) {
  if (!args.manifest.empty() && !args.scene.input.empty())
    throw InputError("give either a SCENE|MESH or --manifest, not both");
  const std::filesystem::path out = std::filesystem::absolute(args.out_dir).lexically_normal();
  const std::string codec = value_or(args.scene.values, "codec", "h264");
  const std::string format = value_or(args.scene.values, "format", "png");
  if (const auto crf = args.scene.values.find("crf"); crf != args.scene.values.end())
    if (const std::string problem = options::check_value_for_codec(options::option("crf"), crf->second, codec); !problem.empty())
      throw InputError("--crf " + problem);
  const std::filesystem::path exe = this_executable(args);
  std::error_code ec;
  std::filesystem::create_directories(out / "logs", ec);
  if (ec) throw IoError(out.string() + ": cannot create the output directory: " + ec.message());

  std::string submit_script = "#!/bin/bash\n# generated by meshtour farm slurm: submits the jobs below (as --submit does)\nset -euo pipefail\n";
  std::string first_sbatch, second_sbatch;  // sbatch arguments of the array and of the dependent job
  int tasks = 0;

  if (!args.manifest.empty()) {
    // One array task per item: `meshtour batch --item` renders and encodes that item's video.
    const std::filesystem::path manifest = std::filesystem::absolute(args.manifest);
    const std::vector<BatchItem> items = read_batch_manifest(manifest);
    tasks = static_cast<int>(items.size());
    std::vector<std::string> cmd = {exe.string(), "batch", manifest.string(), "--out-dir", out.string()};
    const auto forwarded = options::forwarded_args(args.scene.values, options::batch_tasks, options::batch);
    cmd.insert(cmd.end(), forwarded.begin(), forwarded.end());
    cmd.insert(cmd.end(), {"--progress", "json"});
    std::string script = sbatch_header(args, "meshtour-batch", (out / "logs" / "batch_%A_%a.log").string());
    script += "#SBATCH --array=0-" + std::to_string(tasks - 1) + "\n";
    script += "# one task per item of " + manifest.string() + " (" + std::to_string(tasks) + " items)\nset -euo pipefail\n";
    script += "exec" + join_quoted(cmd) + " --item \"$SLURM_ARRAY_TASK_ID\"\n";
    write_text(out / "batch.sbatch", script, true);
    first_sbatch = " " + shell_quote((out / "batch.sbatch").string());
    submit_script += "batch=$(sbatch --parsable" + first_sbatch + ")\necho \"batch_job=${batch%%;*}\"\n";
  } else {
    const Scene scene = resolve_scene(args.scene, codec);
    const std::filesystem::path frames_dir = out / "frames";
    std::vector<std::string> render = {exe.string(), "render"};
    if (!args.scene.input.empty()) render.push_back(std::filesystem::absolute(args.scene.input).string());
    render.insert(render.end(), {"--out-dir", frames_dir.string(), "--format", format});

    // The path, once: every chunk must render the very same path (and it is the expensive part
    // of a process's start-up).
    std::filesystem::path path_file;
    if (scene.path_file) {
      path_file = std::filesystem::absolute(*scene.path_file);
    } else if (scene.path_mode == "paper") {
      // Only the paper path has a path file; the turntable and the feature orbit are cheap and
      // deterministic (thread-count invariant), so every task computes the same one itself.
      const TriangleMesh mesh = load_scene_model(scene);
      const PaperPathResult path = compute_scene_paper_path(scene, mesh);
      path_file = out / "path.json";
      write_path_file(path, path_file, scene.source);
      if (!args.quiet) std::fprintf(stderr, "camera path computed once: %s\n", path_file.string().c_str());
    }
    if (!path_file.empty()) render.insert(render.end(), {"--path-file", path_file.string()});
    // Every option that changes pixels or the path, so each task renders the tour `tour` would.
    const auto forwarded = options::forwarded_args(args.scene.values, options::render_tasks, options::render);
    render.insert(render.end(), forwarded.begin(), forwarded.end());
    render.insert(render.end(), {"--progress", "json"});

    // The frames directory and its manifest now, so that a directory of another tour is refused
    // before anything is submitted.
    FrameDirInfo info = frame_dir_info(scene, format == "png+exr" ? std::vector<std::string>{"png", "exr"} : std::vector<std::string>{format});
    info.path_file = path_file.string();
    prepare_frame_dir(frames_dir, info);

    const int chunk = args.chunk_size;
    tasks = (scene.frames + chunk - 1) / chunk;
    std::string script = sbatch_header(args, "meshtour-render", (out / "logs" / "render_%A_%a.log").string());
    script += "#SBATCH --array=0-" + std::to_string(tasks - 1) + "\n";
    script += "# task i renders frames i*" + std::to_string(chunk) + " .. i*" + std::to_string(chunk) + "+" +
              std::to_string(chunk - 1) + " of " + std::to_string(scene.frames) +
              " (render clamps the last chunk); --threads defaults to SLURM_CPUS_PER_TASK\n";
    script += "set -euo pipefail\n";
    script += "chunk=" + std::to_string(chunk) + "\n";
    script += "first=$(( SLURM_ARRAY_TASK_ID * chunk ))\nlast=$(( first + chunk - 1 ))\n";
    script += "exec" + join_quoted(render) + " --frames \"$first-$last\"\n";
    write_text(out / "render.sbatch", script, true);

    const std::string video = args.output.empty()
                                  ? (args.scene.input.empty() ? std::string("meshtour-default")
                                                              : std::filesystem::path(args.scene.input).stem().string()) +
                                        video_extension(codec)
                                  : args.output;
    std::vector<std::string> encode = {exe.string(), "encode", frames_dir.string(), "-o", (out / video).string(), "--codec", codec};
    const auto forwarded_to_encode = options::forwarded_args(args.scene.values, options::encode_job, options::encode);
    for (std::size_t i = 0; i < forwarded_to_encode.size(); i += 2)
      if (forwarded_to_encode[i] != "--codec")  // given above, with its default
        encode.insert(encode.end(), {forwarded_to_encode[i], forwarded_to_encode[i + 1]});
    std::string enc = sbatch_header(args, "meshtour-encode", (out / "logs" / "encode_%j.log").string());
    enc += "# runs after every render task succeeded (submitted with --dependency=afterok:<render array job>)\n";
    enc += "set -euo pipefail\nexec" + join_quoted(encode) + "\n";
    write_text(out / "encode.sbatch", enc, true);

    first_sbatch = " " + shell_quote((out / "render.sbatch").string());
    second_sbatch = " --kill-on-invalid-dep=yes " + shell_quote((out / "encode.sbatch").string());
    submit_script += "render=$(sbatch --parsable" + first_sbatch + ")\nrender=${render%%;*}\necho \"render_job=$render\"\n";
    submit_script += "encode=$(sbatch --parsable --dependency=afterok:$render" + second_sbatch + ")\necho \"encode_job=${encode%%;*}\"\n";
    if (!args.quiet)
      std::fprintf(stderr, "%d frames in %d chunks of %d; video: %s\n", scene.frames, tasks, chunk, (out / video).string().c_str());
  }
  write_text(out / "submit.sh", submit_script, true);

  if (!args.submit) {
    if (!args.quiet) std::fprintf(stderr, "wrote the sbatch scripts to %s; submit them with %s\n", out.string().c_str(), (out / "submit.sh").string().c_str());
    return;
  }
  if (std::system("command -v sbatch >/dev/null 2>&1") != 0)
    throw RuntimeFailure("sbatch not found (install slurm-client, or submit later on a login node with " + (out / "submit.sh").string() + ")");
  if (!args.manifest.empty()) {
    const std::string id = submit(first_sbatch, "submitting the batch array");
    std::printf("batch_job=%s\n", id.c_str());
    if (!args.quiet) std::fprintf(stderr, "submitted batch array job %s (%d tasks, one per item)\n", id.c_str(), tasks);
  } else {
    const std::string render_id = submit(first_sbatch, "submitting the render array");
    const std::string encode_id = submit(" --dependency=afterok:" + render_id + second_sbatch, "submitting the encode job");
    std::printf("render_job=%s\nencode_job=%s\n", render_id.c_str(), encode_id.c_str());
    if (!args.quiet)
      std::fprintf(stderr, "submitted render array job %s (%d tasks) and encode job %s (afterok)\n", render_id.c_str(), tasks, encode_id.c_str());
  }
  std::fflush(stdout);
}

}  // namespace

void add_farm_command(CLI::App& app) {
  CLI::App* farm = app.add_subcommand("farm", "Split a tour (or a batch) over a render farm's job engine.");
  farm->require_subcommand(1);
  auto args = std::make_shared<FarmArgs>();
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
