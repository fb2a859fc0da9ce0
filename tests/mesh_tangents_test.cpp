// The tangent generator (mesh/tangents.h) against tangents known in closed form: on a cylinder
// whose u runs around it and v up it, the tangent at every corner is the direction of increasing
// angle and w is +1; where the UVs of one half are mirrored, that half's tangents turn round and
// w is -1; corners of one vertex with the same normal and UV get one tangent.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "mesh/tangents.h"

namespace meshtour {
namespace {

struct Cylinder {
  std::vector<Eigen::Vector3f> positions;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<Eigen::Vector3f> normals;  // per corner
  std::vector<Eigen::Vector2f> uvs;      // per corner
};

// `sides` columns around the z axis; columns with angle >= pi get u mirrored when `mirror_half`.
Cylinder cylinder(int sides, bool mirror_half) {
  Cylinder c;
  const auto angle = [&](int i) { return 2.0 * std::numbers::pi * i / sides; };
  for (int i = 0; i <= sides; ++i)
    for (int k = 0; k < 2; ++k)
      c.positions.emplace_back(static_cast<float>(std::cos(angle(i))), static_cast<float>(std::sin(angle(i))), static_cast<float>(k));
  for (int i = 0; i < sides; ++i) {
    const std::uint32_t a = 2 * i, b = 2 * i + 1, d = 2 * (i + 1), e = 2 * (i + 1) + 1;  // a, d bottom; b, e top
    const bool mirrored = mirror_half && angle(i) >= std::numbers::pi - 1e-9;
    const auto u = [&](int col) { return static_cast<float>(mirrored ? 1.0 - static_cast<double>(col) / sides : static_cast<double>(col) / sides); };
    for (const auto& tri : {std::array<std::uint32_t, 3>{a, d, e}, std::array<std::uint32_t, 3>{a, e, b}}) {
      c.triangles.push_back(tri);
      for (const std::uint32_t v : tri) {
        const Eigen::Vector3f& p = c.positions[v];
        c.normals.push_back(Eigen::Vector3f(p.x(), p.y(), 0).normalized());
        c.uvs.emplace_back(u(static_cast<int>(v / 2)), static_cast<float>(v % 2));
      }
    }
  }
  return c;
}

TEST(Tangents, FollowIncreasingUAroundACylinder) {
  const Cylinder c = cylinder(24, false);
  const auto t = corner_tangents(c.positions, c.triangles, c.normals, c.uvs);
  ASSERT_EQ(t.size(), 3 * c.triangles.size());
  for (std::size_t k = 0; k < t.size(); ++k) {
    const Eigen::Vector3f& p = c.positions[c.triangles[k / 3][k % 3]];
    const Eigen::Vector3f around = Eigen::Vector3f(-p.y(), p.x(), 0).normalized();
    EXPECT_GT(t[k].head<3>().dot(around), 0.999f) << "corner " << k;
    EXPECT_NEAR(t[k].head<3>().dot(c.normals[k]), 0.0f, 1e-5f);
    EXPECT_EQ(t[k].w(), 1.0f);
  }
}

TEST(Tangents, MirroredUvsTurnTheTangentAndW) {
  const Cylinder c = cylinder(24, true);
  const auto t = corner_tangents(c.positions, c.triangles, c.normals, c.uvs);
  int mirrored = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    const std::size_t column = k / 6;  // two triangles a column
    const bool flipped = column >= 12;
    const Eigen::Vector3f& p = c.positions[c.triangles[k / 3][k % 3]];
    const Eigen::Vector3f around = Eigen::Vector3f(-p.y(), p.x(), 0).normalized() * (flipped ? -1.0f : 1.0f);
    EXPECT_GT(t[k].head<3>().dot(around), 0.999f) << "corner " << k;
    EXPECT_EQ(t[k].w(), flipped ? -1.0f : 1.0f) << "corner " << k;
    // The bitangent cross(n, t) * w runs up the cylinder (increasing v) on both halves.
    EXPECT_GT(c.normals[k].cross(t[k].head<3>()).z() * t[k].w(), 0.999f) << "corner " << k;
    mirrored += flipped;
  }
  EXPECT_EQ(mirrored, 12 * 6);
}

TEST(Tangents, CornersOfOneVertexShareOneTangent) {
  const Cylinder c = cylinder(7, false);  // uneven columns: the faces around a vertex differ in angle
  const auto t = corner_tangents(c.positions, c.triangles, c.normals, c.uvs);
  for (std::size_t a = 0; a < t.size(); ++a)
    for (std::size_t b = 0; b < t.size(); ++b)
      if (c.triangles[a / 3][a % 3] == c.triangles[b / 3][b % 3] && c.uvs[a] == c.uvs[b]) {
        EXPECT_EQ(t[a], t[b]) << a << " " << b;
      }
}

TEST(Tangents, DegenerateUvsGiveAPerpendicularTangent) {
  const std::vector<Eigen::Vector3f> positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<std::array<std::uint32_t, 3>> triangles = {{0, 1, 2}};
  const std::vector<Eigen::Vector3f> normals(3, Eigen::Vector3f::UnitZ());
  const std::vector<Eigen::Vector2f> uvs(3, Eigen::Vector2f(0.5f, 0.5f));
  for (const Eigen::Vector4f& t : corner_tangents(positions, triangles, normals, uvs)) {
    EXPECT_NEAR(t.head<3>().norm(), 1.0f, 1e-6f);
    EXPECT_NEAR(t.head<3>().dot(Eigen::Vector3f::UnitZ()), 0.0f, 1e-6f);
  }
}

}  // namespace
}  // namespace meshtour
