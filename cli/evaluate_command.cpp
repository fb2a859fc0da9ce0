// meshtour evaluate: what a tour shows. Builds the same cameras `meshtour tour` would render
// (path mode, framing, field of view) and measures them on surface samples (evaluate/evaluate.h).
#include <tbb/global_control.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <utility>

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
      "Measures what a tour shows: asks what every frame of the tour `meshtour tour` would render (same "
      "path, framing and field of view) sees of a fixed number of surface samples (area-weighted, so the "
      "figures do not depend on the tessellation), and reports: features = share of the feature area seen "
      "well in at least one frame; surface = the same for the whole surface; f.min / f.median = fewest and "
      "median number of frames in which a feature region is seen well; cam.speed / cam.accel = largest "
      "angular speed (rad/frame: angle between consecutive directions) and angular acceleration (rad/frame^2: "
      "change of the angular velocity of the frame that follows the direction with the camera's up, so a "
      "steady orbit at any height has none) of the camera position around the centre of the model's bounding "
      "box; view.spd / view.acc = the same for the view direction; out = frames in which some vertex is "
      "outside the image. A sample is seen well in a frame when it is inside the image, not hidden by the "
      "surface, and the angle between its normal and the direction to the camera is below the seen-well "
      "angle (either side of the surface). Features are judged eight ways, so no path wins by one yardstick: "
      "two measures computed on a fixed-resolution proxy of the mesh (patch density = w(f) of docs/METHOD.md "
      "§8; saliency = mesh saliency of Lee, Varshney & Jacobs 2005), each at four seen-well angles "
      "(--seen-angle 75, --strict-angle 60, --stricter-angle 45, --strictest-angle 30); the samples at or "
      "above the --feature-quantile of a measure are its features. Changing them here changes only the "
      "yardstick, not the paths: the feature orbit's search always uses the defaults, so other angles and "
      "quantiles test it on measures it was not tuned to. The first table uses the default (patch density "
      "at --seen-angle); the second gives the feature coverage under every definition, the objective (the "
      "mean over the definitions of features seen plus 0.3 x other surface seen, over the features: what "
      "the feature orbit maximizes, among the curves that see under every definition at least as much as a "
      "level circle and the turntable) and the frame whose view alone scores highest. A feature region is a connected part of the features; it is seen "
      "well in a frame when at least --region-share of it is. Motion is measured around the loop including "
      "the jump from the last frame back to the first.");
  cmd->option_defaults()->always_capture_default();
  cmd->add_option("mesh", args->scene.input, "Mesh file (" + supported_mesh_formats() + ")")->required()->type_name("MESH");
  add_scene_options(*cmd, args->scene, options::evaluate, /*with_input=*/false);
  cmd->add_flag("--compare", args->compare, "Evaluate turntable, paper and feature-orbit and print one table");
  cmd->add_option("--json", args->json,
                  "Also write the numbers as JSON: {\"modes\": {\"<mode>\": {\"feature_coverage\": ..., "
                  "\"surface_coverage\": ..., \"feature_min_frames\": ..., \"feature_median_frames\": ..., "
                  "\"camera_max_angular_speed\": ..., \"view_max_angular_speed\": ..., "
                  "\"view_max_angular_acceleration\": ..., \"frames_out_of_frame\": ..., \"objective\": ..., "
                  "\"frame_scores\": [...], \"definitions\": {\"patch-density-75deg\": {\"feature_coverage\": ..., "
                  "\"surface_coverage\": ..., \"feature_min_frames\": ..., \"feature_median_frames\": ...}, "
                  "\"saliency-75deg\": {...}, \"patch-density-60deg\": {...}, \"saliency-60deg\": {...}, "
                  "\"patch-density-45deg\": {...}, \"saliency-45deg\": {...}, \"patch-density-30deg\": {...}, "
                  "\"saliency-30deg\": {...}}}}} "
                  "(fractions, rad/frame, rad/frame^2; the top-level coverage keys are the first definition's)")
      ->type_name("FILE");
  cmd->add_option("--samples", args->evaluation.coverage.samples, "Surface samples the coverage is measured on")
      ->check(CLI::Range(1024, 1 << 24))
      ->capture_default_str();
  // One option per seen-well angle of CoverageOptions, in its order (each names a pair of definitions).
  static constexpr std::array<std::pair<const char*, const char*>, kSeenAngles> angle_options{{
      {"--seen-angle", "A visible sample is seen well when its normal is within this many degrees of the direction to the camera"},
      {"--strict-angle", "The seen-well angle of the second pair of feature definitions (stricter)"},
      {"--stricter-angle", "The seen-well angle of the third pair of feature definitions (stricter still)"},
      {"--strictest-angle", "The seen-well angle of the fourth pair of feature definitions (the strictest)"},
  }};
  for (std::size_t i = 0; i < angle_options.size(); ++i)
    cmd->add_option(angle_options[i].first, args->evaluation.coverage.seen_angle_deg[i], angle_options[i].second)
        ->check(CLI::Range(1.0, 90.0))
        ->capture_default_str();
  cmd->add_option("--feature-quantile", args->evaluation.coverage.feature_quantile,
                  "Features: the samples at or above this quantile of a measure")
      ->check(CLI::Range(0.0, 0.99))
      ->capture_default_str();
  cmd->add_option("--region-share", args->evaluation.region_seen_share,
                  "Share of a feature region's area that must be seen well for the region to count as seen in a frame")
      ->check(CLI::Range(0.01, 1.0))
      ->capture_default_str();
  cmd->add_flag("-q,--quiet", args->quiet, "Print nothing on success");
  cmd->callback([args] { run_evaluate(*args); });
}

}  // namespace meshtour::cli
