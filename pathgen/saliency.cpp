#include "pathgen/saliency.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>

#include "core/error.h"
#include "core/interrupt.h"
#include "core/triangle_geometry.h"

namespace meshtour {
namespace {

// The scales of Lee et al.: σ_i = k·ε for k in {2, 3, 4, 5, 6}, each compared with 2σ_i. G is
// needed at the union of both lists, kGaussScales; kFine/kCoarse index it for each σ_i.
constexpr int kSaliencyScales = 5;
constexpr std::array<int, 8> kGaussScales = {2, 3, 4, 5, 6, 8, 10, 12};
constexpr std::array<int, kSaliencyScales> kFine = {0, 1, 2, 3, 4};    // 2ε, 3ε, 4ε, 5ε, 6ε
constexpr std::array<int, kSaliencyScales> kCoarse = {2, 4, 5, 6, 7};  // 4ε, 6ε, 8ε, 10ε, 12ε
// The Gaussians up to 5ε read the vertices themselves. From 6ε on, they read the vertices' sums
// over 2ε bins instead (area, curvature, centroid): at most a third of σ, so the bins' extent
// changes the weights by ~1%, and their number within 2σ no longer grows with the vertex density.
// This is what keeps a 100k-vertex mesh under a second.
constexpr int kFirstBinnedScale = 4;  // index into kGaussScales
constexpr double kBinInEpsilon = 2.0;
// The Gaussian is cut off at 2σ (as in the paper), so the widest search radius is 2·12ε = 24ε:
// the grid of bins has 12ε cells, and a point's binned neighbours lie in the 5×5×5 cells around
// its own. Vertex neighbours are needed within 2·5ε (the Gaussians) and 6ε (local maxima): the
// grid of vertices has 5ε cells, so that the 5×5×5 cells searched are not much larger than that.
constexpr double kBinCellInEpsilon = 12.0;
constexpr double kVertexCellInEpsilon = 5.0;
constexpr std::size_t kBlock = 2048;  // points per parallel task; also the interrupt check interval
constexpr double kNoiseFloor = 1.0;   // smallest normalising S_i, in 1/bounding-box diagonal

/// exp(−q/2k²) for q = d²/ε² in [0, 4k²) (out to the 2σ cut-off), tabulated and linearly
/// interpolated: relative error below 1e-5, a fraction of the cost of std::exp.
class GaussianTable {
public:
  explicit GaussianTable(int k) : step_(4.0 * k * k / kSamples) {
    for (int i = 0; i <= kSamples + 1; ++i) value_[i] = std::exp(-i * step_ / (2.0 * k * k));
  }
  double operator()(double q) const {
    const double t = q / step_;
    const auto i = static_cast<int>(t);
    return value_[i] + (t - i) * (value_[i + 1] - value_[i]);
  }

private:
  static constexpr int kSamples = 256;
  double step_;
  std::array<double, kSamples + 2> value_{};
};

/// What every used vertex contributes: its area share and its integrated mean curvature.
struct VertexMeasures {
  std::vector<double> area;         ///< one third of the adjacent faces' areas
  std::vector<double> curvature;    ///< ∫H dA over the vertex's area share (model units)
  std::vector<std::uint8_t> used;   ///< in at least one triangle
};

// Per face, the gradient of its area with respect to a corner is ½ n × (opposite edge): bounded by
// half that edge however thin the face is, unlike the cotangent weights it equals. Summed over the
// faces around a vertex it is 2·H·n·A (the mean-curvature normal times the area), so ½ of its
// component along the vertex normal is the integrated mean curvature. Summing per face needs no
// topology: non-manifold fans and duplicate faces just add up, and a duplicate face doubles both
// the curvature and the area, leaving H unchanged.
VertexMeasures vertex_measures(const TriangleMesh& mesh) {
  const std::size_t n = mesh.positions.size();
  VertexMeasures out;
  out.area.assign(n, 0.0);
  out.curvature.assign(n, 0.0);
  out.used.assign(n, 0);
  std::vector<Eigen::Vector3d> gradient(n, Eigen::Vector3d::Zero());
  std::vector<Eigen::Vector3d> normal(n, Eigen::Vector3d::Zero());
  // Sequential in face order: the sums are bitwise reproducible, and this pass is cheap.
  for (const auto& t : mesh.triangles) {
    for (std::uint32_t v : t) out.used[v] = 1;
    const Eigen::Vector3d& a = mesh.positions[t[0]];
    const Eigen::Vector3d& b = mesh.positions[t[1]];
    const Eigen::Vector3d& c = mesh.positions[t[2]];
    const Eigen::Vector3d cross = triangle_cross(a, b, c);
    const double twice_area = cross.norm();
    const double longest = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    // A face without area has no normal; it contributes nothing (as its area would be 0 anyway).
    if (!(twice_area > 1e-12 * longest) || !std::isfinite(twice_area)) continue;
    const Eigen::Vector3d unit = cross / twice_area;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = t[k];
      const Eigen::Vector3d& from = mesh.positions[t[(k + 1) % 3]];
      const Eigen::Vector3d& to = mesh.positions[t[(k + 2) % 3]];
      gradient[v] += 0.5 * unit.cross(to - from);
      normal[v] += cross;  // area-weighted
      out.area[v] += twice_area / 6.0;
    }
  }
  for (std::size_t v = 0; v < n; ++v) {
    const double length = normal[v].norm();
    if (length > 0.0) out.curvature[v] = 0.5 * gradient[v].dot(normal[v] / length);
  }
  return out;
}

/// Point masses: an area and the integrated mean curvature over it, at a position. Either the
/// used vertices or their sums over bins.
struct Samples {
  std::vector<Eigen::Vector3d> position;
  std::vector<double> area, curvature;
  std::vector<std::uint32_t> vertex;  ///< for vertex samples: the vertex index
};

/// Samples sorted by the cell of a uniform grid, so that the neighbours of a point are read from a
/// few contiguous runs. The sort is a counting sort in sample order: it does not depend on threads.
struct SampleGrid {
  std::array<int, 3> dims{};
  Eigen::Vector3d origin;
  double cell = 0.0;
  std::vector<std::uint32_t> cell_start;  ///< dims product + 1 offsets into `sorted`
  Samples sorted;

  SampleGrid(Samples samples, const Bounds& bounds, double cell_size) : origin(bounds.lo), cell(cell_size) {
    for (int a = 0; a < 3; ++a) dims[a] = std::max(1, static_cast<int>(bounds.extent()[a] / cell) + 1);
    const std::size_t cells = static_cast<std::size_t>(dims[0]) * dims[1] * dims[2];
    const std::size_t count = samples.position.size();
    std::vector<std::uint32_t> cell_of_sample(count);
    cell_start.assign(cells + 1, 0);
    for (std::size_t i = 0; i < count; ++i) {
      const auto c = cell_of(samples.position[i]);
      cell_of_sample[i] = static_cast<std::uint32_t>(index(c[0], c[1], c[2]));
      ++cell_start[cell_of_sample[i] + 1];
    }
    for (std::size_t k = 0; k < cells; ++k) cell_start[k + 1] += cell_start[k];
    std::vector<std::uint32_t> fill(cell_start.begin(), cell_start.end() - 1);
    sorted.position.resize(count);
    sorted.area.resize(count);
    sorted.curvature.resize(count);
    sorted.vertex.resize(samples.vertex.size());
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint32_t to = fill[cell_of_sample[i]]++;
      sorted.position[to] = samples.position[i];
      sorted.area[to] = samples.area[i];
      sorted.curvature[to] = samples.curvature[i];
      if (!samples.vertex.empty()) sorted.vertex[to] = samples.vertex[i];
    }
  }
  std::size_t size() const { return sorted.position.size(); }
  /// How many cells around a point's own hold everything within `radius` of it.
  int reach(double radius) const { return static_cast<int>(std::ceil(radius / cell)); }

  std::array<int, 3> cell_of(const Eigen::Vector3d& p) const {
    std::array<int, 3> c{};
    for (int a = 0; a < 3; ++a) c[a] = std::clamp(static_cast<int>((p[a] - origin[a]) / cell), 0, dims[a] - 1);
    return c;
  }
  std::size_t index(int x, int y, int z) const { return (static_cast<std::size_t>(z) * dims[1] + y) * dims[0] + x; }

  /// Calls visit(sample) for the samples in the cells within `reach` cells of p's whose box is
  /// closer to p than sqrt(radius2), in cell order (a fixed order: the sums are reproducible),
  /// until visit returns false.
  template <class Visit>
  void for_near(const Eigen::Vector3d& p, int reach, double radius2, Visit&& visit) const {
    const auto c = cell_of(p);
    for (int z = std::max(0, c[2] - reach); z <= std::min(dims[2] - 1, c[2] + reach); ++z)
      for (int y = std::max(0, c[1] - reach); y <= std::min(dims[1] - 1, c[1] + reach); ++y)
        for (int x = std::max(0, c[0] - reach); x <= std::min(dims[0] - 1, c[0] + reach); ++x) {
          const std::array<int, 3> q{x, y, z};
          double box2 = 0.0;
          for (int a = 0; a < 3; ++a) {
            const double lo = origin[a] + q[a] * cell, hi = lo + cell;
            const double d = p[a] < lo ? lo - p[a] : (p[a] > hi ? p[a] - hi : 0.0);
            box2 += d * d;
          }
          if (box2 >= radius2) continue;
          const std::size_t k = index(x, y, z);
          for (std::uint32_t i = cell_start[k]; i < cell_start[k + 1]; ++i)
            if (!visit(i)) return;
        }
  }
};

/// The used vertices as samples, in vertex order.
Samples vertex_samples(const TriangleMesh& mesh, const VertexMeasures& m) {
  Samples s;
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    if (!m.used[v]) continue;
    s.position.push_back(mesh.positions[v]);
    s.area.push_back(m.area[v]);
    s.curvature.push_back(m.curvature[v]);
    s.vertex.push_back(static_cast<std::uint32_t>(v));
  }
  return s;
}

/// The vertex samples summed over cubic bins of side `bin`: total area and curvature at the
/// area-weighted centroid. Bins without area are left out. Sequential, in a fixed order.
Samples binned_samples(const Samples& vertices, const Bounds& bounds, double bin) {
  const std::size_t count = vertices.position.size();
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(count);
  for (std::size_t i = 0; i < count; ++i) {
    std::uint64_t key = 0;
    for (int a = 0; a < 3; ++a)
      key = key << 21 | static_cast<std::uint64_t>(std::max(0.0, (vertices.position[i][a] - bounds.lo[a]) / bin));
    keyed[i] = {key, static_cast<std::uint32_t>(i)};
  }
  std::sort(keyed.begin(), keyed.end());  // pairs are unique: a total order
  Samples bins;
  for (std::size_t begin = 0; begin < count;) {
    std::size_t end = begin;
    double area = 0.0, curvature = 0.0;
    Eigen::Vector3d moment = Eigen::Vector3d::Zero();
    for (; end < count && keyed[end].first == keyed[begin].first; ++end) {
      const std::uint32_t i = keyed[end].second;
      area += vertices.area[i];
      curvature += vertices.curvature[i];
      moment += vertices.area[i] * vertices.position[i];
    }
    if (area > 0.0) {
      bins.position.push_back(moment / area);
      bins.area.push_back(area);
      bins.curvature.push_back(curvature);
    }
    begin = end;
  }
  return bins;
}

template <class Body>
void parallel_blocks(std::size_t count, Body&& body) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, kBlock), [&](const tbb::blocked_range<std::size_t>& r) {
    throw_if_interrupted();
    for (std::size_t i = r.begin(); i != r.end(); ++i) body(i);
  });
}

}  // namespace

std::vector<double> vertex_mean_curvature(const TriangleMesh& mesh) {
  const VertexMeasures m = vertex_measures(mesh);
  std::vector<double> h(mesh.positions.size(), 0.0);
  for (std::size_t v = 0; v < h.size(); ++v)
    if (m.area[v] > 0.0) h[v] = m.curvature[v] / m.area[v];
  return h;
}

std::vector<double> vertex_saliency(const TriangleMesh& mesh, const SaliencyOptions& options) {
  if (!(options.epsilon_fraction >= 0.001 && options.epsilon_fraction <= 0.05))
    throw InputError("saliency: epsilon_fraction must be between 0.001 and 0.05 of the bounding-box diagonal (got " +
                     std::to_string(options.epsilon_fraction) + ")");
  std::vector<double> saliency(mesh.positions.size(), 0.0);
  if (mesh.triangles.empty()) return saliency;
  const VertexMeasures measures = vertex_measures(mesh);
  const Bounds bounds = mesh.bounds();
  const double epsilon = options.epsilon_fraction * bounds.diagonal();
  if (!(epsilon > 0.0) || !std::isfinite(epsilon)) return saliency;
  Samples vertex_list = vertex_samples(mesh, measures);
  Samples bin_list = binned_samples(vertex_list, bounds, kBinInEpsilon * epsilon);
  const SampleGrid vertices(std::move(vertex_list), bounds, kVertexCellInEpsilon * epsilon);
  const SampleGrid bins(std::move(bin_list), bounds, kBinCellInEpsilon * epsilon);
  const std::size_t points = vertices.size();

  // G(v, σ) for the eight σ: the area-weighted mean of H with Gaussian weights exp(−d²/2σ²) over
  // the samples within 2σ, i.e. Σ w·∫H dA / Σ w·A. Weighting by area makes it a mean over the
  // surface, not over vertices, so the tessellation does not matter. Distances are in units of ε.
  constexpr std::size_t kG = kGaussScales.size();
  std::array<GaussianTable, kG> weight = {GaussianTable(2), GaussianTable(3), GaussianTable(4),  GaussianTable(5),
                                          GaussianTable(6), GaussianTable(8), GaussianTable(10), GaussianTable(12)};
  std::vector<std::array<double, kG>> gauss(points);
  const double inv_eps2 = 1.0 / (epsilon * epsilon);
  const auto accumulate = [&](const SampleGrid& from, std::size_t first, std::size_t last, const Eigen::Vector3d& x,
                              std::array<double, kG>& num, std::array<double, kG>& den) {
    const double reach = 2.0 * kGaussScales[last - 1];
    from.for_near(x, from.reach(reach * epsilon), reach * reach * epsilon * epsilon, [&](std::uint32_t q) {
      const double d2 = (from.sorted.position[q] - x).squaredNorm() * inv_eps2;
      const double a = from.sorted.area[q], k = from.sorted.curvature[q];
      // Scales from the widest down: a sample out of reach of one is out of reach of the smaller.
      for (std::size_t s = last; s-- > first;) {
        const double cut = 2.0 * kGaussScales[s];
        if (d2 >= cut * cut) break;
        const double w = weight[s](d2);
        num[s] += w * k;
        den[s] += w * a;
      }
      return true;
    });
  };
  parallel_blocks(points, [&](std::size_t p) {
    std::array<double, kG> num{}, den{};
    const Eigen::Vector3d& x = vertices.sorted.position[p];
    accumulate(vertices, 0, kFirstBinnedScale, x, num, den);
    accumulate(bins, kFirstBinnedScale, kG, x, num, den);
    for (std::size_t s = 0; s < kG; ++s) gauss[p][s] = den[s] > 0.0 ? num[s] / den[s] : 0.0;
  });

  // S_i = |G(σ_i) − G(2σ_i)|, normalised to [0, 1] by its maximum — but never by less than a
  // curvature difference of 1/diagonal (that of a sphere whose radius is the diagonal): a shape
  // without features, such as a sphere, has only tessellation noise in S_i, which dividing by
  // its own maximum would promote to full saliency.
  std::vector<std::array<double, kSaliencyScales>> scale_saliency(points);
  std::array<double, kSaliencyScales> maximum{};
  std::array<std::size_t, kSaliencyScales> argmax{};
  for (std::size_t p = 0; p < points; ++p)
    for (int i = 0; i < kSaliencyScales; ++i) {
      const double s = std::abs(gauss[p][kFine[i]] - gauss[p][kCoarse[i]]);
      scale_saliency[p][i] = s;
      if (s > maximum[i]) {
        maximum[i] = s;
        argmax[i] = p;
      }
    }
  const double noise_floor = kNoiseFloor / bounds.diagonal();
  std::array<double, kSaliencyScales> top{};  // M: the maximum after normalisation
  for (int i = 0; i < kSaliencyScales; ++i) top[i] = maximum[i] / std::max(maximum[i], noise_floor);
  for (auto& s : scale_saliency)
    for (int i = 0; i < kSaliencyScales; ++i) s[i] /= std::max(maximum[i], noise_floor);

  // Non-linear suppression: a map with one peak keeps its weight, a map with many similar peaks
  // is damped by (M − m̄)², M the global maximum and m̄ the mean of the other local maxima. A
  // point is a local maximum if no point within σ_i (Euclidean, not the 1-ring: the 1-ring's size
  // depends on the tessellation) is larger; equal values are broken by the point order.
  std::vector<std::uint8_t> is_maximum(points, 0);  // bit i: local maximum of S_i
  parallel_blocks(points, [&](std::size_t p) {
    std::uint8_t bits = 0;
    for (int i = 0; i < kSaliencyScales; ++i)
      if (scale_saliency[p][i] > 0.0) bits |= static_cast<std::uint8_t>(1u << i);
    if (bits == 0) return;
    const Eigen::Vector3d& x = vertices.sorted.position[p];
    const double largest = kGaussScales[kFine.back()];
    vertices.for_near(x, vertices.reach(largest * epsilon), largest * largest * epsilon * epsilon, [&](std::uint32_t q) {
      if (q == p) return true;
      const double d2 = (vertices.sorted.position[q] - x).squaredNorm() * inv_eps2;
      for (int i = 0; i < kSaliencyScales; ++i) {
        const double sigma = kGaussScales[kFine[i]];
        if (d2 >= sigma * sigma) continue;
        const double mine = scale_saliency[p][i], theirs = scale_saliency[q][i];
        if (theirs > mine || (theirs == mine && q < p)) bits &= static_cast<std::uint8_t>(~(1u << i));
      }
      return bits != 0;  // most points are beaten at every scale by one of their first neighbours
    });
    is_maximum[p] = bits;
  });
  std::array<double, kSaliencyScales> factor{};
  for (int i = 0; i < kSaliencyScales; ++i) {
    if (!(maximum[i] > 0.0)) continue;
    double sum = 0.0;
    std::size_t count = 0;
    for (std::size_t p = 0; p < points; ++p)
      if ((is_maximum[p] >> i & 1u) && p != argmax[i]) {
        sum += scale_saliency[p][i];
        ++count;
      }
    const double mean = count > 0 ? sum / static_cast<double>(count) : 0.0;
    factor[i] = (top[i] - mean) * (top[i] - mean);
  }
  for (std::size_t p = 0; p < points; ++p) {
    double total = 0.0;
    for (int i = 0; i < kSaliencyScales; ++i) total += factor[i] * scale_saliency[p][i];
    saliency[vertices.sorted.vertex[p]] = total;
  }
  return saliency;
}

std::vector<double> face_saliency(const TriangleMesh& mesh, const std::vector<double>& vertex_values) {
  if (vertex_values.size() != mesh.positions.size())
    throw InputError("face saliency: one value per vertex is needed (" + std::to_string(vertex_values.size()) +
                     " for " + std::to_string(mesh.positions.size()) + " vertices)");
  std::vector<double> faces(mesh.triangles.size(), 0.0);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto& t = mesh.triangles[f];
    faces[f] = (vertex_values[t[0]] + vertex_values[t[1]] + vertex_values[t[2]]) / 3.0;
  }
  return faces;
}

}  // namespace meshtour
