// §5: vertex normals and the Goldfeather–Interrante cubic-order curvature fit.
#include "pathgen/curvature.h"

#include <tbb/enumerable_thread_specific.h>

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <optional>

#include "core/triangle_geometry.h"

namespace meshtour::surface_detail {
namespace {

// A neighbour in the local frame: unscaled coordinates (x, y, z), its distance, and its normal in
// the frame (a, b, c).
struct LocalNeighbour {
  Eigen::Vector3d xyz;
  double distance;
  Eigen::Vector3d abc;
};

bool lexicographic_less(const LocalNeighbour& p, const LocalNeighbour& q) {
  if (p.xyz.x() != q.xyz.x()) return p.xyz.x() < q.xyz.x();
  if (p.xyz.y() != q.xyz.y()) return p.xyz.y() < q.xyz.y();
  return p.xyz.z() < q.xyz.z();
}

// Least squares M β = r with a rank-revealing QR; nullopt if the rank is below the unknown count.
// Small systems (the usual 1-ring) live in fixed-capacity storage: no heap allocation per vertex.
template <class Matrix, class Vector>
std::optional<Eigen::Vector3d> solve_fit(const std::vector<LocalNeighbour>& set, double scale, int unknowns, int rows) {
  Matrix M(rows, unknowns);
  Vector r(rows);
  int row = 0;
  for (const LocalNeighbour& n : set) {
    const double x = n.xyz.x() / scale, y = n.xyz.y() / scale, z = n.xyz.z() / scale;
    M.row(row).setZero();
    M(row, 0) = x * x / 2;
    M(row, 1) = x * y;
    M(row, 2) = y * y / 2;
    if (unknowns == 7) {
      M(row, 3) = x * x * x;
      M(row, 4) = x * x * y;
      M(row, 5) = x * y * y;
      M(row, 6) = y * y * y;
    }
    r(row++) = z;
    // Slope rows only where the neighbour's normal is not nearly tangent or flipped (c ≥ 0.1).
    if (!(n.abc.z() >= 0.1)) continue;
    M.row(row).setZero();
    M(row, 0) = x;
    M(row, 1) = y;
    if (unknowns == 7) {
      M(row, 3) = 3 * x * x;
      M(row, 4) = 2 * x * y;
      M(row, 5) = y * y;
    }
    r(row++) = -n.abc.x() / n.abc.z();
    M.row(row).setZero();
    M(row, 1) = x;
    M(row, 2) = y;
    if (unknowns == 7) {
      M(row, 4) = x * x;
      M(row, 5) = 2 * x * y;
      M(row, 6) = 3 * y * y;
    }
    r(row++) = -n.abc.y() / n.abc.z();
  }
  Eigen::ColPivHouseholderQR<Matrix> qr(M);
  if (qr.rank() < unknowns) return std::nullopt;
  const auto beta = qr.solve(r).eval();
  if (!beta.allFinite()) return std::nullopt;
  return Eigen::Vector3d(beta(0), beta(1), beta(2));
}

// Fits on one neighbour set; returns the unscaled (A, B, C) or nullopt (too few rows, rank loss).
std::optional<Eigen::Vector3d> fit_set(const std::vector<LocalNeighbour>& set, int unknowns) {
  if (set.empty()) return std::nullopt;
  // ℓ summed in the sorted order, so that it does not depend on the vertex numbering either.
  double sum = 0.0;
  for (const LocalNeighbour& n : set) sum += n.distance;
  const double scale = sum / static_cast<double>(set.size());
  if (!(scale > 0.0) || !std::isfinite(scale)) return std::nullopt;
  int rows = 0;
  for (const LocalNeighbour& n : set) rows += n.abc.z() >= 0.1 ? 3 : 1;
  if (rows < unknowns) return std::nullopt;
  constexpr int kFixedRows = 72;  // 24 neighbours with slope rows
  std::optional<Eigen::Vector3d> abc;
  if (rows <= kFixedRows) {
    using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, kFixedRows, 7>;
    using Vector = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kFixedRows, 1>;
    abc = solve_fit<Matrix, Vector>(set, scale, unknowns, rows);
  } else {
    abc = solve_fit<Eigen::MatrixXd, Eigen::VectorXd>(set, scale, unknowns, rows);
  }
  if (abc) *abc /= scale;  // A = Ã/ℓ, B = B̃/ℓ, C = C̃/ℓ
  return abc;
}

void to_local(const Eigen::Vector3d& p, const Eigen::Vector3d& X, const Eigen::Vector3d& Y, const Eigen::Vector3d& N,
              std::span<const FitNeighbour> ring, std::vector<LocalNeighbour>& out) {
  out.clear();
  for (const FitNeighbour& q : ring) {
    const Eigen::Vector3d d = q.position - p;
    out.push_back({Eigen::Vector3d(d.dot(X), d.dot(Y), d.dot(N)), d.norm(),
                   Eigen::Vector3d(q.normal.dot(X), q.normal.dot(Y), q.normal.dot(N))});
  }
  // Exact lexicographic order of the local coordinates: the rows, and so the rounding of the
  // solve, do not depend on how the file numbers its vertices.
  std::sort(out.begin(), out.end(), lexicographic_less);
}

struct Scratch {
  std::vector<FitNeighbour> ring1, ring2;
  std::vector<std::uint32_t> ids;
  std::vector<LocalNeighbour> local;
};

}  // namespace

std::pair<Eigen::Vector3d, Eigen::Vector3d> tangent_frame(const Eigen::Vector3d& N) {
  int axis = 0;
  for (int c = 1; c < 3; ++c)
    if (std::abs(N(c)) < std::abs(N(axis))) axis = c;
  const Eigen::Vector3d e = Eigen::Vector3d::Unit(axis);
  const Eigen::Vector3d X = (e - e.dot(N) * N).normalized();
  return {X, N.cross(X)};
}

std::vector<Eigen::Vector3d> vertex_normals(const SurfaceMesh& mesh) {
  const std::size_t F = mesh.face_count();
  std::vector<Eigen::Vector3d> face_cross(F), face_normal(F);
  std::vector<std::uint8_t> valid(F);
  parallel_ranges(F, [&](std::size_t b, std::size_t e) {
    for (std::size_t f = b; f < e; ++f) {
      const auto& t = mesh.triangles[f];
      face_cross[f] = triangle_cross(mesh.positions, t);
      const double length = face_cross[f].norm();
      valid[f] = 0.5 * length >= kDegenerateArea;
      face_normal[f] = valid[f] ? (face_cross[f] / length).eval() : Eigen::Vector3d::Zero();
    }
  });
  std::vector<Eigen::Vector3d> normals(mesh.vertex_count());
  parallel_ranges(normals.size(), [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) {
      const Eigen::Vector3d& p = mesh.positions[v];
      Eigen::Vector3d angle_sum = Eigen::Vector3d::Zero(), area_sum = Eigen::Vector3d::Zero();
      int first_valid = -1;
      for (std::uint32_t f : mesh.vertex_faces.row(v)) {
        if (!valid[f]) continue;
        if (first_valid < 0) first_valid = static_cast<int>(f);
        const auto& t = mesh.triangles[f];
        const int k = t[0] == v ? 0 : (t[1] == v ? 1 : 2);
        const Eigen::Vector3d a = mesh.positions[t[(k + 1) % 3]] - p, c = mesh.positions[t[(k + 2) % 3]] - p;
        const double angle = std::atan2(a.cross(c).norm(), a.dot(c));
        angle_sum += angle * face_normal[f];
        area_sum += face_cross[f];
      }
      if (angle_sum.norm() > 0.0)
        normals[v] = angle_sum.normalized();
      else if (area_sum.norm() > 0.0)
        normals[v] = area_sum.normalized();
      else if (first_valid >= 0)
        normals[v] = face_normal[first_valid];
      else
        normals[v] = Eigen::Vector3d::UnitZ();
    }
  });
  return normals;
}

namespace {

// §5.3 with its fallbacks, then §5.4. `ring2()` gathers the 2-ring only when it is needed.
template <class Ring2>
VertexDifferential fit_with_fallbacks(const Eigen::Vector3d& p, const Eigen::Vector3d& N, std::span<const FitNeighbour> ring1,
                                      const Ring2& ring2, CurvatureFit fit, std::vector<LocalNeighbour>& local) {
  const auto [X, Y] = tangent_frame(N);
  const int unknowns = fit == CurvatureFit::cubic ? 7 : 3;
  to_local(p, X, Y, N, ring1, local);
  std::optional<Eigen::Vector3d> abc = fit_set(local, unknowns);
  if (!abc) {
    // Fallback 1: the vertex-based 2-ring; fallback 2: the quadratic part only, on that set.
    to_local(p, X, Y, N, ring2(), local);
    abc = fit_set(local, unknowns);
    if (!abc && unknowns == 7) abc = fit_set(local, 3);
  }
  VertexDifferential d;
  d.normal = N;
  if (!abc) {  // fallback 3: give up, treat the point as flat
    d.t1 = X;
    d.t2 = Y;
    return d;
  }
  const double A = (*abc)(0), B = (*abc)(1), C = (*abc)(2);
  const double mean = (A + C) / 2, radius = std::sqrt(((A - C) / 2) * ((A - C) / 2) + B * B);
  const double plus = mean + radius, minus = mean - radius;
  const double phi = 0.5 * std::atan2(2 * B, A - C);
  const Eigen::Vector3d e_plus = std::cos(phi) * X + std::sin(phi) * Y;
  const Eigen::Vector3d e_minus = -std::sin(phi) * X + std::cos(phi) * Y;
  if (std::abs(plus) <= std::abs(minus)) {
    d.k1 = plus, d.t1 = e_plus, d.k2 = minus, d.t2 = e_minus;
  } else {
    d.k1 = minus, d.t1 = e_minus, d.k2 = plus, d.t2 = e_plus;
  }
  return d;
}

}  // namespace

VertexDifferential fit_vertex(const Eigen::Vector3d& p, const Eigen::Vector3d& N, std::span<const FitNeighbour> ring1,
                              std::span<const FitNeighbour> ring2, CurvatureFit fit) {
  std::vector<LocalNeighbour> local;
  return fit_with_fallbacks(p, N, ring1, [&] { return ring2; }, fit, local);
}

std::vector<VertexDifferential> principal_curvatures(const SurfaceMesh& mesh, const std::vector<Eigen::Vector3d>& normals,
                                                     CurvatureFit fit) {
  std::vector<VertexDifferential> out(mesh.vertex_count());
  tbb::enumerable_thread_specific<Scratch> scratch;
  parallel_ranges(out.size(), [&](std::size_t b, std::size_t e) {
    Scratch& s = scratch.local();
    for (std::size_t v = b; v < e; ++v) {
      s.ring1.clear();
      for (std::uint32_t u : mesh.vertex_neighbours.row(v)) s.ring1.push_back({mesh.positions[u], normals[u]});
      const auto ring2 = [&]() -> std::span<const FitNeighbour> {
        s.ids.clear();
        for (std::uint32_t u : mesh.vertex_neighbours.row(v)) {
          s.ids.push_back(u);
          for (std::uint32_t w : mesh.vertex_neighbours.row(u))
            if (w != v) s.ids.push_back(w);
        }
        std::sort(s.ids.begin(), s.ids.end());
        s.ids.erase(std::unique(s.ids.begin(), s.ids.end()), s.ids.end());
        s.ring2.clear();
        for (std::uint32_t u : s.ids) s.ring2.push_back({mesh.positions[u], normals[u]});
        return s.ring2;
      };
      out[v] = fit_with_fallbacks(mesh.positions[v], normals[v], s.ring1, ring2, fit, s.local);
    }
  });
  return out;
}

}  // namespace meshtour::surface_detail
