#pragma once
// sRGB transfer functions (IEC 61966-2-1), used for vertex colours in and 8-bit frames out.
#include <Eigen/Core>
#include <cmath>

namespace meshtour {

inline float srgb_to_linear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}
inline float linear_to_srgb(float c) {
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}
inline Eigen::Vector3f srgb_to_linear(const Eigen::Vector3f& c) {
  return {srgb_to_linear(c.x()), srgb_to_linear(c.y()), srgb_to_linear(c.z())};
}

}  // namespace meshtour
