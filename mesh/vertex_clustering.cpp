#include "mesh/vertex_clustering.h"

#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <tuple>
#include <unordered_map>

#include "core/error.h"
#include "core/interrupt.h"
#include "core/triangle_geometry.h"

namespace meshtour {
namespace {

// Cell key: 21 bits per axis (2 million cells along an axis is far beyond any target). Grid
// coordinates are at least 0.5 (the origin is half a cell below the bounds).
using Cell = std::array<long long, 3>;
std::uint64_t cell_key(const Cell& c) {
  auto axis = [](long long x) { return static_cast<std::uint64_t>(std::clamp<long long>(x, 0, 2097151)); };
  return (axis(c[0]) << 42) | (axis(c[1]) << 21) | axis(c[2]);
}
Cell cell_of(const Eigen::Vector3d& q) {
  return {static_cast<long long>(std::floor(q.x())), static_cast<long long>(std::floor(q.y())),
          static_cast<long long>(std::floor(q.z()))};
}

// A convex polygon in grid units: a triangle clipped by axis planes has at most 3 + 6 corners.
struct Polygon {
  std::array<Eigen::Vector3d, 12> p;
  int n = 0;
};

// Cuts `poly` at the plane x[axis] = k into the parts below and above.
void cut(const Polygon& poly, int axis, double k, Polygon& below, Polygon& above) {
  below.n = above.n = 0;
  for (int i = 0; i < poly.n; ++i) {
    const Eigen::Vector3d& a = poly.p[i];
    const Eigen::Vector3d& b = poly.p[(i + 1) % poly.n];
    const double da = a[axis] - k, db = b[axis] - k;
    if (da <= 0.0) below.p[below.n++] = a;
    if (da >= 0.0) above.p[above.n++] = a;
    if ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0)) {
      Eigen::Vector3d x = a + (b - a) * (da / (da - db));
      x[axis] = k;
      below.p[below.n++] = x;
      above.p[above.n++] = x;
    }
  }
}

// Calls `emit` with the pieces of `poly` between consecutive integer planes along `axis`.
template <class Emit>
void slabs(const Polygon& poly, int axis, Emit&& emit) {
  double lo = poly.p[0][axis], hi = lo;
  for (int i = 1; i < poly.n; ++i) {
    lo = std::min(lo, poly.p[i][axis]);
    hi = std::max(hi, poly.p[i][axis]);
  }
  if (std::floor(lo) + 1.0 >= hi) return emit(poly);  // within one slab (most faces of a fine mesh)
  Polygon rest = poly, below, above;
  for (double k = std::floor(lo) + 1.0; k < hi; k += 1.0) {
    cut(rest, axis, k, below, above);
    if (below.n >= 3) emit(below);
    rest = above;
    if (rest.n < 3) return;
  }
  emit(rest);
}

// The proxy vertex of cell `c`, -1 if the surface has no area in it.
long long vertex_in(const std::vector<std::uint64_t>& keys, const Cell& c) {
  const std::uint64_t k = cell_key(c);
  const auto it = std::lower_bound(keys.begin(), keys.end(), k);
  return it != keys.end() && *it == k ? static_cast<long long>(it - keys.begin()) : -1;
}

struct Moments {
  double area = 0.0;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();  // area × centroid, grid units
  // The area-weighted quadric of the planes of the surface in the cell: Σ a n nᵀ and Σ a n (n·p).
  Eigen::Matrix3d quadric = Eigen::Matrix3d::Zero();
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  void add(const Moments& o) {
    area += o.area;
    moment += o.moment;
    quadric += o.quadric;
    offset += o.offset;
  }
};

// Where the surface crosses a cell edge: the edge runs along `axis` from grid point `point`; `t` is
// the crossing's coordinate along the axis, `facing` the sign of the surface normal along it.
struct Crossing {
  std::uint64_t point;
  int axis;
  double t;
  int facing;
  bool operator<(const Crossing& o) const { return std::tie(axis, point, t, facing) < std::tie(o.axis, o.point, o.t, o.facing); }
};

struct Chunk {
  std::vector<std::pair<std::uint64_t, Moments>> cells;  // sorted by key
  std::vector<Crossing> crossings;
};

struct CellSums {
  std::unordered_map<std::uint64_t, Moments> map;
  std::uint64_t last_key = 0;
  Moments* last = nullptr;
};

// One triangle (grid units): its area and centroid per cell, and the cell edges it crosses.
void add_triangle(const std::array<Eigen::Vector3d, 3>& q, CellSums& cells, std::vector<Crossing>& crossings) {
  const Eigen::Vector3d normal = triangle_normal(q[0], q[1], q[2]);
  Polygon tri;
  tri.n = 3;
  for (int i = 0; i < 3; ++i) tri.p[i] = q[i];
  slabs(tri, 0, [&](const Polygon& a) {
    slabs(a, 1, [&](const Polygon& b) {
      slabs(b, 2, [&](const Polygon& piece) {
        Moments m;
        for (int i = 1; i + 1 < piece.n; ++i) {
          const double area = triangle_area(piece.p[0], piece.p[i], piece.p[i + 1]);
          m.area += area;
          m.moment += area * (piece.p[0] + piece.p[i] + piece.p[i + 1]) / 3.0;
        }
        if (!(m.area > 0.0)) return;
        m.quadric = m.area * normal * normal.transpose();
        m.offset = m.area * normal * normal.dot(m.moment / m.area);
        // The piece lies in one cell; its centroid is inside it, away from the cell's faces.
        // Consecutive faces mostly lie in the same cell: the last one is kept at hand (a map's
        // elements stay where they are when it grows).
        const std::uint64_t key = cell_key(cell_of(m.moment / m.area));
        if (key != cells.last_key || !cells.last) {
          cells.last = &cells.map[key];
          cells.last_key = key;
        }
        cells.last->add(m);
      });
    });
  });
  // Grid lines along `a` pass through integer (b, c); a line inside the triangle's projection
  // crosses it. Points on the projection's boundary count (a neighbour may count them again: one
  // crossing per cell edge is kept).
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    const double s = (q[1][b] - q[0][b]) * (q[2][c] - q[0][c]) - (q[1][c] - q[0][c]) * (q[2][b] - q[0][b]);
    if (!(s != 0.0) || !std::isfinite(s)) continue;
    const double blo = std::min({q[0][b], q[1][b], q[2][b]}), bhi = std::max({q[0][b], q[1][b], q[2][b]});
    const double clo = std::min({q[0][c], q[1][c], q[2][c]}), chi = std::max({q[0][c], q[1][c], q[2][c]});
    for (double j = std::ceil(blo); j <= bhi; j += 1.0)
      for (double k = std::ceil(clo); k <= chi; k += 1.0) {
        auto edge = [&](int u, int v) {  // twice the signed area of (q[u], q[v], point) in (b, c)
          return (q[v][b] - q[u][b]) * (k - q[u][c]) - (q[v][c] - q[u][c]) * (j - q[u][b]);
        };
        const double w0 = edge(1, 2) / s, w1 = edge(2, 0) / s, w2 = edge(0, 1) / s;
        if (w0 < 0.0 || w1 < 0.0 || w2 < 0.0) continue;
        const double t = (w0 * q[0][a] + w1 * q[1][a] + w2 * q[2][a]) / (w0 + w1 + w2);
        Cell point{};
        point[a] = static_cast<long long>(std::floor(t));
        point[b] = static_cast<long long>(j);
        point[c] = static_cast<long long>(k);
        crossings.push_back({cell_key(point), a, t, s > 0.0 ? 1 : -1});
      }
  }
}

// The point of a cell that best fits the planes of the surface in it (area-weighted quadric
// error), found from the centroid along the directions the planes pin down (eigenvalues above a
// tenth of the largest: a flat piece moves only along its normal, onto the surface), and kept in
// the cell. The centroid alone lies off a curved surface by an amount that changes with how the
// cell cuts it, which reads as curvature noise on the grid.
Eigen::Vector3d representative(const Moments& m, std::uint64_t key) {
  const Eigen::Vector3d c = m.moment / m.area;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(m.quadric / m.area);
  const Eigen::Vector3d r = (m.offset - m.quadric * c) / m.area;
  const double largest = eigen.eigenvalues().maxCoeff();
  Eigen::Vector3d x = c;
  for (int k = 0; k < 3; ++k)
    if (eigen.eigenvalues()[k] > 0.1 * largest && largest > 0.0)
      x += eigen.eigenvectors().col(k) * (eigen.eigenvectors().col(k).dot(r) / eigen.eigenvalues()[k]);
  const Eigen::Vector3d lo(static_cast<double>(key >> 42), static_cast<double>((key >> 21) & 0x1FFFFF), static_cast<double>(key & 0x1FFFFF));
  return x.cwiseMax(lo).cwiseMin(lo + Eigen::Vector3d::Ones());
}

}  // namespace

std::uint32_t ClusteredMesh::vertex_near(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d q = (p - grid_origin) / cell_size;
  if (!q.allFinite()) return 0;
  const Cell c = cell_of(q);
  if (const long long v = vertex_in(cell_keys, c); v >= 0) return static_cast<std::uint32_t>(v);
  std::uint32_t best = 0;
  double closest = std::numeric_limits<double>::infinity();
  for (long long dx = -1; dx <= 1; ++dx)
    for (long long dy = -1; dy <= 1; ++dy)
      for (long long dz = -1; dz <= 1; ++dz) {
        const long long v = vertex_in(cell_keys, {c[0] + dx, c[1] + dy, c[2] + dz});
        if (v < 0) continue;
        const double d = (mesh.positions[static_cast<std::size_t>(v)] - p).squaredNorm();
        if (d < closest) {
          closest = d;
          best = static_cast<std::uint32_t>(v);
        }
      }
  return best;
}

ClusteredMesh cluster_surface(const TriangleMesh& mesh, std::size_t target_cells, bool centred_grid) {
  if (target_cells < 1) throw InputError("surface clustering needs at least one cell");
  double total = 0.0;
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
    const double area = triangle_area(a, b, c);
    if (std::isfinite(area)) total += area;
  }
  if (!(total > 0.0)) throw InputError("the mesh has no surface area to simplify");
  throw_if_interrupted();

  ClusteredMesh out;
  const Bounds bounds = mesh.bounds();
  out.cell_size = std::sqrt(total / static_cast<double>(target_cells));
  out.grid_origin = bounds.lo - Eigen::Vector3d::Constant(0.5 * out.cell_size);
  if (centred_grid) {
    // Cell boundaries at the centre +- (k + 1/2) cells: a set that mirrors onto itself.
    const Eigen::Vector3d centre = 0.5 * (bounds.lo + bounds.hi);
    const Eigen::Vector3d half_cells = (0.5 * (bounds.hi - bounds.lo) / out.cell_size).array().ceil();
    out.grid_origin = centre - (half_cells + Eigen::Vector3d::Constant(0.5)) * out.cell_size;
  }
  const double inverse = 1.0 / out.cell_size;
  auto grid = [&](const Eigen::Vector3d& p) -> Eigen::Vector3d { return (p - out.grid_origin) * inverse; };

  // Fixed chunks of faces (not one per thread), merged in chunk order: every cell's sums are
  // added in the same order whatever the thread count.
  constexpr std::size_t kChunk = 1u << 15;
  const std::size_t faces = mesh.triangles.size();
  std::vector<Chunk> chunks((faces + kChunk - 1) / kChunk);
  tbb::parallel_for(std::size_t{0}, chunks.size(), [&](std::size_t ci) {
    if (interrupt_requested()) return;
    CellSums cells;
    Chunk& chunk = chunks[ci];
    for (std::size_t f = ci * kChunk; f < std::min(faces, (ci + 1) * kChunk); ++f) {
      const auto& t = mesh.triangles[f];
      const std::array<Eigen::Vector3d, 3> q{grid(mesh.positions[t[0]]), grid(mesh.positions[t[1]]), grid(mesh.positions[t[2]])};
      if (!q[0].allFinite() || !q[1].allFinite() || !q[2].allFinite()) continue;
      add_triangle(q, cells, chunk.crossings);
    }
    chunk.cells.assign(cells.map.begin(), cells.map.end());
    std::sort(chunk.cells.begin(), chunk.cells.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  });
  throw_if_interrupted();

  std::vector<std::pair<std::uint64_t, Moments>> all;
  std::vector<Crossing> crossings;
  for (Chunk& c : chunks) {
    all.insert(all.end(), c.cells.begin(), c.cells.end());
    crossings.insert(crossings.end(), c.crossings.begin(), c.crossings.end());
    c = Chunk{};
  }
  std::stable_sort(all.begin(), all.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  std::vector<std::uint64_t>& keys = out.cell_keys;
  for (std::size_t i = 0; i < all.size();) {
    Moments m;
    std::size_t j = i;
    for (; j < all.size() && all[j].first == all[i].first; ++j) {
      m.add(all[j].second);
    }
    keys.push_back(all[i].first);
    out.mesh.positions.push_back(out.grid_origin + out.cell_size * representative(m, all[i].first));
    i = j;
  }
  auto vertex_of = [&](const Cell& c) { return vertex_in(keys, c); };

  // One quad per cell edge the surface crosses, as in dual contouring: the crossings along an edge
  // are counted with their facing (one crossing found by two triangles, on their shared edge,
  // counts once), and an edge the surface enters and leaves again (a sphere's grazing edge, both
  // sides of a thin part) has none.
  std::sort(crossings.begin(), crossings.end());
  struct Key {
    std::array<std::uint32_t, 3> sorted, corners;
  };
  std::vector<Key> triangles;
  for (std::size_t i = 0; i < crossings.size();) {
    const Crossing& x = crossings[i];
    int net = 0;
    std::size_t j = i;
    for (; j < crossings.size() && crossings[j].axis == x.axis && crossings[j].point == x.point; ++j) {
      const bool again = j > i && crossings[j - 1].facing == crossings[j].facing && crossings[j].t - crossings[j - 1].t < 1e-9;
      if (!again) net += crossings[j].facing;
    }
    i = j;
    if (net == 0) continue;
    const int a = x.axis, b = (a + 1) % 3, c = (a + 2) % 3;
    const Cell p{static_cast<long long>(x.point >> 42), static_cast<long long>((x.point >> 21) & 0x1FFFFF),
                 static_cast<long long>(x.point & 0x1FFFFF)};
    // Counter-clockwise around +axis: (b-1, c-1), (b, c-1), (b, c), (b-1, c).
    std::array<long long, 4> v{};
    const int db[4] = {-1, 0, 0, -1}, dc[4] = {-1, -1, 0, 0};
    for (int corner = 0; corner < 4; ++corner) {
      Cell q = p;
      q[b] += db[corner];
      q[c] += dc[corner];
      v[corner] = vertex_of(q);
    }
    if (net < 0) std::swap(v[1], v[3]);
    const auto& P = out.mesh.positions;
    auto at = [&](int corner) { return P[static_cast<std::size_t>(v[corner])]; };
    auto add = [&](int i0, int i1, int i2) {
      if (v[i0] < 0 || v[i1] < 0 || v[i2] < 0) return;
      std::array<std::uint32_t, 3> t{static_cast<std::uint32_t>(v[i0]), static_cast<std::uint32_t>(v[i1]), static_cast<std::uint32_t>(v[i2])};
      std::array<std::uint32_t, 3> s = t;
      std::sort(s.begin(), s.end());
      triangles.push_back({s, t});
    };
    const bool all_there = v[0] >= 0 && v[1] >= 0 && v[2] >= 0 && v[3] >= 0;
    if (all_there && (at(1) - at(3)).squaredNorm() < (at(0) - at(2)).squaredNorm()) {
      add(0, 1, 3);
      add(1, 2, 3);
    } else {
      add(0, 1, 2);
      add(0, 2, 3);
    }
  }
  std::sort(triangles.begin(), triangles.end(), [](const Key& x, const Key& y) {
    return x.sorted != y.sorted ? x.sorted < y.sorted : x.corners < y.corners;
  });
  for (std::size_t k = 0; k < triangles.size(); ++k)
    if (k == 0 || triangles[k].sorted != triangles[k - 1].sorted) out.mesh.triangles.push_back(triangles[k].corners);
  throw_if_interrupted();

  return out;
}

}  // namespace meshtour
