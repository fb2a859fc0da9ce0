#include "mesh/tangents.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numeric>

namespace meshtour {
namespace {

// What makes corners one vertex of the tangent space: its position's index, its normal's and UV's
// bits and its triangle's UV orientation.
struct CornerKey {
  std::array<std::uint32_t, 7> words{};
  auto operator<=>(const CornerKey&) const = default;
};

Eigen::Vector3f any_perpendicular(const Eigen::Vector3f& n) {
  const Eigen::Vector3f axis = std::abs(n.x()) < 0.9f ? Eigen::Vector3f::UnitX() : Eigen::Vector3f::UnitY();
  return (axis - n * n.dot(axis)).normalized();
}

}  // namespace

std::vector<Eigen::Vector4f> corner_tangents(std::span<const Eigen::Vector3f> positions,
                                             std::span<const std::array<std::uint32_t, 3>> triangles,
                                             std::span<const Eigen::Vector3f> corner_normals, std::span<const Eigen::Vector2f> corner_uvs) {
  const std::size_t corners = 3 * triangles.size();
  // Per corner: its triangle's u and v directions projected on the corner's tangent plane, times
  // the corner's angle; and the triangle's orientation.
  std::vector<Eigen::Vector3f> tangent(corners, Eigen::Vector3f::Zero()), bitangent(corners, Eigen::Vector3f::Zero());
  std::vector<bool> preserves(corners, true);
  for (std::size_t f = 0; f < triangles.size(); ++f) {
    const auto& tri = triangles[f];
    const Eigen::Vector3f p[3] = {positions[tri[0]], positions[tri[1]], positions[tri[2]]};
    const Eigen::Vector2f* uv = &corner_uvs[3 * f];
    const Eigen::Vector3f d1 = p[1] - p[0], d2 = p[2] - p[0];
    const Eigen::Vector2f t21 = uv[1] - uv[0], t31 = uv[2] - uv[0];
    const float signed_area = t21.x() * t31.y() - t21.y() * t31.x();
    // dP/du and dP/dv up to the factor 1 / signed_area, whose sign is taken with `orientation`.
    const Eigen::Vector3f os = t31.y() * d1 - t21.y() * d2, ot = -t31.x() * d1 + t21.x() * d2;
    const float orientation = signed_area > 0.0f ? 1.0f : -1.0f;
    const bool has_area = signed_area != 0.0f && std::isfinite(signed_area);
    for (int k = 0; k < 3; ++k) {
      const std::size_t c = 3 * f + static_cast<std::size_t>(k);
      preserves[c] = signed_area > 0.0f;
      if (!has_area) continue;
      const Eigen::Vector3f& n = corner_normals[c];
      // The corner's angle, between its two edges in the tangent plane.
      Eigen::Vector3f e1 = p[(k + 1) % 3] - p[k], e2 = p[(k + 2) % 3] - p[k];
      e1 -= n * n.dot(e1);
      e2 -= n * n.dot(e2);
      const float l1 = e1.norm(), l2 = e2.norm();
      if (!(l1 > 0.0f && l2 > 0.0f)) continue;
      const float angle = std::acos(std::clamp(e1.dot(e2) / (l1 * l2), -1.0f, 1.0f));
      Eigen::Vector3f ts = os - n * n.dot(os), tt = ot - n * n.dot(ot);
      if (ts.squaredNorm() > 0.0f) tangent[c] = orientation * angle * ts.normalized();
      if (tt.squaredNorm() > 0.0f) bitangent[c] = orientation * angle * tt.normalized();
    }
  }
  // Corners grouped by their key (sorted, so the sums' order, and so their bits, do not depend on
  // a hash); each corner gets its group's sum.
  std::vector<CornerKey> keys(corners);
  for (std::size_t c = 0; c < corners; ++c) {
    const Eigen::Vector3f& n = corner_normals[c];
    const Eigen::Vector2f& uv = corner_uvs[c];
    keys[c].words = {triangles[c / 3][c % 3], std::bit_cast<std::uint32_t>(n.x()), std::bit_cast<std::uint32_t>(n.y()),
                     std::bit_cast<std::uint32_t>(n.z()), std::bit_cast<std::uint32_t>(uv.x()), std::bit_cast<std::uint32_t>(uv.y()),
                     preserves[c] ? 1u : 0u};
  }
  std::vector<std::uint32_t> order(corners);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
  std::vector<Eigen::Vector4f> out(corners);
  for (std::size_t begin = 0; begin < corners;) {
    std::size_t end = begin + 1;
    while (end < corners && keys[order[end]] == keys[order[begin]]) ++end;
    Eigen::Vector3f t = Eigen::Vector3f::Zero();
    for (std::size_t i = begin; i < end; ++i) t += tangent[order[i]];
    const std::uint32_t first = order[begin];
    const Eigen::Vector3f& n = corner_normals[first];
    t -= n * n.dot(t);
    const Eigen::Vector3f unit = t.squaredNorm() > 0.0f ? Eigen::Vector3f(t.normalized()) : any_perpendicular(n);
    const float w = preserves[first] ? 1.0f : -1.0f;
    for (std::size_t i = begin; i < end; ++i) out[order[i]] = {unit.x(), unit.y(), unit.z(), w};
    begin = end;
  }
  return out;
}

}  // namespace meshtour
