#include "evaluate/evaluate.h"

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>

#include "core/error.h"
#include "core/interrupt.h"
#include "mesh/convex_hull.h"
#include "pathgen/motion.h"

namespace meshtour {
namespace {

// The camera frame the tracer uses (tracer/renderer.cpp): right = forward × up, up' = right × forward.
struct CameraFrame {
  Eigen::Vector3d forward, right, up;
  double tan_half = 0.0;
};

CameraFrame camera_frame(const Camera& camera) {
  CameraFrame f;
  const LookAtFrame view = look_at(camera);
  f.forward = view.forward;
  f.right = view.right;
  f.up = view.up;
  f.tan_half = std::tan(camera.vertical_fov_deg * std::numbers::pi / 360.0);
  return f;
}

}  // namespace

void EvaluationOptions::validate() const {
  coverage.validate();
  if (!(region_seen_share > 0.0 && region_seen_share <= 1.0))
    throw InputError("the share of a feature region that must be seen must be above 0 and at most 1");
}

struct PathEvaluator::Impl {
  EvaluationOptions options;
  std::unique_ptr<CoverageModel> coverage;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  // centre of the bounding box
  // The convex hull's vertices of the vertices some face uses: whether every vertex is in frame
  // is decided by them (count_out_of_frame's test is a largest value of linear functions).
  std::vector<Eigen::Vector3d> hull_points;
};

PathEvaluator::PathEvaluator(const TriangleMesh& mesh, const EvaluationOptions& options) : impl_(std::make_unique<Impl>()) {
  options.validate();
  if (mesh.triangles.empty()) throw InputError("the mesh has no triangles to evaluate");
  Impl& s = *impl_;
  s.options = options;
  s.center = mesh.bounds().center();
  s.hull_points = convex_hull_vertices(mesh);
  s.coverage = std::make_unique<CoverageModel>(mesh, options.coverage);
}

PathEvaluator::~PathEvaluator() = default;

const CoverageModel& PathEvaluator::coverage() const { return *impl_->coverage; }

PathEvaluation PathEvaluator::evaluate(std::span<const Camera> cameras, double aspect) const {
  if (cameras.empty()) throw InputError("evaluation: the tour has no frames");
  if (!(aspect > 0.0)) throw InputError("the frame's aspect ratio must be positive");
  const Impl& s = *impl_;
  const CoverageModel& model = *s.coverage;
  std::vector<ViewCoverage> views(cameras.size());
  std::vector<ViewPreference> preferences(cameras.size());
  tbb::parallel_for(std::size_t{0}, cameras.size(), [&](std::size_t k) {
    throw_if_interrupted();
    const View view{cameras[k], aspect};
    views[k] = model.coverage(view);
    preferences[k] = model.preference(view);
  });
  throw_if_interrupted();

  PathEvaluation out;
  out.frames = static_cast<int>(cameras.size());
  out.preference = preferences.front();
  for (const ViewPreference& p : preferences) out.frame_preferences.push_back(p.score);
  std::vector<const ViewCoverage*> all(views.size());
  for (std::size_t k = 0; k < views.size(); ++k) {
    all[k] = &views[k];
    out.frame_scores.push_back(model.scores(views[k]).objective);
  }
  const CoverageScores scores = model.scores(all);
  out.objective = scores.objective;

  for (int d = 0; d < kFeatureDefinitions; ++d) {
    const FeatureDefinition& def = feature_definitions()[d];
    DefinitionFigures& f = out.by_definition[d];
    f.feature_coverage = scores.feature_share[d];
    f.surface_coverage = scores.surface_share[def.angle];
    // Frames in which each feature region is seen well (at least region_seen_share of its samples).
    const std::vector<int>& region = model.sample_region(def.measure);
    const int regions = model.region_count(def.measure);
    if (regions == 0) continue;
    std::vector<std::size_t> size(static_cast<std::size_t>(regions), 0), seen(size.size());
    for (int r : region)
      if (r >= 0) ++size[r];
    std::vector<int> frames(size.size(), 0);
    for (const ViewCoverage& v : views) {
      std::fill(seen.begin(), seen.end(), 0);
      const std::vector<std::uint64_t>& bits = v.seen[def.angle];
      for (std::size_t i = 0; i < region.size(); ++i)
        if (region[i] >= 0 && (bits[i / 64] >> (i % 64) & 1u)) ++seen[region[i]];
      for (std::size_t r = 0; r < size.size(); ++r)
        if (static_cast<double>(seen[r]) >= s.options.region_seen_share * static_cast<double>(size[r])) ++frames[r];
    }
    std::sort(frames.begin(), frames.end());
    f.feature_min_frames = frames.front();
    const std::size_t n = frames.size();
    f.feature_median_frames = n % 2 ? frames[n / 2] : 0.5 * (frames[n / 2 - 1] + frames[n / 2]);
  }
  const DefinitionFigures& main = out.by_definition[0];
  out.feature_coverage = main.feature_coverage;
  out.surface_coverage = main.surface_coverage;
  out.feature_min_frames = main.feature_min_frames;
  out.feature_median_frames = main.feature_median_frames;
  measure_motion(cameras, s.center, out);
  out.frames_out_of_frame = count_out_of_frame(cameras, s.hull_points, aspect);
  out.min_edge_margin = narrowest_edge_margin(cameras, s.hull_points, aspect);
  for (const Camera& camera : cameras) {
    // The lowest point along this camera's up (every path's up is the model's).
    double floor = std::numeric_limits<double>::infinity();
    for (const Eigen::Vector3d& p : s.hull_points) floor = std::min(floor, p.dot(camera.up));
    if (camera.eye.dot(camera.up) < floor) ++out.frames_below_floor;
  }
  return out;
}

void measure_motion(std::span<const Camera> cameras, const Eigen::Vector3d& center, PathEvaluation& out) {
  std::vector<Eigen::Vector3d> position(cameras.size()), view(cameras.size()), up(cameras.size());
  for (std::size_t k = 0; k < cameras.size(); ++k) {
    position[k] = (cameras[k].eye - center).normalized();
    view[k] = (cameras[k].target - cameras[k].eye).normalized();
    up[k] = cameras[k].up;
  }
  std::tie(out.camera_max_angular_speed, out.camera_max_angular_acceleration) = angular_motion(position, up);
  std::tie(out.view_max_angular_speed, out.view_max_angular_acceleration) = angular_motion(view, up);
}

int count_out_of_frame(std::span<const Camera> cameras, const std::vector<Eigen::Vector3d>& points, double aspect) {
  int count = 0;
  for (const Camera& camera : cameras) {
    const CameraFrame f = camera_frame(camera);
    // A hair of tolerance: the fitted field of view puts the extreme vertex exactly on its margin.
    const double limit_y = f.tan_half * (1.0 + 1e-9), limit_x = f.tan_half * aspect * (1.0 + 1e-9);
    for (const Eigen::Vector3d& p : points) {
      const Eigen::Vector3d d = p - camera.eye;
      const double z = d.dot(f.forward);
      if (!(z > 0.0) || std::abs(d.dot(f.up)) > limit_y * z || std::abs(d.dot(f.right)) > limit_x * z) {
        ++count;
        break;
      }
    }
  }
  return count;
}

double narrowest_edge_margin(std::span<const Camera> cameras, const std::vector<Eigen::Vector3d>& points, double aspect) {
  // A point at image coordinates (x, y) in [-1, 1] leaves (1 - |x|) of the half-width and
  // (1 - |y|) of the half-height free; in shares of the smaller side those are
  // (1 - |x|) a / 2m and (1 - |y|) / 2m, with a = width / height and m = min(a, 1).
  const double smaller = std::min(aspect, 1.0);
  double narrowest = std::numeric_limits<double>::infinity();
  for (const Camera& camera : cameras) {
    const CameraFrame f = camera_frame(camera);
    for (const Eigen::Vector3d& p : points) {
      const Eigen::Vector3d d = p - camera.eye;
      const double z = d.dot(f.forward);
      if (!(z > 0.0)) return -1.0;
      const double x = std::abs(d.dot(f.right)) / (z * f.tan_half * aspect), y = std::abs(d.dot(f.up)) / (z * f.tan_half);
      narrowest = std::min({narrowest, (1.0 - x) * aspect / (2.0 * smaller), (1.0 - y) / (2.0 * smaller)});
    }
  }
  return cameras.empty() ? 0.0 : narrowest;
}

std::string evaluation_json(const std::vector<std::pair<std::string, PathEvaluation>>& modes, const CoverageOptions& options) {
  nlohmann::ordered_json doc;
  nlohmann::ordered_json& by_mode = doc["modes"];
  by_mode = nlohmann::ordered_json::object();
  for (const auto& [name, e] : modes) {
    // Today's keys first, for the default definition (scripts/evaluate-table.js reads them).
    nlohmann::ordered_json m = {
        {"feature_coverage", e.feature_coverage},
        {"surface_coverage", e.surface_coverage},
        {"feature_min_frames", e.feature_min_frames},
        {"feature_median_frames", e.feature_median_frames},
        {"camera_max_angular_speed", e.camera_max_angular_speed},
        {"view_max_angular_speed", e.view_max_angular_speed},
        {"view_max_angular_acceleration", e.view_max_angular_acceleration},
        {"frames_out_of_frame", e.frames_out_of_frame},
        {"min_edge_margin", e.min_edge_margin},
        {"frames_below_floor", e.frames_below_floor},
    };
    m["objective"] = e.objective;
    m["frame_scores"] = e.frame_scores;
    // The poster's (frame 0's) view preference, beside the coverage scores.
    m["preference"] = {{"score", e.preference.score},
                       {"projected_area", e.preference.projected_area},
                       {"visible_ratio", e.preference.visible_ratio}};
    m["frame_preferences"] = e.frame_preferences;
    nlohmann::ordered_json& definitions = m["definitions"];
    definitions = nlohmann::ordered_json::object();
    for (int d = 0; d < kFeatureDefinitions; ++d) {
      const DefinitionFigures& f = e.by_definition[d];
      definitions[options.key(feature_definitions()[d])] = {
          {"feature_coverage", f.feature_coverage},
          {"surface_coverage", f.surface_coverage},
          {"feature_min_frames", f.feature_min_frames},
          {"feature_median_frames", f.feature_median_frames},
      };
    }
    by_mode[name] = std::move(m);
  }
  return doc.dump(2) + "\n";
}

}  // namespace meshtour
