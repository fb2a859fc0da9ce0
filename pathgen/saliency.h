#pragma once
// Mesh saliency (Lee, Varshney & Jacobs, "Mesh Saliency", SIGGRAPH 2005): a definition of "feature"
// independent of the toroidal patches (docs/METHOD.md §8), so that `evaluate` can judge paths by a
// second, unrelated yardstick. A vertex is salient where the mean curvature around it at a small
// scale differs from the mean curvature at twice that scale. See docs/SALIENCY.md.
//
// Works on a raw triangle soup (no topology, no manifold requirement): duplicate, degenerate and
// non-manifold faces and unused vertices are allowed; whatever cannot be measured counts as 0.
#include <vector>

#include "mesh/mesh.h"

namespace meshtour {

struct SaliencyOptions {
  /// ε as a fraction of the bounding-box diagonal (Lee et al.: 0.3%). Between 0.001 and 0.05.
  double epsilon_fraction = 0.003;
};

/// Signed mean curvature of every vertex (1/model units; positive where convex for outward faces),
/// from the area gradient (the cotangent Laplacian in a form bounded on sliver faces) projected on
/// the area-weighted vertex normal, divided by the vertex's area share. 0 for vertices without
/// area (unused, or only in degenerate faces).
std::vector<double> vertex_mean_curvature(const TriangleMesh& mesh);

/// Saliency of every vertex of `mesh` (one value per position, >= 0; 0 for unused vertices). Sum
/// over the scales σ ∈ {2,3,4,5,6}ε of the suppressed, normalised |G(σ) − G(2σ)|, where G is the
/// Gaussian-weighted, area-weighted mean curvature. Deterministic for any thread count; checks for
/// interrupts. \throw InputError if the options are out of range.
std::vector<double> vertex_saliency(const TriangleMesh& mesh, const SaliencyOptions& options = {});

/// Per-face saliency: the mean of the face's three vertex values, for
/// feature_faces(face_saliency(mesh, s), face_areas(mesh), 0.75) (pathgen/features.h, mesh/mesh.h).
/// \throw InputError if `vertex_values` does not have one value per position.
std::vector<double> face_saliency(const TriangleMesh& mesh, const std::vector<double>& vertex_values);

}  // namespace meshtour
