// §4: one backward-Euler step of cotangent-Laplacian (mean-curvature-flow) smoothing, solved with
// Jacobi-preconditioned conjugate gradients, and the `taubin` alternative.
#include "pathgen/smoothing.h"

#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <limits>
#include <cmath>
#include <string>

#include "core/error.h"

namespace meshtour::surface_detail {
namespace {

// PMP clamps cotangents to angles between 3° and 177°: cot 3° ≈ 19.08.
constexpr double kCotangentClamp = 19.1;

double clamped_cotangent(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double c = a.dot(b) / a.cross(b).norm();
  return std::clamp(c, -kCotangentClamp, kCotangentClamp);
}

// Cotangent of the angle opposite edge (u, v) in face f, or 0 for a degenerate face.
double opposite_cotangent(const SurfaceMesh& mesh, const std::vector<double>& area, std::int32_t f,
                          std::uint32_t u, std::uint32_t v) {
  if (f < 0 || !(area[f] >= kDegenerateArea)) return 0.0;
  const auto& t = mesh.triangles[f];
  const std::uint32_t opposite = t[0] != u && t[0] != v ? t[0] : (t[1] != u && t[1] != v ? t[1] : t[2]);
  const Eigen::Vector3d& c = mesh.positions[opposite];
  return clamped_cotangent(mesh.positions[u] - c, mesh.positions[v] - c);
}


using SparseMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

// Rows per block of the reductions below. Fixed, so the partial sums and the order in which they
// are added do not depend on the number of threads (bitwise reproducible results).
constexpr std::size_t kBlockRows = 4096;
// §4.1: relative residual |b − A x| / |b| at which a column has converged.
constexpr double kRelativeTolerance = 1e-12;

// Runs body(begin, end, block) over fixed blocks of rows in parallel and returns the per-column
// sums of what the bodies return, added in block order.
template <class Body>
Eigen::Vector3d blocked_sum(std::size_t rows, const Body& body) {
  const std::size_t blocks = (rows + kBlockRows - 1) / kBlockRows;
  std::vector<Eigen::Vector3d> partial(blocks);
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t k) {
    partial[k] = body(k * kBlockRows, std::min(rows, (k + 1) * kBlockRows));
  });
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (const auto& p : partial) total += p;
  return total;
}

// Jacobi-preconditioned conjugate gradients for A X = B with three right-hand sides, run in
// lockstep: every column has its own step lengths and stops on its own test, exactly the iteration
// of Eigen's ConjugateGradient<..., Lower|Upper, DiagonalPreconditioner> (relative residual below
// 1e-12, at most 2n iterations), but the three columns share one pass over the matrix per
// iteration and every pass runs in parallel over rows. (Eigen solves column by column with a
// sequential product; three such solves on two cores left a core idle and read the matrix three
// times: 2× slower on a 557k-vertex mesh.) Returns the largest iteration count, or -1 if a column
// did not converge.
int solve_three_columns(const SparseMatrix& A, const RowMatrix& B, RowMatrix& X) {
  const std::size_t n = static_cast<std::size_t>(A.rows());
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  const double* value = A.valuePtr();
  std::vector<double> inverse_diagonal(n, 1.0);
  parallel_ranges(n, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i)
      for (int k = outer[i]; k < outer[i + 1]; ++k)
        if (static_cast<std::size_t>(inner[k]) == i && value[k] != 0.0) inverse_diagonal[i] = 1.0 / value[k];
  });
  const auto product_row = [&](const RowMatrix& P, std::size_t i) {
    Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
    for (int k = outer[i]; k < outer[i + 1]; ++k) sum += value[k] * P.row(inner[k]);
    return sum;
  };

  RowMatrix R(n, 3), P(n, 3), Z(n, 3), Q(n, 3);
  const Eigen::Vector3d rhs_norm2 = blocked_sum(n, [&](std::size_t b, std::size_t e) {
    Eigen::Vector3d s = Eigen::Vector3d::Zero();
    for (std::size_t i = b; i < e; ++i) {
      R.row(i) = B.row(i) - product_row(X, i);
      s += B.row(i).cwiseAbs2().transpose();
    }
    return s;
  });
  Eigen::Vector3d threshold, residual2;
  std::array<bool, 3> active{};
  for (int c = 0; c < 3; ++c) threshold(c) = std::max(kRelativeTolerance * kRelativeTolerance * rhs_norm2(c), std::numeric_limits<double>::min());
  residual2 = blocked_sum(n, [&](std::size_t b, std::size_t e) {
    Eigen::Vector3d s = Eigen::Vector3d::Zero();
    for (std::size_t i = b; i < e; ++i) s += R.row(i).cwiseAbs2().transpose();
    return s;
  });
  for (int c = 0; c < 3; ++c) {
    active[c] = rhs_norm2(c) != 0.0 && !(residual2(c) < threshold(c));
    if (rhs_norm2(c) == 0.0) X.col(c).setZero();
  }
  Eigen::Vector3d rz = blocked_sum(n, [&](std::size_t b, std::size_t e) {
    Eigen::Vector3d s = Eigen::Vector3d::Zero();
    for (std::size_t i = b; i < e; ++i) {
      P.row(i) = inverse_diagonal[i] * R.row(i);
      s += R.row(i).cwiseProduct(P.row(i)).transpose();
    }
    return s;
  });

  const std::size_t max_iterations = 2 * n;
  int iterations = 0;
  for (std::size_t it = 0; it < max_iterations && (active[0] || active[1] || active[2]); ++it) {
    ++iterations;
    const Eigen::Vector3d pq = blocked_sum(n, [&](std::size_t b, std::size_t e) {
      Eigen::Vector3d s = Eigen::Vector3d::Zero();
      for (std::size_t i = b; i < e; ++i) {
        Q.row(i) = product_row(P, i);
        s += P.row(i).cwiseProduct(Q.row(i)).transpose();
      }
      return s;
    });
    Eigen::RowVector3d alpha = Eigen::RowVector3d::Zero();
    for (int c = 0; c < 3; ++c)
      if (active[c]) alpha(c) = rz(c) / pq(c);
    const std::array<Eigen::Vector3d, 2> sums = [&] {
      std::array<Eigen::Vector3d, 2> out;
      const std::size_t blocks = (n + kBlockRows - 1) / kBlockRows;
      std::vector<std::array<Eigen::Vector3d, 2>> partial(blocks);
      tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t k) {
        Eigen::Vector3d r2 = Eigen::Vector3d::Zero(), rz_new = Eigen::Vector3d::Zero();
        for (std::size_t i = k * kBlockRows; i < std::min(n, (k + 1) * kBlockRows); ++i) {
          X.row(i) += alpha.cwiseProduct(P.row(i));
          R.row(i) -= alpha.cwiseProduct(Q.row(i));
          Z.row(i) = inverse_diagonal[i] * R.row(i);
          r2 += R.row(i).cwiseAbs2().transpose();
          rz_new += R.row(i).cwiseProduct(Z.row(i)).transpose();
        }
        partial[k] = {r2, rz_new};
      });
      out = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
      for (const auto& p : partial) out[0] += p[0], out[1] += p[1];
      return out;
    }();
    residual2 = sums[0];
    Eigen::RowVector3d beta = Eigen::RowVector3d::Zero();
    std::array<bool, 3> update{};
    for (int c = 0; c < 3; ++c) {
      update[c] = active[c];
      if (!active[c]) continue;
      if (residual2(c) < threshold(c)) {
        active[c] = false;  // converged: its x is final (alpha of a stopped column stays 0)
        update[c] = false;
        continue;
      }
      beta(c) = sums[1](c) / rz(c);
      rz(c) = sums[1](c);
    }
    if (!(update[0] || update[1] || update[2])) break;
    parallel_ranges(n, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i)
        for (int c = 0; c < 3; ++c)
          if (update[c]) P(i, c) = Z(i, c) + beta(c) * P(i, c);
    });
  }
  return active[0] || active[1] || active[2] ? -1 : iterations;
}

void implicit_step(SurfaceMesh& mesh, double dt, SmoothingResult& result) {
  const std::size_t V = mesh.vertex_count();
  const std::vector<double> area = face_areas(mesh.positions, mesh.triangles);

  // w_ij = max(0, (cot α + cot β)/2) per edge; a boundary edge has only α.
  std::vector<double> edge_weight(mesh.edges.size());
  parallel_ranges(mesh.edges.size(), [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const MeshEdge& edge = mesh.edges[i];
      const double alpha = opposite_cotangent(mesh, area, edge.face[0], edge.vertex[0], edge.vertex[1]);
      const double beta = opposite_cotangent(mesh, area, edge.face[1], edge.vertex[0], edge.vertex[1]);
      edge_weight[i] = std::max(0.0, (alpha + beta) / 2.0);
    }
  });

  // Barycentric masses; a vertex without mass or on a boundary keeps its position.
  std::vector<double> mass(V);
  std::vector<std::uint8_t> fixed(V);
  parallel_ranges(V, [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) {
      double total = 0.0;
      for (std::uint32_t f : mesh.vertex_faces.row(v))
        if (area[f] >= kDegenerateArea) total += area[f];
      mass[v] = total / 3.0;
      fixed[v] = mesh.boundary_vertex[v] || !(mass[v] > 0.0);
    }
  });

  // (M + dt·L) X = M X_old, with the columns of fixed vertices moved to the right-hand side so
  // that the matrix stays symmetric. Row-major CSR with the 1-ring's ascending column order plus
  // the diagonal, written straight into Eigen's compressed storage (no triplet sort).
  const auto& ring = mesh.vertex_neighbours;
  std::vector<int> row_size(V);
  for (std::size_t v = 0; v < V; ++v) {
    int n = 1;
    if (!fixed[v])
      for (std::uint32_t u : ring.row(v)) n += fixed[u] ? 0 : 1;
    row_size[v] = n;
  }
  SparseMatrix A(static_cast<int>(V), static_cast<int>(V));
  std::vector<int> row_start(V + 1, 0);
  for (std::size_t v = 0; v < V; ++v) row_start[v + 1] = row_start[v] + row_size[v];
  A.resizeNonZeros(row_start[V]);
  std::copy(row_start.begin(), row_start.end(), A.outerIndexPtr());
  RowMatrix rhs(V, 3), x(V, 3);
  int* columns = A.innerIndexPtr();
  double* values = A.valuePtr();
  parallel_ranges(V, [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) {
      const Eigen::Vector3d& p = mesh.positions[v];
      x.row(v) = p.transpose();
      int k = row_start[v];
      if (fixed[v]) {
        columns[k] = static_cast<int>(v);
        values[k] = 1.0;
        rhs.row(v) = p.transpose();
        continue;
      }
      double diagonal = 0.0;
      Eigen::Vector3d b_v = mass[v] * p;
      bool diagonal_written = false;
      const std::uint32_t begin = ring.offsets[v], end = ring.offsets[v + 1];
      int diagonal_slot = -1;
      for (std::uint32_t s = begin; s < end; ++s) {
        const std::uint32_t u = ring.items[s];
        const double w = edge_weight[mesh.neighbour_edge[s]];
        diagonal += w;
        if (!diagonal_written && u > v) {
          diagonal_slot = k++;
          diagonal_written = true;
        }
        if (fixed[u]) {
          b_v += dt * w * mesh.positions[u];
        } else {
          columns[k] = static_cast<int>(u);
          values[k] = -dt * w;
          ++k;
        }
      }
      if (!diagonal_written) diagonal_slot = k++;
      columns[diagonal_slot] = static_cast<int>(v);
      values[diagonal_slot] = mass[v] + dt * diagonal;
      rhs.row(v) = b_v.transpose();
    }
  });

  const int iterations = solve_three_columns(A, rhs, x);
  if (iterations < 0)
    throw RuntimeFailure("smoothing: the conjugate-gradient solve did not converge; try --smoothing taubin or none");
  result.iterations = iterations;
  parallel_ranges(V, [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) mesh.positions[v] = x.row(v).transpose();
  });
}

// Taubin λ|μ: each pass moves every free vertex by f·(mean of its neighbours − itself), all from
// the previous pass's positions (simultaneous update, so the order of vertices plays no role).
void taubin(SurfaceMesh& mesh) {
  const std::size_t V = mesh.vertex_count();
  std::vector<Eigen::Vector3d> next(V);
  const double factors[2] = {0.5, -0.53};
  for (int iteration = 0; iteration < 10; ++iteration)
    for (double f : factors) {
      parallel_ranges(V, [&](std::size_t b, std::size_t e) {
        for (std::size_t v = b; v < e; ++v) {
          const auto ring = mesh.vertex_neighbours.row(v);
          if (mesh.boundary_vertex[v] || ring.empty()) {
            next[v] = mesh.positions[v];
            continue;
          }
          Eigen::Vector3d sum = Eigen::Vector3d::Zero();
          for (std::uint32_t u : ring) sum += mesh.positions[u];
          next[v] = mesh.positions[v] + f * (sum / static_cast<double>(ring.size()) - mesh.positions[v]);
        }
      });
      mesh.positions.swap(next);
    }
}

}  // namespace

double mean_edge_length(const SurfaceMesh& mesh) {
  double sum = 0.0;
  for (const MeshEdge& edge : mesh.edges) sum += (mesh.positions[edge.vertex[0]] - mesh.positions[edge.vertex[1]]).norm();
  return mesh.edges.empty() ? 0.0 : sum / static_cast<double>(mesh.edges.size());
}

SmoothingResult smooth(SurfaceMesh& mesh, const SurfaceOptions& options, double mean_edge) {
  SmoothingResult result;
  switch (options.smoothing) {
    case SmoothingMethod::none:
      break;
    case SmoothingMethod::implicit:
      result.dt = options.smoothing_strength * mean_edge * mean_edge;
      implicit_step(mesh, result.dt, result);
      break;
    case SmoothingMethod::pmp_default:
      result.dt = 1e-3;
      implicit_step(mesh, result.dt, result);
      break;
    case SmoothingMethod::taubin:
      taubin(mesh);
      break;
  }
  return result;
}

}  // namespace meshtour::surface_detail
