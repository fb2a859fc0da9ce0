// Camera maths of the turntable and of framing: checked with real numbers.
#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "core/error.h"
#include "helpers.h"
#include "mesh/convex_hull.h"
#include "mesh/mesh.h"
#include "pathgen/turntable.h"
#include "test_meshes.h"

namespace meshtour {
namespace {

// Where a point lands in normalized image coordinates ([-1,1] on both axes when in frame).
Eigen::Vector2d project(const CameraPose& pose, const Lens& lens, const Eigen::Vector3d& p) {
  const Eigen::Vector3d f = (pose.target - pose.eye).normalized();
  const Eigen::Vector3d r = f.cross(pose.up).normalized();
  const Eigen::Vector3d u = r.cross(f);
  const Eigen::Vector3d q = p - pose.eye;
  const double ty = std::tan(lens.vertical_fov_deg * std::numbers::pi / 360.0);
  return {q.dot(r) / (q.dot(f) * ty * lens.aspect), q.dot(u) / (q.dot(f) * ty)};
}

std::vector<Eigen::Vector3d> box_corners(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  std::vector<Eigen::Vector3d> c;
  for (int i = 0; i < 8; ++i) c.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
  return c;
}

TEST(FitPullback, PointsEndUpExactlyInsideTheMargin) {
  const auto points = box_corners({-1, -2, -0.5}, {3, 1, 0.5});
  Lens lens;
  lens.vertical_fov_deg = 40;
  lens.aspect = 1.5;
  lens.margin = 0.1;
  CameraPose pose{{10, 3, 7}, {1, -0.5, 0}, Eigen::Vector3d::UnitY()};
  const double s = fit_pullback(points, pose, lens);
  const Eigen::Vector3d back = (pose.eye - pose.target).normalized();
  pose.eye += s * back;
  pose.target += s * back;
  // The margin is a share of the smaller side (the height here): 10 % of it is 20 % of the
  // half-height and 13.3 % of the half-width.
  const FrameFill fill = frame_fill(lens.aspect, lens.margin);
  EXPECT_NEAR(fill.y, 0.8, 1e-15);
  EXPECT_NEAR(fill.x, 1.0 - 0.2 / 1.5, 1e-15);
  double extreme = 0;
  for (const auto& p : points) {
    const Eigen::Vector2d ndc = project(pose, lens, p);
    extreme = std::max({extreme, std::abs(ndc.x()) / fill.x, std::abs(ndc.y()) / fill.y});
  }
  // The tightest point sits exactly on the margin.
  EXPECT_NEAR(extreme, 1.0, 1e-12);
}

TEST(FitPullback, RejectsDegenerateCameras) {
  const auto points = box_corners({0, 0, 0}, {1, 1, 1});
  EXPECT_THROW(fit_pullback(points, CameraPose{{1, 1, 1}, {1, 1, 1}, {0, 1, 0}}, Lens{}), InputError);
  EXPECT_THROW(fit_pullback(points, CameraPose{{0, 5, 0}, {0, 0, 0}, {0, 1, 0}}, Lens{}), InputError);
}

TEST(Turntable, OrbitIsACircleAroundTheUpAxisAndKeepsEverythingInFrame) {
  const auto points = box_corners({-1, 0, -0.3}, {1, 2.5, 0.3});
  TurntableOptions options;
  options.elevation_deg = 20;
  options.lens.aspect = 16.0 / 9.0;
  const TurntablePath path(points, options);
  // The orbit's axis is the vertical through the box centre; its height balances the framing.
  const Eigen::Vector3d center = path.center();
  EXPECT_EQ(center.x(), 0.0);
  EXPECT_EQ(center.z(), 0.0);
  EXPECT_GT(center.y(), 0.0);
  EXPECT_LT(center.y(), 2.5);
  const FrameFill fill = frame_fill(options.lens.aspect, options.lens.margin);
  double tightest = 0, balance = 0;
  for (int k = 0; k < 360; ++k) {
    const CameraPose pose = frame_pose(path, k, 360);
    EXPECT_NEAR((pose.eye - center).norm(), path.radius(), 1e-12);
    EXPECT_TRUE(pose.target.isApprox(center, 1e-15));
    EXPECT_EQ(pose.up, Eigen::Vector3d::UnitY());
    // Elevation: the height above the centre is radius * sin(20 deg).
    EXPECT_NEAR(pose.eye.y() - center.y(), path.radius() * std::sin(20 * std::numbers::pi / 180), 1e-12);
    double lo = 1e9, hi = -1e9;
    for (const auto& p : points) {
      const Eigen::Vector2d ndc = project(pose, options.lens, p);
      lo = std::min(lo, ndc.y());
      hi = std::max(hi, ndc.y());
      EXPECT_LE(std::abs(ndc.x()), fill.x + 1e-3);
      EXPECT_LE(std::abs(ndc.y()), fill.y + 1e-3);
      tightest = std::max({tightest, std::abs(ndc.x()) / fill.x, std::abs(ndc.y()) / fill.y});
    }
    balance += (lo + hi) / 2 / 360;
  }
  // Vertically centred on average over the orbit.
  EXPECT_NEAR(balance, 0.0, 0.01);
  // Not further than needed: some frame touches the margin.
  EXPECT_GT(tightest, 1.0 - 1e-3);
}

TEST(Turntable, StartsInFrontAndTurnsCounterClockwiseSeenFromUp) {
  const auto points = box_corners({-1, -1, -1}, {1, 1, 1});
  TurntableOptions options;
  options.elevation_deg = 0;
  const TurntablePath y_up(points, options);
  EXPECT_GT(y_up.pose(0).eye.z(), 0.0);                 // +Z is the front of a Y-up model
  EXPECT_GT(y_up.pose(0.25).eye.x(), 0.0);              // a quarter turn later, +X: CCW about +Y
  EXPECT_TRUE(y_up.pose(1.0).eye.isApprox(y_up.pose(0.0).eye, 1e-12));  // periodic

  options.up = Axis::parse("z");
  const TurntablePath z_up(points, options);
  EXPECT_LT(z_up.pose(0).eye.y(), 0.0);                 // -Y is the front of a Z-up model
  EXPECT_EQ(z_up.pose(0).up, Eigen::Vector3d::UnitZ());
  const Eigen::Vector3d a = z_up.pose(0).eye, b = z_up.pose(0.01).eye;
  EXPECT_GT(a.cross(b).z(), 0.0);                        // CCW about +Z
}

// A path that flies too close: FramedPath moves every eye back by one constant distance.
class CloseCircle final : public CameraPath {
public:
  CameraPose pose(double t) const override {
    const double a = 2 * std::numbers::pi * t;
    return {{0.5 * std::cos(a), 0.2, 0.5 * std::sin(a)}, {0, 0, 0}, {0, 1, 0}};
  }
};

TEST(FramedPath, PullsBackJustEnoughAndKeepsTheDirection) {
  const auto points = box_corners({-1, -1, -1}, {1, 1, 1});
  Lens lens;
  const FramedPath framed(std::make_unique<CloseCircle>(), points, lens, 360);
  EXPECT_GT(framed.pullback(), 1.0);
  const CloseCircle raw;
  const FrameFill fill = frame_fill(lens.aspect, lens.margin);
  double tightest = 0;
  for (int k = 0; k < 360; ++k) {
    const double t = k / 360.0;
    const CameraPose a = raw.pose(t), b = framed.pose(t);
    EXPECT_TRUE((b.target - b.eye).normalized().isApprox((a.target - a.eye).normalized(), 1e-12));
    EXPECT_NEAR((b.eye - a.eye).norm(), framed.pullback(), 1e-12);
    for (const auto& p : points) {
      const Eigen::Vector2d ndc = project(b, lens, p);
      EXPECT_LE(std::max(std::abs(ndc.x()) / fill.x, std::abs(ndc.y()) / fill.y), 1.0 + 1e-9);
      tightest = std::max({tightest, std::abs(ndc.x()) / fill.x, std::abs(ndc.y()) / fill.y});
    }
  }
  EXPECT_NEAR(tightest, 1.0, 1e-9);
}

// A lumpy, lopsided model: an icosphere (10k vertices) pushed in and out, stretched and moved off
// the origin, so that many vertices are near the hull without being on it.
std::vector<Eigen::Vector3d> lumpy_model() {
  std::vector<Eigen::Vector3d> points = test_meshes::icosphere(5).positions;
  for (auto& p : points) {
    const double bump = 1.0 + 0.15 * std::sin(5.0 * p.x()) * std::cos(3.0 * p.y()) + 0.3 * std::max(0.0, p.z() - 0.6);
    p = Eigen::Vector3d(2.0 * p.x(), 1.0 * p.y(), 0.7 * p.z()) * bump + Eigen::Vector3d(3.0, -1.0, 0.5);
  }
  return points;
}

// The framing fits read the hull's vertices instead of every vertex (issue 14): the orbit must be
// the same, bit for bit.
void expect_same_turntable(std::span<const Eigen::Vector3d> points, const TurntableOptions& options) {
  const std::vector<Eigen::Vector3d> hull = convex_hull_vertices(points);
  EXPECT_LT(hull.size(), points.size());
  const TurntablePath every(points, options), on_hull(hull, options);
  EXPECT_EQ(on_hull.radius(), every.radius());
  EXPECT_EQ(on_hull.center(), every.center());
  for (int k = 0; k < 8; ++k) EXPECT_EQ(on_hull.pose(k / 8.0).eye, every.pose(k / 8.0).eye);
}

TEST(Turntable, FramingOnTheHullIsTheFramingOnEveryVertex) {
  const auto points = lumpy_model();
  for (const double elevation : {-30.0, 0.0, 15.0, 60.0})
    for (const char* up : {"y", "z", "-x"}) {
      SCOPED_TRACE(std::string("up ") + up + ", elevation " + std::to_string(elevation));
      TurntableOptions options;
      options.up = Axis::parse(up);
      options.elevation_deg = elevation;
      options.lens.vertical_fov_deg = 30.0 + elevation / 4.0;
      expect_same_turntable(points, options);
    }
}

TEST(Turntable, FramingOnTheBunnysHullIsTheFramingOnEveryVertex) {
  MESHTOUR_SHARED_MESH(file, "bunny.ply");
  const TriangleMesh bunny = load_mesh(file);
  expect_same_turntable(bunny.positions, TurntableOptions{});
}

TEST(FramedPath, PullbackOnTheHullIsThePullbackOnEveryVertex) {
  const auto points = lumpy_model();
  const auto hull = convex_hull_vertices(points);
  Lens lens;
  lens.aspect = 1.3;
  const FramedPath every(std::make_unique<CloseCircle>(), points, lens, 90), on_hull(std::make_unique<CloseCircle>(), hull, lens, 90);
  EXPECT_GT(every.pullback(), 0.0);
  EXPECT_EQ(on_hull.pullback(), every.pullback());
  // Single poses too, with the eye inside the model (points behind the eye count).
  for (int k = 0; k < 36; ++k) {
    const CameraPose pose = CloseCircle().pose(k / 36.0);
    const CameraPose shifted{pose.eye + Eigen::Vector3d(3.0, -1.0, 0.5), pose.target + Eigen::Vector3d(3.0, -1.0, 0.5), pose.up};
    EXPECT_EQ(fit_pullback(hull, shifted, lens), fit_pullback(points, shifted, lens)) << k;
  }
}

TEST(Turntable, RejectsEmptyOrPointModels) {
  std::vector<Eigen::Vector3d> none;
  EXPECT_THROW(TurntablePath(none, TurntableOptions{}), InputError);
  std::vector<Eigen::Vector3d> same(3, Eigen::Vector3d(1, 2, 3));
  EXPECT_THROW(TurntablePath(same, TurntableOptions{}), InputError);
}

TEST(Axis, ParsesSignedAxes) {
  EXPECT_EQ(Axis::parse("y").vector(), Eigen::Vector3d::UnitY());
  EXPECT_EQ(Axis::parse("-Z").vector(), -Eigen::Vector3d::UnitZ());
  EXPECT_EQ(Axis::parse("+x").name(), "+x");
  EXPECT_THROW(Axis::parse("w"), InputError);
  EXPECT_THROW(Axis::parse(""), InputError);
  EXPECT_THROW(Axis::parse("xy"), InputError);
}

}  // namespace
}  // namespace meshtour
