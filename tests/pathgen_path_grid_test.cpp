// §9–§11, §13 and §17.6–§17.7: bounding cylinder, grid and cell weights, control points, start
// cell, gaze/position paths and metrics, driven with synthetic surfaces (no §3–§8 involved).
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <numbers>
#include <random>

#include "core/error.h"
#include "pathgen/paper_path.h"

namespace meshtour {
namespace {

constexpr double kPi = std::numbers::pi;

// Open tube around the Y axis through `center`: `around` × `along` quads, each split in two.
SurfaceAnalysis make_tube(double radius, double height, int around, int along,
                          const Eigen::Vector3d& center = Eigen::Vector3d::Zero()) {
  SurfaceAnalysis s;
  for (int i = 0; i <= along; ++i)
    for (int k = 0; k < around; ++k) {
      const double a = 2 * kPi * (k + 0.5) / around;
      s.positions.push_back(center + Eigen::Vector3d(radius * std::sin(a), -height / 2 + height * i / along,
                                                     radius * std::cos(a)));
    }
  for (int i = 0; i < along; ++i)
    for (int k = 0; k < around; ++k) {
      const auto v = [&](int ii, int kk) { return static_cast<std::uint32_t>(ii * around + (kk % around)); };
      s.triangles.push_back({v(i, k), v(i, k + 1), v(i + 1, k + 1)});
      s.triangles.push_back({v(i, k), v(i + 1, k + 1), v(i + 1, k)});
    }
  s.face_weight.assign(s.triangles.size(), 1.0);
  s.face_patch.assign(s.triangles.size(), 0);
  s.patch_count = 1;
  return s;
}

Eigen::Vector3d centroid(const SurfaceAnalysis& s, std::size_t f) {
  const auto& t = s.triangles[f];
  return (s.positions[t[0]] + s.positions[t[1]] + s.positions[t[2]]) / 3.0;
}

// A grid filled by hand (no faces), for the tie rules.
CellGrid make_grid(int rows, int columns, double value = 1.0) {
  CellGrid g;
  g.rows = rows;
  g.columns = columns;
  g.weight.assign(static_cast<std::size_t>(rows) * columns, value);
  g.face_count.assign(g.weight.size(), 1);
  return g;
}
void set(CellGrid& g, int i, int j, double w, int count = 1) {
  g.weight[static_cast<std::size_t>(i) * g.columns + j] = w;
  g.face_count[static_cast<std::size_t>(i) * g.columns + j] = count;
}

TEST(PathgenPathCylinder, AngularFrameFollowsTheTableAndIsRightHanded) {
  const auto check = [](const Eigen::Vector3d& up, const Eigen::Vector3d& ex, const Eigen::Vector3d& ey) {
    const auto [e_x, e_y] = angular_frame(up);
    EXPECT_TRUE(e_x.isApprox(ex, 1e-15)) << up.transpose();
    EXPECT_TRUE(e_y.isApprox(ey, 1e-15)) << up.transpose();
  };
  const Eigen::Vector3d X = Eigen::Vector3d::UnitX(), Y = Eigen::Vector3d::UnitY(), Z = Eigen::Vector3d::UnitZ();
  check(Y, Z, X);
  check(Z, X, Y);
  check(X, Y, Z);
  check(-Y, Z, -X);
  check(-Z, X, -Y);
  check(-X, Y, -Z);
  const Eigen::Vector3d up = Eigen::Vector3d(0.2, 1.0, 0.3).normalized();
  const auto [e_x, e_y] = angular_frame(up);
  EXPECT_NEAR(e_x.norm(), 1.0, 1e-15);
  EXPECT_NEAR(e_x.dot(up), 0.0, 1e-15);
  EXPECT_NEAR(e_x.cross(e_y).dot(up), 1.0, 1e-15);
  EXPECT_GT(e_x.x(), 0.9);  // projected from X, the world axis least aligned with up
}

TEST(PathgenPathCylinder, UpDirectionParsing) {
  EXPECT_EQ(UpDirection::parse("y").axis, (Axis{1, false}));
  EXPECT_EQ(UpDirection::parse("-Z").axis, (Axis{2, true}));
  EXPECT_EQ(UpDirection::parse("pca").kind, UpDirection::Kind::pca);
  EXPECT_EQ(UpDirection::parse("longest-aabb").kind, UpDirection::Kind::longest_aabb);
  const UpDirection v = UpDirection::parse("0,2,0");
  EXPECT_EQ(v.kind, UpDirection::Kind::vector);
  EXPECT_TRUE(v.vector.isApprox(Eigen::Vector3d::UnitY()));
  EXPECT_EQ(UpDirection::parse(v.name()).vector, v.vector);
  EXPECT_THROW(UpDirection::parse("w"), InputError);
  EXPECT_THROW(UpDirection::parse("0,0,0"), InputError);
  EXPECT_THROW(UpDirection::parse("1,2"), InputError);
}

TEST(PathgenPathCylinder, TightCylinderAroundAnOffsetTube) {
  const Eigen::Vector3d center(0.1, 0.05, -0.2);
  const SurfaceAnalysis s = make_tube(0.2, 0.8, 64, 40, center);
  const Cylinder c = fit_cylinder(s.positions, s.triangles, Eigen::Vector3d::UnitY());
  EXPECT_NEAR(c.radius, 0.2, 1e-12);
  EXPECT_NEAR(c.height, 0.8, 1e-12);
  EXPECT_NEAR(c.base, center.y() - 0.4, 1e-12);
  EXPECT_NEAR(c.axis_point.x(), center.x(), 1e-12);
  EXPECT_NEAR(c.axis_point.z(), center.z(), 1e-12);
  const Cylinder box = fit_cylinder(s.positions, s.triangles, Eigen::Vector3d::UnitY(), AxisPointMode::aabb_center);
  EXPECT_NEAR(box.axis_point.x(), center.x(), 1e-12);
  EXPECT_NEAR(box.radius, 0.2, 1e-3);
}

TEST(PathgenPathCylinder, FlatModelAcrossTheUpAxisIsAClearError) {
  SurfaceAnalysis s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}};
  s.triangles = {{0, 1, 2}};
  try {
    fit_cylinder(s.positions, s.triangles, Eigen::Vector3d::UnitY());
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--up"), std::string::npos) << e.what();
  }
}

TEST(PathgenPathCylinder, LongestAabbAndPcaFindTheLongAxis) {
  SurfaceAnalysis s = make_tube(0.05, 0.9, 32, 30);  // long along Y
  EXPECT_TRUE(resolve_up(UpDirection::parse("longest-aabb"), s.positions, s.triangles).isApprox(Eigen::Vector3d::UnitY()));
  // Tilt the tube: PCA follows it, with a reproducible sign.
  const Eigen::Vector3d dir = Eigen::Vector3d(0.3, 1.0, -0.2).normalized();
  const Eigen::Matrix3d rot = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitY(), dir).toRotationMatrix();
  for (auto& p : s.positions) p = rot * p;
  const Eigen::Vector3d pca = resolve_up(UpDirection::parse("pca"), s.positions, s.triangles);
  EXPECT_NEAR(pca.dot(dir), 1.0, 1e-9);
}

TEST(PathgenPathGrid, EveryFaceLandsInExactlyOneCell) {
  const SurfaceAnalysis s = make_tube(0.3, 0.8, 100, 55);
  const Cylinder c = fit_cylinder(s.positions, s.triangles, Eigen::Vector3d::UnitY());
  const CellGrid g = build_grid(s.positions, s.triangles, s.face_weight, c, 11, 20);
  int total = 0;
  for (int n : g.face_count) total += n;
  EXPECT_EQ(total, static_cast<int>(s.triangles.size()));
  EXPECT_EQ(g.empty_cells(), 0);
  for (std::size_t f = 0; f < s.triangles.size(); ++f) {
    const auto [i, j] = grid_cell(c, centroid(s, f), 11, 20);
    EXPECT_EQ(g.face_cell[f], i * 20 + j);
  }
  for (double w : g.weight) EXPECT_DOUBLE_EQ(w, 1.0);
}

TEST(PathgenPathGrid, BoundaryCentroidsStayInsideTheGrid) {
  Cylinder c;  // up +Y, e_x = +Z, e_y = +X, axis through the origin, base 0, height 1
  c.height = 1.0;
  c.radius = 1.0;
  EXPECT_EQ(grid_cell(c, Eigen::Vector3d(0, 1.0, 1), 11, 20).first, 10);   // u = 1 → last row
  EXPECT_EQ(grid_cell(c, Eigen::Vector3d(0, 1.5, 1), 11, 20).first, 10);   // clamped
  EXPECT_EQ(grid_cell(c, Eigen::Vector3d(0, -0.5, 1), 11, 20).first, 0);
  for (double eps : {1e-15, 1e-16, 1e-17, 1e-300}) {
    // Angle 2π − ε: just below e_x, on the e_y < 0 side.
    const double v = 2 * kPi - eps;
    const int j = grid_cell(c, Eigen::Vector3d(std::sin(v), 0.5, std::cos(v)), 11, 20).second;
    EXPECT_TRUE(j == 19 || j == 0) << j;
    const int j2 = grid_cell(c, Eigen::Vector3d(-eps, 0.5, 1.0), 11, 20).second;
    EXPECT_TRUE(j2 == 19 || j2 == 0) << j2;
  }
  EXPECT_EQ(grid_cell(c, Eigen::Vector3d(0, 0.5, 0), 11, 20).second, 0);  // on the axis: v = 0
  EXPECT_EQ(grid_cell(c, Eigen::Vector3d(1, 0.5, 0), 11, 20).second, 5);  // +X is angle π/2
}

TEST(PathgenPathGrid, CellWeightIsTheMeanOrTheAreaWeightedMean) {
  SurfaceAnalysis s;
  // Two faces in the same cell (around +Z, mid-height), areas 1 and 3, weights 2 and 6.
  s.positions = {{0, 0, 1}, {0.1, 0, 1}, {0, 1, 1}, {0, 0, 1.01}, {0.3, 0, 1.01}, {0, 1, 1.01},
                 {-1, -5, -1}, {1, 5, 1}};
  s.triangles = {{0, 1, 2}, {3, 4, 5}};
  s.face_weight = {2.0, 6.0};
  Cylinder c;
  c.height = 10;
  c.base = -5;
  c.radius = 2;
  const CellGrid mean = build_grid(s.positions, s.triangles, s.face_weight, c, 1, 20);
  EXPECT_DOUBLE_EQ(mean.at(0, 0), 4.0);
  const CellGrid area = build_grid(s.positions, s.triangles, s.face_weight, c, 1, 20, CellAveraging::area_weighted);
  EXPECT_DOUBLE_EQ(area.at(0, 0), (0.05 * 2 + 0.15 * 6) / 0.2);
  EXPECT_EQ(area.empty_cells(), 19);
}

TEST(PathgenPathControl, UniformAndEmptyColumnsSelectTheMiddleRow) {
  CellGrid g = make_grid(11, 20, 1.0);
  for (int i = 0; i < 11; ++i) set(g, i, 4, 0.0, 0);  // column 4 entirely empty
  const ControlPoints cp = choose_control_points(g);
  for (int j = 0; j < 20; ++j) {
    EXPECT_EQ(cp.rows[j], 5) << j;
    EXPECT_DOUBLE_EQ(cp.heights[j], 5.5 / 11);
    EXPECT_DOUBLE_EQ(cp.angles[j], (j + 0.5) * 2 * kPi / 20);
  }
}

TEST(PathgenPathControl, TieRulesPreferTheMiddleThenTheLowerRow) {
  CellGrid g = make_grid(11, 20, 1.0);
  set(g, 2, 0, 5.0);
  set(g, 9, 0, 5.0);  // |9−5| = 4 > |2−5| = 3 → row 2
  set(g, 3, 1, 5.0);
  set(g, 7, 1, 5.0);  // equal distance → lower row 3
  set(g, 8, 2, 5.0);
  set(g, 10, 2, 5.0 - 1e-13);  // within the tie tolerance, but farther from the middle
  set(g, 0, 3, 5.0);
  set(g, 5, 3, 0.0, 0);  // an empty middle cell never wins over a non-empty one
  const ControlPoints cp = choose_control_points(g);
  EXPECT_EQ(cp.rows[0], 2);
  EXPECT_EQ(cp.rows[1], 3);
  EXPECT_EQ(cp.rows[2], 8);
  EXPECT_EQ(cp.rows[3], 0);

  CellGrid e = make_grid(11, 20, 1.0);
  set(e, 0, 6, 1.0 + 1e-13);  // ties with the rest of the column (relative 1e-12)
  EXPECT_EQ(choose_control_points(e).rows[6], 5);
}

TEST(PathgenPathControl, InterpolatedEmptyColumns) {
  CellGrid g = make_grid(11, 20, 1.0);
  set(g, 10, 2, 3.0);  // column 2 → row 10
  set(g, 0, 6, 3.0);   // column 6 → row 0
  for (int j = 3; j <= 5; ++j)
    for (int i = 0; i < 11; ++i) set(g, i, j, 0.0, 0);
  const ControlPoints cp = choose_control_points(g, EmptyColumnMode::interpolate);
  const double top = 10.5 / 11, bottom = 0.5 / 11;
  EXPECT_DOUBLE_EQ(cp.heights[3], top + (bottom - top) * 1 / 4);
  EXPECT_DOUBLE_EQ(cp.heights[4], top + (bottom - top) * 2 / 4);
  EXPECT_DOUBLE_EQ(cp.heights[5], top + (bottom - top) * 3 / 4);
  EXPECT_EQ(cp.rows[4], 5);
}

TEST(PathgenPathControl, StartCellIsTheHeaviestWithTheTieRules) {
  CellGrid g = make_grid(11, 20, 1.0);
  set(g, 9, 3, 7.0);
  set(g, 1, 12, 7.0);  // |1−5| = |9−5|: smaller j wins → column 3
  set(g, 8, 15, 6.9);
  StartCell s = choose_start_cell(g);
  EXPECT_EQ(s.row, 9);
  EXPECT_EQ(s.column, 3);
  EXPECT_DOUBLE_EQ(s.parameter, 3.0 / 20);
  set(g, 6, 17, 7.0);  // nearer the middle wins over a smaller j
  s = choose_start_cell(g);
  EXPECT_EQ(s.column, 17);
  EXPECT_EQ(s.row, 6);
}

// A tube with a heavy patch facing column 3 at row 8: the whole §9–§14 chain.
class PathgenPathChain : public ::testing::Test {
protected:
  void SetUp() override {
    surface_ = make_tube(0.3, 0.8, 200, 110);
    surface_.scale = 2.5;
    surface_.offset = Eigen::Vector3d(1, -2, 3);
    const Cylinder c = fit_cylinder(surface_.positions, surface_.triangles, Eigen::Vector3d::UnitY());
    for (std::size_t f = 0; f < surface_.triangles.size(); ++f) {
      const auto [i, j] = grid_cell(c, centroid(surface_, f), 11, 20);
      if (i == 8 && j == 3) surface_.face_weight[f] = 9.0;
      if (i == 2 && j == 14) surface_.face_weight[f] = 4.0;
    }
  }
  SurfaceAnalysis surface_;
};

TEST_F(PathgenPathChain, ControlRowsStartAndMetrics) {
  const PaperPathResult r = compute_paper_path(surface_, PaperPathOptions{});
  for (int j = 0; j < 20; ++j) EXPECT_EQ(r.control.rows[j], j == 3 ? 8 : j == 14 ? 2 : 5) << j;
  EXPECT_EQ(r.start.row, 8);
  EXPECT_EQ(r.start.column, 3);
  EXPECT_DOUBLE_EQ(r.geometry.start_parameter, 3.0 / 20);
  EXPECT_DOUBLE_EQ(r.metrics.weight_max, 9.0);
  EXPECT_NEAR(r.metrics.weight_avg, (218 + 9 + 4) / 220.0, 1e-12);
  EXPECT_EQ(r.metrics.empty_cells, 0);
  EXPECT_DOUBLE_EQ(r.metrics.weight_avg_nonempty, r.metrics.weight_avg);
  // Up to the peak, down, flat (no sign), down to the trough, up: two sign changes of U′.
  EXPECT_EQ(r.metrics.extreme_points, 2);
  EXPECT_DOUBLE_EQ(r.metrics.amplitude_gaze, 0.5 * r.metrics.amplitude_curve);
  EXPECT_DOUBLE_EQ(r.metrics.amplitude_position, 0.25 * r.metrics.amplitude_curve);
  // The peaks of isolated controls: 5.5/11 + (8.5 − 5.5)/11 · 2/3 and 5.5/11 − 3/11 · 2/3.
  EXPECT_NEAR(r.metrics.amplitude_curve, 6.0 / 11 * 2.0 / 3.0, 1e-12);
  EXPECT_NEAR(r.metrics.height_over_radius, 0.8 / 0.3, 1e-9);
  EXPECT_EQ(r.metrics.radius_factor, 6.0);
  EXPECT_GE(r.stage_seconds.size(), 5u);
}

TEST_F(PathgenPathChain, PathsLieOnTheirCylinders) {
  const PaperPathResult r = compute_paper_path(surface_, PaperPathOptions{});
  const PaperPathGeometry& g = r.geometry;
  const double rad = r.cylinder.radius;
  for (int k = 0; k < 997; ++k) {
    const double t = k / 997.0;
    EXPECT_NEAR(g.angle(t), std::fmod(kPi / 20 + 2 * kPi * t, 2 * kPi), 1e-12);
    EXPECT_NEAR(r.cylinder.axis_distance(g.base_point(t)), rad, 1e-12);
    EXPECT_NEAR(r.cylinder.axis_distance(g.gaze_point(t)), rad, 1e-12);
    EXPECT_NEAR(r.cylinder.axis_distance(g.position_point(t)), 6 * rad, 1e-12);
    const double u = g.base_height(t);
    EXPECT_NEAR(g.gaze_height(t), 0.5 + 0.5 * (u - 0.5), 1e-15);
    EXPECT_NEAR(g.position_height(t), 0.5 + 0.25 * (u - 0.5), 1e-15);
    const double eta = g.base_point(t).dot(r.cylinder.up);
    EXPECT_NEAR((eta - r.cylinder.base) / r.cylinder.height, u, 1e-12);
  }
}

TEST_F(PathgenPathChain, CameraPoseStartsAtT0AndIsInModelUnits) {
  const PaperPathResult r = compute_paper_path(surface_, PaperPathOptions{});
  const PaperCameraPath path = r.camera_path();
  const PaperPathGeometry& g = path.geometry();
  for (double t : {0.0, 0.1, 0.37, 0.999}) {
    const CameraPose p = path.pose(t);
    EXPECT_TRUE(p.eye.isApprox(2.5 * g.position_point(g.start_parameter + t) + Eigen::Vector3d(1, -2, 3), 1e-14));
    EXPECT_TRUE(p.target.isApprox(2.5 * g.gaze_point(g.start_parameter + t) + Eigen::Vector3d(1, -2, 3), 1e-14));
    EXPECT_EQ(p.up, Eigen::Vector3d::UnitY());
    const CameraPose q = path.pose(t + 1.0);
    EXPECT_LT((p.eye - q.eye).norm(), 1e-12);
    EXPECT_LT((p.target - q.target).norm(), 1e-12);
  }
  // At t = 0 the camera faces the start column: the eye is at angle V(t0) = (j0 + 0.5)·2π/n.
  const Eigen::Vector3d radial = path.normalized_pose(0.0).eye - r.cylinder.axis_foot(path.normalized_pose(0.0).eye.y());
  const double angle = std::atan2(radial.dot(r.cylinder.e_y), radial.dot(r.cylinder.e_x));
  EXPECT_NEAR(angle, 3.5 * 2 * kPi / 20, 1e-12);
}

TEST_F(PathgenPathChain, OptionsChangeTheRightThings) {
  PaperPathOptions o;
  o.gaze_radius = GazeRadiusMode::scaled;
  o.height_reference = HeightReference::curve_mean;
  o.degree = 2;
  const PaperPathResult r = compute_paper_path(surface_, o);
  EXPECT_NEAR(r.geometry.gaze_radius, 0.5 * r.cylinder.radius, 1e-15);
  EXPECT_NEAR(r.geometry.height_reference, (18 * 5.5 + 8.5 + 2.5) / 11 / 20, 1e-15);
  EXPECT_EQ(r.geometry.curve.degree(), 2);
  EXPECT_EQ(r.metrics.extreme_points, 2);
  o = PaperPathOptions{};
  o.rows = 0;
  EXPECT_THROW(compute_paper_path(surface_, o), InputError);
  o = PaperPathOptions{};
  o.gaze_scale = 1.5;
  EXPECT_THROW(compute_paper_path(surface_, o), InputError);
}

TEST(PathgenPathRadius, FactorIsSixExactlyWhenTallerThanTwoRadii) {
  EXPECT_EQ(position_radius_factor(2.0, 1.0), 4.0);
  EXPECT_EQ(position_radius_factor(2.0 + 1e-12, 1.0), 6.0);
  EXPECT_EQ(position_radius_factor(0.5, 1.0), 4.0);
  SurfaceAnalysis wide = make_tube(0.3, 0.5, 64, 10);
  const PaperPathResult r = compute_paper_path(wide, PaperPathOptions{});
  EXPECT_EQ(r.metrics.radius_factor, 4.0);
  EXPECT_NEAR(r.geometry.position_radius, 4.0 * r.cylinder.radius, 1e-15);
}

}  // namespace
}  // namespace meshtour
