#include "pathgen/coverage.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <bit>
#include <cstdio>
#include <cmath>
#include <numeric>

#include "core/error.h"
#include "core/interrupt.h"
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
  const SurfaceAnalysis surface = analyze_surface(proxy, options);
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

}  // namespace

std::string CoverageOptions::key(const FeatureDefinition& d) const {
  const char* name = d.measure == FeatureMeasure::patch_density ? "patch-density" : "saliency";
  char angle[32];
  std::snprintf(angle, sizeof angle, "%g", seen_angle_deg[d.angle]);
  return std::string(name) + "-" + angle + "deg";
}

const std::array<FeatureDefinition, kFeatureDefinitions>& feature_definitions() {
  static const std::array<FeatureDefinition, kDefinitions> definitions{{
      {FeatureMeasure::patch_density, 0},
      {FeatureMeasure::saliency, 0},
      {FeatureMeasure::patch_density, 1},
      {FeatureMeasure::saliency, 1},
  }};
  return definitions;
}

void CoverageOptions::validate() const {
  if (samples < 1024 || samples > (1u << 24)) throw InputError("coverage: the surface samples must be 1024 to 16777216");
  if (proxy_cells < 500 || proxy_cells > 2000000) throw InputError("coverage: the proxy cells must be 500 to 2000000");
  if (!(feature_quantile >= 0.0 && feature_quantile < 1.0)) throw InputError("coverage: the feature quantile must be in [0, 1)");
  if (!(surface_weight >= 0.0)) throw InputError("coverage: the surface weight must not be negative");
  for (double a : seen_angle_deg)
    if (!(a > 0.0 && a <= 90.0)) throw InputError("coverage: the seen-well angles must be above 0 and at most 90 degrees");
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
  ClusteredMesh proxy = cluster_vertices(mesh, options.proxy_cells);
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
  s.scene = std::make_unique<VisibilityScene>(mesh);
  timer.done("visibility scene");

  // Each sample takes the values of the proxy vertices its face's corners merged into, blended
  // by its barycentric coordinates.
  const std::size_t n = s.samples.size();
  s.words = (n + 63) / 64;
  std::vector<std::uint32_t> nearest_cluster(n);
  for (int m = 0; m < kFeatureMeasures; ++m) {
    std::vector<double> value(n);
    for (std::size_t i = 0; i < n; ++i) {
      const auto& t = mesh.triangles[s.samples.faces[i]];
      const Eigen::Vector2d& b = s.samples.barycentric[i];
      const std::array<double, 3> w{1.0 - b.x() - b.y(), b.x(), b.y()};
      const std::array<std::uint32_t, 3> c{proxy.vertex_cluster[t[0]], proxy.vertex_cluster[t[1]], proxy.vertex_cluster[t[2]]};
      value[i] = given ? options.face_features[s.samples.faces[i]]
                       : w[0] * proxy_value[m][c[0]] + w[1] * proxy_value[m][c[1]] + w[2] * proxy_value[m][c[2]];
      if (m == 0) nearest_cluster[i] = c[static_cast<std::size_t>(std::max_element(w.begin(), w.end()) - w.begin())];
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
    std::vector<std::uint32_t> parent(clusters);
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](std::uint32_t x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    for (const auto& t : proxy.mesh.triangles)
      for (int e = 0; e < 3; ++e) {
        const std::uint32_t a = t[e], b = t[(e + 1) % 3];
        if (!feature_cluster[a] || !feature_cluster[b]) continue;
        const std::uint32_t x = find(a), y = find(b);
        if (x != y) parent[std::max(x, y)] = std::min(x, y);
      }
    std::vector<int> id(clusters, -1);
    s.region[m].assign(n, -1);
    for (std::size_t i = 0; i < n; ++i) {
      if (!s.feature[m][i]) continue;
      const std::uint32_t root = find(nearest_cluster[i]);
      if (id[root] < 0) id[root] = s.regions[m]++;
      s.region[m][i] = id[root];
    }
  }
  timer.done("sample features");
}

CoverageModel::~CoverageModel() = default;

ViewCoverage CoverageModel::coverage(const View& view) const {
  const Impl& s = *impl_;
  // One pass at the widest angle; the stricter angles filter its cosines.
  const double widest = std::max(s.options.seen_angle_deg[0], s.options.seen_angle_deg[1]);
  const VisibleSamples visible = s.scene->visible(view, s.samples, widest);
  ViewCoverage out;
  for (int a = 0; a < kSeenAngles; ++a) {
    out.seen[a].assign(s.words, 0);
    const float limit = static_cast<float>(std::cos(s.options.seen_angle_deg[a] * 3.14159265358979323846 / 180.0));
    for (std::size_t k = 0; k < visible.samples.size(); ++k)
      if (visible.cosines[k] > limit) out.seen[a][visible.samples[k] / 64] |= std::uint64_t{1} << (visible.samples[k] % 64);
  }
  return out;
}

CoverageScores CoverageModel::scores(std::span<const ViewCoverage* const> views) const {
  const Impl& s = *impl_;
  CoverageScores out;
  const std::size_t n = s.samples.size();
  for (int a = 0; a < kSeenAngles; ++a) {
    std::array<std::size_t, kFeatureMeasures> features_seen{};
    std::size_t seen = 0;
    for (std::size_t w = 0; w < s.words; ++w) {
      std::uint64_t word = 0;
      for (const ViewCoverage* v : views) word |= v->seen[a][w];
      seen += static_cast<std::size_t>(std::popcount(word));
      for (int m = 0; m < kFeatureMeasures; ++m) features_seen[m] += static_cast<std::size_t>(std::popcount(word & s.feature_bits[m][w]));
    }
    out.surface_share[a] = static_cast<double>(seen) / static_cast<double>(n);
    for (int d = 0; d < kDefinitions; ++d) {
      const FeatureDefinition& def = feature_definitions()[d];
      if (def.angle != a) continue;
      const int m = static_cast<int>(def.measure);
      const double features = static_cast<double>(std::max<std::size_t>(1, s.feature_count[m]));
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

const SurfaceSamples& CoverageModel::samples() const { return impl_->samples; }
const std::vector<std::uint8_t>& CoverageModel::features(FeatureMeasure m) const { return impl_->feature[static_cast<int>(m)]; }
const std::vector<int>& CoverageModel::sample_region(FeatureMeasure m) const { return impl_->region[static_cast<int>(m)]; }
int CoverageModel::region_count(FeatureMeasure m) const { return impl_->regions[static_cast<int>(m)]; }
const CoverageOptions& CoverageModel::options() const { return impl_->options; }
const std::vector<std::pair<std::string, double>>& CoverageModel::stage_seconds() const { return impl_->stage_seconds; }

}  // namespace meshtour
