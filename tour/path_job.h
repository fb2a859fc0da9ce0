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
  /// The cylinder's axis (I-18); with up_auto, decided from the model once it is loaded. The
  /// modes other than paper take a coordinate axis only.
  UpDirection up;
  bool up_auto = false;
  std::string output;
  std::string plot;
  std::string debug_dir;
  PathMode mode = PathMode::paper;
  /// The tour's settings (frames, size, field of view, path search) as `tour` applies them, for
  /// the exports and the overview.
  Scene scene;
  std::string gltf, camera_frames, overview;
  int overview_width = 1200, overview_height = 900;
  int threads = 0;
  bool quiet = false;
  PaperPathOptions options;  ///< the path search: the scene's, with the samples of samples.csv
  ResourceArgs resources;
};

/// Runs the job: throws meshtour errors (InputError, IoError, ...) with one-line messages, and
/// Interrupted after SIGINT/SIGTERM, leaving no partial output behind.
/// Runs the job: throws meshtour errors (InputError, IoError, ...) with one-line messages, and
/// Interrupted after SIGINT/SIGTERM, leaving no partial output behind.
void run_path(PathJob& a);

}  // namespace meshtour
