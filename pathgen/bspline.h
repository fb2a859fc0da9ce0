#pragma once
// §12 of docs/METHOD.md: the closed (periodic) uniform B-spline of the control heights, with its
// derivatives, exact range and extreme-point count (§14).
#include <utility>
#include <vector>

namespace meshtour {

/// The centred cardinal B-spline N_p of degree p ∈ {2, 3} (§12.1), or its `derivative`-th
/// derivative (0..p; at the knots, where a derivative jumps, the right-hand limit is returned).
/// Supported on |x| < (p + 1) / 2.
double cardinal_bspline(int degree, double x, int derivative = 0);

/// U(t) = Σ_j c_j Σ_k N_p(n·t − j − k·n), t ∈ ℝ with period 1, n = number of control values.
/// Basis j is centred at t = j/n, so for p = 3 the curve at t = j/n "belongs" to control j.
class PeriodicBSpline {
public:
  PeriodicBSpline() = default;
  /// \throw InputError if `control` has fewer than 3 values or the degree is not 2 or 3.
  PeriodicBSpline(std::vector<double> control, int degree);

  int degree() const { return degree_; }
  int size() const { return static_cast<int>(control_.size()); }
  const std::vector<double>& control() const { return control_; }

  /// U(t) (derivative = 0) or d^k U / dt^k (derivative = k, in units per loop^k).
  double evaluate(double t, int derivative = 0) const;
  double value(double t) const { return evaluate(t, 0); }

  /// The n distinct knots in [0, 1): j/n for p = 3, (j + 0.5)/n for p = 2 (the centred basis
  /// of even degree has its knots half-way between the control parameters).
  std::vector<double> knots() const;

  /// Exact {min, max} of U over a loop: U is a polynomial of degree p between knots, so its
  /// extremes are at the knots or at the roots of U′ inside a span.
  std::pair<double, double> range() const;

  /// §14 "extreme points" of `scale`·U: sign changes of U′ sampled at 256 points per span,
  /// samples with |scale·U′| ≤ 1e-9 dropped, counted cyclically. Always even.
  int extreme_points(double scale = 1.0) const;

private:
  // Power-basis coefficients a0..a3 of U on span `span` in the local variable x ∈ [0, 1]
  // (s = n·t = span_start + x).
  std::vector<double> span_polynomial(int span) const;
  double span_start(int span) const;

  std::vector<double> control_;
  int degree_ = 3;
};

}  // namespace meshtour
