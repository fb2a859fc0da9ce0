#pragma once
// The farm job of `meshtour farm` slurm: splits a tour over a Slurm cluster. The camera path is computed once here
// (a path file beside the frames), a job array renders the frames in chunks (`meshtour render
// --frames A-B --path-file ...`, the chunk derived from SLURM_ARRAY_TASK_ID), and a job that
// depends on the whole array (afterok) encodes them (`meshtour encode`). With a batch manifest,
// one array task per item instead (`meshtour batch --item`). Everything is written as sbatch
// scripts with absolute paths (the cluster shares the filesystem), submitted with --submit.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "tour/encode_frames.h"
#include "tour/resources.h"
#include "tour/tour.h"

namespace meshtour {

struct FarmJob {
  std::string input;           // the SCENE|MESH given ("" = the built-in scene): the render tasks' input
  std::optional<Scene> scene;  // its settings, resolved at the edge (unset with a manifest)
  std::string manifest;
  int manifest_items = 0;      // the manifest's items: one array task each
  std::string out_dir;
  std::string output;  // video name inside out_dir
  std::string executable;
  std::string partition, time_limit;
  std::string max_memory;  // --max-memory as given ("" = none): each task's budget and Slurm's --mem
  VideoCodec codec = VideoCodec::h264;      // of the video the encode job writes
  FrameFormats format = FrameFormats::png;  // of the frames
  bool web = false;            // with a manifest: web outputs per item and the contact sheet
  bool alpha = false;          // the encode job keeps the frames' alpha (its arguments say so: encode_args)
  /// The options given that each task must be given again, as command-line arguments for the
  /// scripts (options::forwarded_args): render tasks, the encode job, batch tasks.
  std::vector<std::string> render_args, encode_args, batch_args;
  int chunk_size = 10;
  int cpus_per_task = 1;
  bool submit = false;
  bool quiet = false;
};

/// Runs the job: throws meshtour errors (InputError, IoError, ...) with one-line messages, and
/// Interrupted after SIGINT/SIGTERM, leaving no partial output behind.
/// Runs the job: throws meshtour errors (InputError, IoError, ...) with one-line messages, and
/// Interrupted after SIGINT/SIGTERM, leaving no partial output behind.
void run_farm_slurm(const FarmJob& args);

}  // namespace meshtour
