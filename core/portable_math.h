#pragma once
// Transcendental functions from IEEE-exact operations only (+, -, *, /, sqrt): glibc picks its
// atan2, acos and sin by the CPU's features (FMA variants), and pixels, normals and sampling
// densities must be the same bits on every machine of a farm.
#include <cmath>
#include <numbers>

namespace meshtour {

/// atan2(y, x) in (-pi, pi]. Two half-angle steps bring the argument under 0.2, where 7 terms of
/// the series leave an error below 1e-12.
inline double portable_atan2(double y, double x) {
  if (y < 0.0) return -portable_atan2(-y, x);
  const double ax = std::abs(x);
  if (!(y > 0.0)) return x < 0.0 ? std::numbers::pi : 0.0;
  const bool steep = y > ax;
  double t = steep ? ax / y : y / ax;  // in [0, 1]
  for (int k = 0; k < 2; ++k) t = t / (1.0 + std::sqrt(1.0 + t * t));
  const double t2 = t * t;
  double series = 1.0 / 13.0;
  for (const double c : {-1.0 / 11.0, 1.0 / 9.0, -1.0 / 7.0, 1.0 / 5.0, -1.0 / 3.0, 1.0}) series = c + t2 * series;
  double angle = 4.0 * t * series;
  if (steep) angle = 0.5 * std::numbers::pi - angle;
  return x < 0.0 ? std::numbers::pi - angle : angle;
}

/// sin and cos of 2 pi t: reduction to [-pi/4, pi/4] by quadrant and Taylor series of 9 and 10
/// terms there (error below 1e-15).
inline void portable_sincos_turns(double t, double& s, double& c) {
  const double q = std::floor(t * 4.0 + 0.5);  // the quadrant, exact
  const double x = (t - 0.25 * q) * (2.0 * std::numbers::pi);
  const double x2 = x * x;
  double sin_x = 0.0, cos_x = 0.0, term_s = x, term_c = 1.0;
  for (int k = 0; k < 10; ++k) {
    sin_x += term_s;
    cos_x += term_c;
    term_s *= -x2 / ((2.0 * k + 2.0) * (2.0 * k + 3.0));
    term_c *= -x2 / ((2.0 * k + 1.0) * (2.0 * k + 2.0));
  }
  const long long quadrant = static_cast<long long>(q) & 3;
  const double s0 = (quadrant & 1) ? cos_x : sin_x, c0 = (quadrant & 1) ? sin_x : cos_x;
  s = (quadrant & 2) ? -s0 : s0;
  c = ((quadrant + 1) & 2) ? -c0 : c0;
}

}  // namespace meshtour
