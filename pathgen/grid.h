#pragma once
// §10-§11 and §13.2 of docs/METHOD.md: the m×n grid of cell weights on the bounding cylinder, one
// control point per column, and the start cell.
#include <utility>
#include <vector>

#include "pathgen/cylinder.h"

namespace meshtour {

enum class CellAveraging { mean, area_weighted };        ///< I-17
enum class EmptyColumnMode { middle_row, interpolate };  ///< I-21: columns without any face
std::string to_string(CellAveraging mode);
std::string to_string(EmptyColumnMode mode);

/// The cell weights of §10.
struct CellGrid {
  int rows = 0;
  int columns = 0;
  std::vector<double> weight;    ///< W_ij, row-major (i * columns + j); 0 for empty cells
  std::vector<int> face_count;   ///< n_ij
  std::vector<int> face_cell;    ///< cell index i * columns + j of every face

  double at(int i, int j) const { return weight[static_cast<std::size_t>(i) * columns + j]; }
  bool empty(int i, int j) const { return face_count[static_cast<std::size_t>(i) * columns + j] == 0; }
  int empty_cells() const;
};

/// §10.2 for one point (a face centroid): its (row, column).
std::pair<int, int> grid_cell(const Cylinder& cylinder, const Eigen::Vector3d& point, int rows, int columns);

/// §10: projects every face centroid onto the grid and averages w(f) per cell.
CellGrid build_grid(const std::vector<Eigen::Vector3d>& positions,
                    const std::vector<std::array<std::uint32_t, 3>>& triangles,
                    const std::vector<double>& face_weight, const Cylinder& cylinder, int rows, int columns,
                    CellAveraging averaging = CellAveraging::mean);

/// §11: one control point per column.
struct ControlPoints {
  std::vector<int> rows;        ///< i*_j (the tie rule's row, also for interpolated columns)
  std::vector<double> heights;  ///< u_j, normalized height in [0, 1]
  std::vector<double> angles;   ///< θ_j = (j + 0.5)·2π/n
};
ControlPoints choose_control_points(const CellGrid& grid, EmptyColumnMode empty_columns = EmptyColumnMode::middle_row);

/// §13.2: the heaviest cell (ties: nearest the middle row, then smallest j, then smallest i).
struct StartCell {
  int row = 0;
  int column = 0;
  double parameter = 0.0;  ///< t0 = j0 / n
};
StartCell choose_start_cell(const CellGrid& grid);

}  // namespace meshtour
