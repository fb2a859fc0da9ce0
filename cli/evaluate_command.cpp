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
#include "cli/path_options.h"
#include "cli/scene_args.h"
#include "core/error.h"
#include "evaluate/evaluate.h"
#include "pathgen/features.h"
#include "pathgen/path_file.h"
#include "scenes/scene.h"

namespace meshtour::cli {
namespace {

struct EvaluateArgs {
  SceneArgs scene;  // the mesh and the tour's registry options (size, frames, camera, path search)
  std::string json;
  bool compare = false;
  bool quiet = false;
  double feature_quantile = 0.75;
  EvaluationOptions evaluation;
};

void print_table(const std::vector<std::pair<std::string, PathEvaluation>>& rows, std::ostream& out) {
  char line[512];
  std::snprintf(line, sizeof line, "%-14s %9s %9s %6s %7s %9s %9s %9s %9s %6s\n", "mode", "features", "surface",
                "f.min", "f.median", "cam.speed", "cam.accel", "view.spd", "view.acc", "out");
  out << line;
  for (const auto& [mode, e] : rows) {
    std::snprintf(line, sizeof line, "%-14s %8.2f%% %8.2f%% %6d %7.1f %9.4f %9.4f %9.4f %9.4f %6d\n", mode.c_str(),
                  100.0 * e.feature_coverage, 100.0 * e.surface_coverage, e.feature_min_frames, e.feature_median_frames,
                  e.camera_max_angular_speed, e.camera_max_angular_acceleration, e.view_max_angular_speed,
                  e.view_max_angular_acceleration, e.frames_out_of_frame);
    out << line;
  }
}

void run_evaluate(EvaluateArgs& a) {
  install_interrupt_handlers();
  const options::Values& values = a.scene.values;
  const int threads = thread_count(int_value_or(values, "threads", 0), a.quiet);
  tbb::global_control thread_limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  a.evaluation.validate();
  const bool path_file = values.count("path-file") != 0;
  if (a.compare && path_file) throw InputError("--compare evaluates the built-in path modes; leave out --path-file");
  if (values.count("path") && path_file) throw InputError("give --path or --path-file, not both");

  Scene scene = resolve_scene(a.scene);
  const PaperPathOptions paper = path_search_options(scene.path_search);
  paper.validate();

  const TriangleMesh mesh = load_scene_model(scene);
  throw_if_interrupted();
  // Feature faces once per mesh, whatever the path mode: w(f) of §8 at the paper's settings.
  const SurfaceAnalysis surface = analyze_surface(mesh, paper.surface);
  const std::vector<std::uint8_t> features =
      feature_faces(input_face_weights(surface, mesh.triangles.size()), face_areas(mesh), a.feature_quantile);
  const PathEvaluator evaluator(mesh, features, a.evaluation);
  throw_if_interrupted();

  Lens lens;
  lens.vertical_fov_deg = scene.vertical_fov_deg;
  lens.aspect = static_cast<double>(scene.render.width) / scene.render.height;
  std::vector<std::string> modes;
  if (a.compare)
    modes = {"turntable", "paper", "feature-orbit"};
  else
    modes = {path_file ? std::string("path-file") : scene.path_mode};
  std::vector<std::pair<std::string, PathEvaluation>> rows;
  for (const std::string& mode : modes) {
    if (mode != "path-file") scene.path_mode = mode;
    const auto path = make_path(scene, mesh, lens, true);
    const double fov = choose_fov(scene, *path, mesh, lens, true);
    std::vector<Camera> cameras;
    for (int k = 0; k < scene.frames; ++k) {
      const CameraPose pose = frame_pose(*path, k, scene.frames);
      cameras.push_back(Camera::at(pose, fov));
    }
    rows.emplace_back(mode, evaluator.evaluate(cameras, lens.aspect));
    throw_if_interrupted();
  }
  if (!a.json.empty()) {
    const std::string text = evaluation_json(rows);
    write_text_file_atomically(a.json, text, "evaluation");
  }
  if (!a.quiet) {
    std::cout << "meshtour evaluate: " << a.scene.input << " (up " << scene.up.name() << ", " << scene.frames << " frames, "
              << mesh.triangles.size() << " faces, " << evaluator.regions().count << " feature regions)\n";
    print_table(rows, std::cout);
    if (!a.json.empty()) std::cout << "wrote " << a.json << "\n";
  }
}

}  // namespace

void add_evaluate_command(CLI::App& app) {
  auto args = std::make_shared<EvaluateArgs>();
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
