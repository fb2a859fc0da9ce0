#include "pathgen/coverage.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <bit>
#include <cstdio>
#include <cmath>
#include <unordered_map>
#include <limits>
#include <numeric>

#include "core/disjoint_sets.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "core/triangle_geometry.h"
#include "mesh/vertex_clustering.h"
#include "pathgen/features.h"
#include "pathgen/saliency.h"
#include "pathgen/stage_timer.h"

namespace meshtour {
namespace {

constexpr int kDefinitions = kFeatureDefinitions;

// Value of every proxy vertex under the patch density: the area-weighted mean of w(f) over the
// proxy faces around it.
std::vector<double> proxy_patch_density(const TriangleMesh& proxy, const SurfaceOptions& options) {
  // ε in the specification's diagonal unit whatever the paper path's unit (I-34): the proxy's
  // cells are coarse, and the 2.5 times tighter box-half-extent ε breaks its clean regions into
  // single faces, so the features would follow where the cells fall, not the shape (a sphere and
  // its split share 87 % of their feature samples instead of over 90 %:
  // Coverage.SameShapeFinerTessellationSameComputedFeatures).
  SurfaceOptions proxy_options = options;
  proxy_options.tolerance_unit = ToleranceUnit::diagonal;
  const SurfaceAnalysis surface = analyze_surface(proxy, proxy_options);
  const std::vector<double> w = input_face_weights(surface, proxy.triangles.size());
  const std::vector<double> area = face_areas(proxy);
  std::vector<double> sum(proxy.positions.size(), 0.0), weight(proxy.positions.size(), 0.0);
  for (std::size_t f = 0; f < proxy.triangles.size(); ++f)
    for (std::uint32_t v : proxy.triangles[f]) {
      sum[v] += area[f] * w[f];
      weight[v] += area[f];
    }
  for (std::size_t v = 0; v < sum.size(); ++v) sum[v] = weight[v] > 0.0 ? sum[v] / weight[v] : 0.0;
  return sum;
}

// The samples at or above the quantile of their values; where more than a quantile's worth of
// samples share the lowest value (often 0: flat), those are not features.
std::vector<std::uint8_t> top_quantile(const std::vector<double>& value, double quantile) {
  std::vector<double> sorted = value;
  const std::size_t k = std::min(sorted.size() - 1, static_cast<std::size_t>(quantile * static_cast<double>(sorted.size())));
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(k), sorted.end());
  const double threshold = sorted[k];
  const double lowest = *std::min_element(value.begin(), value.end());
  std::vector<std::uint8_t> feature(value.size());
  for (std::size_t i = 0; i < value.size(); ++i)
    feature[i] = value[i] >= threshold && (value[i] > lowest || threshold > lowest) ? 1 : 0;
  return feature;
}


// For each sample, the proxy vertices it takes its values from and their weights (summing to 1),
// and the nearest of them (its feature region's anchor).
struct SampleKernel {
  std::vector<std::size_t> first;  // sample i uses entries first[i] .. first[i+1]-1
  std::vector<std::uint32_t> vertex;
  std::vector<double> weight;
  std::vector<std::uint32_t> nearest;
};

SampleKernel proxy_kernel(const ClusteredMesh& proxy, const SurfaceSamples& samples, const TriangleMesh& mesh) {
  const TriangleMesh& p = proxy.mesh;
  std::vector<Eigen::Vector3d> normal(p.positions.size(), Eigen::Vector3d::Zero());
  for (const auto& t : p.triangles) {
    const Eigen::Vector3d a = triangle_cross(p.positions, t);
    for (std::uint32_t v : t) normal[v] += a;
  }
  for (auto& v : normal) v.normalize();
  auto cell_of = [&](const Eigen::Vector3d& x) {
    const Eigen::Vector3d q = ((x - proxy.grid_origin) / proxy.cell_size).array().floor();
    return std::array<long long, 3>{static_cast<long long>(q.x()), static_cast<long long>(q.y()), static_cast<long long>(q.z())};
  };
  auto key = [](const std::array<long long, 3>& c) {
    return (static_cast<std::uint64_t>(c[0] & 0x1FFFFF) << 42) | (static_cast<std::uint64_t>(c[1] & 0x1FFFFF) << 21) |
           static_cast<std::uint64_t>(c[2] & 0x1FFFFF);
  };
  // A cluster's vertex is a mean of points in its cell, so it lies in that cell.
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> in_cell;
  for (std::uint32_t v = 0; v < p.positions.size(); ++v) in_cell[key(cell_of(p.positions[v]))].push_back(v);
  const double radius = proxy.cell_size;
  SampleKernel k;
  k.first.assign(samples.size() + 1, 0);
  k.nearest.assign(samples.size(), 0);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const Eigen::Vector3d& x = samples.points[i];
    const auto c = cell_of(x);
    const std::size_t start = k.vertex.size();
    double total = 0.0, closest = std::numeric_limits<double>::infinity();
    for (long long dx = -1; dx <= 1; ++dx)
      for (long long dy = -1; dy <= 1; ++dy)
        for (long long dz = -1; dz <= 1; ++dz) {
          const auto it = in_cell.find(key({c[0] + dx, c[1] + dy, c[2] + dz}));
          if (it == in_cell.end()) continue;
          for (std::uint32_t v : it->second) {
            const double d2 = (p.positions[v] - x).squaredNorm();
            const double r = 1.0 - d2 / (radius * radius);
            const double facing = std::abs(normal[v].dot(samples.normals[i]));
            if (!(r > 0.0) || !(facing > 0.0)) continue;
            const double w = r * r * facing;
            k.vertex.push_back(v);
            k.weight.push_back(w);
            total += w;
            if (d2 < closest) {
              closest = d2;
              k.nearest[i] = v;
            }
          }
        }
    if (total > 0.0) {
      for (std::size_t e = start; e < k.vertex.size(); ++e) k.weight[e] /= total;
    } else {
      const auto& t = mesh.triangles[samples.faces[i]];
      const Eigen::Vector2d& b = samples.barycentric[i];
      const std::array<double, 3> w{1.0 - b.x() - b.y(), b.x(), b.y()};
      for (int corner = 0; corner < 3; ++corner) {
        k.vertex.push_back(proxy.vertex_near(mesh.positions[t[corner]]));
        k.weight.push_back(w[corner]);
      }
      k.nearest[i] = k.vertex[start + static_cast<std::size_t>(std::max_element(w.begin(), w.end()) - w.begin())];
    }
    k.first[i + 1] = k.vertex.size();
  }
  return k;
}

}  // namespace

std::string CoverageOptions::key(const FeatureDefinition& d) const {
  const char* name = d.measure == FeatureMeasure::patch_density ? "patch-density" : "saliency";
  char angle[32];
  std::snprintf(angle, sizeof angle, "%g", seen_angle_deg[d.angle]);
  return std::string(name) + "-" + angle + "deg";
}

const std::array<FeatureDefinition, kFeatureDefinitions>& feature_definitions() {
  // Both measures at each angle, the angles in the order of CoverageOptions::seen_angle_deg.
  static const std::array<FeatureDefinition, kDefinitions> definitions = [] {
    std::array<FeatureDefinition, kDefinitions> all{};
    for (int a = 0; a < kSeenAngles; ++a) {
      all[static_cast<std::size_t>(2 * a)] = {FeatureMeasure::patch_density, a};
      all[static_cast<std::size_t>(2 * a + 1)] = {FeatureMeasure::saliency, a};
    }
    return all;
  }();
  return definitions;
}

void CoverageOptions::validate() const {
  if (samples < 1024 || samples > (1u << 24)) throw InputError("coverage: the surface samples must be 1024 to 16777216");
  if (proxy_cells < 500 || proxy_cells > 2000000) throw InputError("coverage: the proxy cells must be 500 to 2000000");
  if (!(feature_quantile >= 0.0 && feature_quantile < 1.0)) throw InputError("coverage: the feature quantile must be in [0, 1)");
  if (!(surface_weight >= 0.0)) throw InputError("coverage: the surface weight must not be negative");
  for (double a : seen_angle_deg)
    if (!(a > 0.0 && a <= 90.0)) throw InputError("coverage: the seen-well angles must be above 0 and at most 90 degrees");
  for (std::size_t i = 0; i < seen_angle_deg.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (seen_angle_deg[i] == seen_angle_deg[j]) {
        char text[200];
        std::snprintf(text, sizeof text,
                      "coverage: two seen-well angles are both %g degrees; --seen-angle, --strict-angle, --stricter-angle and "
                      "--strictest-angle must differ (each names a pair of feature definitions)",
                      seen_angle_deg[i]);
        throw InputError(text);
      }
}

std::size_t count_bits(const std::vector<std::uint64_t>& bits) {
  std::size_t n = 0;
  for (std::uint64_t w : bits) n += static_cast<std::size_t>(std::popcount(w));
  return n;
}

struct CoverageModel::Impl {
  CoverageOptions options;
  SurfaceSamples samples;
  std::array<std::vector<std::uint8_t>, kFeatureMeasures> feature;
  std::array<std::vector<std::uint64_t>, kFeatureMeasures> feature_bits;
  std::array<std::size_t, kFeatureMeasures> feature_count{};
  std::array<std::vector<int>, kFeatureMeasures> region;
  std::array<int, kFeatureMeasures> regions{};
  std::unique_ptr<VisibilityScene> scene;
  std::vector<std::pair<std::string, double>> stage_seconds;
  std::size_t words = 0;
  // The view preference's proxy (ViewPreferenceModel): the six directions, and the goodness of
  // each (then of each on one half of the samples and of the area grid), with its two terms.
  std::array<Eigen::Vector3d, 6> proxy_direction;
  std::array<double, 6> proxy_area{}, proxy_visible{};
  std::array<std::array<double, 6>, 2> proxy_half_goodness{};
  int outside = 0;
};

CoverageModel::CoverageModel(const TriangleMesh& mesh, const CoverageOptions& options) : impl_(std::make_unique<Impl>()) {
  options.validate();
  if (mesh.triangles.empty()) throw InputError("coverage: the mesh has no triangles");
  Impl& s = *impl_;
  s.options = options;
  StageTimer timer(s.stage_seconds);

  // One after the other, not side by side: an interrupt cancelling a TBB task group while
  // Embree builds inside it leaves Embree's build state broken (a crash instead of exit 130).
  const bool given = !options.face_features.empty();
  if (given && options.face_features.size() != mesh.triangles.size())
    throw InputError("coverage: one feature flag per face is needed");
  s.samples = sample_surface(mesh, options.samples);
  ClusteredMesh proxy = coverage_proxy(mesh, options);
  std::array<std::vector<double>, kFeatureMeasures> proxy_value;
  timer.done("samples and proxy");
  if (!given) {
    throw_if_interrupted();
    proxy_value[0] = proxy_patch_density(proxy.mesh, options.surface);
    timer.done("patch density");
    throw_if_interrupted();
    proxy_value[1] = vertex_saliency(proxy.mesh);
    timer.done("saliency");
  }
  throw_if_interrupted();
  s.scene = options.ray_scene ? std::make_unique<VisibilityScene>(options.ray_scene) : std::make_unique<VisibilityScene>(mesh);
  timer.done("visibility scene");

  // Each sample takes the values of the proxy vertices near it (within one cell), weighted by a
  // smooth kernel of the distance and by how well their normals agree with its own. What a sample
  // gets then depends on where it is on the shape, not on the face it lies on: a coarse face
  // spans several cells, a fine one none. Where no proxy vertex is near or faces its way (a thin
  // part whose sides share cells), the proxy vertices of its face's corners are blended instead.
  const std::size_t n = s.samples.size();
  s.words = (n + 63) / 64;
  const SampleKernel kernel = proxy_kernel(proxy, s.samples, mesh);
  std::vector<std::uint32_t> nearest_cluster(n);
  for (std::size_t i = 0; i < n; ++i) nearest_cluster[i] = kernel.nearest[i];
  for (int m = 0; m < kFeatureMeasures; ++m) {
    std::vector<double> value(n);
    for (std::size_t i = 0; i < n; ++i) {
      if (given) {
        value[i] = options.face_features[s.samples.faces[i]];
        continue;
      }
      double sum = 0.0;
      for (std::size_t k = kernel.first[i]; k < kernel.first[i + 1]; ++k) sum += kernel.weight[k] * proxy_value[m][kernel.vertex[k]];
      value[i] = sum;
    }
    if (given) {
      s.feature[m].resize(n);
      for (std::size_t i = 0; i < n; ++i) s.feature[m][i] = value[i] > 0.0;
    } else {
      s.feature[m] = top_quantile(value, options.feature_quantile);
    }
    s.feature_bits[m].assign(s.words, 0);
    for (std::size_t i = 0; i < n; ++i)
      if (s.feature[m][i]) s.feature_bits[m][i / 64] |= std::uint64_t{1} << (i % 64);
    s.feature_count[m] = count_bits(s.feature_bits[m]);

    // Regions: proxy vertices holding feature samples, joined along proxy edges.
    const std::size_t clusters = proxy.mesh.positions.size();
    std::vector<std::uint8_t> feature_cluster(clusters, 0);
    for (std::size_t i = 0; i < n; ++i)
      if (s.feature[m][i]) feature_cluster[nearest_cluster[i]] = 1;
    DisjointSets regions(clusters);
    for (const auto& t : proxy.mesh.triangles)
      for (int e = 0; e < 3; ++e) {
        const std::uint32_t a = t[e], b = t[(e + 1) % 3];
        if (!feature_cluster[a] || !feature_cluster[b]) continue;
        regions.join(a, b);
      }
    std::vector<int> id(clusters, -1);
    s.region[m].assign(n, -1);
    for (std::size_t i = 0; i < n; ++i) {
      if (!s.feature[m][i]) continue;
      const std::uint32_t root = regions.root(nearest_cluster[i]);
      if (id[root] < 0) id[root] = s.regions[m]++;
      s.region[m][i] = id[root];
    }
  }
  timer.done("sample features");

  // The view preference's proxy (ViewPreferenceModel): the principal axes of the samples (each
  // stands for the same area), and what the model shows along each of their six directions, seen
  // from far enough that the long lens holds the bounding sphere (nearly a parallel projection).
  {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& p : s.samples.points) mean += p;
    mean /= static_cast<double>(n);
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    for (const Eigen::Vector3d& p : s.samples.points) covariance += (p - mean) * (p - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> axes(covariance);
    const Eigen::Vector3d center = mesh.bounds().center();
    const double radius = 0.5 * s.scene->diagonal();
    constexpr double kFov = 10.0;
    const double distance = radius / std::sin(0.5 * kFov * 3.14159265358979323846 / 180.0);
    const double cos_limit = std::cos(ViewPreferenceModel::seen_angle_deg * 3.14159265358979323846 / 180.0);
    // Per direction: samples seen within the angle, by side (0: the normals' side) and by half.
    std::array<std::array<std::array<std::size_t, 2>, 2>, 6> seen{};
    std::array<ProjectedArea, 6> area;
    for (int i = 0; i < 6; ++i) {
      throw_if_interrupted();
      const Eigen::Vector3d d = (i < 3 ? 1.0 : -1.0) * axes.eigenvectors().col(2 - i % 3).normalized();
      s.proxy_direction[i] = d;
      const Camera camera{center + distance * d, center, d.unitOrthogonal(), kFov};
      const VisibleSamples visible = s.scene->visible(View{camera, 1.0}, s.samples, ViewPreferenceModel::seen_angle_deg);
      for (std::size_t k = 0; k < visible.samples.size(); ++k)
        if (visible.cosines[k] > cos_limit) ++seen[i][visible.front[k] ? 0 : 1][visible.samples[k] % 2];
      area[i] = s.scene->projected_area(d, ViewPreferenceModel::area_grid);
    }
    std::array<std::size_t, 2> side_total{};
    for (const auto& by_side : seen)
      for (int side = 0; side < 2; ++side) side_total[side] += by_side[side][0] + by_side[side][1];
    // A tie (a surface seen equally from both sides) keeps the normals' side.
    s.outside = side_total[1] > side_total[0] ? 1 : 0;
    double area_max = 0.0, seen_max = 0.0;
    for (int i = 0; i < 6; ++i) {
      area_max = std::max(area_max, area[i].area);
      seen_max = std::max(seen_max, static_cast<double>(seen[i][s.outside][0] + seen[i][s.outside][1]));
    }
    area_max = std::max(area_max, 1e-300);
    seen_max = std::max(seen_max, 1.0);
    constexpr double w = ViewPreferenceModel::area_weight;
    for (int i = 0; i < 6; ++i) {
      s.proxy_area[i] = area[i].area / area_max;
      s.proxy_visible[i] = static_cast<double>(seen[i][s.outside][0] + seen[i][s.outside][1]) / seen_max;
      // Each half: its own estimate of the area, twice its half of the samples.
      for (int h = 0; h < 2; ++h)
        s.proxy_half_goodness[h][i] = w * area[i].halves[h] / area_max + (1.0 - w) * 2.0 * static_cast<double>(seen[i][s.outside][h]) / seen_max;
    }
    timer.done("view preference proxy");
  }
}

CoverageModel::~CoverageModel() = default;

ClusteredMesh coverage_proxy(const TriangleMesh& mesh, const CoverageOptions& options) {
  return cluster_surface(mesh, options.proxy_cells);
}

ViewCoverage CoverageModel::coverage(const View& view, std::size_t stride) const {
  const Impl& s = *impl_;
  if (stride < 1 || stride > 64 || !std::has_single_bit(stride)) throw InputError("coverage: the sample stride must be a power of two up to 64");
  // One pass at the widest angle; the stricter angles filter its cosines.
  const double widest = *std::max_element(s.options.seen_angle_deg.begin(), s.options.seen_angle_deg.end());
  const VisibleSamples visible = s.scene->visible(view, s.samples, widest, stride);
  ViewCoverage out;
  out.stride = stride;
  for (int a = 0; a < kSeenAngles; ++a) {
    out.seen[a].assign(s.words, 0);
    const float limit = static_cast<float>(std::cos(s.options.seen_angle_deg[a] * 3.14159265358979323846 / 180.0));
    for (std::size_t k = 0; k < visible.samples.size(); ++k)
      if (visible.cosines[k] > limit) out.seen[a][visible.samples[k] / 64] |= std::uint64_t{1} << (visible.samples[k] % 64);
  }
  return out;
}

namespace {
// The stride shared by `views` (every stride-th sample was tested).
std::size_t common_stride(std::span<const ViewCoverage* const> views) {
  const std::size_t stride = views.empty() ? 1 : views.front()->stride;
  for (const ViewCoverage* v : views)
    if (v->stride != stride) throw InputError("coverage: views tested on different sample subsets cannot be scored together");
  return stride;
}
// The samples tested at `stride`: a bit pattern that repeats in every word (the stride divides 64).
std::uint64_t stride_pattern(std::size_t stride) {
  std::uint64_t tested = 0;
  for (std::size_t b = 0; b < 64; b += stride) tested |= std::uint64_t{1} << b;
  return tested;
}
}  // namespace

CoverageScores CoverageModel::scores(std::span<const ViewCoverage* const> views) const {
  return scores_on(views, stride_pattern(common_stride(views)));
}

std::array<CoverageScores, 2> CoverageModel::half_scores(std::span<const ViewCoverage* const> views) const {
  // Every other tested sample: the tested pattern's set bits, alternately.
  const std::uint64_t tested = stride_pattern(common_stride(views));
  std::uint64_t even = 0;
  bool take = true;
  for (int b = 0; b < 64; ++b)
    if (tested >> b & 1u) {
      if (take) even |= std::uint64_t{1} << b;
      take = !take;
    }
  return {scores_on(views, even), scores_on(views, tested & ~even)};
}

CoverageScores CoverageModel::scores_on(std::span<const ViewCoverage* const> views, std::uint64_t counted) const {
  const Impl& s = *impl_;
  CoverageScores out;
  // The samples counted: the bits of `counted` in every word, up to the last sample.
  const auto counted_in = [&](std::size_t w) {
    const std::size_t rest = s.samples.size() - 64 * w;
    return rest >= 64 ? counted : counted & ((std::uint64_t{1} << rest) - 1);
  };
  std::size_t n = 0;
  std::array<std::size_t, kFeatureMeasures> feature_count{};
  for (std::size_t w = 0; w < s.words; ++w) {
    n += static_cast<std::size_t>(std::popcount(counted_in(w)));
    for (int m = 0; m < kFeatureMeasures; ++m) feature_count[m] += static_cast<std::size_t>(std::popcount(s.feature_bits[m][w] & counted_in(w)));
  }
  n = std::max<std::size_t>(n, 1);
  for (int a = 0; a < kSeenAngles; ++a) {
    std::array<std::size_t, kFeatureMeasures> features_seen{};
    std::size_t seen = 0;
    for (std::size_t w = 0; w < s.words; ++w) {
      std::uint64_t word = 0;
      for (const ViewCoverage* v : views) word |= v->seen[a][w];
      word &= counted_in(w);
      seen += static_cast<std::size_t>(std::popcount(word));
      for (int m = 0; m < kFeatureMeasures; ++m) features_seen[m] += static_cast<std::size_t>(std::popcount(word & s.feature_bits[m][w]));
    }
    out.surface_share[a] = static_cast<double>(seen) / static_cast<double>(n);
    for (int d = 0; d < kDefinitions; ++d) {
      const FeatureDefinition& def = feature_definitions()[d];
      if (def.angle != a) continue;
      const int m = static_cast<int>(def.measure);
      const double features = static_cast<double>(std::max<std::size_t>(1, feature_count[m]));
      out.feature_share[d] = static_cast<double>(features_seen[m]) / features;
      out.value[d] = (static_cast<double>(features_seen[m]) +
                      s.options.surface_weight * static_cast<double>(seen - features_seen[m])) / features;
    }
  }
  out.objective = 0.0;
  for (double v : out.value) out.objective += v / kDefinitions;
  return out;
}

CoverageScores CoverageModel::scores(const ViewCoverage& view) const {
  const ViewCoverage* one[] = {&view};
  return scores(one);
}

ViewPreference CoverageModel::preference(const View& view) const {
  const Impl& s = *impl_;
  const Eigen::Vector3d v = (view.camera.eye - view.camera.target).normalized();
  constexpr double w = ViewPreferenceModel::area_weight;
  ViewPreference out;
  for (int i = 0; i < 6; ++i) {
    const double c = std::max(0.0, v.dot(s.proxy_direction[i]));
    out.projected_area += c * s.proxy_area[i];
    out.visible_ratio += c * s.proxy_visible[i];
    for (int h = 0; h < 2; ++h) out.half_scores[h] += c * s.proxy_half_goodness[h][i];
  }
  out.score = w * out.projected_area + (1.0 - w) * out.visible_ratio;
  return out;
}

std::array<Eigen::Vector3d, 6> CoverageModel::preference_directions() const { return impl_->proxy_direction; }

int CoverageModel::outside_side() const { return impl_->outside; }

const SurfaceSamples& CoverageModel::samples() const { return impl_->samples; }
const std::vector<std::uint8_t>& CoverageModel::features(FeatureMeasure m) const { return impl_->feature[static_cast<int>(m)]; }
const std::vector<int>& CoverageModel::sample_region(FeatureMeasure m) const { return impl_->region[static_cast<int>(m)]; }
int CoverageModel::region_count(FeatureMeasure m) const { return impl_->regions[static_cast<int>(m)]; }
const CoverageOptions& CoverageModel::options() const { return impl_->options; }
const std::vector<std::pair<std::string, double>>& CoverageModel::stage_seconds() const { return impl_->stage_seconds; }

}  // namespace meshtour
