// The one triangle geometry (core/triangle_geometry.h): a known triangle's cross product, area
// and normal, in double and float, and the operation order the hashed outputs depend on.
#include <gtest/gtest.h>

#include <random>

#include "core/triangle_geometry.h"

namespace meshtour {
namespace {

TEST(CoreTriangleGeometry, RightTriangleThreeFour) {
  // Legs 3 and 4 along x and y, counter-clockwise seen from +z: area 6, normal +z.
  const Eigen::Vector3d a(1, 2, 5), b(4, 2, 5), c(1, 6, 5);
  EXPECT_EQ(triangle_cross(a, b, c), Eigen::Vector3d(0, 0, 12));
  EXPECT_EQ(triangle_area(a, b, c), 6.0);
  EXPECT_EQ(triangle_normal(a, b, c), Eigen::Vector3d(0, 0, 1));
  // The other winding turns the normal, not the area.
  EXPECT_EQ(triangle_normal(a, c, b), Eigen::Vector3d(0, 0, -1));
  EXPECT_EQ(triangle_area(a, c, b), 6.0);
}

TEST(CoreTriangleGeometry, FloatCornersGiveFloatResults) {
  const Eigen::Vector3f a(0, 0, 0), b(0, 2, 0), c(0, 0, 3);
  const float area = triangle_area(a, b, c);  // no promotion to double on the way
  EXPECT_EQ(area, 3.0f);
  EXPECT_EQ(triangle_normal(a, b, c), Eigen::Vector3f(1, 0, 0));
}

TEST(CoreTriangleGeometry, DegenerateTriangleHasNoAreaAndAZeroNormal) {
  const Eigen::Vector3d a(0, 0, 0), b(1, 1, 1), c(2, 2, 2);
  EXPECT_EQ(triangle_area(a, b, c), 0.0);
  EXPECT_EQ(triangle_normal(a, b, c), Eigen::Vector3d::Zero());
}

TEST(CoreTriangleGeometry, MeshOverloadsReadTheTrianglesCorners) {
  const std::vector<Eigen::Vector3d> positions = {{9, 9, 9}, {0, 0, 0}, {2, 0, 0}, {0, 2, 0}};
  const std::array<std::uint32_t, 3> t = {1, 2, 3};
  EXPECT_EQ(triangle_area(positions, t), 2.0);
  EXPECT_EQ(triangle_cross(positions, t), Eigen::Vector3d(0, 0, 4));
  EXPECT_EQ(triangle_normal(positions, t), Eigen::Vector3d(0, 0, 1));
}

// Every stage's area used to be written out as ½|(b − a) × (c − a)| with a as the origin; the
// output hashes depend on that order to the last bit (another origin rounds differently).
TEST(CoreTriangleGeometry, AreaIsHalfTheCrossProductFromTheFirstCornerBitForBit) {
  // Coordinates in [-1000, 1000) from the generator's bits (its sequence is fixed by the standard;
  // the standard distributions are not).
  std::mt19937_64 random(34);
  const auto coordinate = [&] { return static_cast<double>(random() >> 11) * 0x1.0p-53 * 2000.0 - 1000.0; };
  const auto point = [&] { return Eigen::Vector3d(coordinate(), coordinate(), coordinate()); };
  int other_origin_differs = 0;
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3d a = point(), b = point(), c = point();
    EXPECT_EQ(triangle_area(a, b, c), 0.5 * (b - a).cross(c - a).norm());
    other_origin_differs += triangle_area(a, b, c) != 0.5 * (c - b).cross(a - b).norm();
  }
  // The check above can tell orders apart: the area from another corner differs often.
  EXPECT_GT(other_origin_differs, 100);
}

}  // namespace
}  // namespace meshtour
