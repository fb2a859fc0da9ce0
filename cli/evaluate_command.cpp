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
#include "cli/tour_setup.h"
#include "core/error.h"
#include "evaluate/evaluate.h"
#include "pathgen/features.h"
#include "pathgen/path_file.h"
#include "scenes/scene.h"

namespace meshtour::cli {
namespace {

struct EvaluateArgs {
  std::string mesh;
  std::string up = "y";
  std::string path_mode = "feature-orbit";  // the tour's default
  std::string path_file;
  int frames = 120;
  int width = 1280, height = 720;
  std::string fov = "auto";
  std::string json;
  bool compare = false;
  int threads = 0;
  bool quiet = false;
  double feature_quantile = 0.75;
  EvaluationOptions evaluation;
  PaperPathOptions paper;
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
  std::optional<tbb::global_control> thread_limit;
  if (a.threads > 0) thread_limit.emplace(tbb::global_control::max_allowed_parallelism, a.threads);
  a.paper.surface.threads = a.threads;
  a.paper.validate();
  a.evaluation.validate();
  if (a.compare && !a.path_file.empty()) throw InputError("--compare evaluates the built-in path modes; leave out --path-file");

  Scene scene = default_scene();
  scene.source = a.mesh;
  scene.mesh_file = a.mesh;
  scene.up = Axis::parse(a.up);
  scene.frames = a.frames;
  scene.render.width = a.width;
  scene.render.height = a.height;
  if (a.fov == "auto") {
    scene.auto_fov = true;
  } else {
    scene.vertical_fov_deg = std::stod(a.fov);
    scene.auto_fov = false;
  }
  if (!a.path_file.empty()) scene.path_file = a.path_file;

  const TriangleMesh mesh = load_scene_model(scene);
  throw_if_interrupted();
  // Feature faces once per mesh, whatever the path mode: w(f) of §8 at the paper's settings.
  const SurfaceAnalysis surface = analyze_surface(mesh, a.paper.surface);
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
    modes = {a.path_file.empty() ? a.path_mode : std::string("path-file")};
  std::vector<std::pair<std::string, PathEvaluation>> rows;
  for (const std::string& mode : modes) {
    if (mode != "path-file") scene.path_mode = mode;
    const auto path = make_path(scene, mesh, lens, a.paper, true);
    const double fov = choose_fov(scene, *path, mesh, lens, true);
    std::vector<Camera> cameras;
    for (int k = 0; k < scene.frames; ++k) {
      const CameraPose pose = frame_pose(*path, k, scene.frames);
      cameras.push_back(Camera{pose.eye, pose.target, pose.up, fov});
    }
    rows.emplace_back(mode, evaluator.evaluate(cameras, lens.aspect));
    throw_if_interrupted();
  }
  if (!a.json.empty()) {
    const std::string text = evaluation_json(rows);
    write_text_file_atomically(a.json, text, "evaluation");
  }
  if (!a.quiet) {
    std::cout << "meshtour evaluate: " << a.mesh << " (up " << scene.up.name() << ", " << scene.frames << " frames, "
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
  cmd->add_option("mesh", args->mesh, "Mesh file (" + supported_mesh_formats() + ")")->required()->type_name("MESH");
  cmd->add_option("--up", args->up, "The model's up axis: x, y, z, -x, -y or -z")
      ->check(CLI::IsMember({"x", "y", "z", "-x", "-y", "-z", "+x", "+y", "+z"}, CLI::ignore_case))
      ->capture_default_str();
  auto* path_file = cmd->add_option("--path-file", args->path_file, "Evaluate the camera path in this file (from 'meshtour path -o')")
                        ->check(CLI::ExistingFile);
  cmd->add_option("--path", args->path_mode, "Path mode to evaluate, as for 'meshtour tour --path': feature-orbit, paper or turntable")
      ->check(CLI::IsMember({"paper", "turntable", "feature-orbit"}))
      ->excludes(path_file)
      ->capture_default_str();
  cmd->add_flag("--compare", args->compare, "Evaluate turntable, paper and feature-orbit and print one table");
  cmd->add_option("--frames", args->frames, "Frames in one loop of the tour")->check(CLI::Range(1, 100000))->capture_default_str();
  cmd->add_option("--width", args->width, "Frame width of the tour (sets the aspect ratio)")->check(CLI::Range(2, 16384))->capture_default_str();
  cmd->add_option("--height", args->height, "Frame height of the tour")->check(CLI::Range(2, 16384))->capture_default_str();
  cmd->add_option("--fov", args->fov, "Vertical field of view as for 'meshtour tour': degrees or auto")
      ->check(CLI::IsMember({"auto"}) | CLI::Range(5.0, 120.0))
      ->capture_default_str();
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
  cmd->add_option("--threads", args->threads, "Worker threads; 0 = all cores. Results do not depend on it")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_flag("-q,--quiet", args->quiet, "Print nothing on success");
  add_paper_path_options(*cmd, args->paper);
  cmd->callback([args] { run_evaluate(*args); });
}

}  // namespace meshtour::cli
