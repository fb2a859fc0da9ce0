#include "mesh/vertex_clustering.h"

#include <tbb/parallel_sort.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/interrupt.h"

namespace meshtour {

ClusteredMesh cluster_vertices(const TriangleMesh& mesh, std::size_t target_cells) {
  if (target_cells < 1) throw InputError("vertex clustering needs at least one cell");
  const std::size_t n = mesh.positions.size();
  // Area owned by each vertex (a third of each face it is a corner of): the weight of its position
  // in the cluster's mean, so that a finely tessellated region does not pull the mean its way.
  std::vector<double> vertex_area(n, 0.0);
  std::vector<std::uint8_t> used(n, 0);
  double total = 0.0;
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
    double area = 0.5 * (b - a).cross(c - a).norm();
    if (!std::isfinite(area)) area = 0.0;
    total += area;
    for (std::uint32_t v : t) {
      vertex_area[v] += area / 3.0;
      used[v] = 1;
    }
  }
  if (!(total > 0.0)) throw InputError("the mesh has no surface area to simplify");
  throw_if_interrupted();

  ClusteredMesh out;
  const Bounds bounds = mesh.bounds();
  out.cell_size = std::sqrt(total / static_cast<double>(target_cells));
  out.grid_origin = bounds.lo - Eigen::Vector3d::Constant(0.5 * out.cell_size);
  // Cell key: 21 bits per axis (2 million cells along an axis is far beyond any target).
  auto key = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3d q = (p - out.grid_origin) / out.cell_size;
    auto axis = [](double x) { return static_cast<std::uint64_t>(std::clamp(x, 0.0, 2097151.0)); };
    return (axis(q.x()) << 42) | (axis(q.y()) << 21) | axis(q.z());
  };
  struct Entry {
    std::uint64_t cell;
    std::uint32_t vertex;
  };
  std::vector<Entry> entries;
  entries.reserve(n);
  for (std::size_t v = 0; v < n; ++v)
    if (used[v]) entries.push_back({key(mesh.positions[v]), static_cast<std::uint32_t>(v)});
  // Sorting by (cell, vertex) numbers the clusters in cell order whatever the thread count.
  tbb::parallel_sort(entries.begin(), entries.end(),
                     [](const Entry& x, const Entry& y) { return x.cell != y.cell ? x.cell < y.cell : x.vertex < y.vertex; });
  throw_if_interrupted();

  out.vertex_cluster.assign(n, 0);
  std::vector<double> weight;
  for (std::size_t i = 0; i < entries.size();) {
    std::size_t j = i;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero(), plain = Eigen::Vector3d::Zero();
    double w = 0.0;
    const auto cluster = static_cast<std::uint32_t>(out.mesh.positions.size());
    for (; j < entries.size() && entries[j].cell == entries[i].cell; ++j) {
      const std::uint32_t v = entries[j].vertex;
      sum += vertex_area[v] * mesh.positions[v];
      plain += mesh.positions[v];
      w += vertex_area[v];
      out.vertex_cluster[v] = cluster;
    }
    out.mesh.positions.push_back(w > 0.0 ? Eigen::Vector3d(sum / w) : Eigen::Vector3d(plain / static_cast<double>(j - i)));
    i = j;
  }

  // Triangles with three distinct clusters survive; one copy of each (as an unordered triple).
  struct Key {
    std::array<std::uint32_t, 3> sorted, corners;
  };
  std::vector<Key> keys;
  for (const auto& t : mesh.triangles) {
    const std::array<std::uint32_t, 3> c{out.vertex_cluster[t[0]], out.vertex_cluster[t[1]], out.vertex_cluster[t[2]]};
    if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) continue;
    std::array<std::uint32_t, 3> s = c;
    std::sort(s.begin(), s.end());
    keys.push_back({s, c});
  }
  throw_if_interrupted();
  tbb::parallel_sort(keys.begin(), keys.end(), [](const Key& x, const Key& y) {
    return x.sorted != y.sorted ? x.sorted < y.sorted : x.corners < y.corners;
  });
  for (std::size_t k = 0; k < keys.size(); ++k)
    if (k == 0 || keys[k].sorted != keys[k - 1].sorted) out.mesh.triangles.push_back(keys[k].corners);
  return out;
}

}  // namespace meshtour
