// meshtour evaluate: what a tour shows. Builds the same cameras `meshtour tour` would render
// (path mode, framing, field of view) and measures them with item buffers (evaluate/evaluate.h).
#include <tbb/global_control.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>

#include "cli/commands.h"
#include "tour/evaluate_job.h"
#include "cli/path_options.h"
#include "cli/scene_args.h"
#include "core/error.h"
#include "evaluate/evaluate.h"
#include "pathgen/features.h"
#include "pathgen/path_file.h"
#include "scenes/scene.h"

namespace meshtour::cli {

void add_evaluate_command(CLI::App& app) {
  auto args = std::make_shared<EvaluateJob>();
  CLI::App* cmd = app.add_subcommand(
      "evaluate",
      "Measures what a tour shows: renders an item buffer (which face is visible in each pixel) for every "
      "frame of the tour `meshtour tour` would render, with the same path, framing and field of view, and "
      "reports: features = share of the feature area seen well in at least one frame; surface = the same "
      "for the whole surface; f.min / f.median = fewest and median number of frames in which a feature "
      "region is seen well; cam.speed / cam.accel = largest angular speed (rad/frame: angle between "
      "consecutive directions) and angular acceleration (rad/frame^2: change of the angular velocity of "
      "the frame that follows the direction with the camera's up, so a steady orbit at any height has "
      "none) of the camera position around the centre of the model's bounding box; view.spd / view.acc "
      "= the same for the view direction; "
      "out = frames in which some vertex is outside the image. A face is seen well in a frame when it "
      "is visible in the item buffer and the angle between its normal and the direction to the camera "
      "is below --seen-angle (either side of the face). Feature faces: w(f) of ALGORITHM.md §8 at or "
      "above its area-weighted --feature-quantile, computed once per mesh. A feature region is a "
      "connected component (faces sharing an edge) of feature faces; it is seen well in a frame when "
      "at least --region-share of its area is. Motion is measured around the loop including the jump "
      "from the last frame back to the first.");
  cmd->option_defaults()->always_capture_default();
  cmd->add_option("mesh", args->scene.input, "Mesh file (" + supported_mesh_formats() + ")")->required()->type_name("MESH");
  add_scene_options(*cmd, args->scene, options::evaluate, /*with_input=*/false);
  cmd->add_flag("--compare", args->compare, "Evaluate turntable, paper and feature-orbit and print one table");
  cmd->add_option("--json", args->json,
                  "Also write the numbers as JSON: {\"modes\": {\"<mode>\": {\"feature_coverage\": ..., "
                  "\"surface_coverage\": ..., \"feature_min_frames\": ..., \"feature_median_frames\": ..., "
                  "\"camera_max_angular_speed\": ..., \"view_max_angular_speed\": ..., "
                  "\"view_max_angular_acceleration\": ..., \"frames_out_of_frame\": ...}}} (fractions, rad/frame, rad/frame^2)")
      ->type_name("FILE");
  cmd->add_option("--pixels", args->evaluation.long_side_pixels, "Item-buffer pixels on the frame's long side")
      ->check(CLI::Range(8, 8192))
      ->capture_default_str();
  cmd->add_option("--seen-angle", args->evaluation.seen_angle_deg,
                  "A visible face is seen well when its normal is within this many degrees of the direction to the camera")
      ->check(CLI::Range(1.0, 90.0))
      ->capture_default_str();
  cmd->add_option("--feature-quantile", args->feature_quantile,
                  "Feature faces: w(f) at or above this area-weighted quantile of all face weights")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--region-share", args->evaluation.region_seen_share,
                  "Share of a feature region's area that must be seen well for the region to count as seen in a frame")
      ->check(CLI::Range(0.01, 1.0))
      ->capture_default_str();
  cmd->add_flag("-q,--quiet", args->quiet, "Print nothing on success");
  cmd->callback([args] { run_evaluate(*args); });
}

}  // namespace meshtour::cli
