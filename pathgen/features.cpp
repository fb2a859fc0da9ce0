#include "pathgen/features.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <numeric>

#include "core/error.h"

namespace meshtour {

std::vector<double> input_face_weights(const SurfaceAnalysis& surface, std::size_t input_faces) {
  std::vector<double> weights(input_faces, 0.0);
  for (std::size_t f = 0; f < surface.face_weight.size() && f < surface.input_face.size(); ++f) {
    const std::size_t input = surface.input_face[f];
    if (input < input_faces) weights[input] = std::max(weights[input], surface.face_weight[f]);
  }
  return weights;
}

double area_weighted_quantile(const std::vector<double>& weights, const std::vector<double>& areas, double quantile) {
  if (weights.size() != areas.size()) throw InputError("feature faces: one weight per face is needed");
  if (!(quantile >= 0.0 && quantile <= 1.0)) throw InputError("the feature quantile must be between 0 and 1");
  std::vector<std::size_t> order(weights.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  // Stable sort by weight, so that equal weights sum their areas in face order (determinism).
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return weights[a] < weights[b]; });
  double total = 0.0;
  for (std::size_t f : order) total += areas[f];
  if (!(total > 0.0)) throw InputError("feature faces: the mesh has no area");
  double below = 0.0;
  for (std::size_t k = 0; k < order.size(); ++k) {
    below += areas[order[k]];
    // Only at the end of a run of equal weights does the area "at or below" this weight count.
    if (k + 1 < order.size() && weights[order[k + 1]] == weights[order[k]]) continue;
    if (below >= quantile * total * (1.0 - 1e-12)) return weights[order[k]];
  }
  return weights[order.back()];
}

std::vector<std::uint8_t> feature_faces(const std::vector<double>& weights, const std::vector<double>& areas,
                                        double quantile) {
  const double threshold = area_weighted_quantile(weights, areas, quantile);
  std::vector<std::uint8_t> feature(weights.size());
  for (std::size_t f = 0; f < weights.size(); ++f) feature[f] = weights[f] >= threshold ? 1 : 0;
  return feature;
}

}  // namespace meshtour
