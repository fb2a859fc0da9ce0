#pragma once
// Internal to §3–§8: the cleaned mesh with the adjacency every stage needs, as flat arrays so that
// per-vertex and per-face loops can run in parallel without touching a halfedge structure.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "mesh/mesh.h"
#include "pathgen/surface.h"

namespace meshtour::surface_detail {

/// Compressed rows: the items of row i are items[offsets[i] .. offsets[i+1]).
struct Csr {
  std::vector<std::uint32_t> offsets;
  std::vector<std::uint32_t> items;
  std::span<const std::uint32_t> row(std::size_t i) const {
    return {items.data() + offsets[i], items.data() + offsets[i + 1]};
  }
  std::size_t rows() const { return offsets.empty() ? 0 : offsets.size() - 1; }
};

/// An edge of the halfedge structure and its one or two faces (face[1] = -1 on a boundary).
struct MeshEdge {
  std::array<std::uint32_t, 2> vertex{};
  std::array<std::int32_t, 2> face{-1, -1};
};

struct SurfaceMesh {
  std::vector<Eigen::Vector3d> positions;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<std::uint32_t> input_vertex;  ///< per vertex: the input vertex it came from
  std::vector<std::uint32_t> input_face;    ///< per face: the input face it came from
  Csr vertex_faces;                         ///< incident faces, ascending face index
  Csr vertex_neighbours;                    ///< 1-ring, ascending vertex index
  std::vector<std::uint32_t> neighbour_edge;  ///< edge index of each vertex_neighbours item
  std::vector<MeshEdge> edges;
  /// Face across edge (t[k], t[k+1]) of each face, -1 on a boundary.
  std::vector<std::array<std::int32_t, 3>> face_neighbours;
  std::vector<std::uint8_t> boundary_vertex;

  std::size_t vertex_count() const { return positions.size(); }
  std::size_t face_count() const { return triangles.size(); }
};

// §3 step 1 and §1.2 in four steps, so that the OpenMesh check can run beside other work:
//   prepare_mesh → openmesh_refused_faces → repair_refused_faces → build_adjacency → finish_cleanup.
// Positions stay in input units.

/// Validates the input, drops faces that cannot be used (non-finite, repeated vertex), merges
/// vertices with identical coordinates and removes unreferenced vertices. Fills positions,
/// triangles, input_vertex, input_face. \throw InputError if nothing usable is left.
SurfaceMesh prepare_mesh(const TriangleMesh& mesh, const SurfaceOptions& options, CleanupCounts& counts);
/// Adds the faces to an OpenMesh halfedge structure in order; returns those add_face refuses
/// (non-manifold edge or vertex, or oriented against an accepted neighbour). Reads only
/// triangles and the vertex count.
std::vector<std::size_t> openmesh_refused_faces(const SurfaceMesh& mesh);
/// Drops refused faces that repeat an accepted face and splits off the others (own vertex
/// copies), then renumbers. Adjacency must be (re)built afterwards.
void repair_refused_faces(SurfaceMesh& mesh, const std::vector<std::size_t>& refused, CleanupCounts& counts);
/// Fills the adjacency arrays. Returns false if a directed edge is used twice (the face list
/// still holds faces OpenMesh refuses).
bool build_adjacency(SurfaceMesh& mesh);
/// Counts components and boundary edges and writes the clean-up notes.
void finish_cleanup(SurfaceMesh& mesh, CleanupCounts& counts, std::vector<std::string>& notes);
/// All of the above in sequence.
SurfaceMesh clean_and_build(const TriangleMesh& mesh, const SurfaceOptions& options, CleanupCounts& counts,
                            std::vector<std::string>& notes);

/// §3 steps 2–3: p ← (p − centre)/d with the AABB centre and diagonal d. Returns {centre, d}.
/// \throw InputError if the diagonal is 0 or not finite.
std::pair<Eigen::Vector3d, double> normalize_positions(std::vector<Eigen::Vector3d>& positions);

/// Faces whose area is below this (normalized units) get no normal, no cotangent weight, no mass.
inline constexpr double kDegenerateArea = 1e-20;

/// Runs body(begin, end) over [0, n) in parallel chunks. Bodies must only write per-index
/// results, which keeps every result independent of the thread count.
template <class Body>
void parallel_ranges(std::size_t n, const Body& body);

}  // namespace meshtour::surface_detail

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/interrupt.h"

namespace meshtour::surface_detail {
template <class Body>
void parallel_ranges(std::size_t n, const Body& body) {
  // Every chunk looks at the interrupt flag, so each stage built on this loop stops within
  // moments of Ctrl-C or SIGTERM (TBB cancels the other chunks and rethrows).
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
    throw_if_interrupted();
    body(r.begin(), r.end());
  });
}
}  // namespace meshtour::surface_detail
