// Convex hull vertices through Qhull (reentrant libqhull_r), with a filter that discards the
// points that are surely inside before Qhull sees them.
//
// Why Qhull rather than a quickhull of our own: the hard part of a 3D hull is not the algorithm
// but floating-point robustness on scanned and CAD meshes (nearly coplanar facets, points within
// rounding of a facet, duplicates), which Qhull handles by merging facets with tolerances derived
// from the input's rounding error and has done on decades of degenerate input. Its option 'Qc'
// reports the points it finds within rounding of a facet (including vertices it merged away); of
// those we keep the ones that stick out of their facet by more than kOnFacetShare.
//
// Why the filter: Qhull costs about a microsecond per input point on one core and cannot be
// interrupted, so 8.9M points would take seconds. Most points of a mesh are well inside the hull of
// a sparse sample of it. So the hull of every 16th point is found first (recursively, the same
// way), and a point goes to the final Qhull run only when it is not surely inside that sample's
// hull; the test is a few plane tests per point (the sample hull's facets are looked up by the
// direction of the point from the hull's centre), in parallel, with interrupt checks. The hull of
// the sample's hull vertices and the survivors is the hull of all points. Everything depends on
// the input only (fixed sampling, no thread-dependent order): the same result for any thread count.
#include "mesh/convex_hull.h"

#include <Eigen/Geometry>
#include <libqhull_r/libqhull_r.h>
#include <libqhull_r/geom_r.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>
#include <string>

#include "core/error.h"
#include "core/interrupt.h"

namespace meshtour {
namespace {

// Sets up to this size go to Qhull directly; larger ones are first filtered by the hull of every
// kSampleStride-th point (found the same way).
constexpr std::size_t kDirectPoints = std::size_t{1} << 14;
constexpr std::size_t kSampleStride = 16;
// Points per task of the parallel filter (and between interrupt checks).
constexpr std::size_t kFilterBlock = std::size_t{1} << 15;
// A point counts as inside a facet when it is at most this share of the model's size (or of its
// coordinates' magnitude, whichever is larger) above it: points on a facet (a flat side of a CAD
// part, midpoints of a hull edge) are not vertices, and a vertex sticking out by less than this
// cannot change a framing result by more than this share (1e-13, far below the 1e-12 that the
// framing promises).
constexpr double kOnFacetShare = 1e-13;
// A set whose points all lie within this share of its size (or of its coordinates' magnitude,
// whichever is larger) from a plane is treated as flat. Qhull calls a set flat when it is within
// its own rounding estimate (~1e-15 of the coordinates' magnitude) of a plane, far below this, so
// only sets that Qhull has refused are measured against it.
constexpr double kFlatShare = 1e-12;

struct QhullFacet {
  Eigen::Vector3d normal;            // outward unit normal
  double offset = 0.0;               // normal . x + offset > 0 outside
  std::array<std::size_t, 3> corner{};  // input positions of the triangle's corners
};
// What one Qhull run found: the positions (0 .. count-1 in its input) of the hull's vertices and
// of the coplanar points that stick out; or its exit code and message when it failed.
struct QhullOutcome {
  int exit_code = qh_ERRnone;
  std::string message;
  std::vector<std::size_t> kept;
  std::vector<QhullFacet> facets;  // with `want_facets` only: the triangulated facets
  double max_outside = 0.0;        // how far Qhull's facets may lie below some input point
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

// Qhull on `coords.size() / dim` points of `dim` coordinates each (row-major); its default merging
// keeps the facets convex under rounding. Of the points it finds within rounding of a facet
// ('Qc'), those more than `above` over it are kept (a vertex that Qhull merged away sticks out);
// the others lie on the facet. With `want_facets` (3D only): the vertices and the facets,
// triangulated ('Qt'). `coords` must stay alive while Qhull runs (it points into it).
QhullOutcome run_qhull(int dim, std::vector<double>& coords, double above, bool want_facets = false) {
  QhullOutcome out;
  const auto count = coords.size() / static_cast<std::size_t>(dim);
  if (count > static_cast<std::size_t>(std::numeric_limits<int>::max() / 4))
    throw InputError("convex hull: too many points for Qhull (" + std::to_string(count) + ")");
  QhullSession session;
  char keep_coplanar[] = "qhull Qc", triangulate[] = "qhull Qt";
  out.exit_code = qh_new_qhull(session.get(), dim, static_cast<int>(count), coords.data(), False,
                               want_facets ? triangulate : keep_coplanar, nullptr, session.errors());
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
      FOREACHpoint_(facet->coplanarset) {
        realT distance = 0.0;
        qh_distplane(qh, point, facet, &distance);
        if (distance > above) keep(point);
      }
    }
  }
  if (want_facets) {
    out.max_outside = qh->max_outside;
    vertexT** vertexp = nullptr;
    FORALLfacets {
      QhullFacet f;
      f.normal = Eigen::Vector3d(facet->normal[0], facet->normal[1], facet->normal[2]);
      f.offset = facet->offset;
      int corners = 0;
      bool valid = true;
      FOREACHvertex_(facet->vertices) {
        const int id = qh_pointid(qh, vertex->point);
        if (corners >= 3 || id < 0 || static_cast<std::size_t>(id) >= count) {
          valid = false;
          break;
        }
        f.corner[corners++] = static_cast<std::size_t>(id);
      }
      // 'Qt' makes every facet a triangle; anything else cannot be looked up, so the filter is off.
      if (!valid || corners != 3) {
        out.facets.clear();
        return out;
      }
      out.facets.push_back(f);
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
std::vector<std::size_t> degenerate_hull(std::span<const Eigen::Vector3d> points, const std::vector<std::size_t>& ids,
                                         double on_facet) {
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
  QhullOutcome plane = run_qhull(2, coords, on_facet);
  if (plane.exit_code == qh_ERRmem) throw std::bad_alloc();
  if (plane.exit_code != qh_ERRnone) return ids;
  std::vector<std::size_t> kept{below, above};
  for (std::size_t k : plane.kept) kept.push_back(ids[k]);
  return kept;
}

// The hull's vertices (and points within rounding of it) among `ids`.
std::vector<std::size_t> hull_of(std::span<const Eigen::Vector3d> points, std::vector<std::size_t> ids, double tolerance) {
  if (ids.size() <= 4) return ids;  // Qhull needs more points than a simplex has; all are kept
  std::vector<double> coords;
  coords.reserve(3 * ids.size());
  for (std::size_t i : ids) coords.insert(coords.end(), points[i].data(), points[i].data() + 3);
  QhullOutcome outcome = run_qhull(3, coords, tolerance);
  if (outcome.exit_code == qh_ERRmem) throw std::bad_alloc();
  if (outcome.exit_code == qh_ERRinput) throw RuntimeFailure("convex hull: Qhull refused its input: " + outcome.message);
  if (outcome.exit_code != qh_ERRnone) return degenerate_hull(points, ids, tolerance);
  std::vector<std::size_t> kept;
  kept.reserve(outcome.kept.size());
  for (std::size_t k : outcome.kept) kept.push_back(ids[k]);
  std::sort(kept.begin(), kept.end());
  kept.erase(std::unique(kept.begin(), kept.end()), kept.end());
  return kept;
}


// "Surely inside" test against a convex polytope given by Qhull's triangulated facets. The cones
// from an interior centre over the facets' triangles tile all directions, and a point is inside
// the polytope exactly when it is below the plane of the triangle whose cone holds it. The
// directions are cut into cells (a cube map: 6 faces of R x R cells); each cell lists every
// triangle whose cone may meet it, so a point is tested against a few planes: below all of them
// (by kOnFacetShare) means inside. Every doubt (a direction on a cube edge, a triangle that is
// not small seen from the centre) falls on the safe side: more planes listed, or the point kept.
class InsideFilter {
public:
  /// Nothing when the facets do not enclose a volume (then no point is filtered).
  static std::optional<InsideFilter> build(std::span<const Eigen::Vector3d> points, const std::vector<std::size_t>& ids,
                                           const QhullOutcome& hull, double tolerance) {
    if (hull.facets.size() < 4) return std::nullopt;
    InsideFilter f;
    f.tolerance_ = tolerance + 2.0 * hull.max_outside;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (std::size_t k : hull.kept) sum += points[ids[k]];
    f.center_ = sum / static_cast<double>(hull.kept.size());
    // The centre must be clearly inside every facet, or the cones do not tile the directions.
    for (const QhullFacet& facet : hull.facets)
      if (!(facet.normal.dot(f.center_) + facet.offset < -f.tolerance_)) return std::nullopt;
    const std::size_t triangles = hull.facets.size();
    f.resolution_ = std::clamp(static_cast<int>(std::sqrt(static_cast<double>(triangles) / 6.0)), 2, 96);
    const int r = f.resolution_;
    const std::size_t cells = 6 * static_cast<std::size_t>(r) * static_cast<std::size_t>(r);
    std::vector<std::vector<std::uint32_t>> lists(cells);
    std::vector<Plane> planes;
    planes.reserve(triangles);

    for (std::size_t t = 0; t < triangles; ++t) {
      const QhullFacet& facet = hull.facets[t];
      planes.push_back({facet.normal, facet.offset});
      std::array<Eigen::Vector3d, 3> d;
      for (int k = 0; k < 3; ++k) d[k] = points[ids[facet.corner[k]]] - f.center_;
      f.register_cone(lists, static_cast<std::uint32_t>(t), d);
    }
    f.cell_start_.reserve(cells + 1);
    f.cell_start_.push_back(0);
    // Each cell's planes side by side (a plane is copied into every cell that lists it), so that
    // a point's test reads one short run of memory.
    for (const auto& list : lists) {
      for (std::uint32_t t : list) f.cell_planes_.push_back(planes[t]);
      f.cell_start_.push_back(static_cast<std::uint32_t>(f.cell_planes_.size()));
    }
    return f;
  }

  /// True only when `p` is inside the polytope (or within the tolerance above a facet).
  bool surely_inside(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d d = p - center_;
    const int face = face_of(d);
    if (face < 0) return false;  // on a cube edge, or at the centre: not worth the doubt
    const auto [i, j] = cell_of(face, d);
    const std::size_t c = cell_index(face, i, j);
    for (std::uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
      const Plane& plane = cell_planes_[k];
      if (plane.normal.dot(p) + plane.offset > tolerance_) return false;
    }
    return cell_start_[c + 1] > cell_start_[c];
  }


private:
  struct Plane {
    Eigen::Vector3d normal;
    double offset;
  };
  // Lists triangle t in every cell of every face that the cone over the triangle d (corner
  // directions from the centre) may meet.
  void register_cone(std::vector<std::vector<std::uint32_t>>& lists, std::uint32_t t,
                     const std::array<Eigen::Vector3d, 3>& d) const {
    for (int face = 0; face < 6; ++face) register_on_face(lists, t, d, face, 0);
  }

  void register_on_face(std::vector<std::vector<std::uint32_t>>& lists, std::uint32_t t,
                        const std::array<Eigen::Vector3d, 3>& d, int face, int depth) const {
    const int a = face / 2, b = (a + 1) % 3, c = (a + 2) % 3, r = resolution_;
    const double s = face % 2 ? -1.0 : 1.0;
    // The face's pyramid is where s d_a >= |d_b| and s d_a >= |d_c|: four half-spaces. When every
    // corner is clearly outside one of them, so is the whole cone.
    for (const auto& [other, sign] : {std::pair{b, 1.0}, std::pair{b, -1.0}, std::pair{c, 1.0}, std::pair{c, -1.0}}) {
      bool all_outside = true;
      for (const auto& corner : d)
        all_outside = all_outside && s * corner[a] - sign * corner[other] < -1e-12 * corner.cwiseAbs().maxCoeff();
      if (all_outside) return;
    }
    if (d[0][a] * s > 0.0 && d[1][a] * s > 0.0 && d[2][a] * s > 0.0) {
      // Every corner in front of the face: the cone's trace on the face's plane is the triangle
      // of the corners' traces. List it in every cell that this triangle overlaps, widened by far
      // more than the rounding of the traces (of the corners here, of the point in surely_inside()).
      const std::array<Eigen::Vector2d, 3> x{trace(face, d[0]), trace(face, d[1]), trace(face, d[2])};
      const Eigen::Vector2d lo = x[0].cwiseMin(x[1]).cwiseMin(x[2]), hi = x[0].cwiseMax(x[1]).cwiseMax(x[2]);
      constexpr double kSlack = 1e-6;  // in cells
      if (!(lo.x() < r + kSlack && lo.y() < r + kSlack && hi.x() > -kSlack && hi.y() > -kSlack)) return;
      // Each edge's outward normal (away from the third corner) and offset: a cell wholly beyond
      // one edge does not meet the triangle (a degenerate triangle keeps its bounding box).
      std::array<std::pair<Eigen::Vector2d, double>, 3> edges;
      const double area = (x[1] - x[0]).x() * (x[2] - x[0]).y() - (x[1] - x[0]).y() * (x[2] - x[0]).x();
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector2d e = x[(k + 1) % 3] - x[k];
        const Eigen::Vector2d n = area > 0.0 ? Eigen::Vector2d(e.y(), -e.x()) : Eigen::Vector2d(-e.y(), e.x());
        edges[k] = {n, n.dot(x[k]) + kSlack * n.norm()};
      }
      const auto cell = [&](double v) { return static_cast<int>(std::clamp(std::floor(v), 0.0, r - 1.0)); };
      for (int i = cell(lo.x() - kSlack); i <= cell(hi.x() + kSlack); ++i)
        for (int j = cell(lo.y() - kSlack); j <= cell(hi.y() + kSlack); ++j) {
          bool apart = false;
          for (const auto& [n, offset] : edges) {
            if (area == 0.0) break;
            // The cell's corner least far along n.
            const Eigen::Vector2d corner(n.x() > 0.0 ? i : i + 1, n.y() > 0.0 ? j : j + 1);
            apart = apart || n.dot(corner) > offset;
          }
          if (!apart) lists[cell_index(face, i, j)].push_back(t);
        }
      return;
    }
    if (depth < 6) {
      // Partly behind the face's plane: split the triangle at its edges' midpoints (the cones of
      // the four parts make up its cone) and look again.
      const Eigen::Vector3d m01 = 0.5 * (d[0] + d[1]), m12 = 0.5 * (d[1] + d[2]), m20 = 0.5 * (d[2] + d[0]);
      for (const auto& part : {std::array{d[0], m01, m20}, std::array{d[1], m12, m01}, std::array{d[2], m20, m12},
                               std::array{m01, m12, m20}})
        register_on_face(lists, t, part, face, depth + 1);
      return;
    }
    for (int i = 0; i < r; ++i)
      for (int j = 0; j < r; ++j) lists[cell_index(face, i, j)].push_back(t);
  }

  // Face 2a (+axis a) or 2a+1 (-axis a) of the cube map, for the dominant axis a of d; -1 when two
  // axes nearly tie (the face could be either under rounding) or d is zero.
  static int face_of(const Eigen::Vector3d& d) {
    const Eigen::Vector3d m = d.cwiseAbs();
    int a = 0;
    if (m[1] > m[a]) a = 1;
    if (m[2] > m[a]) a = 2;
    const double second = std::max(m[(a + 1) % 3], m[(a + 2) % 3]);
    if (!(m[a] - second > 1e-9 * m[a])) return -1;
    return 2 * a + (d[a] < 0.0 ? 1 : 0);
  }
  // Where the direction d (in face's pyramid) meets the face, in cells: [0, R] on both axes.
  Eigen::Vector2d trace(int face, const Eigen::Vector3d& d) const {
    const int a = face / 2;
    const double scale = 0.5 * resolution_ / std::abs(d[a]);
    return {(d[(a + 1) % 3] + std::abs(d[a])) * scale, (d[(a + 2) % 3] + std::abs(d[a])) * scale};
  }
  std::pair<int, int> cell_of(int face, const Eigen::Vector3d& d) const {
    const Eigen::Vector2d x = trace(face, d);
    return {std::clamp(static_cast<int>(std::floor(x.x())), 0, resolution_ - 1),
            std::clamp(static_cast<int>(std::floor(x.y())), 0, resolution_ - 1)};
  }
  std::size_t cell_index(int face, int i, int j) const {
    return (static_cast<std::size_t>(face) * resolution_ + static_cast<std::size_t>(i)) * resolution_ + static_cast<std::size_t>(j);
  }

  Eigen::Vector3d center_;
  double tolerance_ = 0.0;
  int resolution_ = 0;
  std::vector<std::uint32_t> cell_start_;  // cell c's planes: cell_planes_[cell_start_[c] .. cell_start_[c + 1])
  std::vector<Plane> cell_planes_;
};

// The hull of the points `ids`: of a sample first when they are many, then of the sample's hull
// and the points that are not surely inside it.
std::vector<std::size_t> reduce(std::span<const Eigen::Vector3d> points, std::vector<std::size_t> ids, double tolerance) {
  if (ids.size() <= kDirectPoints) return hull_of(points, std::move(ids), tolerance);
  std::vector<std::size_t> sample;
  sample.reserve(ids.size() / kSampleStride + 1);
  for (std::size_t k = 0; k < ids.size(); k += kSampleStride) sample.push_back(ids[k]);
  std::vector<std::size_t> sample_hull = reduce(points, std::move(sample), tolerance);
  throw_if_interrupted();

  std::vector<double> coords;
  coords.reserve(3 * sample_hull.size());
  for (std::size_t i : sample_hull) coords.insert(coords.end(), points[i].data(), points[i].data() + 3);
  const QhullOutcome facets = sample_hull.size() > 4 ? run_qhull(3, coords, tolerance, true) : QhullOutcome{};
  if (facets.exit_code == qh_ERRmem) throw std::bad_alloc();
  const std::optional<InsideFilter> filter =
      facets.exit_code == qh_ERRnone ? InsideFilter::build(points, sample_hull, facets, tolerance) : std::nullopt;
  if (!filter) return hull_of(points, std::move(ids), tolerance);  // a sample without volume: no filter

  const std::size_t blocks = (ids.size() + kFilterBlock - 1) / kFilterBlock;
  std::vector<std::vector<std::size_t>> survivors(blocks);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t b = r.begin(); b < r.end(); ++b) {
      throw_if_interrupted();
      for (std::size_t k = b * kFilterBlock; k < std::min(ids.size(), (b + 1) * kFilterBlock); ++k)
        if (!filter->surely_inside(points[ids[k]])) survivors[b].push_back(ids[k]);
    }
  });
  std::vector<std::size_t> candidates = std::move(sample_hull);
  for (const auto& block : survivors) candidates.insert(candidates.end(), block.begin(), block.end());
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  throw_if_interrupted();
  return hull_of(points, std::move(candidates), tolerance);
}

}  // namespace

std::vector<std::size_t> convex_hull_vertex_indices(std::span<const Eigen::Vector3d> points) {
  const std::size_t n = points.size();
  if (n == 0) return {};
  // The first point with a coordinate that is not finite (the same one for any thread count).
  const std::size_t bad = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, n, kFilterBlock), n,
      [&](const tbb::blocked_range<std::size_t>& r, std::size_t first) {
        for (std::size_t i = r.begin(); i < r.end() && i < first; ++i)
          if (!points[i].allFinite()) return i;
        return first;
      },
      [](std::size_t x, std::size_t y) { return std::min(x, y); });
  if (bad < n)
    throw InputError("convex hull: point " + std::to_string(bad) + " has a coordinate that is not a finite number");

  // The model's scale for the on-facet tolerance: its extent or its coordinates' magnitude.
  const auto [lo, hi] = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, n, kFilterBlock), std::pair{points[0], points[0]},
      [&](const tbb::blocked_range<std::size_t>& r, std::pair<Eigen::Vector3d, Eigen::Vector3d> box) {
        for (std::size_t i = r.begin(); i < r.end(); ++i) box = {box.first.cwiseMin(points[i]), box.second.cwiseMax(points[i])};
        return box;
      },
      [](const auto& x, const auto& y) { return std::pair{x.first.cwiseMin(y.first), x.second.cwiseMax(y.second)}; });
  const double scale = std::max({(hi - lo).norm(), lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff()});
  std::vector<std::size_t> ids(n);
  std::iota(ids.begin(), ids.end(), std::size_t{0});
  std::vector<std::size_t> kept = reduce(points, std::move(ids), kOnFacetShare * scale);
  // One of identical points (Qhull may keep a duplicate of a vertex as a coplanar point); the one
  // with the lowest index that Qhull kept, the same in every run.
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

std::vector<HullTriangle> convex_hull_triangles(std::span<const Eigen::Vector3d> hull_vertices) {
  if (hull_vertices.size() < 4) return {};
  std::vector<double> coords;
  coords.reserve(3 * hull_vertices.size());
  for (const Eigen::Vector3d& p : hull_vertices) coords.insert(coords.end(), p.data(), p.data() + 3);
  Eigen::Vector3d lo = hull_vertices[0], hi = lo;
  for (const Eigen::Vector3d& p : hull_vertices) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double scale = std::max({(hi - lo).norm(), lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff()});
  const QhullOutcome hull = run_qhull(3, coords, kOnFacetShare * scale, true);
  if (hull.exit_code == qh_ERRmem) throw std::bad_alloc();
  // Qhull refuses sets without volume (qh_ERRsingular / qh_ERRprec on a flat set): no facets.
  if (hull.exit_code == qh_ERRsingular) return {};
  if (hull.exit_code != qh_ERRnone) throw RuntimeFailure("convex hull: Qhull failed: " + hull.message);
  std::vector<HullTriangle> out;
  out.reserve(hull.facets.size());
  for (const QhullFacet& f : hull.facets)
    out.push_back({f.normal, {hull_vertices[f.corner[0]], hull_vertices[f.corner[1]], hull_vertices[f.corner[2]]}});
  return out;
}

std::vector<Eigen::Vector2d> convex_polygon(std::vector<Eigen::Vector2d> points) {
  std::sort(points.begin(), points.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.y() != b.y() ? a.y() < b.y() : a.x() < b.x();
  });
  points.erase(std::unique(points.begin(), points.end()), points.end());
  if (points.size() < 3) return points;
  const auto turn = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
  };
  std::vector<Eigen::Vector2d> hull(2 * points.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {  // right chain, bottom to top
    while (k >= 2 && turn(hull[k - 2], hull[k - 1], points[i]) <= 0.0) --k;
    hull[k++] = points[i];
  }
  for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {  // left chain, top to bottom
    while (k >= lower && turn(hull[k - 2], hull[k - 1], points[i]) <= 0.0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);  // the last point is the first
  return hull;
}

}  // namespace meshtour
