#pragma once
// §6–§7: per-vertex osculating tori, the best-fit-first seed order and the toroidal-patch
// decomposition (Phase A growth, Phase B leftovers).
#include <vector>

#include "pathgen/surface_mesh.h"

namespace meshtour::surface_detail {

/// T_v of §6.2 at every vertex (parallel).
std::vector<Torus> vertex_tori(const SurfaceMesh& mesh, const std::vector<VertexDifferential>& differential,
                               double kappa_min);

/// §7.1–§7.2: e_v = max over the 1-ring of d(q, T_v) (0 without neighbours), per vertex.
std::vector<double> seed_errors(const SurfaceMesh& mesh, const std::vector<Torus>& tori);

/// §7.2: vertices sorted by the quantized keys (⌊e/1e-12⌋, ⌊x/1e-9⌋, ⌊y/1e-9⌋, ⌊z/1e-9⌋, index).
std::vector<std::uint32_t> best_fit_first_order(const SurfaceMesh& mesh, const std::vector<double>& errors);

struct Decomposition {
  std::vector<int> face_patch;
  std::vector<PatchRecord> patches;
  int grown = 0;
  int single = 0;
  int orphans = 0;
  int largest = 0;
};

/// I-34: the length of the tolerance's unit in the normalized frame of `positions` (bounding-box
/// diagonal 1): 1 for the diagonal, else the box's largest side or half of it.
double tolerance_unit_length(const std::vector<Eigen::Vector3d>& positions, ToleranceUnit unit);

/// §7.3–§7.4. `seed_order` lists the vertices in seed order (its ranks also break Phase-B ties);
/// `phase_a_seeds`, if not empty, replaces it as the list Phase A visits (test hook).
/// `test_positions`, when given, are the vertex positions the faces are tested at (I-33).
Decomposition decompose(const SurfaceMesh& mesh, const std::vector<Torus>& tori, const std::vector<std::uint32_t>& seed_order,
                        const std::vector<std::uint32_t>& phase_a_seeds, const SurfaceOptions& options,
                        const std::vector<Eigen::Vector3d>* test_positions = nullptr);

}  // namespace meshtour::surface_detail
