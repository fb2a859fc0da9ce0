#pragma once
// What a camera tour shows: item buffers cast with Embree for every frame give the share of the
// surface, and of its feature faces, that the tour shows well; the camera's motion gives its
// smoothness. Used by `meshtour evaluate` to compare path modes with numbers instead of by eye.
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "mesh/mesh.h"
#include "tracer/tracer.h"

namespace meshtour {

struct EvaluationOptions {
  /// Pixels on the long side of each frame's item buffer (the short side follows the aspect).
  int long_side_pixels = 256;
  /// A visible face is seen well when the angle between its normal and the direction to the
  /// camera is below this (either side of the face counts: orientation is not trusted).
  double seen_angle_deg = 75.0;
  /// A feature region counts as seen well in a frame when at least this share of its area is.
  double region_seen_share = 0.25;

  /// \throw InputError naming the value that is out of range.
  void validate() const;
};

/// The numbers of one tour. Coverages are fractions of area; angles are radians per frame
/// (speed) and per frame² (acceleration), measured around the loop including its join.
struct PathEvaluation {
  int frames = 0;
  double surface_coverage = 0.0;  ///< area seen well in at least one frame / total area
  double feature_coverage = 0.0;  ///< the same over the feature faces
  int feature_min_frames = 0;     ///< fewest frames any feature region is seen well in
  double feature_median_frames = 0.0;  ///< median over the feature regions
  double camera_max_angular_speed = 0.0;         ///< of the eye's direction from the model centre
  /// Change of the angular velocity of that direction's frame (up = the camera's up), see
  /// pathgen/motion.h: a constant-rate orbit has none, a jerk or a sudden climb has.
  double camera_max_angular_acceleration = 0.0;
  double view_max_angular_speed = 0.0;           ///< of the view direction (target - eye)
  double view_max_angular_acceleration = 0.0;
  int frames_out_of_frame = 0;  ///< frames where a vertex is behind the camera or outside the image
};

/// Edge-connected components of the feature faces: region id per face (-1 for other faces).
struct FeatureRegions {
  std::vector<int> face_region;
  int count = 0;
};
FeatureRegions feature_regions(const TriangleMesh& mesh, const std::vector<std::uint8_t>& feature_face);

/// Evaluates camera sets on one mesh. Builds the Embree scene once; evaluate() may be called
/// for any number of tours. Results do not depend on the thread count.
class PathEvaluator {
public:
  /// `feature_face`: 1 for each feature face of `mesh` (see pathgen/features.h).
  /// \throw InputError for an empty mesh, sizes that do not match or bad options,
  ///        RuntimeFailure if Embree fails.
  PathEvaluator(const TriangleMesh& mesh, std::vector<std::uint8_t> feature_face, const EvaluationOptions& options = {});
  ~PathEvaluator();
  PathEvaluator(const PathEvaluator&) = delete;
  PathEvaluator& operator=(const PathEvaluator&) = delete;

  /// The numbers for the loop of `cameras` (frame k is followed by frame k+1, the last by the
  /// first) rendered at `aspect` = width / height.
  PathEvaluation evaluate(std::span<const Camera> cameras, double aspect) const;

  /// 1 for each face seen well by `camera` (visible in its item buffer and within the angle).
  std::vector<std::uint8_t> seen_well(const Camera& camera, double aspect) const;

  const std::vector<std::uint8_t>& feature_face() const;
  const FeatureRegions& regions() const;

  struct Impl;

private:
  std::unique_ptr<Impl> impl_;
};

/// Smoothness part alone (no mesh needed): fills the four angular fields of `out` for the loop
/// of `cameras` around `center`.
void measure_motion(std::span<const Camera> cameras, const Eigen::Vector3d& center, PathEvaluation& out);

/// Number of cameras that do not see every one of `points` inside their frame (no margin).
int count_out_of_frame(std::span<const Camera> cameras, const std::vector<Eigen::Vector3d>& points, double aspect);

/// The JSON document of `meshtour evaluate --json`:
/// {"modes": {"<mode>": {"feature_coverage": ..., ...}, ...}} in the order given.
std::string evaluation_json(const std::vector<std::pair<std::string, PathEvaluation>>& modes);

}  // namespace meshtour
