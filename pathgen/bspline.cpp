#include "pathgen/bspline.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"

namespace meshtour {
namespace {

// Polynomial pieces are chosen on half-open intervals [a, b) so that a derivative that jumps at a
// knot returns its right-hand limit everywhere (including negative knots).
double cubic_piece(double x, int derivative) {
  if (x < -2.0 || x >= 2.0) return 0.0;
  const double ax = std::abs(x);
  const double sg = x < 0.0 ? -1.0 : 1.0;
  const bool inner = x >= -1.0 && x < 1.0;
  switch (derivative) {
    case 0: return inner ? 2.0 / 3.0 - x * x + ax * ax * ax / 2.0 : (2.0 - ax) * (2.0 - ax) * (2.0 - ax) / 6.0;
    case 1: return inner ? -2.0 * x + 1.5 * x * ax : -sg * (2.0 - ax) * (2.0 - ax) / 2.0;
    case 2: return inner ? -2.0 + 3.0 * ax : 2.0 - ax;
    case 3: return inner ? 3.0 * sg : -sg;
    default: return 0.0;
  }
}

double quadratic_piece(double x, int derivative) {
  if (x < -1.5 || x >= 1.5) return 0.0;
  const double ax = std::abs(x);
  const double sg = x < 0.0 ? -1.0 : 1.0;
  const bool inner = x >= -0.5 && x < 0.5;
  switch (derivative) {
    case 0: return inner ? 0.75 - x * x : (1.5 - ax) * (1.5 - ax) / 2.0;
    case 1: return inner ? -2.0 * x : -sg * (1.5 - ax);
    case 2: return inner ? -2.0 : 1.0;
    default: return 0.0;
  }
}

double horner(const std::vector<double>& a, double x) {
  double v = 0.0;
  for (auto it = a.rbegin(); it != a.rend(); ++it) v = v * x + *it;
  return v;
}

// Derivative of the span polynomial with respect to the local variable x.
double horner_derivative(const std::vector<double>& a, double x) {
  double v = 0.0;
  for (std::size_t k = a.size() - 1; k >= 1; --k) v = v * x + static_cast<double>(k) * a[k];
  return v;
}

}  // namespace

double cardinal_bspline(int degree, double x, int derivative) {
  if (degree == 3) return cubic_piece(x, derivative);
  if (degree == 2) return quadratic_piece(x, derivative);
  throw InputError("B-spline degree " + std::to_string(degree) + " is not supported: use 2 or 3 (I-23)");
}

PeriodicBSpline::PeriodicBSpline(std::vector<double> control, int degree)
    : control_(std::move(control)), degree_(degree) {
  if (degree_ != 2 && degree_ != 3)
    throw InputError("B-spline degree " + std::to_string(degree_) + " is not supported: use 2 or 3 (I-23)");
  if (control_.size() < 3)
    throw InputError("a closed B-spline needs at least 3 control points (grid columns), got " +
                     std::to_string(control_.size()));
}

double PeriodicBSpline::evaluate(double t, int derivative) const {
  const int n = size();
  if (n == 0) return 0.0;
  double s = (t - std::floor(t)) * n;
  if (s >= n) s -= n;  // t just below an integer can round up to exactly n
  const int span = static_cast<int>(std::floor(s));
  double sum = 0.0;
  for (int l = -2; l <= 2; ++l) {
    const int j = span + l;
    const int index = ((j % n) + n) % n;
    sum += control_[index] * cardinal_bspline(degree_, s - j, derivative);
  }
  return sum * std::pow(static_cast<double>(n), derivative);
}

std::vector<double> PeriodicBSpline::knots() const {
  const int n = size();
  std::vector<double> k(n);
  const double shift = degree_ == 2 ? 0.5 : 0.0;
  for (int j = 0; j < n; ++j) k[j] = (j + shift) / n;
  return k;
}

double PeriodicBSpline::span_start(int span) const { return degree_ == 2 ? span - 0.5 : span; }

std::vector<double> PeriodicBSpline::span_polynomial(int span) const {
  const int n = size();
  auto c = [&](int offset) { return control_[(((span + offset) % n) + n) % n]; };
  if (degree_ == 3) {
    // Span [J, J+1) in s: the uniform cubic B-spline matrix applied to c_{J-1..J+2}.
    const double cm = c(-1), c0 = c(0), c1 = c(1), c2 = c(2);
    return {(cm + 4.0 * c0 + c1) / 6.0, (-3.0 * cm + 3.0 * c1) / 6.0, (3.0 * cm - 6.0 * c0 + 3.0 * c1) / 6.0,
            (-cm + 3.0 * c0 - 3.0 * c1 + c2) / 6.0};
  }
  // Span [K - 1/2, K + 1/2) in s: the uniform quadratic B-spline matrix applied to c_{K-1..K+1}.
  const double cm = c(-1), c0 = c(0), c1 = c(1);
  return {(cm + c0) / 2.0, c0 - cm, (cm - 2.0 * c0 + c1) / 2.0};
}

std::pair<double, double> PeriodicBSpline::range() const {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  for (int span = 0; span < size(); ++span) {
    const std::vector<double> a = span_polynomial(span);
    std::vector<double> xs = {0.0, 1.0};
    // Roots of the derivative a1 + 2 a2 x (+ 3 a3 x²) inside the span.
    const double qa = a.size() > 3 ? 3.0 * a[3] : 0.0, qb = 2.0 * a[2], qc = a[1];
    if (qa == 0.0) {
      if (qb != 0.0) xs.push_back(-qc / qb);
    } else {
      const double disc = qb * qb - 4.0 * qa * qc;
      if (disc >= 0.0) {
        // Numerically stable pair of roots (no cancellation in either).
        const double q = -0.5 * (qb + std::copysign(std::sqrt(disc), qb));
        xs.push_back(q / qa);
        if (q != 0.0) xs.push_back(qc / q);
      }
    }
    for (double x : xs) {
      if (!(x >= 0.0 && x <= 1.0)) continue;
      const double v = horner(a, x);
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  return {lo, hi};
}

int PeriodicBSpline::extreme_points(double scale) const {
  constexpr int samples_per_span = 256;
  constexpr double zero_slope = 1e-9;
  const int n = size();
  std::vector<signed char> signs;
  signs.reserve(static_cast<std::size_t>(n) * samples_per_span);
  for (int span = 0; span < n; ++span) {
    const std::vector<double> a = span_polynomial(span);
    for (int k = 0; k < samples_per_span; ++k) {
      const double x = static_cast<double>(k) / samples_per_span;
      const double slope = scale * n * horner_derivative(a, x);  // dU/dt = n · dU/dx
      if (std::abs(slope) <= zero_slope) continue;
      signs.push_back(slope > 0.0 ? 1 : -1);
    }
  }
  int changes = 0;
  for (std::size_t i = 0; i < signs.size(); ++i)
    if (signs[i] != signs[(i + 1) % signs.size()]) ++changes;
  return changes;
}

}  // namespace meshtour
