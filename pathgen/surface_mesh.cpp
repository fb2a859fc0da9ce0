// §3 and §1.2: clean-up of scanner meshes, the OpenMesh halfedge structure, normalization.

// OpenMesh's PropertyT<VectorT>::push_back copies a default-constructed (deliberately
// uninitialized) vector; GCC 12 reports that as maybe-uninitialized in optimized sanitizer builds.
// The property is never read before it is written, so the false positive is silenced here (GCC
// only: clang has no such warning and warns about the unknown name in the fuzz build).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <numeric>

#include "core/disjoint_sets.h"
#include "core/error.h"
#include "mesh/morton_order.h"
#include "pathgen/surface_mesh.h"

namespace meshtour::surface_detail {
namespace {

// Only connectivity is kept in the halfedge structure; positions stay in our own arrays.
// No optional attributes (not even prev-halfedge links): the structure is built for 1M faces.
struct TopologyTraits : OpenMesh::DefaultTraits {
  VertexAttributes(0);
  HalfedgeAttributes(0);
  EdgeAttributes(0);
  FaceAttributes(0);
};
using TopologyMesh = OpenMesh::TriMesh_ArrayKernelT<TopologyTraits>;

std::string count_text(std::size_t n, const char* singular, const char* plural) {
  return std::to_string(n) + " " + (n == 1 ? singular : plural);
}

// OpenMesh prints one line to its error stream for every face add_face refuses. We count those
// faces ourselves and report them in the clean-up notes, so the stream is muted during the build
// rather than printing thousands of lines in the middle of a progress display.
class MutedOpenMeshErrors {
public:
  MutedOpenMeshErrors() : lock_(mutex()) {
    was_enabled_ = ::omerr().is_enabled();
    ::omerr().disable();
  }
  ~MutedOpenMeshErrors() {
    if (was_enabled_) ::omerr().enable();
  }
  MutedOpenMeshErrors(const MutedOpenMeshErrors&) = delete;
  MutedOpenMeshErrors& operator=(const MutedOpenMeshErrors&) = delete;

private:
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
  std::lock_guard<std::mutex> lock_;
  bool was_enabled_ = true;
};

// Counting sort of (row, item) pairs into compressed rows; items of a row keep their input order.
template <class RowOf>
Csr build_csr(std::size_t rows, std::size_t pairs, const RowOf& row_of, std::vector<std::uint32_t>* source = nullptr) {
  Csr csr;
  csr.offsets.assign(rows + 1, 0);
  for (std::size_t k = 0; k < pairs; ++k) ++csr.offsets[row_of(k).first + 1];
  std::partial_sum(csr.offsets.begin(), csr.offsets.end(), csr.offsets.begin());
  csr.items.resize(pairs);
  if (source) source->resize(pairs);
  std::vector<std::uint32_t> fill(csr.offsets.begin(), csr.offsets.end() - 1);
  for (std::size_t k = 0; k < pairs; ++k) {
    const auto [row, item] = row_of(k);
    const std::uint32_t slot = fill[row]++;
    csr.items[slot] = item;
    if (source) (*source)[slot] = static_cast<std::uint32_t>(k);
  }
  return csr;
}

// Keeps the vertices `faces` use, in ascending index order, and renumbers `faces` to match.
// `origin[new] = old`.
void compact_vertices(const std::vector<Eigen::Vector3d>& positions, std::vector<std::array<std::uint32_t, 3>>& faces,
                      std::vector<Eigen::Vector3d>& kept, std::vector<std::uint32_t>& origin) {
  std::vector<std::int32_t> new_index(positions.size(), -1);
  for (const auto& t : faces)
    for (std::uint32_t v : t) new_index[v] = 0;
  kept.clear();
  origin.clear();
  for (std::size_t v = 0; v < positions.size(); ++v) {
    if (new_index[v] < 0) continue;
    new_index[v] = static_cast<std::int32_t>(kept.size());
    kept.push_back(positions[v]);
    origin.push_back(static_cast<std::uint32_t>(v));
  }
  for (auto& t : faces)
    for (auto& v : t) v = static_cast<std::uint32_t>(new_index[v]);
}

// Adds `vertex_count` vertices and the faces in order; returns the faces add_face refused.
std::vector<std::size_t> build_topology(TopologyMesh& om, std::size_t vertex_count,
                                        const std::vector<std::array<std::uint32_t, 3>>& faces) {
  om.reserve(vertex_count, faces.size() * 3 / 2 + 3, faces.size());
  om.resize(vertex_count, 0, 0);  // isolated vertices; add_face connects them
  std::vector<std::size_t> refused;
  MutedOpenMeshErrors muted;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto& t = faces[f];
    if (!om.add_face(TopologyMesh::VertexHandle(static_cast<int>(t[0])), TopologyMesh::VertexHandle(static_cast<int>(t[1])),
                     TopologyMesh::VertexHandle(static_cast<int>(t[2])))
             .is_valid())
      refused.push_back(f);
  }
  return refused;
}

// The flat adjacency of a face list that OpenMesh accepts completely (every directed edge used by
// at most one face): incident faces, unique edges with their faces, the 1-ring with edge ids,
// edge-adjacent faces and boundary vertices. Per-vertex passes run in parallel; edges are numbered
// by (smaller vertex, larger vertex).
// Returns false (leaving `out` unusable) if some directed edge is used by two faces, which only
// happens when OpenMesh refused faces too.
bool build_adjacency_of(std::size_t V, const std::vector<std::array<std::uint32_t, 3>>& faces, SurfaceMesh& out) {
  const std::size_t F = faces.size();
  out.vertex_faces = build_csr(V, 3 * F, [&](std::size_t k) {
    return std::pair<std::uint32_t, std::uint32_t>(faces[k / 3][k % 3], static_cast<std::uint32_t>(k / 3));
  });
  const Csr& vf = out.vertex_faces;

  // The sorted, unique 1-ring of v from its faces' corners.
  const auto ring_of = [&](std::size_t v, std::vector<std::uint32_t>& ring) {
    ring.clear();
    for (std::uint32_t f : vf.row(v)) {
      const auto& t = faces[f];
      const int k = t[0] == v ? 0 : (t[1] == v ? 1 : 2);
      ring.push_back(t[(k + 1) % 3]);
      ring.push_back(t[(k + 2) % 3]);
    }
    std::sort(ring.begin(), ring.end());
    ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
  };
  tbb::enumerable_thread_specific<std::vector<std::uint32_t>> rings;
  Csr& nb = out.vertex_neighbours;
  nb.offsets.assign(V + 1, 0);
  std::vector<std::uint32_t> owned(V + 1, 0);  // edges (v, u) with u > v, numbered from owned[v]
  parallel_ranges(V, [&](std::size_t b, std::size_t e) {
    auto& ring = rings.local();
    for (std::size_t v = b; v < e; ++v) {
      ring_of(v, ring);
      nb.offsets[v + 1] = static_cast<std::uint32_t>(ring.size());
      owned[v + 1] = static_cast<std::uint32_t>(ring.end() - std::upper_bound(ring.begin(), ring.end(), v));
    }
  });
  std::partial_sum(nb.offsets.begin(), nb.offsets.end(), nb.offsets.begin());
  std::partial_sum(owned.begin(), owned.end(), owned.begin());
  nb.items.resize(nb.offsets[V]);
  out.neighbour_edge.resize(nb.offsets[V]);
  out.edges.assign(owned[V], MeshEdge{});
  std::atomic<bool> conflict{false};
  parallel_ranges(V, [&](std::size_t b, std::size_t e) {
    auto& ring = rings.local();
    for (std::size_t v = b; v < e; ++v) {
      ring_of(v, ring);
      std::copy(ring.begin(), ring.end(), nb.items.begin() + nb.offsets[v]);
      const std::size_t first_owned = static_cast<std::size_t>(std::upper_bound(ring.begin(), ring.end(), v) - ring.begin());
      for (std::size_t k = first_owned; k < ring.size(); ++k) out.edges[owned[v] + (k - first_owned)].vertex = {static_cast<std::uint32_t>(v), ring[k]};
      // The faces of each owned edge: the face holding v→u and the face holding u→v.
      for (std::uint32_t f : vf.row(v)) {
        const auto& t = faces[f];
        const int k = t[0] == v ? 0 : (t[1] == v ? 1 : 2);
        for (const auto& [u, side] : {std::pair<std::uint32_t, int>{t[(k + 1) % 3], 0}, {t[(k + 2) % 3], 1}}) {
          if (u < v) continue;
          const std::size_t slot = static_cast<std::size_t>(std::lower_bound(ring.begin(), ring.end(), u) - ring.begin());
          MeshEdge& edge = out.edges[owned[v] + (slot - first_owned)];
          if (edge.face[side] >= 0) conflict = true;
          edge.face[side] = static_cast<std::int32_t>(f);
        }
      }
    }
  });
  if (conflict) return false;
  // Edge ids of the 1-ring slots; boundary edges get their one face first (face[1] = -1), with
  // the vertices in the face's direction.
  parallel_ranges(V, [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) {
      const auto row = nb.row(v);
      for (std::size_t k = 0; k < row.size(); ++k) {
        const std::uint32_t u = row[k];
        const std::uint32_t lo = std::min<std::uint32_t>(static_cast<std::uint32_t>(v), u), hi = std::max<std::uint32_t>(static_cast<std::uint32_t>(v), u);
        const auto lo_row = nb.row(lo);
        const std::size_t first_owned = static_cast<std::size_t>(std::upper_bound(lo_row.begin(), lo_row.end(), lo) - lo_row.begin());
        const std::size_t slot = static_cast<std::size_t>(std::lower_bound(lo_row.begin(), lo_row.end(), hi) - lo_row.begin());
        out.neighbour_edge[nb.offsets[v] + k] = static_cast<std::uint32_t>(owned[lo] + (slot - first_owned));
      }
    }
  });
  parallel_ranges(out.edges.size(), [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      MeshEdge& edge = out.edges[i];
      if (edge.face[0] < 0) {
        edge.face = {edge.face[1], -1};
        edge.vertex = {edge.vertex[1], edge.vertex[0]};
      }
    }
  });
  out.face_neighbours.resize(F);
  parallel_ranges(F, [&](std::size_t b, std::size_t e) {
    for (std::size_t f = b; f < e; ++f) {
      const auto& t = faces[f];
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = t[k], u = t[(k + 1) % 3];
        const auto row = nb.row(v);
        const std::size_t slot = static_cast<std::size_t>(std::lower_bound(row.begin(), row.end(), u) - row.begin());
        const MeshEdge& edge = out.edges[out.neighbour_edge[nb.offsets[v] + slot]];
        out.face_neighbours[f][k] = edge.face[0] == static_cast<std::int32_t>(f) ? edge.face[1] : edge.face[0];
      }
    }
  });
  out.boundary_vertex.assign(V, 0);
  for (const MeshEdge& edge : out.edges)
    if (edge.face[1] < 0) out.boundary_vertex[edge.vertex[0]] = out.boundary_vertex[edge.vertex[1]] = 1;
  return true;
}

}  // namespace

SurfaceMesh prepare_mesh(const TriangleMesh& mesh, const SurfaceOptions& options, CleanupCounts& counts) {
  const std::size_t input_vertices = mesh.positions.size();
  const std::size_t input_faces = mesh.triangles.size();
  counts.input_vertices = input_vertices;
  counts.input_faces = input_faces;
  if (input_faces == 0)
    throw InputError("the mesh has no faces (a point cloud or an empty mesh has no surface to analyse)");
  if (input_vertices > std::numeric_limits<std::int32_t>::max() || input_faces > std::numeric_limits<std::int32_t>::max())
    throw InputError("the mesh is too large (more than 2^31 vertices or faces)");
  for (std::size_t f = 0; f < input_faces; ++f)
    for (std::uint32_t v : mesh.triangles[f])
      if (v >= input_vertices)
        throw InputError("face " + std::to_string(f) + " refers to vertex " + std::to_string(v) + " but the mesh has only " +
                         std::to_string(input_vertices) + " vertices (the mesh data is corrupt; re-export it)");

  // Vertices with NaN/infinite coordinates cannot be placed: their faces are dropped.
  std::vector<std::uint8_t> finite(input_vertices);
  parallel_ranges(input_vertices, [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) finite[v] = mesh.positions[v].allFinite() ? 1 : 0;
  });

  // Representative of each vertex: the lowest-index vertex with bit-for-bit equal coordinates
  // (scanner and STL exports repeat a vertex per face; without merging there is no topology).
  std::vector<std::uint32_t> representative(input_vertices);
  std::iota(representative.begin(), representative.end(), 0u);
  std::vector<std::uint8_t> referenced(input_vertices, 0);
  for (const auto& t : mesh.triangles)
    if (finite[t[0]] && finite[t[1]] && finite[t[2]]) referenced[t[0]] = referenced[t[1]] = referenced[t[2]] = 1;
  if (options.merge_duplicate_vertices) {
    std::vector<std::uint32_t> order;
    order.reserve(input_vertices);
    for (std::uint32_t v = 0; v < input_vertices; ++v)
      if (referenced[v]) order.push_back(v);
    const auto& P = mesh.positions;
    tbb::parallel_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
      if (P[a].x() != P[b].x()) return P[a].x() < P[b].x();
      if (P[a].y() != P[b].y()) return P[a].y() < P[b].y();
      if (P[a].z() != P[b].z()) return P[a].z() < P[b].z();
      return a < b;
    });
    for (std::size_t k = 1; k < order.size(); ++k)
      if (P[order[k]] == P[order[k - 1]]) {
        representative[order[k]] = representative[order[k - 1]];
        ++counts.merged_vertices;
      }
  }

  // Faces that survive: finite, three distinct (merged) vertices.
  std::vector<std::array<std::uint32_t, 3>> faces;
  std::vector<std::uint32_t> face_origin;
  faces.reserve(input_faces);
  face_origin.reserve(input_faces);
  for (std::size_t f = 0; f < input_faces; ++f) {
    const auto& t = mesh.triangles[f];
    if (!(finite[t[0]] && finite[t[1]] && finite[t[2]])) {
      ++counts.non_finite_faces;
      continue;
    }
    const std::array<std::uint32_t, 3> r{representative[t[0]], representative[t[1]], representative[t[2]]};
    if (r[0] == r[1] || r[1] == r[2] || r[2] == r[0]) {
      ++counts.repeated_index_faces;
      continue;
    }
    faces.push_back(r);
    face_origin.push_back(static_cast<std::uint32_t>(f));
  }
  if (faces.empty())
    throw InputError("the mesh has no usable face: all " + std::to_string(input_faces) +
                     " faces use a vertex twice or have non-finite coordinates");

  // Compact numbering: the used representatives (unreferenced ones go), renumbered along a
  // Morton curve so that vertices close on the surface are close in memory. Every per-vertex
  // stage gathers neighbour data, and files numbered by subdivision or by a scanner's merge
  // scatter neighbours across the arrays; this order makes those gathers cache hits. (Face order
  // is kept; input_vertex leads back to the file's numbering.)
  SurfaceMesh out;
  {
    std::vector<Eigen::Vector3d> positions;
    std::vector<std::uint32_t> origin;
    compact_vertices(mesh.positions, faces, positions, origin);
    const std::vector<std::uint32_t> order = morton_order(positions);
    std::vector<std::uint32_t> rank(order.size());
    out.positions.resize(order.size());
    out.input_vertex.resize(order.size());
    for (std::size_t i = 0; i < order.size(); ++i) {
      rank[order[i]] = static_cast<std::uint32_t>(i);
      out.positions[i] = positions[order[i]];
      out.input_vertex[i] = origin[order[i]];
    }
    for (auto& t : faces)
      for (auto& v : t) v = rank[v];
  }
  std::size_t used_inputs = 0;  // input vertices represented in the output, merged ones included
  {
    std::vector<std::uint8_t> used(input_vertices, 0);
    for (std::uint32_t v : out.input_vertex) used[v] = 1;
    for (std::uint32_t v = 0; v < input_vertices; ++v)
      if (finite[v] && used[representative[v]]) ++used_inputs;
  }
  counts.unreferenced_vertices = input_vertices - used_inputs;

  // The halfedge structure. add_face refuses a face that would make an edge or a vertex
  // non-manifold or that is oriented against an existing neighbour; such a face is either a second
  // copy of an accepted face (dropped) or split off with its own three vertex copies, as OpenMesh's
  // reader does, so its area still counts and it is never lost silently (§1.2).
  out.triangles = std::move(faces);
  out.input_face = std::move(face_origin);
  return out;
}

std::vector<std::size_t> openmesh_refused_faces(const SurfaceMesh& mesh) {
  TopologyMesh om;
  return build_topology(om, mesh.vertex_count(), mesh.triangles);
}

void repair_refused_faces(SurfaceMesh& out, const std::vector<std::size_t>& refused, CleanupCounts& counts) {
  if (refused.empty()) return;
  auto& faces = out.triangles;
  auto& face_origin = out.input_face;
  // The structure as it stood when OpenMesh refused the faces, to recognize second copies.
  TopologyMesh om;
  build_topology(om, out.vertex_count(), faces);
  std::vector<std::uint8_t> drop(faces.size(), 0);
  for (std::size_t f : refused) {
    const auto& t = faces[f];
    // Same three vertices as a face already in the structure, in either orientation?
    bool duplicate = false;
    for (int k = 0; k < 3 && !duplicate; ++k) {
      const TopologyMesh::VertexHandle a(static_cast<int>(t[k])), b(static_cast<int>(t[(k + 1) % 3]));
      const std::uint32_t c = t[(k + 2) % 3];
      for (auto h : {om.find_halfedge(a, b), om.find_halfedge(b, a)}) {
        if (!h.is_valid() || om.is_boundary(h)) continue;
        if (static_cast<std::uint32_t>(om.to_vertex_handle(om.next_halfedge_handle(h)).idx()) == c) duplicate = true;
      }
    }
    if (duplicate) {
      drop[f] = 1;
      ++counts.duplicate_faces;
      continue;
    }
    // Split off: the face gets its own three vertex copies, as OpenMesh's reader does, so its
    // area still counts and it is never lost silently (§1.2).
    ++counts.split_faces;
    for (auto& v : faces[f]) {
      const auto copy = static_cast<std::uint32_t>(out.positions.size());
      out.positions.push_back(out.positions[v]);
      out.input_vertex.push_back(out.input_vertex[v]);
      v = copy;
    }
  }
  std::size_t kept = 0;
  for (std::size_t f = 0; f < faces.size(); ++f)
    if (!drop[f]) {
      faces[kept] = faces[f];
      face_origin[kept++] = face_origin[f];
    }
  faces.resize(kept);
  face_origin.resize(kept);
  // A vertex used only by split-off faces is now unused: renumber once more. The split faces are
  // isolated triangles and every other face meets the same neighbours in the same order as
  // before, so OpenMesh now accepts every face.
  std::vector<Eigen::Vector3d> positions;
  std::vector<std::uint32_t> origin;
  compact_vertices(out.positions, faces, positions, origin);
  for (auto& v : origin) v = out.input_vertex[v];
  out.positions = std::move(positions);
  out.input_vertex = std::move(origin);
  if (!openmesh_refused_faces(out).empty())
    throw RuntimeFailure("internal: OpenMesh refused a face after the non-manifold faces were split off");
}

bool build_adjacency(SurfaceMesh& mesh) { return build_adjacency_of(mesh.vertex_count(), mesh.triangles, mesh); }

void finish_cleanup(SurfaceMesh& out, CleanupCounts& counts, std::vector<std::string>& notes) {
  const std::size_t V = out.positions.size();
  for (const auto& edge : out.edges) counts.boundary_edges += edge.face[1] < 0 ? 1 : 0;

  // Connected components (faces sharing a vertex), for the report only.
  DisjointSets components(V);
  for (const auto& edge : out.edges) components.join(edge.vertex[0], edge.vertex[1]);
  for (std::uint32_t v = 0; v < V; ++v)
    if (components.root(v) == v) ++counts.components;

  if (counts.non_finite_faces)
    notes.push_back("dropped " + count_text(counts.non_finite_faces, "face", "faces") +
                    " using a vertex with non-finite (NaN or infinite) coordinates");
  if (counts.merged_vertices)
    notes.push_back("merged " + count_text(counts.merged_vertices, "vertex", "vertices") +
                    " with the same coordinates as another vertex");
  if (counts.repeated_index_faces)
    notes.push_back("dropped " + count_text(counts.repeated_index_faces, "degenerate face", "degenerate faces") +
                    " using the same vertex twice");
  if (counts.duplicate_faces)
    notes.push_back("dropped " + count_text(counts.duplicate_faces, "duplicate face", "duplicate faces") +
                    " (same three vertices as an earlier face)");
  if (counts.unreferenced_vertices)
    notes.push_back("removed " + count_text(counts.unreferenced_vertices, "vertex", "vertices") +
                    " not used by any face");
  if (counts.split_faces)
    notes.push_back("split off " + count_text(counts.split_faces, "non-manifold face", "non-manifold faces") +
                    " (edge used by more than two faces, vertex joining separate fans, or face oriented "
                    "against its neighbours): each keeps its own copies of its vertices");
}

std::pair<Eigen::Vector3d, double> normalize_positions(std::vector<Eigen::Vector3d>& positions) {
  Eigen::Vector3d lo = positions.front(), hi = positions.front();
  for (const auto& p : positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double diagonal = (hi - lo).norm();
  if (!(diagonal > 0.0) || !std::isfinite(diagonal))
    throw InputError(diagonal > 0.0 ? "the mesh's bounding box is too large to normalize (coordinates overflow)"
                                    : "all vertices of the mesh are at the same point: there is no shape to look at");
  const Eigen::Vector3d center = (lo + hi) / 2.0;
  parallel_ranges(positions.size(), [&](std::size_t b, std::size_t e) {
    for (std::size_t v = b; v < e; ++v) positions[v] = (positions[v] - center) / diagonal;
  });
  return {center, diagonal};
}

}  // namespace meshtour::surface_detail

namespace meshtour::surface_detail {

SurfaceMesh clean_and_build(const TriangleMesh& mesh, const SurfaceOptions& options, CleanupCounts& counts,
                            std::vector<std::string>& notes) {
  SurfaceMesh out = prepare_mesh(mesh, options, counts);
  repair_refused_faces(out, openmesh_refused_faces(out), counts);
  if (!build_adjacency(out)) throw RuntimeFailure("internal: an edge is used twice in one direction after clean-up");
  finish_cleanup(out, counts, notes);
  return out;
}

}  // namespace meshtour::surface_detail
