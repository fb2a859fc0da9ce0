// The feature orbit: it rises to show features on top and dips to show features underneath,
// stays within its smoothness limits, loops seamlessly and keeps the model framed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>

#include "pathgen/feature_orbit.h"
#include "test_meshes.h"

namespace {

using namespace meshtour;
constexpr double kDegree = std::numbers::pi / 180.0;

// A sphere whose features are the faces within `cap_deg` of the +Y (top) or -Y pole.
std::vector<std::uint8_t> polar_features(const TriangleMesh& mesh, double sign, double cap_deg) {
  std::vector<std::uint8_t> features(mesh.triangles.size(), 0);
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const auto& t = mesh.triangles[f];
    const Eigen::Vector3d c = (mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]).normalized();
    features[f] = sign * c.y() > std::cos(cap_deg * kDegree);
  }
  return features;
}

FeatureOrbitOptions fast_orbit_options(std::vector<std::uint8_t> features = {}) {
  FeatureOrbitOptions o;
  o.coverage.surface_weight = 0.0;  // the polar caps are 1 % of the area: judge by them alone
  o.coverage.samples = 1u << 15;
  o.coverage.face_features = std::move(features);
  o.azimuth_samples = 16;
  o.phases = 8;
  return o;
}

TEST(FeatureOrbit, RisesToShowFeaturesOnTheTop) {
  const TriangleMesh mesh = test_meshes::icosphere(4);
  // Within 12° of the pole: a level camera sees them at 78° or more, never "well" (75°).
  const FeatureOrbitOptions options = fast_orbit_options(polar_features(mesh, 1.0, 12.0));
  const FeatureOrbitResult r = compute_feature_orbit(mesh, options);
  EXPECT_GT(r.geometry.elevation.base / kDegree, 10.0);
  EXPECT_GT(r.feature_share_seen, 0.95);
  EXPECT_LE(r.angular_speed, options.max_angular_speed);
  EXPECT_LE(r.angular_acceleration, options.max_angular_acceleration);
}

TEST(FeatureOrbit, StaysInItsBandAboveTheFloorEvenForFeaturesUnderneath) {
  // Features only on the underside: the default band (10 to 30 degrees above the centre) still
  // holds, so no eye is below the floor the model stands on (the plane through its lowest point).
  const TriangleMesh mesh = test_meshes::icosphere(4);
  const FeatureOrbitOptions options = fast_orbit_options(polar_features(mesh, -1.0, 12.0));
  const FeatureOrbitResult r = compute_feature_orbit(mesh, options);
  const FeatureOrbitPath path = r.camera_path();
  const double floor = mesh.bounds().lo.y();
  for (int k = 0; k < 360; ++k) {
    const double e = r.geometry.elevation(k / 360.0) / kDegree;
    EXPECT_GE(e, options.lowest_deg - 1e-9) << k;
    EXPECT_LE(e, options.highest_deg + 1e-9) << k;
    EXPECT_GT(path.pose(k / 360.0).eye.y(), floor) << k;
  }
}

TEST(FeatureOrbit, DipsToShowFeaturesUnderneathWhenItsBandAllows) {
  // With a band reaching below the model's equator (a look without a floor), the search goes
  // there for the features underneath.
  const TriangleMesh mesh = test_meshes::icosphere(4);
  FeatureOrbitOptions options = fast_orbit_options(polar_features(mesh, -1.0, 12.0));
  options.lowest_deg = -37.5;
  options.highest_deg = 75.0;
  options.base_min_deg = -15.0;
  options.base_max_deg = 60.0;
  options.base_step_deg = 5.0;
  options.swing_max_deg = 45.0;
  options.swing_step_deg = 5.0;
  options.elevation_grid_deg = 7.5;
  const FeatureOrbitResult r = compute_feature_orbit(mesh, options);
  double lowest = 1e9;
  for (int k = 0; k < 360; ++k) lowest = std::min(lowest, r.geometry.elevation(k / 360.0));
  EXPECT_LT(lowest / kDegree, -10.0);
  EXPECT_GT(r.feature_share_seen, 0.25);  // a level orbit sees none of it
}

TEST(FeatureOrbit, LoopsSeamlesslyLooksAtTheCentreAndKeepsItsLimits) {
  TriangleMesh mesh = test_meshes::bumpy_sphere(3);
  for (auto& p : mesh.positions) p = Eigen::Vector3d(3.0 * p.x(), p.y(), p.z()) + Eigen::Vector3d(1, 2, 3);  // slender, off-centre
  std::vector<std::uint8_t> features(mesh.triangles.size());
  for (std::size_t f = 0; f < features.size(); ++f) features[f] = mesh.positions[mesh.triangles[f][0]].z() > 3.4;
  FeatureOrbitOptions options = fast_orbit_options(features);
  options.coverage.surface_weight = 0.3;
  const FeatureOrbitResult r = compute_feature_orbit(mesh, options);
  const FeatureOrbitPath path = r.camera_path();
  const CameraPose a = path.pose(0.0), b = path.pose(1.0), c = path.pose(1e-6);
  EXPECT_LT((a.eye - b.eye).norm(), 1e-9);
  EXPECT_LT((a.eye - c.eye).norm(), 1e-3);
  EXPECT_LT((a.target - mesh.bounds().center()).norm(), 1e-12);
  const auto [speed, acceleration] = loop_angular_extremes([&](double t) -> Eigen::Vector3d { return path.pose(t).eye - path.pose(t).target; }, Eigen::Vector3d::UnitY(), 720);
  EXPECT_LE(speed, options.max_angular_speed * 1.001);
  EXPECT_LE(acceleration, options.max_angular_acceleration * 1.01);
  // The dolly: every pose keeps every vertex inside the planned lens (up to the smooth envelope's sampling).
  Lens lens;
  lens.vertical_fov_deg = options.vertical_fov_deg;
  lens.aspect = options.aspect;
  for (int k = 0; k < 48; ++k) EXPECT_LT(fit_pullback(mesh.positions, path.pose(k / 48.0), lens), 0.02) << k;
  // Closer from the slender side than from the end: the distance follows the silhouette.
  double nearest = 1e9, farthest = 0.0;
  for (int k = 0; k < 72; ++k) {
    const double d = r.geometry.distance_at(k / 72.0);
    nearest = std::min(nearest, d);
    farthest = std::max(farthest, d);
  }
  EXPECT_GT(farthest, 1.1 * nearest);
}

TEST(FeatureOrbit, EveryFrameCarriesItsCoverageScore) {
  // Features on one side only (+x): the frames that face them score far above the far side's.
  // (Where the loop starts is the view preference's choice: pathgen_view_preference_test.cpp.)
  TriangleMesh mesh = test_meshes::bumpy_sphere(3);
  std::vector<std::uint8_t> features(mesh.triangles.size());
  for (std::size_t f = 0; f < features.size(); ++f) features[f] = mesh.positions[mesh.triangles[f][0]].x() > 0.5;
  FeatureOrbitOptions options = fast_orbit_options(features);
  options.coverage.surface_weight = 0.3;
  options.frames = 24;
  const FeatureOrbitResult r = compute_feature_orbit(mesh, options);
  ASSERT_EQ(r.frame_scores.size(), 24u);
  ASSERT_EQ(r.frame_preferences.size(), 24u);
  EXPECT_DOUBLE_EQ(r.frame_scores[0], r.start_score);
  EXPECT_GE(r.start_tie_band, options.tie_tolerance);
  const UniformTurnPath path(std::make_unique<FeatureOrbitPath>(r.geometry));
  double facing = -1.0, away = 2.0;
  for (int k = 0; k < 24; ++k) {
    const CameraPose pose = frame_pose(path, k, 24);
    const double x = (pose.eye - pose.target).normalized().x();
    if (x > 0.9) facing = std::max(facing, r.frame_scores[k]);
    if (x < -0.9) away = std::min(away, r.frame_scores[k]);
  }
  EXPECT_GT(facing, away + 0.1) << "the frames facing the +x features do not score above the far side's";
}

TEST(FeatureOrbit, ItsLongLensSeesTheSurfaceMoreSquarelyThanAWideOne) {
  // Why the orbit plans for a 10-degree lens (FeatureOrbitOptions::vertical_fov_deg): from farther
  // away each view sees more of the surface within the seen-well angle. The same search planned
  // for 35 degrees must see less under every definition, clearly so at the strict angle.
  const TriangleMesh mesh = test_meshes::bumpy_sphere(3, 0.0, 11);
  std::vector<std::uint8_t> features(mesh.triangles.size());
  for (std::size_t f = 0; f < features.size(); ++f) features[f] = mesh.positions[mesh.triangles[f][0]].z() > 0.2;
  FeatureOrbitOptions long_lens = fast_orbit_options(features);
  long_lens.coverage.surface_weight = 0.3;
  FeatureOrbitOptions wide = long_lens;
  ASSERT_EQ(long_lens.vertical_fov_deg, 10.0);
  wide.vertical_fov_deg = 35.0;
  const FeatureOrbitResult a = compute_feature_orbit(mesh, long_lens), b = compute_feature_orbit(mesh, wide);
  for (int d = 0; d < kFeatureDefinitions; ++d) EXPECT_GE(a.scores.feature_share[d], b.scores.feature_share[d]) << "definition " << d;
  EXPECT_GT(a.scores.surface_share[1], b.scores.surface_share[1] + 0.02);  // the strict angle's whole surface
  EXPECT_GT(a.scores.objective, b.scores.objective);
  // The long lens's orbit is farther away: the distance that frames the model through it.
  EXPECT_GT(a.geometry.distance_at(0.0), 2.5 * b.geometry.distance_at(0.0));
}

TEST(FeatureOrbit, SameShapeFinerTessellationSameOrbit) {
  // The same shape split 1-to-4 twice (16 times the faces), with the same features (by position):
  // the search and the start must give the same orbit (elevation within 1 degree everywhere).
  const TriangleMesh coarse = test_meshes::bumpy_sphere(3, 0.0, 11);
  const TriangleMesh fine = test_meshes::split_at_midpoints(test_meshes::split_at_midpoints(coarse));
  auto features = [](const TriangleMesh& mesh) {
    std::vector<std::uint8_t> f(mesh.triangles.size());
    for (std::size_t i = 0; i < f.size(); ++i) {
      const auto& t = mesh.triangles[i];
      const Eigen::Vector3d c = (mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) / 3.0;
      f[i] = c.y() > 0.4 || c.x() < -0.6;
    }
    return f;
  };
  FeatureOrbitOptions oa = fast_orbit_options(features(coarse)), ob = fast_orbit_options(features(fine));
  oa.coverage.surface_weight = ob.coverage.surface_weight = 0.3;
  oa.frames = ob.frames = 12;
  const FeatureOrbitResult a = compute_feature_orbit(coarse, oa), b = compute_feature_orbit(fine, ob);
  const FeatureOrbitPath pa = a.camera_path(), pb = b.camera_path();
  for (int k = 0; k < 72; ++k) {
    const Eigen::Vector3d da = (pa.pose(k / 72.0).eye - pa.pose(k / 72.0).target).normalized();
    const Eigen::Vector3d db = (pb.pose(k / 72.0).eye - pb.pose(k / 72.0).target).normalized();
    EXPECT_NEAR(std::asin(da.y()) / kDegree, std::asin(db.y()) / kDegree, 1.0) << "at " << k * 5 << " degrees into the loop";
  }
  EXPECT_NEAR(a.scores.objective, b.scores.objective, 0.01 * a.scores.objective);
}


TEST(FeatureOrbit, SameShapeFinerTessellationSameOrbitFromComputedFeatures) {
  // As above, with the features the coverage module computes itself (patch density and saliency
  // on its proxy): the proxy is made of the surface, not of the input's vertices, so the split
  // shape has the same features (up to where its samples fall) and the same orbit.
  const TriangleMesh coarse = test_meshes::bumpy_sphere(4, 0.0, 11);
  const TriangleMesh fine = test_meshes::split_at_midpoints(test_meshes::split_at_midpoints(coarse));
  FeatureOrbitOptions options = fast_orbit_options();
  options.coverage.surface_weight = 0.3;
  options.coverage.proxy_cells = 2000;  // cells of about twice the coarse edges
  options.frames = 12;
  // On this small sphere (32k samples, evenly spread bumps) the leading curves lie within 0.3
  // points of each other: where the samples fall would decide between them (a 5 degree flip
  // under a fixed 0.2-point tolerance). The tie band, twice the noise measured on the two halves
  // of the samples, takes them as equals, and the fixed rule picks the same curve and start at
  // both levels: every frame within 1 degree of elevation and 2 of azimuth.
  const FeatureOrbitResult a = compute_feature_orbit(coarse, options), b = compute_feature_orbit(fine, options);
  // (Here the start is the rule's: two views along the curve score within the noise.)
  EXPECT_GT(a.curves_tied + a.starts_tied + b.curves_tied + b.starts_tied, 4) << "the rule decided no choice: the test no longer tests it";
  const FeatureOrbitPath pa = a.camera_path(), pb = b.camera_path();
  double worst = 0.0, worst_azimuth = 0.0;
  for (int k = 0; k < 72; ++k) {
    const Eigen::Vector3d da = (pa.pose(k / 72.0).eye - pa.pose(k / 72.0).target).normalized();
    const Eigen::Vector3d db = (pb.pose(k / 72.0).eye - pb.pose(k / 72.0).target).normalized();
    worst = std::max(worst, std::abs(std::asin(da.y()) - std::asin(db.y())) / kDegree);
    const double turn = std::abs(std::atan2(da.x() * db.z() - da.z() * db.x(), da.x() * db.x() + da.z() * db.z()));
    worst_azimuth = std::max(worst_azimuth, turn / kDegree);
  }
  EXPECT_LT(worst, 1.0) << "largest elevation difference, degrees";
  EXPECT_LT(worst_azimuth, 2.0) << "largest azimuth difference, degrees";
  EXPECT_NEAR(a.scores.objective, b.scores.objective, 0.002);
}

}  // namespace
