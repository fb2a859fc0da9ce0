// §10 (grid and cell weights), §11 (control points) and §13.2 (start cell).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <limits>
#include <cmath>
#include <numbers>
#include <string>

#include "core/angles.h"
#include "core/error.h"
#include "core/triangle_geometry.h"
#include "pathgen/grid.h"

namespace meshtour {
namespace {

// Distance of row i from the middle row (m−1)/2, doubled so that it stays an integer.
int middle_distance(int i, int rows) { return std::abs(2 * i - (rows - 1)); }

// The tie tolerance of §11 and §13.2: a weight within 1e-12 (relative above 1) of the maximum ties.
double tie_threshold(double w_max) { return w_max - 1e-12 * std::max(1.0, w_max); }

}  // namespace

int CellGrid::empty_cells() const {
  return static_cast<int>(std::count(face_count.begin(), face_count.end(), 0));
}

std::pair<int, int> grid_cell(const Cylinder& cylinder, const Eigen::Vector3d& point, int rows, int columns) {
  const double u = std::clamp((point.dot(cylinder.up) - cylinder.base) / cylinder.height, 0.0, 1.0);
  const Eigen::Vector3d d = point - cylinder.axis_point;
  const Eigen::Vector3d radial = d - d.dot(cylinder.up) * cylinder.up;
  double v = 0.0;
  if (radial.norm() >= 1e-12) {
    v = std::atan2(radial.dot(cylinder.e_y), radial.dot(cylinder.e_x));
    if (v < 0.0) v += kFullTurn;
    if (v >= kFullTurn) v = 0.0;  // −1e-17 + 2π rounds to 2π, which is angle 0
  }
  const int i = std::min(static_cast<int>(std::floor(u * rows)), rows - 1);
  const int j = std::clamp(static_cast<int>(std::floor(v * columns / kFullTurn)), 0, columns - 1);
  return {i, j};
}

CellGrid build_grid(const std::vector<Eigen::Vector3d>& positions,
                    const std::vector<std::array<std::uint32_t, 3>>& triangles,
                    const std::vector<double>& face_weight, const Cylinder& cylinder, int rows, int columns,
                    CellAveraging averaging) {
  if (face_weight.size() != triangles.size())
    throw InputError("internal: " + std::to_string(face_weight.size()) + " face weights for " +
                     std::to_string(triangles.size()) + " faces");
  if (rows < 1 || columns < 3) throw InputError("the grid needs at least 1 row and 3 columns");
  CellGrid grid;
  grid.rows = rows;
  grid.columns = columns;
  const std::size_t cells = static_cast<std::size_t>(rows) * columns;
  grid.weight.assign(cells, 0.0);
  grid.face_count.assign(cells, 0);
  grid.face_cell.resize(triangles.size());
  std::vector<double> area_sum(averaging == CellAveraging::area_weighted ? cells : 0, 0.0);
  std::vector<double> area_weight_sum(area_sum.size(), 0.0);

  // The cell of each face is independent of the others: computed in parallel. The sums are then
  // accumulated sequentially in face order, so they are bitwise reproducible (§10.3) for any
  // thread count.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, triangles.size(), 4096),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t f = range.begin(); f != range.end(); ++f) {
                        const auto& tri = triangles[f];
                        const Eigen::Vector3d g = (positions[tri[0]] + positions[tri[1]] + positions[tri[2]]) / 3.0;
                        const auto [i, j] = grid_cell(cylinder, g, rows, columns);
                        grid.face_cell[f] = i * columns + j;
                      }
                    });
  for (std::size_t f = 0; f < triangles.size(); ++f) {
    const int cell = grid.face_cell[f];
    grid.face_count[cell] += 1;
    grid.weight[cell] += face_weight[f];
    if (!area_sum.empty()) {
      const auto& tri = triangles[f];
      const double area = triangle_area(positions, tri);
      area_sum[cell] += area;
      area_weight_sum[cell] += area * face_weight[f];
    }
  }
  for (std::size_t cell = 0; cell < cells; ++cell) {
    if (grid.face_count[cell] == 0) continue;
    // A cell of degenerate faces only has no area to weight by; fall back to the plain mean.
    if (!area_sum.empty() && area_sum[cell] > 0.0)
      grid.weight[cell] = area_weight_sum[cell] / area_sum[cell];
    else
      grid.weight[cell] /= grid.face_count[cell];
  }
  return grid;
}

ControlPoints choose_control_points(const CellGrid& grid, EmptyColumnMode empty_columns) {
  const int m = grid.rows, n = grid.columns;
  ControlPoints cp;
  cp.rows.resize(n);
  cp.heights.resize(n);
  cp.angles.resize(n);
  std::vector<bool> column_empty(n, true);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < m; ++i)
      if (!grid.empty(i, j)) column_empty[j] = false;
    // I-16: an empty cell competes only when the whole column is empty (then every cell ties).
    double w_col = -std::numeric_limits<double>::infinity();
    for (int i = 0; i < m; ++i)
      if (column_empty[j] || !grid.empty(i, j)) w_col = std::max(w_col, grid.at(i, j));
    int best = -1;
    for (int i = 0; i < m; ++i) {
      if (!column_empty[j] && grid.empty(i, j)) continue;
      if (grid.at(i, j) < tie_threshold(w_col)) continue;
      // Ties go to the row nearest the middle, then to the lower row (I-21).
      if (best < 0 || middle_distance(i, m) < middle_distance(best, m)) best = i;
    }
    cp.rows[j] = best;
    cp.heights[j] = (best + 0.5) / m;
    cp.angles[j] = (j + 0.5) * kFullTurn / n;
  }
  if (empty_columns == EmptyColumnMode::interpolate &&
      std::count(column_empty.begin(), column_empty.end(), false) > 0) {
    // I-21 option: an all-empty column takes the height interpolated linearly (in column steps,
    // around the loop) between the nearest non-empty columns on either side.
    const std::vector<double> chosen = cp.heights;
    for (int j = 0; j < n; ++j) {
      if (!column_empty[j]) continue;
      int left = 1, right = 1;
      while (column_empty[((j - left) % n + n) % n]) ++left;
      while (column_empty[(j + right) % n]) ++right;
      const double u_left = chosen[((j - left) % n + n) % n];
      const double u_right = chosen[(j + right) % n];
      cp.heights[j] = u_left + (u_right - u_left) * left / (left + right);
    }
  }
  return cp;
}

StartCell choose_start_cell(const CellGrid& grid) {
  const int m = grid.rows, n = grid.columns;
  const double w_max = *std::max_element(grid.weight.begin(), grid.weight.end());
  StartCell start{-1, -1, 0.0};
  // Scan column by column, rows upward: the first cell found at the smallest distance from the
  // middle row is then the one with the smallest j, then the smallest i (§13.2).
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < m; ++i) {
      if (grid.at(i, j) < tie_threshold(w_max)) continue;
      if (start.row < 0 || middle_distance(i, m) < middle_distance(start.row, m)) {
        start.row = i;
        start.column = j;
      }
    }
  start.parameter = static_cast<double>(start.column) / n;
  return start;
}

}  // namespace meshtour
