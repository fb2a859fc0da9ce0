// §5 normals and Goldfeather–Interrante curvature, §6 osculating torus and distances:
// the exact and expected items of §17.3 and §17.4, plus hand-checked cases.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <numbers>

#include "pathgen/curvature.h"
#include "pathgen/surface.h"
#include "pathgen/torus.h"
#include "test_meshes.h"

namespace meshtour {
namespace {

using namespace test_meshes;
using surface_detail::FitNeighbour;


// z(x, y) = A/2x² + Bxy + C/2y² + Dx³ + Ex²y + Fxy² + Gy³ and its unit normal (−z_x, −z_y, 1)/|·|.
struct Cubic {
  double A, B, C, D, E, F, G;
  double z(double x, double y) const {
    return A / 2 * x * x + B * x * y + C / 2 * y * y + D * x * x * x + E * x * x * y + F * x * y * y + G * y * y * y;
  }
  Eigen::Vector3d normal(double x, double y) const {
    const double zx = A * x + B * y + 3 * D * x * x + 2 * E * x * y + F * y * y;
    const double zy = B * x + C * y + E * x * x + 2 * F * x * y + 3 * G * y * y;
    return Eigen::Vector3d(-zx, -zy, 1.0).normalized();
  }
};

void expect_weingarten(const VertexDifferential& d, const Eigen::Matrix2d& W, double tolerance) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(W);
  const Eigen::Vector2d lambda = eig.eigenvalues();
  // κ1 has the smaller magnitude.
  const int small = std::abs(lambda(0)) <= std::abs(lambda(1)) ? 0 : 1;
  EXPECT_NEAR(d.k1, lambda(small), tolerance);
  EXPECT_NEAR(d.k2, lambda(1 - small), tolerance);
  const Eigen::Vector2d e1 = eig.eigenvectors().col(small), e2 = eig.eigenvectors().col(1 - small);
  // Directions up to sign, in the world frame (the normal at the origin is +Z, the frame axes X/Y).
  EXPECT_NEAR(std::abs(d.t1.head<2>().normalized().dot(e1)), 1.0, tolerance);
  EXPECT_NEAR(std::abs(d.t2.head<2>().normalized().dot(e2)), 1.0, tolerance);
  EXPECT_NEAR(d.t1.dot(d.normal), 0.0, 1e-12);
  EXPECT_NEAR(d.t2.dot(d.normal), 0.0, 1e-12);
  EXPECT_NEAR(d.t1.dot(d.t2), 0.0, 1e-12);
}

TEST(PathgenSurfaceCurvature, CubicFitWithExactNormalsRecoversTheWeingartenMatrix) {
  // Irregular 1-ring (7 neighbours at different radii) so no symmetry helps the fit.
  const Cubic c{1.3, -0.4, -2.1, 0.7, -1.1, 0.5, 0.9};
  std::vector<FitNeighbour> ring;
  for (int k = 0; k < 7; ++k) {
    const double a = 2 * std::numbers::pi * k / 7 + 0.1 * k * k, r = 0.05 + 0.01 * k;
    const double x = r * std::cos(a), y = r * std::sin(a);
    ring.push_back({Eigen::Vector3d(x, y, c.z(x, y)), c.normal(x, y)});
  }
  const VertexDifferential d = surface_detail::fit_vertex(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), ring, {}, CurvatureFit::cubic);
  expect_weingarten(d, (Eigen::Matrix2d() << c.A, c.B, c.B, c.C).finished(), 1e-9);
  // Same answer for any neighbour order (the rows are sorted by position).
  std::reverse(ring.begin(), ring.end());
  const VertexDifferential r = surface_detail::fit_vertex(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), ring, {}, CurvatureFit::cubic);
  EXPECT_EQ(r.k1, d.k1);
  EXPECT_EQ(r.k2, d.k2);
  EXPECT_EQ(r.t1, d.t1);
}

TEST(PathgenSurfaceCurvature, ExactNormalsHookOnAGridRecoversTheCubicAtTheOrigin) {
  // A 9×9 grid sampled from the cubic, analysed end to end with smoothing off and the exact
  // normals supplied; curvatures scale with the normalization (κ_normalized = d·κ_model).
  const Cubic c{2.0, 0.6, -1.0, 0.3, -0.2, 0.4, -0.5};
  TriangleMesh m;
  std::vector<Eigen::Vector3d> normals;
  const int n = 8;
  const double h = 0.05;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = (i - n / 2) * h, y = (j - n / 2) * h;
      m.positions.emplace_back(x, y, c.z(x, y));
      normals.push_back(c.normal(x, y));
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const auto v = static_cast<std::uint32_t>(j * (n + 1) + i);
      m.triangles.push_back({v, v + 1, v + n + 2});
      m.triangles.push_back({v, v + n + 2, v + n + 1});
    }
  SurfaceOptions o = no_smoothing();
  o.exact_normals = normals;
  const SurfaceAnalysis s = analyze_surface(m, o);
  const auto input_origin = static_cast<std::uint32_t>((n / 2) * (n + 1) + n / 2);
  const auto origin = static_cast<std::size_t>(std::find(s.input_vertex.begin(), s.input_vertex.end(), input_origin) - s.input_vertex.begin());
  ASSERT_LT(origin, s.input_vertex.size());
  expect_weingarten(s.differential[origin], s.scale * (Eigen::Matrix2d() << c.A, c.B, c.B, c.C).finished(), 1e-9);
}

TEST(PathgenSurfaceCurvature, IcosphereLevel5HasSphereCurvatureEverywhere) {
  const SurfaceAnalysis s = analyze_surface(icosphere(5), no_smoothing());
  const double rho = 1.0 / (2.0 * std::sqrt(3.0));  // the unit sphere's cube has diagonal 2√3
  double worst_split = 0.0;
  for (std::size_t v = 0; v < s.differential.size(); ++v) {
    const VertexDifferential& d = s.differential[v];
    ASSERT_GE(d.k1, -3.55);
    ASSERT_LE(d.k1, -3.38);
    ASSERT_GE(d.k2, -3.55);
    ASSERT_LE(d.k2, -3.38);
    worst_split = std::max(worst_split, std::abs(d.k2 - d.k1));
    ASSERT_GT(d.normal.dot(s.positions[v].normalized()), 0.9999);  // outward
  }
  EXPECT_LT(worst_split, 0.15);
  EXPECT_NEAR(-1.0 / rho, -3.4641, 1e-4);
}

TEST(PathgenSurfaceCurvature, QuadraticFitOnTheSphereIsCloseToo) {
  SurfaceOptions o = no_smoothing();
  o.curvature_fit = CurvatureFit::quadratic;
  const SurfaceAnalysis s = analyze_surface(icosphere(4), o);
  for (const auto& d : s.differential) {
    ASSERT_NEAR(d.k1, -3.464, 0.2);
    ASSERT_NEAR(d.k2, -3.464, 0.2);
  }
}

TEST(PathgenSurfaceCurvature, OpenCylinderHasOnePrincipalCurvatureAlongTheAxis) {
  const TriangleMesh m = open_cylinder();
  const SurfaceAnalysis s = analyze_surface(m, no_smoothing());
  const double radius = 0.2 / s.scale;  // ≈ 0.204 in normalized units
  EXPECT_NEAR(radius, 0.204, 0.001);
  double worst_k1 = 0.0, worst_angle = 0.0;
  int checked = 0;
  for (std::size_t v = 0; v < s.positions.size(); ++v) {
    const double y = m.positions[s.input_vertex[v]].y();
    if (std::abs(std::abs(y) - 0.4) < 2.5 * 0.8 / 128) continue;  // boundary rows and their neighbours
    const VertexDifferential& d = s.differential[v];
    ASSERT_NEAR(d.k2, -1.0 / radius, 0.01 * (1.0 / radius));
    worst_k1 = std::max(worst_k1, std::abs(d.k1));
    worst_angle = std::max(worst_angle, std::acos(std::min(1.0, std::abs(d.t1.y()))) * 180.0 / std::numbers::pi);
    ++checked;
  }
  EXPECT_GT(checked, 10000);
  EXPECT_LT(worst_k1, 0.01);
  EXPECT_LT(worst_angle, 2.0);
  RecordProperty("worst_abs_k1", std::to_string(worst_k1));
  RecordProperty("worst_t1_angle_deg", std::to_string(worst_angle));
}

TEST(PathgenSurfaceCurvature, PlaneIsFlat) {
  const SurfaceAnalysis s = analyze_surface(plane(16), no_smoothing());
  for (const auto& d : s.differential) {
    ASSERT_LT(std::abs(d.k1), 1e-9);
    ASSERT_LT(std::abs(d.k2), 1e-9);
    ASSERT_EQ(d.normal, Eigen::Vector3d::UnitZ());
  }
}

TEST(PathgenSurfaceCurvature, FrameIsRightHandedOrthonormalAndPicksTheLeastAlignedAxis) {
  for (const Eigen::Vector3d& n : {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 2, 3).normalized(), Eigen::Vector3d(-1, 0, 0),
                                   Eigen::Vector3d(1, 1, 1).normalized()}) {
    const auto [X, Y] = surface_detail::tangent_frame(n);
    EXPECT_NEAR(X.norm(), 1.0, 1e-15);
    EXPECT_NEAR(X.dot(n), 0.0, 1e-15);
    EXPECT_NEAR((X.cross(Y) - n).norm(), 0.0, 1e-15);
  }
  // Ties go to x before y before z: for (1,1,1)/√3 the X axis comes from e_x.
  const auto [X, Y] = surface_detail::tangent_frame(Eigen::Vector3d(1, 1, 1).normalized());
  EXPECT_GT(X.x(), 0.8);
  (void)Y;
  // Hand-checked: N = +Z gives X = e_x, Y = e_y.
  const auto [Xz, Yz] = surface_detail::tangent_frame(Eigen::Vector3d::UnitZ());
  EXPECT_EQ(Xz, Eigen::Vector3d::UnitX());
  EXPECT_EQ(Yz, Eigen::Vector3d::UnitY());
}

// ---- §6 -------------------------------------------------------------------------------------

Eigen::Vector3d torus_normal(const Torus& t, const Eigen::Vector3d& q) {
  const Eigen::Vector3d w = q - t.center;
  const Eigen::Vector3d radial = w - w.dot(t.axis) * t.axis;
  const Eigen::Vector3d on_circle = t.center + t.major_radius * radial.normalized();
  return (q - on_circle).normalized();
}

TEST(PathgenSurfaceTorus, HandCheckedSphereAndSaddle) {
  // Sphere: outward N, κ1 = κ2 = −1 at p = (0,0,1) → centre at the origin, R = 0, r = 1.
  const Torus sphere = osculating_torus({0, 0, 1}, {0, 0, 1}, -1.0, {1, 0, 0}, -1.0, {0, 1, 0});
  EXPECT_EQ(sphere.center, Eigen::Vector3d::Zero());
  EXPECT_EQ(sphere.major_radius, 0.0);
  EXPECT_EQ(sphere.minor_radius, 1.0);
  EXPECT_DOUBLE_EQ(point_torus_distance(sphere, {0, 3, 0}), 2.0);
  EXPECT_DOUBLE_EQ(point_torus_distance(sphere, {0, 0, 0}), 1.0);
  // Saddle: κ1 = 0.5 along x, κ2 = −1 along y, N = +Z at the origin: ρ1 = 2, ρ2 = 1, σ = −1,
  // m = +N → C = (0,0,2), axis = ±y, R = 2 + 1 = 3, r_T = 1; the origin is on the inner equator.
  const Torus saddle = osculating_torus({0, 0, 0}, {0, 0, 1}, 0.5, {1, 0, 0}, -1.0, {0, 1, 0});
  EXPECT_EQ(saddle.center, Eigen::Vector3d(0, 0, 2));
  EXPECT_EQ(saddle.major_radius, 3.0);
  EXPECT_EQ(saddle.minor_radius, 1.0);
  EXPECT_EQ(point_torus_distance(saddle, Eigen::Vector3d::Zero()), 0.0);
  // Outer equator on the far side of the axis: (0,0,2) + 4·(0,0,1) → distance 0.
  EXPECT_EQ(point_torus_distance(saddle, {0, 0, 6}), 0.0);
  // The tube centre circle passes through (0,0,−1); its centre point is at distance r_T.
  EXPECT_DOUBLE_EQ(point_torus_distance(saddle, {0, 0, -1}), 1.0);
}

TEST(PathgenSurfaceTorus, OsculatingTorusTouchesToSecondOrder) {
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d p = drawn_vector([&] { return uniform(rng) - 0.5; });
    const Eigen::Vector3d N = drawn_vector([&] { return gaussian(rng); }).normalized();
    const auto [X, Y] = surface_detail::tangent_frame(N);
    const double phi0 = 2 * std::numbers::pi * uniform(rng);
    const Eigen::Vector3d t1 = std::cos(phi0) * X + std::sin(phi0) * Y, t2 = N.cross(t1);
    double k1 = 20 * uniform(rng) - 10, k2 = 20 * uniform(rng) - 10;
    if (std::abs(k1) > std::abs(k2)) std::swap(k1, k2);
    const Torus t = osculating_torus(p, N, k1, t1, k2, t2);
    ASSERT_LT(point_torus_distance(t, p), 1e-12);
    ASSERT_NEAR(std::abs(torus_normal(t, p).dot(N)), 1.0, 1e-9);
    for (double phi : {0.0, 0.4, 1.1, 2.0, 2.9}) {
      const Eigen::Vector3d dir = std::cos(phi) * t1 + std::sin(phi) * t2;
      const double kappa = k1 * std::cos(phi) * std::cos(phi) + k2 * std::sin(phi) * std::sin(phi);
      const auto q = [&](double s) { return (p + s * dir + (kappa * s * s / 2) * N).eval(); };
      const double d1 = point_torus_distance(t, q(1e-3)), d2 = point_torus_distance(t, q(5e-4)), d3 = point_torus_distance(t, q(2.5e-4));
      // Shrinks like s³ or faster (down to rounding, ~1e-16 relative to the torus size).
      if (d2 > 1e-12) {
        ASSERT_GE(d1 / d2, 7.0) << "trial " << trial;
      }
      if (d3 > 1e-12) {
        ASSERT_GE(d2 / d3, 7.0) << "trial " << trial;
      }
    }
  }
}

TEST(PathgenSurfaceTorus, DistanceToAnAnalyticRingTorusIsExact) {
  const Torus t{Eigen::Vector3d(0.1, -0.2, 0.3), Eigen::Vector3d(1, 2, 2) / 3.0, 0.3, 0.1};
  const auto [X, Y] = surface_detail::tangent_frame(t.axis);
  std::mt19937_64 rng(5);
  for (int k = 0; k < 500; ++k) {
    const double u = 2 * std::numbers::pi * uniform(rng), v = 2 * std::numbers::pi * uniform(rng);
    const Eigen::Vector3d radial = std::cos(u) * X + std::sin(u) * Y;
    const Eigen::Vector3d normal = std::cos(v) * radial + std::sin(v) * t.axis;
    const Eigen::Vector3d q = t.center + t.major_radius * radial + t.minor_radius * normal;
    ASSERT_LT(point_torus_distance(t, q), 1e-12);
    const double delta = (2 * uniform(rng) - 1) * 0.099;
    ASSERT_NEAR(point_torus_distance(t, q + delta * normal), std::abs(delta), 1e-12);
  }
}

TEST(PathgenSurfaceTorus, UmbilicGivesASphereAndFlatDirectionsAHugeRing) {
  const Torus umbilic = osculating_torus({1, 2, 3}, {0, 1, 0}, 2.5, {1, 0, 0}, 2.5, {0, 0, 1});
  EXPECT_EQ(umbilic.major_radius, 0.0);
  EXPECT_EQ(umbilic.minor_radius, 0.4);
  const Torus cylinder = osculating_torus({0, 0, 0}, {0, 0, 1}, 0.0, {1, 0, 0}, -4.0, {0, 1, 0});
  EXPECT_GE(cylinder.major_radius, 1e5);
  EXPECT_EQ(cylinder.minor_radius, 0.25);
  // Flat: both clamped to +κ_min: a sphere of radius 10⁶ tangent at p.
  const Torus flat = osculating_torus({0, 0, 0}, {0, 0, 1}, 0.0, {1, 0, 0}, 0.0, {0, 1, 0});
  EXPECT_EQ(flat.major_radius, 0.0);
  EXPECT_DOUBLE_EQ(flat.minor_radius, 1e6);
  EXPECT_NEAR(point_torus_distance(flat, {0.5, 0.0, 0.0}), 0.125e-6, 1e-9);  // rounding ~1e-10 at |C| = 10⁶
}

TEST(PathgenSurfaceTorus, FaceDistanceUsesSevenSamplesOrTheVertices) {
  // A triangle inscribed in the unit sphere: vertices on it, the interior sags inward.
  const Torus sphere{Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 0.0, 1.0};
  const Eigen::Vector3d a = Eigen::Vector3d(1, 0.1, 0.05).normalized(), b = Eigen::Vector3d(1, -0.1, 0.05).normalized(),
                        c = Eigen::Vector3d(1, 0.0, -0.1).normalized();
  EXPECT_LT(face_torus_distance(sphere, a, b, c, FaceSamples::vertices), 1e-15);
  const double centroid_sag = 1.0 - ((a + b + c) / 3.0).norm();
  EXPECT_NEAR(face_torus_distance(sphere, a, b, c, FaceSamples::seven), centroid_sag, 1e-15);
  EXPECT_TRUE(face_within(sphere, a, b, c, FaceSamples::seven, centroid_sag * 1.0001));
  EXPECT_FALSE(face_within(sphere, a, b, c, FaceSamples::seven, centroid_sag * 0.9999));
  EXPECT_TRUE(face_within(sphere, a, b, c, FaceSamples::vertices, 1e-12));
  // The result does not depend on where the face's corner list starts.
  EXPECT_EQ(face_torus_distance(sphere, a, b, c, FaceSamples::seven), face_torus_distance(sphere, b, c, a, FaceSamples::seven));
  EXPECT_EQ(face_torus_distance(sphere, a, b, c, FaceSamples::seven), face_torus_distance(sphere, c, a, b, FaceSamples::seven));
}

}  // namespace
}  // namespace meshtour
