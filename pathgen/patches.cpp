// §6–§7: osculating tori per vertex and the toroidal-patch decomposition.
#include "pathgen/patches.h"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace meshtour::surface_detail {
namespace {

// ⌊value/bin⌋ as an integer key; non-finite or out-of-range values sort last.
std::int64_t quantize(double value, double bin) {
  const double q = std::floor(value / bin);
  constexpr double kLimit = 9.0e18;
  if (!(q > -kLimit && q < kLimit)) return std::isnan(q) || q > 0 ? std::numeric_limits<std::int64_t>::max()
                                                                   : std::numeric_limits<std::int64_t>::min();
  return static_cast<std::int64_t>(q);
}

struct SeedKey {
  std::int64_t error, x, y, z;
  std::uint32_t vertex;
  bool operator<(const SeedKey& o) const {
    if (error != o.error) return error < o.error;
    if (x != o.x) return x < o.x;
    if (y != o.y) return y < o.y;
    if (z != o.z) return z < o.z;
    return vertex < o.vertex;
  }
};

// Best vertex torus of a leftover face: (D, seed rank, vertex), smallest first (§7.4).
struct Leftover {
  double distance = std::numeric_limits<double>::infinity();
  std::uint32_t rank = std::numeric_limits<std::uint32_t>::max();
  std::uint32_t vertex = 0;
};

}  // namespace

double tolerance_unit_length(const std::vector<Eigen::Vector3d>& positions, ToleranceUnit unit) {
  if (unit == ToleranceUnit::diagonal || positions.empty()) return 1.0;
  Eigen::Vector3d lo = positions.front(), hi = positions.front();
  for (const Eigen::Vector3d& p : positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Eigen::Vector3d extent = hi - lo;
  const double diagonal = extent.norm();
  if (!(diagonal > 0.0)) return 1.0;
  const double side = extent.maxCoeff() / diagonal;
  return unit == ToleranceUnit::box_extent ? side : side / 2.0;
}

std::vector<Torus> vertex_tori(const SurfaceMesh& mesh, const std::vector<VertexDifferential>& differential,
                               double kappa_min) {
  std::vector<Torus> tori(mesh.vertex_count());
  parallel_ranges(tori.size(), [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) {
      const VertexDifferential& d = differential[v];
      tori[v] = osculating_torus(mesh.positions[v], d.normal, d.k1, d.t1, d.k2, d.t2, kappa_min);
    }
  });
  return tori;
}

std::vector<double> seed_errors(const SurfaceMesh& mesh, const std::vector<Torus>& tori) {
  std::vector<double> errors(mesh.vertex_count());
  parallel_ranges(errors.size(), [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) {
      double worst = 0.0;
      for (std::uint32_t u : mesh.vertex_neighbours.row(v)) {
        const double d = point_torus_distance(tori[v], mesh.positions[u]);
        worst = std::isnan(d) ? std::numeric_limits<double>::infinity() : std::max(worst, d);
      }
      errors[v] = worst;
    }
  });
  return errors;
}

std::vector<std::uint32_t> best_fit_first_order(const SurfaceMesh& mesh, const std::vector<double>& errors) {
  constexpr double kErrorBin = 1e-12, kPositionBin = 1e-9;
  std::vector<SeedKey> keys(mesh.vertex_count());
  parallel_ranges(keys.size(), [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) {
      const Eigen::Vector3d& p = mesh.positions[v];
      keys[v] = {quantize(errors[v], kErrorBin), quantize(p.x(), kPositionBin), quantize(p.y(), kPositionBin),
                 quantize(p.z(), kPositionBin), static_cast<std::uint32_t>(v)};
    }
  });
  // The keys are unique (the index is the last one), so any sort gives the same order.
  tbb::parallel_sort(keys.begin(), keys.end());
  std::vector<std::uint32_t> order(keys.size());
  for (std::size_t k = 0; k < keys.size(); ++k) order[k] = keys[k].vertex;
  return order;
}

Decomposition decompose(const SurfaceMesh& mesh, const std::vector<Torus>& tori, const std::vector<std::uint32_t>& seed_order,
                        const std::vector<std::uint32_t>& phase_a_seeds, const SurfaceOptions& options,
                        const std::vector<Eigen::Vector3d>* test_positions) {
  const std::size_t F = mesh.face_count();
  const double eps = options.tolerance * tolerance_unit_length(mesh.positions, options.tolerance_unit);
  const PatchTest test{options.face_samples, options.patch_measure, options.patch_normal_angle_deg};
  // The surface the faces are tested on (I-33: the unsmoothed one, in the tori's frame).
  const auto& P = test_positions ? *test_positions : mesh.positions;
  const auto within = [&](std::size_t f, const Torus& torus) {
    const auto& t = mesh.triangles[f];
    return face_within(torus, P[t[0]], P[t[1]], P[t[2]], test, eps);
  };

  Decomposition out;
  out.face_patch.assign(F, -1);
  auto& pid = out.face_patch;
  // tested[f] = number of the growth attempt that last tested f: no clearing between patches.
  std::vector<int> tested(F, -1);
  std::vector<std::uint32_t> queue;
  queue.reserve(1024);
  int attempt = 0;

  // Grows patch `id` with `torus` from the faces already in `queue` (breadth first over shared
  // edges, uncovered faces only). The accepted set does not depend on the traversal order.
  const auto grow = [&](int id, const Torus& torus) {
    for (std::size_t head = 0; head < queue.size(); ++head)
      for (std::int32_t g : mesh.face_neighbours[queue[head]]) {
        if (g < 0 || pid[g] >= 0 || tested[g] == attempt) continue;
        tested[g] = attempt;
        if (within(static_cast<std::size_t>(g), torus)) {
          pid[g] = id;
          queue.push_back(static_cast<std::uint32_t>(g));
        }
      }
  };

  // Phase A (sequential: each patch takes faces the next one can no longer have).
  const std::vector<std::uint32_t>& visit = phase_a_seeds.empty() ? seed_order : phase_a_seeds;
  for (std::uint32_t v : visit) {
    const auto faces = mesh.vertex_faces.row(v);
    if (std::any_of(faces.begin(), faces.end(), [&](std::uint32_t f) { return pid[f] >= 0; })) continue;
    const Torus& torus = tori[v];
    const int id = static_cast<int>(out.patches.size());
    ++attempt;
    queue.clear();
    for (std::uint32_t f : faces) {
      tested[f] = attempt;
      if (within(f, torus)) {
        pid[f] = id;
        queue.push_back(f);
      }
    }
    if (queue.empty()) continue;
    grow(id, torus);
    out.patches.push_back({PatchRecord::Kind::grown, v, torus, static_cast<int>(queue.size()), true});
  }
  out.grown = static_cast<int>(out.patches.size());

  // Phase B: the best vertex torus of every leftover face (independent decisions, parallel).
  std::vector<std::uint32_t> rank(mesh.vertex_count());
  for (std::size_t k = 0; k < seed_order.size(); ++k) rank[seed_order[k]] = static_cast<std::uint32_t>(k);
  std::vector<Leftover> best(F);
  parallel_ranges(F, [&](std::size_t b, std::size_t e) {
    for (std::size_t f = b; f < e; ++f) {
      if (pid[f] >= 0) continue;
      const auto& t = mesh.triangles[f];
      for (std::uint32_t u : t) {
        double d = face_torus_distance(tori[u], P[t[0]], P[t[1]], P[t[2]], test);
        if (std::isnan(d)) d = std::numeric_limits<double>::infinity();
        if (d < best[f].distance || (d == best[f].distance && rank[u] < best[f].rank)) best[f] = {d, rank[u], u};
      }
    }
  });
  // Ids in ascending face order.
  for (std::size_t f = 0; f < F; ++f) {
    if (pid[f] >= 0) continue;
    const Leftover& choice = best[f];
    const bool accurate = choice.distance <= eps;
    if (!accurate && !options.keep_inaccurate_patches) continue;
    const int id = static_cast<int>(out.patches.size());
    pid[f] = id;
    const Torus& torus = tori[choice.vertex];
    int size = 1;
    if (accurate && options.leftovers == LeftoverMode::grow) {
      ++attempt;
      tested[f] = attempt;
      queue.assign(1, static_cast<std::uint32_t>(f));
      grow(id, torus);
      size = static_cast<int>(queue.size());
    }
    out.patches.push_back({PatchRecord::Kind::single, choice.vertex, torus, size, accurate});
  }
  out.single = static_cast<int>(out.patches.size()) - out.grown;
  for (std::size_t f = 0; f < F; ++f) out.orphans += pid[f] < 0 ? 1 : 0;
  for (const PatchRecord& p : out.patches) out.largest = std::max(out.largest, p.face_count);
  return out;
}

}  // namespace meshtour::surface_detail
