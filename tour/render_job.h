#pragma once
// The render job of `meshtour render`: the frames of a tour (all, or a farm chunk of them) into a frames directory,
// resumable. Every process that renders part of a tour computes the same camera path and the same
// field of view (fitted over every frame of the tour), so frame k is the same bytes whichever
// process renders it; `meshtour encode` turns the directory into a video.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "tour/encode_frames.h"
#include "tour/resources.h"
#include "tour/tour.h"

namespace meshtour {

struct RenderJob {
  Scene scene;
  std::string out_dir;
  std::string frames = "all";  ///< the frames to render: a selection (jobs/frame_range.h)
  FrameFormats format = FrameFormats::png;
  int threads = 0;             ///< 0 = thread_count()'s default
  ProgressMode progress = ProgressMode::automatic;
  ResourceArgs resources;  // --max-memory, --verbose
  bool overwrite = false;
  bool quiet = false;
};

/// Runs the job: throws meshtour errors (InputError, IoError, ...) with one-line messages, and
/// Interrupted after SIGINT/SIGTERM, leaving no partial output behind.
/// Runs the job: throws meshtour errors (InputError, IoError, ...) with one-line messages, and
/// Interrupted after SIGINT/SIGTERM, leaving no partial output behind.
void run_render(const RenderJob& args);

}  // namespace meshtour
