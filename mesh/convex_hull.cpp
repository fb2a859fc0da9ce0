// Convex hull vertices through Qhull (reentrant libqhull_r), in parallel blocks.
//
// Why Qhull rather than a quickhull of our own: the hard part of a 3D hull is not the algorithm
// but floating-point robustness on scanned and CAD meshes (nearly coplanar facets, points within
// rounding of a facet, duplicates), which Qhull handles by merging facets with tolerances derived
// from the input's rounding error and has done on decades of degenerate input. Its option 'Qc'
// keeps the points it finds within rounding of a facet (including vertices it merged away), which
// is what makes the reduction safe: a point is dropped only when it is clearly inside.
//
// Why blocks: Qhull cannot be interrupted and runs on one core. The points are cut into blocks
// of a fixed size (never dependent on the thread count, so the result is the same for any), each
// block's hull is computed in parallel, and the hulls of groups of blocks' survivors are merged
// round by round until one is left; the hull of the union of hulls is the hull of all points.
// Interrupts are checked between blocks.
#include "mesh/convex_hull.h"

#include <Eigen/Geometry>
#include <libqhull_r/libqhull_r.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <numeric>
#include <string>

#include "core/error.h"
#include "core/interrupt.h"

namespace meshtour {
namespace {

// Points per block of the first round: big enough that Qhull's set-up cost is small against the
// block's work, small enough that an interrupt is noticed within milliseconds and that both
// cores have blocks to share on a mid-size mesh.
constexpr std::size_t kBlockPoints = std::size_t{1} << 15;
// Blocks whose survivors are merged into one hull per task of the later rounds.
constexpr std::size_t kMergeFanIn = 8;
// A set whose points all lie within this share of its size (or of its coordinates' magnitude,
// whichever is larger) from a plane is treated as flat. Qhull calls a set flat when it is within
// its own rounding estimate (~1e-15 of the coordinates' magnitude) of a plane, far below this, so
// only sets that Qhull has refused are measured against it.
constexpr double kFlatShare = 1e-12;

// What one Qhull run found: the positions (0 .. count-1 in its input) of the hull's vertices and
// of the points it kept as coplanar; or its exit code and message when it failed.
struct QhullOutcome {
  int exit_code = qh_ERRnone;
  std::string message;
  std::vector<std::size_t> kept;
};

// One Qhull session, released on every path out (Qhull's own memory, and the stream that collects
// its messages so they never reach the user's terminal).
class QhullSession {
public:
  QhullSession() : qh_(std::make_unique<qhT>()) {
    errors_ = open_memstream(&error_text_, &error_size_);
    if (!errors_) throw RuntimeFailure("convex hull: could not open a stream for Qhull's messages");
    qh_zero(qh_.get(), errors_);
  }
  ~QhullSession() {
    int still_long = 0, total_long = 0;
    qh_freeqhull(qh_.get(), !qh_ALL);
    qh_memfreeshort(qh_.get(), &still_long, &total_long);
    std::fclose(errors_);
    std::free(error_text_);
  }
  QhullSession(const QhullSession&) = delete;
  QhullSession& operator=(const QhullSession&) = delete;

  qhT* get() { return qh_.get(); }
  FILE* errors() { return errors_; }
  std::string message() {
    std::fflush(errors_);
    return error_text_ ? std::string(error_text_, error_size_) : std::string();
  }

private:
  std::unique_ptr<qhT> qh_;
  FILE* errors_ = nullptr;
  char* error_text_ = nullptr;
  std::size_t error_size_ = 0;
};

// Qhull on `coords.size() / dim` points of `dim` coordinates each (row-major). 'Qc' keeps the
// points within rounding of a facet; Qhull's default merging ('C-0', 'Qx') keeps the facets
// convex under rounding. `coords` must stay alive while Qhull runs (it points into it).
QhullOutcome run_qhull(int dim, std::vector<double>& coords) {
  QhullOutcome out;
  const auto count = coords.size() / static_cast<std::size_t>(dim);
  if (count > static_cast<std::size_t>(std::numeric_limits<int>::max() / 4))
    throw InputError("convex hull: too many points for Qhull (" + std::to_string(count) + ")");
  QhullSession session;
  char command[] = "qhull Qc";
  out.exit_code = qh_new_qhull(session.get(), dim, static_cast<int>(count), coords.data(), False, command, nullptr,
                               session.errors());
  if (out.exit_code != qh_ERRnone) {
    out.message = session.message();
    return out;
  }
  // The names Qhull's iteration macros expect.
  qhT* qh = session.get();
  facetT* facet = nullptr;
  vertexT* vertex = nullptr;
  pointT *point = nullptr, **pointp = nullptr;
  const auto keep = [&](pointT* p) {
    const int id = qh_pointid(qh, p);
    if (id >= 0 && static_cast<std::size_t>(id) < count) out.kept.push_back(static_cast<std::size_t>(id));
  };
  FORALLvertices keep(vertex->point);
  FORALLfacets {
    if (facet->coplanarset) {
      FOREACHpoint_(facet->coplanarset) keep(point);
    }
  }
  return out;
}

double largest_magnitude(std::span<const Eigen::Vector3d> points, const std::vector<std::size_t>& ids) {
  double m = 0.0;
  for (std::size_t i : ids) m = std::max(m, points[i].cwiseAbs().maxCoeff());
  return m;
}

// The hull of a set Qhull refused. Qhull refuses sets with no volume (all points in a plane, on a
// line or at one place); a set that does have volume (Qhull failed for another reason) is kept
// whole, which is always a correct superset.
std::vector<std::size_t> degenerate_hull(std::span<const Eigen::Vector3d> points, const std::vector<std::size_t>& ids) {
  const auto farthest_from = [&](auto&& distance) {
    std::size_t best = ids.front();
    double best_distance = -1.0;
    for (std::size_t i : ids)
      if (const double d = distance(points[i]); d > best_distance) best = i, best_distance = d;
    return std::pair{best, best_distance};
  };
  // Two points about as far apart as any (at least half the diameter), then the one farthest from
  // their line, span the plane of a flat set.
  const Eigen::Vector3d& p0 = points[ids.front()];
  const auto [ia, da] = farthest_from([&](const Eigen::Vector3d& p) { return (p - p0).norm(); });
  if (!(da > 0.0)) return {ids.front()};  // every point at one place
  const Eigen::Vector3d a = points[ia];
  const auto [ib, db] = farthest_from([&](const Eigen::Vector3d& p) { return (p - a).norm(); });
  const Eigen::Vector3d e1 = (points[ib] - a) / db;
  const double tolerance = kFlatShare * std::max(db, largest_magnitude(points, ids));
  const auto off_line = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3d d = p - a;
    return (d - d.dot(e1) * e1).norm();
  };
  const auto [ic, dc] = farthest_from(off_line);
  if (dc <= tolerance) {
    // On a line: its two ends.
    std::size_t lo = ids.front(), hi = ids.front();
    double lo_t = std::numeric_limits<double>::infinity(), hi_t = -lo_t;
    for (std::size_t i : ids) {
      const double t = (points[i] - a).dot(e1);
      if (t < lo_t) lo = i, lo_t = t;
      if (t > hi_t) hi = i, hi_t = t;
    }
    return {lo, hi};
  }
  const Eigen::Vector3d c = points[ic] - a;
  const Eigen::Vector3d e2 = (c - c.dot(e1) * e1).normalized();
  const Eigen::Vector3d normal = e1.cross(e2);
  // The points farthest on either side of the plane: with them, a set that is flat only to within
  // the tolerance loses at most the tolerance in any direction.
  std::size_t below = ids.front(), above = ids.front();
  double below_d = std::numeric_limits<double>::infinity(), above_d = -below_d;
  for (std::size_t i : ids) {
    const double d = (points[i] - a).dot(normal);
    if (d < below_d) below = i, below_d = d;
    if (d > above_d) above = i, above_d = d;
  }
  if (above_d - below_d > tolerance) return ids;  // not flat: keep everything (see above)
  std::vector<double> coords;
  coords.reserve(2 * ids.size());
  for (std::size_t i : ids) {
    const Eigen::Vector3d d = points[i] - a;
    coords.push_back(d.dot(e1));
    coords.push_back(d.dot(e2));
  }
  QhullOutcome plane = run_qhull(2, coords);
  if (plane.exit_code == qh_ERRmem) throw std::bad_alloc();
  if (plane.exit_code != qh_ERRnone) return ids;
  std::vector<std::size_t> kept{below, above};
  for (std::size_t k : plane.kept) kept.push_back(ids[k]);
  return kept;
}

// The hull's vertices (and points within rounding of it) among `ids`.
std::vector<std::size_t> hull_of(std::span<const Eigen::Vector3d> points, std::vector<std::size_t> ids) {
  if (ids.size() <= 4) return ids;  // Qhull needs more points than a simplex has; all are kept
  std::vector<double> coords;
  coords.reserve(3 * ids.size());
  for (std::size_t i : ids) coords.insert(coords.end(), points[i].data(), points[i].data() + 3);
  QhullOutcome outcome = run_qhull(3, coords);
  if (outcome.exit_code == qh_ERRmem) throw std::bad_alloc();
  if (outcome.exit_code == qh_ERRinput) throw RuntimeFailure("convex hull: Qhull refused its input: " + outcome.message);
  if (outcome.exit_code != qh_ERRnone) return degenerate_hull(points, ids);
  std::vector<std::size_t> kept;
  kept.reserve(outcome.kept.size());
  for (std::size_t k : outcome.kept) kept.push_back(ids[k]);
  std::sort(kept.begin(), kept.end());
  kept.erase(std::unique(kept.begin(), kept.end()), kept.end());
  return kept;
}

}  // namespace

std::vector<std::size_t> convex_hull_vertex_indices(std::span<const Eigen::Vector3d> points) {
  const std::size_t n = points.size();
  if (n == 0) return {};
  // The first point with a coordinate that is not finite (the same one for any thread count).
  const std::size_t bad = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, n, kBlockPoints), n,
      [&](const tbb::blocked_range<std::size_t>& r, std::size_t first) {
        for (std::size_t i = r.begin(); i < r.end() && i < first; ++i)
          if (!points[i].allFinite()) return i;
        return first;
      },
      [](std::size_t x, std::size_t y) { return std::min(x, y); });
  if (bad < n)
    throw InputError("convex hull: point " + std::to_string(bad) + " has a coordinate that is not a finite number");

  // Round 1: each block of consecutive points on its own.
  std::vector<std::vector<std::size_t>> pieces((n + kBlockPoints - 1) / kBlockPoints);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pieces.size(), 1), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t b = r.begin(); b < r.end(); ++b) {
      throw_if_interrupted();
      std::vector<std::size_t> ids(std::min(kBlockPoints, n - b * kBlockPoints));
      std::iota(ids.begin(), ids.end(), b * kBlockPoints);
      pieces[b] = hull_of(points, std::move(ids));
    }
  });
  // Later rounds: the survivors of consecutive groups of pieces, until one piece is left.
  while (pieces.size() > 1) {
    std::vector<std::vector<std::size_t>> merged((pieces.size() + kMergeFanIn - 1) / kMergeFanIn);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, merged.size(), 1), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t g = r.begin(); g < r.end(); ++g) {
        throw_if_interrupted();
        std::vector<std::size_t> ids;
        for (std::size_t p = g * kMergeFanIn; p < std::min(pieces.size(), (g + 1) * kMergeFanIn); ++p)
          ids.insert(ids.end(), pieces[p].begin(), pieces[p].end());
        merged[g] = hull_of(points, std::move(ids));
      }
    });
    pieces = std::move(merged);
  }
  std::vector<std::size_t> kept = std::move(pieces.front());
  // Of identical points the first only (Qhull keeps a duplicate of a vertex as a coplanar point).
  const auto coordinates_less = [&](std::size_t i, std::size_t j) {
    const Eigen::Vector3d &p = points[i], &q = points[j];
    if (p.x() != q.x()) return p.x() < q.x();
    if (p.y() != q.y()) return p.y() < q.y();
    if (p.z() != q.z()) return p.z() < q.z();
    return i < j;
  };
  std::sort(kept.begin(), kept.end(), coordinates_less);
  kept.erase(std::unique(kept.begin(), kept.end(), [&](std::size_t i, std::size_t j) { return points[i] == points[j]; }),
             kept.end());
  std::sort(kept.begin(), kept.end());
  return kept;
}

std::vector<Eigen::Vector3d> convex_hull_vertices(std::span<const Eigen::Vector3d> points) {
  std::vector<Eigen::Vector3d> out;
  for (std::size_t i : convex_hull_vertex_indices(points)) out.push_back(points[i]);
  return out;
}

std::vector<Eigen::Vector3d> convex_hull_vertices(const TriangleMesh& mesh) {
  std::vector<std::uint8_t> used(mesh.positions.size(), 0);
  for (const auto& t : mesh.triangles)
    for (std::uint32_t v : t)
      if (v < used.size()) used[v] = 1;
  std::vector<Eigen::Vector3d> points;
  for (std::size_t v = 0; v < used.size(); ++v)
    if (used[v]) points.push_back(mesh.positions[v]);
  return convex_hull_vertices(points);
}

}  // namespace meshtour
