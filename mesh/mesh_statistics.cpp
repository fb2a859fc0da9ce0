#include "mesh/mesh_statistics.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cstdio>
#include <numeric>
#include <utility>
#include <vector>

#include "core/disjoint_sets.h"

namespace meshtour {

MeshStatistics mesh_statistics(const TriangleMesh& mesh) {
  MeshStatistics s;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  edges.reserve(3 * mesh.triangles.size());
  DisjointSets components(mesh.positions.size());
  std::vector<bool> used(mesh.positions.size(), false);
  for (const auto& t : mesh.triangles) {
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t a = t[c], b = t[(c + 1) % 3];
      edges.emplace_back(std::min(a, b), std::max(a, b));
      used[a] = true;
      components.join(a, b);
    }
    const Eigen::Vector3d& p0 = mesh.positions[t[0]];
    s.surface_area += 0.5 * (mesh.positions[t[1]] - p0).cross(mesh.positions[t[2]] - p0).norm();
  }
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    ++s.edges;
    if (j - i == 1) ++s.boundary_edges;
    if (j - i > 2) ++s.non_manifold_edges;
    i = j;
  }
  for (std::uint32_t v = 0; v < mesh.positions.size(); ++v) {
    if (!used[v]) ++s.unreferenced_vertices;
    else if (components.root(v) == v) ++s.components;
  }
  return s;
}

std::string guess_units(double diagonal) {
  char text[96];
  const char* unit = diagonal >= 50.0 ? "millimetres" : diagonal >= 5.0 ? "centimetres (or inches)" : "metres";
  std::snprintf(text, sizeof text, "%s (bounding-box diagonal %.4g)", unit, diagonal);
  return text;
}

}  // namespace meshtour
