#pragma once
// What a camera tour shows: every frame is asked what it sees of the surface through the
// coverage module (pathgen/coverage.h, the same one the feature orbit's search uses): surface
// samples, features under two independent measures (patch density, saliency) and four seen-well
// angles. The camera's motion gives its smoothness. Used by `meshtour evaluate` to compare path
// modes with numbers instead of by eye, under more than one yardstick.
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/camera.h"
#include "mesh/mesh.h"
#include "pathgen/coverage.h"

namespace meshtour {

struct EvaluationOptions {
  CoverageOptions coverage;  ///< samples, features, seen-well angles
  /// A feature region counts as seen well in a frame when at least this share of its area is.
  double region_seen_share = 0.25;

  /// \throw InputError naming the value that is out of range.
  void validate() const;
};

/// The coverage figures of one tour under one feature definition (fractions of area).
struct DefinitionFigures {
  double feature_coverage = 0.0;  ///< feature area seen well in at least one frame / feature area
  double surface_coverage = 0.0;  ///< the same for the whole surface (at this definition's angle)
  int feature_min_frames = 0;     ///< fewest frames any feature region is seen well in
  double feature_median_frames = 0.0;  ///< median over the feature regions
};

/// The numbers of one tour. The top-level coverage fields are those of the default definition
/// (patch density at 75°); by_definition has all of them, in feature_definitions() order.
/// Angles are radians per frame (speed) and per frame² (acceleration), measured around the loop
/// including its join.
struct PathEvaluation {
  int frames = 0;
  double surface_coverage = 0.0;
  double feature_coverage = 0.0;
  int feature_min_frames = 0;
  double feature_median_frames = 0.0;
  std::array<DefinitionFigures, kFeatureDefinitions> by_definition{};
  double objective = 0.0;            ///< the feature orbit's objective for the whole tour
  std::vector<double> frame_scores;  ///< the same objective for each frame alone
  /// How much people would prefer frame 0, the poster (pathgen/coverage.h, ViewPreferenceModel),
  /// and the preference score of every frame: beside the coverage, which cannot tell a front from
  /// a back.
  ViewPreference preference;
  std::vector<double> frame_preferences;
  double camera_max_angular_speed = 0.0;         ///< of the eye's direction from the model centre
  /// Change of the angular velocity of that direction's frame (up = the camera's up), see
  /// pathgen/motion.h: a constant-rate orbit has none, a jerk or a sudden climb has.
  double camera_max_angular_acceleration = 0.0;
  double view_max_angular_speed = 0.0;           ///< of the view direction (target - eye)
  double view_max_angular_acceleration = 0.0;
  int frames_out_of_frame = 0;  ///< frames where a vertex is behind the camera or outside the image
  /// The narrowest space between the model and an edge of the image over all frames, as a share of
  /// the image's smaller side (the action-safe margin asks for at least 0.05; negative: cut off).
  double min_edge_margin = 0.0;
  /// Frames whose eye is below the floor the model stands on (the plane through its lowest point,
  /// across the cameras' up direction): a studio look's ground would hide the model's underside.
  int frames_below_floor = 0;
};

/// Evaluates camera sets on one mesh. Builds the coverage model once; evaluate() may be called
/// for any number of tours. Results do not depend on the thread count.
class PathEvaluator {
public:
  /// \throw InputError for an empty mesh or bad options, RuntimeFailure if Embree fails.
  explicit PathEvaluator(const TriangleMesh& mesh, const EvaluationOptions& options = {});
  ~PathEvaluator();
  PathEvaluator(const PathEvaluator&) = delete;
  PathEvaluator& operator=(const PathEvaluator&) = delete;

  /// The numbers for the loop of `cameras` (frame k is followed by frame k+1, the last by the
  /// first) rendered at `aspect` = width / height.
  PathEvaluation evaluate(std::span<const Camera> cameras, double aspect) const;

  const CoverageModel& coverage() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Smoothness part alone (no mesh needed): fills the four angular fields of `out` for the loop
/// of `cameras` around `center`.
void measure_motion(std::span<const Camera> cameras, const Eigen::Vector3d& center, PathEvaluation& out);

/// Number of cameras that do not see every one of `points` inside their frame (no margin).
int count_out_of_frame(std::span<const Camera> cameras, const std::vector<Eigen::Vector3d>& points, double aspect);

/// The narrowest space left between `points` and an edge of the image over `cameras`, as a share
/// of the image's smaller side (PathEvaluation::min_edge_margin); -1 when a point is behind a camera.
double narrowest_edge_margin(std::span<const Camera> cameras, const std::vector<Eigen::Vector3d>& points, double aspect);

/// The JSON document of `meshtour evaluate --json`: {"modes": {"<mode>": {"feature_coverage": ...,
/// ..., "objective": ..., "frame_scores": [...], "preference": {"score": ..., "projected_area": ...,
/// "visible_ratio": ...}, "frame_preferences": [...], "definitions": {"<key>": {...}, ...}}, ...}}
/// in the order given; the keys of the definitions come from `options`.
std::string evaluation_json(const std::vector<std::pair<std::string, PathEvaluation>>& modes, const CoverageOptions& options);

}  // namespace meshtour
