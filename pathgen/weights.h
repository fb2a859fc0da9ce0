#pragma once
// §8: the per-face weight w(f), the number of distinct patches around a face.
#include <vector>

#include "pathgen/surface_mesh.h"

namespace meshtour::surface_detail {

/// w(f) for every face, with the neighbourhood of I-15 chosen by `neighbourhood`.
std::vector<double> face_weights(const SurfaceMesh& mesh, const std::vector<int>& face_patch, int patch_count,
                                 WeightNeighbourhood neighbourhood);

}  // namespace meshtour::surface_detail
