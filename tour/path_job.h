#pragma once
// The path job of `meshtour path`: the camera path of a mesh by the toroidal-patch method (docs/METHOD.md), written
// as a JSON path file, with an optional plot and debug outputs. No rendering.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "tour/encode_frames.h"
#include "tour/resources.h"
#include "tour/tour.h"

namespace meshtour {

struct PathJob {
  std::string mesh;
  std::string up = "y";
  std::string output;
  std::string plot;
  std::string debug_dir;
  std::string mode = "paper";
  options::Values values;  // registry rows of `path`: frames, threads, exports, path search
  std::string gltf, camera_frames, overview;
  std::string overview_size = "1200x900";
  int threads = 0;
  bool quiet = false;
  PaperPathOptions options;
  ResourceArgs resources;
};

/// Runs the job: throws meshtour errors (InputError, IoError, ...) with one-line messages, and
/// Interrupted after SIGINT/SIGTERM, leaving no partial output behind.
/// Runs the job: throws meshtour errors (InputError, IoError, ...) with one-line messages, and
/// Interrupted after SIGINT/SIGTERM, leaving no partial output behind.
void run_path(PathJob& a);

}  // namespace meshtour
