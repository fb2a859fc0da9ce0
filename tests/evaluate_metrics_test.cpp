// The evaluation's metrics on cases with known answers: a cube seen by its six axis cameras, the
// seen-well cap of a sphere, motion of circular orbits, framing, feature quantiles and regions,
// and the JSON shape `meshtour evaluate --json` promises.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>

#include "core/error.h"
#include "evaluate/evaluate.h"
#include "pathgen/features.h"
#include "visibility/visibility.h"
#include "test_meshes.h"

namespace {

using namespace meshtour;
constexpr double kPi = std::numbers::pi;

TriangleMesh cube() {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i) m.positions.emplace_back(i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? 1.0 : -1.0);
  // Two outward triangles per side: -x, +x, -y, +y, -z, +z.
  m.triangles = {{0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}, {0, 1, 5}, {0, 5, 4},
                 {2, 6, 7}, {2, 7, 3}, {0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}};
  return m;
}

std::vector<Camera> axis_cameras(double distance) {
  std::vector<Camera> cameras;
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : {-1.0, 1.0}) {
      Eigen::Vector3d eye = Eigen::Vector3d::Zero();
      eye[axis] = sign * distance;
      cameras.push_back(Camera{eye, Eigen::Vector3d::Zero(), axis == 1 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitY(), 40.0});
    }
  return cameras;
}

EvaluationOptions given_features(std::vector<std::uint8_t> features) {
  EvaluationOptions o;
  o.coverage.samples = 6 * 4096;
  o.coverage.face_features = std::move(features);
  return o;
}

TEST(EvaluateMetrics, CubeSeenByItsSixAxisCamerasIsFullyCovered) {
  const TriangleMesh mesh = cube();
  std::vector<std::uint8_t> features(12, 0);
  features[2] = features[3] = 1;  // the +x side: one region of two triangles
  const PathEvaluator evaluator(mesh, given_features(features));
  EXPECT_EQ(evaluator.coverage().region_count(FeatureMeasure::patch_density), 1);
  const std::vector<Camera> cameras = axis_cameras(6.0);
  const PathEvaluation e = evaluator.evaluate(cameras, 1.0);
  EXPECT_DOUBLE_EQ(e.surface_coverage, 1.0);
  EXPECT_DOUBLE_EQ(e.feature_coverage, 1.0);
  // Each side faces exactly one camera; the others see it edge-on (90 degrees, not seen well).
  EXPECT_EQ(e.feature_min_frames, 1);
  EXPECT_DOUBLE_EQ(e.feature_median_frames, 1.0);
  EXPECT_EQ(e.frames_out_of_frame, 0);
  // Every definition agrees here (given features, both angles see a side head-on).
  for (const DefinitionFigures& d : e.by_definition) EXPECT_DOUBLE_EQ(d.feature_coverage, 1.0);
  // One camera alone sees exactly one side: a sixth of the samples, all on faces 2 and 3.
  const ViewCoverage one = evaluator.coverage().coverage(View{cameras[1], 1.0});
  EXPECT_NEAR(static_cast<double>(count_bits(one.seen[0])), 4096.0, 1.0);
  const auto& samples = evaluator.coverage().samples();
  for (std::size_t i = 0; i < samples.size(); ++i)
    if (one.seen[0][i / 64] >> (i % 64) & 1u) {
      ASSERT_TRUE(samples.faces[i] == 2 || samples.faces[i] == 3);
    }
  // Five of the six cameras leave the +x side unseen: coverage 5/6.
  const std::vector<Camera> five = {cameras[0], cameras[2], cameras[3], cameras[4], cameras[5]};
  const PathEvaluation partial = evaluator.evaluate(five, 1.0);
  EXPECT_NEAR(partial.surface_coverage, 5.0 / 6.0, 1e-4);
  EXPECT_DOUBLE_EQ(partial.feature_coverage, 0.0);
  EXPECT_EQ(partial.feature_min_frames, 0);
  // Frame scores: the one camera that sees the feature side scores highest.
  ASSERT_EQ(e.frame_scores.size(), 6u);
  EXPECT_EQ(std::max_element(e.frame_scores.begin(), e.frame_scores.end()) - e.frame_scores.begin(), 1);
}

TEST(EvaluateMetrics, SphereSeenWellCapMatchesTheAnalyticAngle) {
  // A unit sphere seen from distance D: the seen-well cap has a closed form (test_meshes.h).
  const TriangleMesh mesh = test_meshes::icosphere(5);
  const double D = 4.0;
  auto cap = [&](double angle_deg) { return test_meshes::sphere_seen_well_share(D, angle_deg); };
  EvaluationOptions options = given_features(std::vector<std::uint8_t>(mesh.triangles.size(), 1));
  options.coverage.samples = 1u << 16;
  const PathEvaluator evaluator(mesh, options);
  const Camera camera{Eigen::Vector3d(0, 0, D), Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY(), 40.0};
  const PathEvaluation e = evaluator.evaluate(std::vector<Camera>{camera}, 1.0);
  EXPECT_NEAR(e.surface_coverage, cap(75.0), 0.005) << "analytic cap " << cap(75.0);
  EXPECT_DOUBLE_EQ(e.surface_coverage, e.feature_coverage);
  EXPECT_NEAR(e.by_definition[2].surface_coverage, cap(60.0), 0.005);  // the stricter angle
  // A wider seen-well angle shows more, and the far side is never seen.
  options.coverage.seen_angle_deg[0] = 89.0;
  const PathEvaluator wide(mesh, options);
  const double wide_coverage = wide.evaluate(std::vector<Camera>{camera}, 1.0).surface_coverage;
  EXPECT_GT(wide_coverage, e.surface_coverage + 0.03);
  EXPECT_LT(wide_coverage, 0.5 * (1.0 - 1.0 / D) + 0.005);  // the horizon cap: cos θ = 1/D
}

TEST(EvaluateMetrics, CircularOrbitHasConstantSpeedAndNoAcceleration) {
  constexpr int kFrames = 90;
  std::vector<Camera> cameras;
  for (int k = 0; k < kFrames; ++k) {
    const double a = 2.0 * kPi * k / kFrames;
    cameras.push_back(Camera{Eigen::Vector3d(5 * std::sin(a), 0, 5 * std::cos(a)), Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY(), 30});
  }
  PathEvaluation e;
  measure_motion(cameras, Eigen::Vector3d::Zero(), e);
  EXPECT_NEAR(e.camera_max_angular_speed, 2.0 * kPi / kFrames, 1e-12);
  EXPECT_NEAR(e.view_max_angular_speed, 2.0 * kPi / kFrames, 1e-12);
  EXPECT_LT(e.camera_max_angular_acceleration, 1e-12);
  EXPECT_LT(e.view_max_angular_acceleration, 1e-12);

  // A jump: one frame moved by 0.1 rad up gives that speed and about twice that acceleration.
  cameras[10].eye = 5.0 * Eigen::Vector3d(std::sin(2 * kPi * 10 / kFrames) * std::cos(0.1), std::sin(0.1),
                                          std::cos(2 * kPi * 10 / kFrames) * std::cos(0.1));
  measure_motion(cameras, Eigen::Vector3d::Zero(), e);
  EXPECT_GT(e.camera_max_angular_speed, 0.1);
  EXPECT_GT(e.camera_max_angular_acceleration, 0.19);
}

TEST(EvaluateMetrics, OutOfFrameCountsFramesThatCutTheModel) {
  const TriangleMesh mesh = cube();
  std::vector<Camera> cameras = axis_cameras(6.0);
  EXPECT_EQ(count_out_of_frame(cameras, mesh.positions, 1.0), 0);
  cameras[0].vertical_fov_deg = 10.0;  // too narrow: the cube's corners leave the image
  cameras[3].target = 2.0 * cameras[3].eye;  // looking away from the model
  EXPECT_EQ(count_out_of_frame(cameras, mesh.positions, 1.0), 2);
  // A wide image keeps the sides in that a square one cuts off.
  const Camera close{Eigen::Vector3d(0, 0, 3.2), Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY(), 70.0};
  const std::vector<Camera> one{close};
  EXPECT_EQ(count_out_of_frame(one, mesh.positions, 1.0), 0);
  EXPECT_EQ(count_out_of_frame(one, mesh.positions, 0.5), 1);
}

TEST(EvaluateMetrics, FeatureFacesAreAtOrAboveTheAreaWeightedQuantile) {
  // Weights 1..4, areas 1, 1, 1, 5: 75 % of the area (6 of 8) is reached at weight 4, so only the
  // big face is a feature; with equal areas the 75 % quantile is 3 (weights 3 and 4 are features).
  EXPECT_DOUBLE_EQ(area_weighted_quantile({1, 2, 3, 4}, {1, 1, 1, 5}, 0.75), 4.0);
  EXPECT_DOUBLE_EQ(area_weighted_quantile({1, 2, 3, 4}, {1, 1, 1, 1}, 0.75), 3.0);
  EXPECT_EQ(feature_faces({4, 1, 3, 2}, {1, 1, 1, 1}, 0.75), (std::vector<std::uint8_t>{1, 0, 1, 0}));
  // Ties: all faces with the threshold weight are features.
  EXPECT_EQ(feature_faces({2, 2, 2, 1}, {1, 1, 1, 1}, 0.75), (std::vector<std::uint8_t>{1, 1, 1, 0}));
  EXPECT_THROW(area_weighted_quantile({1}, {1, 2}, 0.5), InputError);
}

TEST(EvaluateMetrics, ResultsDoNotDependOnTheThreadCount) {
  const TriangleMesh mesh = test_meshes::bumpy_sphere(3);
  EvaluationOptions options;
  options.coverage.samples = 1u << 15;
  const PathEvaluator evaluator(mesh, options);  // computed features: patch density and saliency
  std::vector<Camera> cameras;
  for (int k = 0; k < 12; ++k)
    cameras.push_back(Camera{Eigen::Vector3d(4 * std::cos(k * 0.5), 1.0, 4 * std::sin(k * 0.5)), Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY(), 35});
  PathEvaluation one;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = evaluator.evaluate(cameras, 16.0 / 9.0);
  }
  const PathEvaluation all = evaluator.evaluate(cameras, 16.0 / 9.0);
  EXPECT_EQ(one.surface_coverage, all.surface_coverage);
  EXPECT_EQ(one.feature_coverage, all.feature_coverage);
  EXPECT_EQ(one.feature_median_frames, all.feature_median_frames);
  EXPECT_EQ(one.frame_scores, all.frame_scores);
  for (int d = 0; d < kFeatureDefinitions; ++d) EXPECT_EQ(one.by_definition[d].feature_coverage, all.by_definition[d].feature_coverage);
  EXPECT_GT(all.surface_coverage, 0.5);
  EXPECT_LT(all.surface_coverage, 1.0);
}

TEST(EvaluateMetrics, JsonHasExactlyTheDocumentedShape) {
  PathEvaluation a;
  a.feature_coverage = 0.5;
  a.surface_coverage = 0.75;
  a.feature_min_frames = 3;
  a.feature_median_frames = 7.5;
  a.camera_max_angular_speed = 0.05;
  a.view_max_angular_speed = 0.06;
  a.view_max_angular_acceleration = 0.001;
  a.frames_out_of_frame = 2;
  a.by_definition[3].feature_coverage = 0.25;
  a.objective = 0.9;
  a.frame_scores = {0.5, 0.25};
  a.preference.score = 0.75;
  a.preference.projected_area = 0.5;
  a.preference.visible_ratio = 1.0;
  a.frame_preferences = {0.75, 0.5};
  const nlohmann::json doc = nlohmann::json::parse(evaluation_json({{"turntable", a}, {"paper", PathEvaluation{}}}, CoverageOptions{}));
  ASSERT_EQ(doc.size(), 1u);
  ASSERT_TRUE(doc.at("modes").is_object());
  ASSERT_EQ(doc["modes"].size(), 2u);
  const std::vector<std::string> keys = {"feature_coverage", "surface_coverage", "feature_min_frames",
                                         "feature_median_frames", "camera_max_angular_speed", "view_max_angular_speed",
                                         "view_max_angular_acceleration", "frames_out_of_frame", "min_edge_margin",
                                         "frames_below_floor"};
  for (const char* mode : {"turntable", "paper"}) {
    const auto& m = doc["modes"].at(mode);
    EXPECT_EQ(m.size(), keys.size() + 5);  // + objective, frame_scores, preference, frame_preferences, definitions
    for (const auto& k : keys) EXPECT_TRUE(m.contains(k) && m[k].is_number()) << mode << " " << k;
    EXPECT_TRUE(m.at("objective").is_number());
    EXPECT_TRUE(m.at("frame_scores").is_array());
    EXPECT_TRUE(m.at("frame_preferences").is_array());
    for (const char* k : {"score", "projected_area", "visible_ratio"}) EXPECT_TRUE(m.at("preference").at(k).is_number()) << k;
    const auto& d = m.at("definitions");
    ASSERT_EQ(d.size(), 8u);
    for (const char* key : {"patch-density-75deg", "saliency-75deg", "patch-density-60deg", "saliency-60deg", "patch-density-45deg",
                            "saliency-45deg", "patch-density-30deg", "saliency-30deg"}) {
      ASSERT_TRUE(d.contains(key)) << key;
      for (const char* k : {"feature_coverage", "surface_coverage", "feature_min_frames", "feature_median_frames"})
        EXPECT_TRUE(d[key].contains(k) && d[key][k].is_number()) << key << " " << k;
    }
  }
  EXPECT_EQ(doc["modes"]["turntable"]["definitions"]["saliency-60deg"]["feature_coverage"].get<double>(), 0.25);
  EXPECT_EQ(doc["modes"]["turntable"]["frame_scores"][1].get<double>(), 0.25);
  EXPECT_EQ(doc["modes"]["turntable"]["preference"]["score"].get<double>(), 0.75);
  EXPECT_EQ(doc["modes"]["turntable"]["preference"]["visible_ratio"].get<double>(), 1.0);
  EXPECT_EQ(doc["modes"]["turntable"]["frame_preferences"][1].get<double>(), 0.5);
  const auto& t = doc["modes"]["turntable"];
  EXPECT_EQ(t["feature_coverage"].get<double>(), 0.5);
  EXPECT_EQ(t["feature_median_frames"].get<double>(), 7.5);
  EXPECT_TRUE(t["feature_min_frames"].is_number_integer());
  EXPECT_TRUE(t["frames_out_of_frame"].is_number_integer());
  EXPECT_EQ(t["frames_out_of_frame"].get<int>(), 2);
}

}  // namespace
