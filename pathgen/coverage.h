#pragma once
// What views show of a mesh's features, measured so that neither the tessellation nor one
// particular notion of "feature" decides the answer. The one coverage module: the feature orbit's
// search scores its candidate views with it, `meshtour evaluate` scores whole tours with it, and
// the tour records each frame's score with it.
//
//  - Where: a fixed number of area-weighted samples of the surface (visibility/), so a shape and
//    any finer tessellation of it are measured alike.
//  - What counts as a feature: each sample takes its value from the proxy vertices within one
//    cell of it (a proxy of the surface at a fixed resolution, made of the surface and not of the
//    input's vertices, so a finer tessellation gives the same proxy: mesh/vertex_clustering.h; a
//    smooth kernel of the distance, so not the face it lies on decides), under two independent
//    measures: the paper's patch density w(f) (docs/METHOD.md §8) and mesh saliency (Lee, Varshney
//    & Jacobs 2005, pathgen/saliency.h). The top `feature_quantile` of the samples by value are the features.
//  - Seen well: in the frame, unoccluded, and facing the camera within an angle; four angles,
//    the evaluation's traditional 75° and stricter 60°, 45° and 30° (a path tuned at the lenient
//    angles alone lost at the strict ones: pathgen/feature_orbit.cpp).
// A definition is one measure at one angle; the objective of a set of views is the mean over the
// eight definitions of (features seen + surface_weight × other surface seen) / features.
//
// Beside coverage, the module judges single views as people would pick them (view preference,
// ViewPreferenceModel below): with --first-view preferred the first frame and the poster are the
// preferred view, and `evaluate` reports its score next to the coverage scores. It reads the same samples and rays.
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/camera.h"
#include "mesh/mesh.h"
#include "mesh/vertex_clustering.h"
#include "pathgen/surface.h"
#include "visibility/visibility.h"

namespace meshtour {

enum class FeatureMeasure { patch_density, saliency };
constexpr int kFeatureMeasures = 2;
constexpr int kSeenAngles = 4;
constexpr int kFeatureDefinitions = kFeatureMeasures * kSeenAngles;

/// One way of judging what a view shows: which samples are features, and how squarely they must be seen.
struct FeatureDefinition {
  FeatureMeasure measure = FeatureMeasure::patch_density;
  int angle = 0;  ///< index into CoverageOptions::seen_angle_deg
};
/// The definitions, default (today's: patch density at the first angle, 75°) first.
const std::array<FeatureDefinition, kFeatureDefinitions>& feature_definitions();

struct CoverageOptions {
  SurfaceOptions surface;             ///< how w(f) is computed on the proxy
  std::size_t samples = 1u << 16;     ///< surface samples (fixed: independent of the face count)
  /// Resolution of the proxy the features are measured on (cells of the clustering grid, for the
  /// surface's area). Coarser than the meshes it should not tell apart: a scan whose edges are
  /// longer than a cell is measured on itself, not on a proxy.
  std::size_t proxy_cells = 8000;
  double feature_quantile = 0.75;     ///< features: samples at or above this quantile of a measure
  double surface_weight = 0.3;        ///< worth of non-feature area relative to feature area
  /// Seen well below these angles between the normal and the direction to the eye: the
  /// evaluation's traditional angle and three stricter ones. The feature orbit's choice must hold
  /// under every one (pathgen/feature_orbit.cpp): tuned at 75 and 60 degrees alone it chose paths
  /// that the paper's path beat by up to 8.5 points at 45 and 30.
  std::array<double, kSeenAngles> seen_angle_deg{75.0, 60.0, 45.0, 30.0};
  /// Test hook: when not empty (one flag per face), both measures take these feature faces
  /// instead of computing w(f) and saliency.
  std::vector<std::uint8_t> face_features;
  /// The mesh's ray-tracing scene when the caller already has one (a tour shares it with the
  /// tracer: one BVH per job); built for the coverage model when null.
  std::shared_ptr<const RayScene> ray_scene;

  /// \throw InputError naming the value out of range.
  void validate() const;
  /// "patch-density-75deg", "saliency-60deg", ...: the key under which evaluate --json reports `d`.
  std::string key(const FeatureDefinition& d) const;
};

/// A published model of the views people prefer, with its published weights (none fitted here):
/// Gao, Wang & Han, "Efficient view selection by measuring proxy information", Computer
/// Animation and Virtual Worlds 27(3-4):351-357, 2016, as the Euclid library implements it
/// (unclejimbo/Euclid, include/Euclid/ViewSelection/ProxyView.h, whose default weight is 0.5).
/// The model's oriented bounding box (its principal axes) stands for it: along each of the six
/// directions ±a_i the model shows a projected area A_i and a visible ratio R_i (the share of its
/// surface facing that way within 60°), each divided by its largest value over the six, and a view
/// from direction v (from the model's centre to the eye) scores
///   sum over i of (area_weight · A_i / A_max + (1 − area_weight) · R_i / R_max) · max(0, v · a_i),
/// so a view that sees two good sides at once (a three-quarter view) can outscore either side.
/// Both attributes are among those of Secord et al., "Perceptual models of viewpoint preference"
/// (ACM TOG 30(5), 2011), whose own table of weights could not be obtained here
/// (docs/EVALUATION.md). Measured here as this module measures what a view sees, so that neither
/// the tessellation nor the thread count changes it: the axes are those of the area-weighted
/// surface samples (not of the vertices), A_i is counted by parallel rays through the shared
/// RayScene, R_i on the samples with occlusion rays (Euclid counts faces by their normals alone),
/// on the side of the surface the eye sees from outside (CoverageModel::outside_side). No rule per
/// kind of object; no elevation term (the model has none: the orbit's band decides the height).
struct ViewPreferenceModel {
  static constexpr double area_weight = 0.5;  ///< Gao et al.'s weight of the projected area term
  static constexpr double seen_angle_deg = 60.0;  ///< "visible": facing the direction within this angle
  /// Cells across the ray grid that measures a projected area (Euclid renders 256² pixels).
  static constexpr int area_grid = 256;
};

/// What one view sees: a bitset over the samples for each seen-well angle.
struct ViewCoverage {
  std::array<std::vector<std::uint64_t>, kSeenAngles> seen;
  /// Every stride-th sample was tested (1 = all); scores count only those samples.
  std::size_t stride = 1;
};

/// How much people would prefer one view (ViewPreferenceModel): its score, its two terms (the
/// sums over the six directions of A_i / A_max and of R_i / R_max, weighted as the score weighs
/// them: 1 for a view straight along the best direction), and the score measured on each half of
/// the samples and of the area grid alone, whose difference measures its noise.
struct ViewPreference {
  double score = 0.0;
  double projected_area = 0.0;
  double visible_ratio = 0.0;
  std::array<double, 2> half_scores{};
};

/// Shares seen by a set of views under each definition (same order as feature_definitions()).
struct CoverageScores {
  std::array<double, kFeatureDefinitions> feature_share{};  ///< feature samples seen / features
  std::array<double, kSeenAngles> surface_share{};                     ///< samples seen / all samples
  /// Per definition: (features seen + surface_weight × others seen) / features.
  std::array<double, kFeatureDefinitions> value{};
  double objective = 0.0;  ///< mean of `value` over the definitions: what the path search maximizes
};

/// Samples, features and the visibility scene of one mesh. Building it is the expensive part
/// (proxy, w(f) and saliency on the proxy, an Embree scene of the full mesh); views are cheap.
class CoverageModel {
public:
  /// \throw InputError for a mesh without area or bad options, Interrupted on Ctrl-C / SIGTERM.
  CoverageModel(const TriangleMesh& mesh, const CoverageOptions& options);
  ~CoverageModel();
  CoverageModel(const CoverageModel&) = delete;
  CoverageModel& operator=(const CoverageModel&) = delete;

  /// What `view` sees. Thread-safe. With `stride` > 1 (a power of two up to 64) only every
  /// stride-th sample is tested: an estimate at 1/stride of the cost, for searches that compare
  /// many views (the scores of such views are shares of that subset, on the same scale).
  ViewCoverage coverage(const View& view, std::size_t stride = 1) const;
  /// Scores of the union of `views` (all of one stride). \throw InputError for mixed strides.
  CoverageScores scores(std::span<const ViewCoverage* const> views) const;
  CoverageScores scores(const ViewCoverage& view) const;
  /// The same scores on each half of the tested samples alone (the even-numbered ones, then the
  /// odd-numbered ones): two independent estimates, whose difference measures how much of a
  /// score is where the samples happen to fall (the path search's tie rule).
  std::array<CoverageScores, 2> half_scores(std::span<const ViewCoverage* const> views) const;
  /// How much people would prefer `view` (ViewPreferenceModel): a function of the direction from
  /// its target to its eye. Thread-safe; the same bits on any thread count.
  ViewPreference preference(const View& view) const;
  /// The six directions ±a_i of the view preference's proxy (unit, from the model's centre).
  std::array<Eigen::Vector3d, 6> preference_directions() const;
  /// The side of the surface taken as its outside for the view preference's visible ratio (0: the
  /// side the normals point to): the side the six directions' views see more of, as scans are not
  /// reliably oriented and a shell (a face scan, a mask) seen from behind shows its inside.
  int outside_side() const;

  const SurfaceSamples& samples() const;
  /// 1 for each feature sample under `measure`.
  const std::vector<std::uint8_t>& features(FeatureMeasure measure) const;
  /// Connected feature regions under `measure` (connected through the proxy): region of each
  /// sample, -1 for non-features.
  const std::vector<int>& sample_region(FeatureMeasure measure) const;
  int region_count(FeatureMeasure measure) const;
  const CoverageOptions& options() const;
  /// Seconds spent on each part of the construction: {"proxy", s}, {"patch density", s}, ...
  const std::vector<std::pair<std::string, double>>& stage_seconds() const;

private:
  // The scores counting only the samples whose bit is set in `counted` (a pattern repeated in
  // every 64-sample word).
  CoverageScores scores_on(std::span<const ViewCoverage* const> views, std::uint64_t counted) const;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The proxy the features are measured on (what CoverageModel builds; for diagnostics and tests).
ClusteredMesh coverage_proxy(const TriangleMesh& mesh, const CoverageOptions& options);

/// Number of bits set in `bits` (a ViewCoverage bitset).
std::size_t count_bits(const std::vector<std::uint64_t>& bits);

}  // namespace meshtour
