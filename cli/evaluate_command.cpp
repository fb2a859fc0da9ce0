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
#include "cli/scene_args.h"
#include "core/error.h"
#include "evaluate/evaluate.h"
#include "pathgen/features.h"
#include "pathgen/path_file.h"
#include "scenes/scene.h"

namespace meshtour::cli {

namespace {

struct EvaluateArgs {
  SceneArgs scene;
  EvaluateJob job;
};

}  // namespace

void add_evaluate_command(CLI::App& app) {
  auto args = std::make_shared<EvaluateArgs>();
  EvaluateJob& job = args->job;
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
      "outside the image; margin = the narrowest space between the model and an edge of the image over all "
      "frames, as a share of its smaller side (action-safe framing asks for 5 %); below = frames whose eye is "
      "below the floor the model stands on (the plane through its lowest point). A sample is seen well in a frame when it is inside the image, not hidden by the "
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
  add_mesh_argument(*cmd, args->scene.input);
  CoverageOptions& coverage = job.evaluation.coverage;
  add_scene_options(*cmd, args->scene, options::evaluate,
                    {{"threads", options::to(job.threads)},
                     {"quiet", options::to(job.quiet)},
                     {"compare", options::to(job.compare)},
                     {"json-file", options::to(job.json)},
                     {"coverage-samples", options::to(coverage.samples)},
                     // One row per seen-well angle of CoverageOptions, in its order.
                     {"seen-angle", options::to(coverage.seen_angle_deg[0])},
                     {"strict-angle", options::to(coverage.seen_angle_deg[1])},
                     {"stricter-angle", options::to(coverage.seen_angle_deg[2])},
                     {"strictest-angle", options::to(coverage.seen_angle_deg[3])},
                     {"feature-quantile", options::to(coverage.feature_quantile)},
                     {"region-share", options::to(job.evaluation.region_seen_share)}},
                    /*with_input=*/false);
  cmd->callback([args] {
    const options::Values& given = args->scene.values;
    if (given.contains("path") && given.contains("path-file")) throw InputError("give --path or --path-file, not both");
    args->job.mesh = args->scene.input;
    args->job.scene = resolve_scene(args->scene);
    run_evaluate(args->job);
  });
}

}  // namespace meshtour::cli
