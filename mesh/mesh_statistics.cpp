#include "mesh/mesh_statistics.h"

#include <Eigen/Geometry>

#include <cstdio>
#include <vector>

#include "core/disjoint_sets.h"
#include "core/triangle_geometry.h"
#include "mesh/mesh_edges.h"

namespace meshtour {

MeshStatistics mesh_statistics(const TriangleMesh& mesh) {
  MeshStatistics s;
  const EdgeTally tally = tally_edges(mesh);
  s.edges = tally.edges;
  s.boundary_edges = tally.boundary.size();
  s.non_manifold_edges = tally.non_manifold_edges;
  DisjointSets components(mesh.positions.size());
  std::vector<bool> used(mesh.positions.size(), false);
  for (const auto& t : mesh.triangles) {
    for (int c = 0; c < 3; ++c) {
      used[t[c]] = true;
      components.join(t[c], t[(c + 1) % 3]);
    }
    s.surface_area += triangle_area(mesh.positions, t);
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
