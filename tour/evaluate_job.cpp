#include "tour/evaluate_job.h"

#include "tour/thread_limit.h"
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <algorithm>
#include <optional>
#include "core/error.h"
#include "evaluate/evaluate.h"
#include "mesh/convex_hull.h"
#include "pathgen/features.h"
#include "pathgen/path_file.h"
#include "scenes/scene.h"
#include "core/interrupt.h"
#include "tour/mesh_warnings.h"
#include "tour/path_overview.h"
#include "tour/path_plot.h"
#include "tour/progress.h"

namespace meshtour {
namespace {

void print_table(const std::vector<std::pair<std::string, PathEvaluation>>& rows, std::ostream& out) {
  char line[512];
  std::snprintf(line, sizeof line, "%-14s %9s %9s %6s %7s %9s %9s %9s %9s %6s %7s %6s\n", "mode", "features", "surface",
                "f.min", "f.median", "cam.speed", "cam.accel", "view.spd", "view.acc", "out", "margin", "below");
  out << line;
  for (const auto& [mode, e] : rows) {
    std::snprintf(line, sizeof line, "%-14s %8.2f%% %8.2f%% %6d %7.1f %9.4f %9.4f %9.4f %9.4f %6d %6.2f%% %6d\n", mode.c_str(),
                  100.0 * e.feature_coverage, 100.0 * e.surface_coverage, e.feature_min_frames, e.feature_median_frames,
                  e.camera_max_angular_speed, e.camera_max_angular_acceleration, e.view_max_angular_speed,
                  e.view_max_angular_acceleration, e.frames_out_of_frame, 100.0 * e.min_edge_margin, e.frames_below_floor);
    out << line;
  }
}

// The feature coverage under every definition, and the objective the feature orbit maximizes.
void print_definitions(const std::vector<std::pair<std::string, PathEvaluation>>& rows, const CoverageOptions& options,
                       std::ostream& out) {
  char cell[64];
  std::snprintf(cell, sizeof cell, "%-14s", "features by");
  out << "\n" << cell;
  for (const FeatureDefinition& d : feature_definitions()) {
    std::snprintf(cell, sizeof cell, " %20s", options.key(d).c_str());
    out << cell;
  }
  out << "  objective  best frame  poster preference  preferred frame\n";
  for (const auto& [mode, e] : rows) {
    std::snprintf(cell, sizeof cell, "%-14s", mode.c_str());
    out << cell;
    for (const DefinitionFigures& f : e.by_definition) {
      std::snprintf(cell, sizeof cell, " %19.2f%%", 100.0 * f.feature_coverage);
      out << cell;
    }
    const auto best = std::max_element(e.frame_scores.begin(), e.frame_scores.end());
    const auto preferred = std::max_element(e.frame_preferences.begin(), e.frame_preferences.end());
    std::snprintf(cell, sizeof cell, "  %9.4f  %10d  %17.3f  %15d\n", e.objective, static_cast<int>(best - e.frame_scores.begin()),
                  e.preference.score, static_cast<int>(preferred - e.frame_preferences.begin()));
    out << cell;
  }
}

}  // namespace

void run_evaluate(EvaluateJob& a) {
  install_interrupt_handlers();
  const ThreadLimit thread_limit(a.threads, a.quiet);
  a.evaluation.validate();
  const bool path_file = a.scene.path_file.has_value();
  if (a.compare && path_file) throw InputError("--compare evaluates the built-in path modes; leave out --path-file");

  Scene scene = a.scene;
  const PaperPathOptions& paper = scene.path_search;
  paper.validate();

  const TriangleMesh mesh = load_scene_model(scene);
  resolve_auto_up(scene, mesh, a.quiet);
  throw_if_interrupted();
  // Features once per mesh, whatever the path mode: w(f) of §8 at the paper's settings and mesh
  // saliency, both on the coverage module's fixed-resolution proxy.
  a.evaluation.coverage.surface = paper.surface;
  // One BVH for the evaluation and every feature orbit it plans.
  const auto rays = std::make_shared<const RayScene>(mesh);
  a.evaluation.coverage.ray_scene = rays;
  const PathEvaluator evaluator(mesh, a.evaluation);
  throw_if_interrupted();

  Lens lens;
  lens.vertical_fov_deg = scene.vertical_fov_deg;
  lens.aspect = static_cast<double>(scene.render.width) / scene.render.height;
  // The modes measured, by name; the path file's cameras are measured as "path-file".
  std::vector<std::pair<std::string, PathMode>> modes;
  if (a.compare)
    for (const PathMode m : {PathMode::turntable, PathMode::paper, PathMode::feature_orbit}) modes.emplace_back(path_mode_name(m), m);
  else
    modes = {{path_file ? std::string("path-file") : std::string(path_mode_name(scene.path_mode)), scene.path_mode}};
  std::vector<std::pair<std::string, PathEvaluation>> rows;
  // Once per mesh, for every mode: the framing fits read only the hull's vertices.
  const std::vector<Eigen::Vector3d> hull = convex_hull_vertices(mesh.positions);
  for (const auto& [mode, path_mode] : modes) {
    scene.path_mode = path_mode;
    // With the frames' scores asked for, the feature orbit turns its loop so that its preferred
    // view comes first, as `tour` does: the cameras measured are the ones the tour renders.
    std::vector<double> view_scores;
    const auto path = make_path(scene, mesh, hull, lens, true, &view_scores, rays);
    const double fov = choose_fov(scene, *path, mesh, hull, lens, true);
    std::vector<Camera> cameras;
    for (int k = 0; k < scene.frames; ++k) {
      const CameraPose pose = frame_pose(*path, k, scene.frames);
      cameras.push_back(Camera::at(pose, fov));
    }
    rows.emplace_back(mode, evaluator.evaluate(cameras, lens.aspect));
    throw_if_interrupted();
  }
  if (!a.json.empty()) {
    const std::string text = evaluation_json(rows, a.evaluation.coverage);
    write_text_file_atomically(a.json, text, "evaluation");
  }
  if (!a.quiet) {
    std::cout << "meshtour evaluate: " << a.mesh << " (up " << scene.up.name() << ", " << scene.frames << " frames, "
              << mesh.triangles.size() << " faces, " << evaluator.coverage().region_count(FeatureMeasure::patch_density)
              << " feature regions)\n";
    print_table(rows, std::cout);
    print_definitions(rows, a.evaluation.coverage, std::cout);
    if (!a.json.empty()) std::cout << "wrote " << a.json << "\n";
  }
}

}  // namespace meshtour
