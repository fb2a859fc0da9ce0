#pragma once
// §4: smoothing of the normalized mesh (implicit cotangent-Laplacian step and the alternatives).
#include "pathgen/surface_mesh.h"

namespace meshtour::surface_detail {

struct SmoothingResult {
  double dt = 0.0;          ///< step size of the implicit step (0 otherwise)
  int iterations = 0;       ///< largest CG iteration count over the three coordinate columns
};

/// Mean length of the unique edges (ē), summed in edge order.
double mean_edge_length(const SurfaceMesh& mesh);

/// Moves mesh.positions according to options.smoothing. Boundary vertices stay fixed.
/// \throw RuntimeFailure if the conjugate gradients do not converge.
SmoothingResult smooth(SurfaceMesh& mesh, const SurfaceOptions& options, double mean_edge);

}  // namespace meshtour::surface_detail
