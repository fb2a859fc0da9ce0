// The view preference (pathgen/coverage.h, ViewPreferenceModel): its attributes measure what they
// say on shapes whose answer is known, it picks the front of an object that has one, whatever the
// surface's orientation, the feature orbit starts there, and the numbers do not depend on the
// thread count or the tessellation.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "pathgen/coverage.h"
#include "pathgen/feature_orbit.h"
#include "test_meshes.h"

namespace {

using namespace meshtour;
constexpr double kDegree = std::numbers::pi / 180.0;

// A bust-like shell with a clear front: the front half of a wide ellipsoid (shoulders 1.6 across,
// 1 high, 0.8 deep), open at the back as many bust and mask scans are, with a nose; its front
// faces azimuth `front_deg` about +y (0 = +Z, 90 = +X), away from the orbit's default start so the
// front tie rule alone cannot find it. Normals point outwards (or inwards with `inward`).
TriangleMesh bust(double front_deg, bool inward = false) {
  TriangleMesh m;
  constexpr int kRings = 48, kSegments = 64;
  for (int i = 0; i <= kRings; ++i)
    for (int j = 0; j <= kSegments; ++j) {
      const double theta = std::numbers::pi * i / kRings, phi = std::numbers::pi * (static_cast<double>(j) / kSegments - 0.5);
      Eigen::Vector3d p(1.6 * std::sin(theta) * std::sin(phi), std::cos(theta), 0.8 * std::sin(theta) * std::cos(phi));
      // The nose: a bump on the front, a little above the middle.
      const double d2 = (p - Eigen::Vector3d(0, 0.25, 0.8)).squaredNorm();
      p.z() += 0.25 * std::exp(-d2 / 0.02);
      m.positions.push_back(p);
    }
  const auto at = [](int i, int j) { return static_cast<std::uint32_t>(i * (kSegments + 1) + j); };
  for (int i = 0; i < kRings; ++i)
    for (int j = 0; j < kSegments; ++j) {
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  // Orient every face away from (or towards) the shell's centre.
  for (auto& t : m.triangles) {
    const Eigen::Vector3d a = m.positions[t[0]], b = m.positions[t[1]], c = m.positions[t[2]];
    const bool out = (b - a).cross(c - a).dot(a + b + c) > 0.0;
    if (out == inward) std::swap(t[1], t[2]);
  }
  const Eigen::Matrix3d turn = test_meshes::rotation(Eigen::Vector3d::UnitY(), front_deg * kDegree);
  for (auto& p : m.positions) p = turn * p;
  return m;
}

CoverageOptions quick_coverage() {
  CoverageOptions o;
  o.samples = 1u << 15;
  o.proxy_cells = 2000;
  return o;
}

FeatureOrbitOptions quick_orbit() {
  FeatureOrbitOptions o;
  o.coverage = quick_coverage();
  o.azimuth_samples = 16;
  o.phases = 8;
  o.frames = 24;
  return o;
}

View view_along(const Eigen::Vector3d& direction, double distance = 20.0) {
  return View{Camera{distance * direction.normalized(), Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY(), 10.0}, 1.0};
}

// Azimuth (degrees in [0, 360)) of the eye about the target, +y up: 0 = +Z, 90 = +X.
double azimuth_of(const CameraPose& pose) {
  const Eigen::Vector3d d = pose.eye - pose.target;
  const double a = std::atan2(d.x(), d.z()) / kDegree;
  return a < 0.0 ? a + 360.0 : a;
}

double azimuth_gap(double a, double b) {
  const double d = std::fmod(std::abs(a - b), 360.0);
  return std::min(d, 360.0 - d);
}

TEST(VisibilityProjectedArea, IsTheOutlinesAreaAlongAnyDirection) {
  // A unit sphere shows a disc of area pi from every side; a 2 x 1 x 0.5 box its three faces.
  const VisibilityScene sphere(test_meshes::icosphere(5));
  for (const Eigen::Vector3d& d : {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 2, -3), Eigen::Vector3d(-1, 0, 0)})
    EXPECT_NEAR(sphere.projected_area(d, 256).area, std::numbers::pi, 0.01 * std::numbers::pi) << d.transpose();
  TriangleMesh box;
  box.positions = {{-1, -0.5, -0.25}, {1, -0.5, -0.25}, {1, 0.5, -0.25}, {-1, 0.5, -0.25},
                   {-1, -0.5, 0.25},  {1, -0.5, 0.25},  {1, 0.5, 0.25},  {-1, 0.5, 0.25}};
  box.triangles = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                   {3, 6, 2}, {3, 7, 6}, {0, 4, 7}, {0, 7, 3}, {1, 2, 6}, {1, 6, 5}};
  const VisibilityScene scene(box);
  EXPECT_NEAR(scene.projected_area({0, 0, 1}, 256).area, 2.0, 0.02);
  EXPECT_NEAR(scene.projected_area({0, 1, 0}, 256).area, 1.0, 0.02);
  EXPECT_NEAR(scene.projected_area({1, 0, 0}, 256).area, 0.5, 0.01);
  // The two halves of the grid are two estimates of the same area.
  const ProjectedArea a = scene.projected_area({0, 0, 1}, 256);
  for (double h : a.halves) EXPECT_NEAR(h, a.area, 0.01);
  EXPECT_THROW(scene.projected_area(Eigen::Vector3d::Zero(), 64), InputError);
  EXPECT_THROW(scene.projected_area({0, 0, 1}, 1), InputError);
}

TEST(ViewPreference, PrefersTheFrontOfABustAndNeverItsOpenBack) {
  const CoverageModel model(bust(60.0), quick_coverage());
  // Around the bust at 15 degrees of elevation: the best view faces its front (azimuth 60), the
  // open back (240) scores far below it, as people would judge.
  int best = 0;
  std::vector<double> score(72);
  for (int j = 0; j < 72; ++j) {
    const double az = 5.0 * j * kDegree, el = 15.0 * kDegree;
    const View v = view_along({std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az)});
    score[j] = model.preference(v).score;
    if (score[j] > score[best]) best = j;
  }
  EXPECT_LE(azimuth_gap(5.0 * best, 60.0), 30.0) << "the preferred view is at azimuth " << 5.0 * best;
  EXPECT_GT(score[12], score[48] + 0.3) << "front " << score[12] << ", back " << score[48];
  // Normalized by the best of the six directions of the model's box: 1 straight along the best,
  // at most sqrt(3) between three.
  EXPECT_GT(score[best], 0.9);
  EXPECT_LT(score[best], std::sqrt(3.0));
}

TEST(ViewPreference, TakesTheOutsideWhicheverWayTheNormalsPoint) {
  // The same bust with its faces wound the other way: the outside is the side the reference views
  // see more of, so every view scores the same (up to where the samples fall: a face's samples
  // are placed from its corners in order, and the order changed).
  const CoverageModel out(bust(60.0), quick_coverage()), in(bust(60.0, true), quick_coverage());
  EXPECT_EQ(out.outside_side(), 0);
  EXPECT_EQ(in.outside_side(), 1);
  for (const Eigen::Vector3d& d : {Eigen::Vector3d(0.8, 0.2, 0.5), Eigen::Vector3d(-0.8, 0.2, -0.5), Eigen::Vector3d(0, 1, 0)}) {
    const View v = view_along(d);
    EXPECT_NEAR(out.preference(v).score, in.preference(v).score, 1e-3) << d.transpose();
  }
}

TEST(ViewPreference, TheSameBitsOnOneAndTwoThreadsAndNearlyTheSameWhenSplit) {
  const TriangleMesh mesh = bust(60.0);
  const View v = view_along({0.5, 0.3, 0.8});
  const auto with = [&](int threads, const TriangleMesh& m) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    const CoverageModel model(m, quick_coverage());
    return model.preference(v);
  };
  const ViewPreference one = with(1, mesh), two = with(2, mesh);
  EXPECT_EQ(one.score, two.score);
  EXPECT_EQ(one.projected_area, two.projected_area);
  EXPECT_EQ(one.visible_ratio, two.visible_ratio);
  EXPECT_EQ(one.half_scores, two.half_scores);
  // Four times the faces, the same shape: the samples and the ray grid measure the shape.
  const ViewPreference split = with(2, test_meshes::split_at_midpoints(mesh));
  EXPECT_NEAR(split.score, two.score, 0.01);
}

TEST(ViewPreference, TheFeatureOrbitStartsAtThePreferredViewAboveTheFloor) {
  const TriangleMesh mesh = bust(60.0);
  FeatureOrbitOptions options = quick_orbit();
  options.start = OrbitStart::preferred;  // --first-view preferred (the default is best-covering)
  const FeatureOrbitResult r = compute_feature_orbit(mesh, options);
  const CameraPose first = r.camera_path().pose(0.0);
  EXPECT_LE(azimuth_gap(azimuth_of(first), 60.0), 30.0) << "frame 0 is at azimuth " << azimuth_of(first);
  const double elevation = std::asin((first.eye - first.target).normalized().y()) / kDegree;
  EXPECT_GE(elevation, options.lowest_deg - 1e-9);
  EXPECT_LE(elevation, options.highest_deg + 1e-9);
  // Frame 0 is the tour's preferred frame, or within the noise of the best (the tie band).
  ASSERT_EQ(r.frame_preferences.size(), 24u);
  EXPECT_DOUBLE_EQ(r.frame_preferences[0], r.start_preference.score);
  for (int k = 1; k < 24; ++k) EXPECT_GE(r.frame_preferences[0], r.frame_preferences[k] - r.start_tie_band - 0.02) << k;
  // Wound the other way, the same start.
  const FeatureOrbitResult flipped = compute_feature_orbit(bust(60.0, true), options);
  EXPECT_EQ(flipped.geometry.start, r.geometry.start);
}

}  // namespace
