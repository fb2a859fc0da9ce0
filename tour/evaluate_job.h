#pragma once
// The evaluate job of `meshtour evaluate`: what a tour shows. Builds the same cameras `meshtour tour` would render
// (path mode, framing, field of view) and measures them with item buffers (evaluate/evaluate.h).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "tour/encode_frames.h"
#include "tour/resources.h"
#include "evaluate/evaluate.h"
#include "tour/tour.h"

namespace meshtour {

struct EvaluateJob {
  std::string mesh;  // as given, for the report
  Scene scene;       // the tour's settings (size, frames, camera, path search), resolved at the edge
  std::string json;
  bool compare = false;
  bool quiet = false;
  int threads = 0;  // 0 = thread_count()'s default
  EvaluationOptions evaluation;
};

/// Runs the job: throws meshtour errors (InputError, IoError, ...) with one-line messages, and
/// Interrupted after SIGINT/SIGTERM, leaving no partial output behind.
/// Runs the job: throws meshtour errors (InputError, IoError, ...) with one-line messages, and
/// Interrupted after SIGINT/SIGTERM, leaving no partial output behind.
void run_evaluate(EvaluateJob& a);

}  // namespace meshtour
