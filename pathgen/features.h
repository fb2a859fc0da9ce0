#pragma once
// Feature faces: the faces whose weight w(f) (docs/METHOD.md §8) is at or above an area-weighted
// quantile of all the weights. Shared by the evaluation (what a tour should show) and the
// feature-orbit path (what it tries to show), so both judge by the same faces.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mesh/mesh.h"
#include "pathgen/surface.h"

namespace meshtour {

/// w(f) of every face of the *input* mesh (`input_faces` faces), taken from the analysis through
/// SurfaceAnalysis::input_face. Faces the clean-up dropped get 0. A face split into several
/// (non-manifold repairs) keeps the largest weight of its parts.
std::vector<double> input_face_weights(const SurfaceAnalysis& surface, std::size_t input_faces);

/// The area-weighted `quantile` (0..1) of `weights`: the smallest weight q such that the faces with
/// a weight <= q hold at least `quantile` of the total area. \throw InputError if the sizes differ,
/// the quantile is outside [0, 1] or the mesh has no area.
double area_weighted_quantile(const std::vector<double>& weights, const std::vector<double>& areas, double quantile);

/// 1 for the faces with weight >= area_weighted_quantile(weights, areas, quantile), else 0.
std::vector<std::uint8_t> feature_faces(const std::vector<double>& weights, const std::vector<double>& areas,
                                        double quantile = 0.75);

}  // namespace meshtour
