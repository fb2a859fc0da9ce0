// §12 and §17.7: the periodic B-spline base curve, its derivatives, range and extreme points.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "core/error.h"
#include "pathgen/bspline.h"

namespace meshtour {
namespace {

std::vector<double> random_heights(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> row(0, 10);
  std::vector<double> u(n);
  for (double& x : u) x = (row(rng) + 0.5) / 11.0;
  return u;
}

// One-sided limit of the d-th derivative of the periodic spline at s = n·t, built from the basis
// alone. cardinal_bspline() returns right-hand limits; because N_p is even, the left-hand limit
// of N^(d) at x is (−1)^d times the right-hand limit at −x.
double one_sided(const std::vector<double>& c, int degree, double s, int d, bool left) {
  const int n = static_cast<int>(c.size());
  double sum = 0.0;
  for (int j = -n; j < 2 * n; ++j) {  // every periodic copy whose support can reach s ∈ [0, n]
    const double x = s - j;
    const double basis = left ? std::pow(-1.0, d) * cardinal_bspline(degree, -x, d) : cardinal_bspline(degree, x, d);
    sum += c[((j % n) + n) % n] * basis;
  }
  return sum * std::pow(static_cast<double>(n), d);
}

TEST(PathgenPathCurve, CardinalBasisIsAPartitionOfUnity) {
  for (int degree : {2, 3})
    for (double x = -3.0; x <= 3.0; x += 0.0137) {
      double sum = 0.0, slope = 0.0;
      for (int k = -5; k <= 5; ++k) {
        sum += cardinal_bspline(degree, x - k);
        slope += cardinal_bspline(degree, x - k, 1);
      }
      EXPECT_NEAR(sum, 1.0, 1e-14) << "degree " << degree << " x " << x;
      EXPECT_NEAR(slope, 0.0, 1e-13);
    }
}

TEST(PathgenPathCurve, KnownValuesAtTheControlParameters) {
  const std::vector<double> u = random_heights(20, 1);
  const PeriodicBSpline cubic(u, 3);
  const PeriodicBSpline quadratic(u, 2);
  for (int j = 0; j < 20; ++j) {
    const double t = j / 20.0;
    EXPECT_NEAR(cubic.value(t), (u[(j + 19) % 20] + 4 * u[j] + u[(j + 1) % 20]) / 6.0, 1e-15);
    EXPECT_NEAR(quadratic.value(t), (u[(j + 19) % 20] + 6 * u[j] + u[(j + 1) % 20]) / 8.0, 1e-15);
  }
}

TEST(PathgenPathCurve, ConstantHeightsGiveAConstantCurve) {
  for (int degree : {2, 3}) {
    const PeriodicBSpline curve(std::vector<double>(20, 0.5), degree);
    for (double t = -1.0; t < 2.0; t += 0.0031) {
      EXPECT_NEAR(curve.value(t), 0.5, 1e-14);
      EXPECT_NEAR(curve.evaluate(t, 1), 0.0, 1e-11);
    }
    EXPECT_EQ(curve.extreme_points(), 0);
    const auto [lo, hi] = curve.range();
    EXPECT_NEAR(hi - lo, 0.0, 1e-14);
  }
}

TEST(PathgenPathCurve, CurveStaysWithinTheControlHeightsAndIsPeriodic) {
  for (int degree : {2, 3}) {
    const std::vector<double> u = random_heights(20, 7 + degree);
    const PeriodicBSpline curve(u, degree);
    const double lo = *std::min_element(u.begin(), u.end()), hi = *std::max_element(u.begin(), u.end());
    const auto [rlo, rhi] = curve.range();
    EXPECT_GE(rlo, lo - 1e-15);
    EXPECT_LE(rhi, hi + 1e-15);
    for (double t = 0.0; t < 1.0; t += 0.00071) {
      const double v = curve.value(t);
      EXPECT_GE(v, rlo - 1e-14);
      EXPECT_LE(v, rhi + 1e-14);
      EXPECT_NEAR(curve.value(t + 1.0), v, 1e-13);
      EXPECT_NEAR(curve.value(t - 3.0), v, 1e-13);
    }
  }
}

TEST(PathgenPathCurve, DerivativesMatchFiniteDifferences) {
  for (int degree : {2, 3}) {
    const PeriodicBSpline curve(random_heights(20, 3), degree);
    const double h = 1e-7;
    for (double t = 0.013; t < 1.0; t += 0.0477) {
      for (int d = 1; d < degree; ++d) {
        const double fd = (curve.evaluate(t + h, d - 1) - curve.evaluate(t - h, d - 1)) / (2 * h);
        EXPECT_NEAR(curve.evaluate(t, d), fd, 1e-5 * std::max(1.0, std::abs(fd))) << "degree " << degree << " d " << d;
      }
    }
  }
}

// §17.7: U, U′, U″ continuous at every knot and at the seam (cubic); U‴ jumps.
TEST(PathgenPathCurve, CubicIsC2AtEveryKnotAndTheSeamAndTheThirdDerivativeJumps) {
  const std::vector<double> u = random_heights(20, 11);
  const PeriodicBSpline curve(u, 3);
  const std::vector<double> knots = curve.knots();
  ASSERT_EQ(knots.size(), 20u);
  int jumps = 0;
  for (std::size_t k = 0; k <= knots.size(); ++k) {
    const double s = k == knots.size() ? 20.0 : knots[k] * 20.0;  // s = 20 is the seam seen from the left
    for (int d = 0; d <= 2; ++d) {
      const double left = one_sided(u, 3, s, d, true), right = one_sided(u, 3, s, d, false);
      EXPECT_NEAR(left, right, 1e-10) << "knot " << k << " derivative " << d;
      // The class agrees with the basis sum (right-hand side).
      if (k < knots.size()) {
        EXPECT_NEAR(curve.evaluate(knots[k], d), right, 1e-9);
      }
    }
    const double left3 = one_sided(u, 3, s, 3, true), right3 = one_sided(u, 3, s, 3, false);
    if (std::abs(left3 - right3) > 1e-6) ++jumps;
  }
  EXPECT_GE(jumps, 10) << "U''' should jump at the knots of a generic control polygon";
  // Seam: the same values at t = 0 from the left (t → 1⁻) as from the right.
  for (int d = 0; d <= 2; ++d)
    EXPECT_NEAR(one_sided(u, 3, 20.0, d, true), one_sided(u, 3, 0.0, d, false), 1e-10);
}

TEST(PathgenPathCurve, QuadraticIsC1AndItsSecondDerivativeJumps) {
  const std::vector<double> u = random_heights(20, 5);
  const PeriodicBSpline curve(u, 2);
  int jumps = 0;
  for (double knot : curve.knots()) {
    const double s = knot * 20.0;
    for (int d = 0; d <= 1; ++d)
      EXPECT_NEAR(one_sided(u, 2, s, d, true), one_sided(u, 2, s, d, false), 1e-10);
    if (std::abs(one_sided(u, 2, s, 2, true) - one_sided(u, 2, s, 2, false)) > 1e-6) ++jumps;
  }
  EXPECT_GE(jumps, 10);
  EXPECT_DOUBLE_EQ(curve.knots()[0], 0.5 / 20.0);
}

TEST(PathgenPathCurve, SingleColumnPeakHasTwoExtremesAndMaximumTwoThirds) {
  for (int j = 0; j < 20; ++j) {
    std::vector<double> u(20, 0.0);
    u[j] = 1.0;
    const PeriodicBSpline curve(u, 3);
    EXPECT_EQ(curve.extreme_points(), 2) << "peak in column " << j;
    const auto [lo, hi] = curve.range();
    EXPECT_NEAR(hi, 2.0 / 3.0, 1e-15);
    EXPECT_NEAR(lo, 0.0, 1e-15);
    EXPECT_NEAR(curve.value(j / 20.0), 2.0 / 3.0, 1e-15);
  }
}

TEST(PathgenPathCurve, ExtremePointCountIsEvenAndTheSameForScaledCurves) {
  for (unsigned seed = 0; seed < 50; ++seed)
    for (int degree : {2, 3}) {
      const PeriodicBSpline curve(random_heights(20, seed), degree);
      const int e = curve.extreme_points();
      EXPECT_EQ(e % 2, 0);
      EXPECT_EQ(curve.extreme_points(0.5), e);
      EXPECT_EQ(curve.extreme_points(0.25), e);
    }
}

TEST(PathgenPathCurve, RangeIsTheTrueExtremeOfTheCurve) {
  const PeriodicBSpline curve(random_heights(20, 42), 3);
  const auto [lo, hi] = curve.range();
  double slo = 1e9, shi = -1e9;
  for (int k = 0; k < 200000; ++k) {
    const double v = curve.value(k / 200000.0);
    slo = std::min(slo, v);
    shi = std::max(shi, v);
  }
  EXPECT_LE(lo, slo + 1e-15);
  EXPECT_GE(hi, shi - 1e-15);
  EXPECT_NEAR(lo, slo, 1e-8);
  EXPECT_NEAR(hi, shi, 1e-8);
}

TEST(PathgenPathCurve, RejectsBadDegreeAndTooFewControls) {
  EXPECT_THROW(PeriodicBSpline(std::vector<double>(20, 0.5), 4), InputError);
  EXPECT_THROW(PeriodicBSpline(std::vector<double>(2, 0.5), 3), InputError);
}

}  // namespace
}  // namespace meshtour
