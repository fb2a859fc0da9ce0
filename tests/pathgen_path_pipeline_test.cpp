// The whole method (§3–§14) on the generated meshes of §17.1: expected control rows on the
// bumpy sphere (§17.6) and the invariances of §17.8 as far as §9–§14 are concerned.
#include <gtest/gtest.h>

#include <numbers>

#include "pathgen/paper_path.h"
#include "test_meshes.h"

namespace meshtour {
namespace {

namespace tm = test_meshes;

std::string rows_text(const std::vector<int>& rows) {
  std::string s;
  for (int r : rows) s += std::to_string(r) + " ";
  return s;
}

// §17.6 expected: the bump centres lie in x > 0, which faces columns 0–9 (+Y up); the far side is
// smooth, every cell there has W = 1, so each far column takes the middle row. Bumps centred close
// to the plane x = 0 spill (with their Gaussian tails and the 2-ring weights) into columns 10 and
// 18–19, so only the columns well inside the far side are required to stay in the middle. (The
// reference rows of §17.6, 5 7 7 7 7 6 8 6 6 5 | 5 ..., came from other random bump centres.)
TEST(PathgenPathPipeline, BumpySphereRowsFollowTheBumps) {
  PaperPathOptions options;
  options.surface = tm::specification_units();  // §17.6's rows are the specification's (ε per diagonal)
  const PaperPathResult r = compute_paper_path(tm::bumpy_sphere(5), options);
  const std::string rows = rows_text(r.control.rows);
  for (int j = 11; j <= 17; ++j) EXPECT_EQ(r.control.rows[j], 5) << "far column " << j << ": " << rows;
  int above = 0;
  for (int j = 0; j < 10; ++j) above += r.control.rows[j] > 5;
  EXPECT_GE(above, 7) << rows;
  EXPECT_GT(r.start.row, 5);  // the heaviest cell is among the bumps, above the equator
  // §17.7 expected range for bumpy spheres: A in 15–35 %, E in 4–12 (with a margin).
  EXPECT_GT(r.metrics.amplitude_gaze, 0.05) << rows;
  EXPECT_LT(r.metrics.amplitude_gaze, 0.45) << rows;
  EXPECT_GE(r.metrics.extreme_points, 2);
  EXPECT_LE(r.metrics.extreme_points, 14);
  EXPECT_EQ(r.metrics.empty_cells, 0);
}

// §17.8 expected: a scaled and translated input gives the same rows, T and E, W within 1e-9,
// and the same path up to that similarity.
TEST(PathgenPathPipeline, SimilarityTransformGivesTheSamePath) {
  const TriangleMesh base = tm::bumpy_sphere(5);
  const Eigen::Vector3d shift(100, -5, 3);
  const TriangleMesh moved = tm::transformed(base, 7.3, Eigen::Matrix3d::Identity(), shift);
  const PaperPathResult a = compute_paper_path(base, PaperPathOptions{});
  const PaperPathResult b = compute_paper_path(moved, PaperPathOptions{});
  EXPECT_EQ(a.control.rows, b.control.rows);
  EXPECT_EQ(a.surface.patch_count, b.surface.patch_count);
  EXPECT_EQ(a.metrics.extreme_points, b.metrics.extreme_points);
  ASSERT_EQ(a.grid.weight.size(), b.grid.weight.size());
  for (std::size_t c = 0; c < a.grid.weight.size(); ++c) EXPECT_NEAR(a.grid.weight[c], b.grid.weight[c], 1e-9);
  const PaperCameraPath pa = a.camera_path(), pb = b.camera_path();
  for (double t = 0.0; t < 1.0; t += 0.01) {
    const CameraPose p = pa.pose(t), q = pb.pose(t);
    EXPECT_LT((7.3 * p.eye + shift - q.eye).norm(), 1e-6 * 7.3);
    EXPECT_LT((7.3 * p.target + shift - q.target).norm(), 1e-6 * 7.3);
  }
}

// §17.8 exact (smoothing off): permuting vertices, faces and corners changes nothing but rounding.
TEST(PathgenPathPipeline, PermutationGivesTheSamePath) {
  PaperPathOptions options;
  options.surface.smoothing = SmoothingMethod::none;
  const TriangleMesh base = tm::bumpy_sphere(4);
  const auto permuted = tm::permuted(base, 99);
  const PaperPathResult a = compute_paper_path(base, options);
  const PaperPathResult b = compute_paper_path(permuted.mesh, options);
  EXPECT_EQ(a.control.rows, b.control.rows);
  EXPECT_EQ(a.start.column, b.start.column);
  EXPECT_EQ(a.start.row, b.start.row);
  EXPECT_EQ(a.metrics.extreme_points, b.metrics.extreme_points);
  EXPECT_NEAR(a.metrics.weight_max, b.metrics.weight_max, 1e-12);
  const PaperCameraPath pa = a.camera_path(), pb = b.camera_path();
  for (double t = 0.0; t < 1.0; t += 0.01) {
    EXPECT_LT((pa.pose(t).eye - pb.pose(t).eye).norm(), 1e-12 * a.geometry.scale * 10);
    EXPECT_LT((pa.pose(t).target - pb.pose(t).target).norm(), 1e-12 * a.geometry.scale * 10);
  }
}

// §17.8 expected: rotating the model about the up axis through its centroid by 360°/n shifts the
// control rows by one column (identical in at least 19 of 20; allow 18, the normalization scale
// changes slightly because the bounding box turns with the model).
TEST(PathgenPathPipeline, RotationByOneColumnShiftsTheRows) {
  const TriangleMesh base = tm::bumpy_sphere(5);
  const PaperPathResult a = compute_paper_path(base, PaperPathOptions{});
  const Eigen::Vector3d c = a.geometry.scale * a.cylinder.axis_point + a.geometry.offset;  // model units
  const Eigen::Matrix3d rot = tm::rotation(Eigen::Vector3d::UnitY(), 2 * std::numbers::pi / 20);
  const TriangleMesh turned = tm::transformed(base, 1.0, rot, c - rot * c);
  const PaperPathResult b = compute_paper_path(turned, PaperPathOptions{});
  int same = 0;
  for (int j = 0; j < 20; ++j) same += b.control.rows[(j + 1) % 20] == a.control.rows[j];
  EXPECT_GE(same, 18) << rows_text(a.control.rows) << "\n" << rows_text(b.control.rows);
}

}  // namespace
}  // namespace meshtour
