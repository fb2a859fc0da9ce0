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
  SceneArgs scene;
  std::string manifest;
  std::string out_dir;
  std::string output;  // video name inside out_dir
  std::string executable;
  std::string partition, time_limit;
  std::string codec = "h264";  // of the video the encode job writes
  std::string format = "png";  // of the frames: png, exr or png+exr
  bool web = false;            // with a manifest: web outputs per item and the contact sheet
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
