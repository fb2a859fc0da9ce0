#pragma once
// The OFF reader (private to mesh/): one pass over a text or binary OFF (Geomview's object file
// format: [ST][C][N][4]OFF, a vertex list, then polygons as vertex indices) that checks it (the
// counts against the file's size before anything is allocated, every vertex finite, every index
// in the list, colours in range; errors name the line, or the vertex or face of a binary file) and,
// when asked, reads it: polygons are fanned into triangles, COFF vertex colours kept.
//
// It replaced OpenMesh's reader, which needed a separate check before it (it reserved what the
// header announced, read counts only from the line after the keyword, took a comment line in the
// lists for data and lost the faces after it) and gave a non-manifold vertex's faces copies of it.
// Comments and blank lines may now stand anywhere, the counts on the keyword's line, and the model
// has the file's vertices, in its order.
#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "mesh/mesh.h"

namespace meshtour::off_detail {

struct OffContents {
  MeshFileSummary summary;  ///< vertices, faces and corners as stored
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector3f> colors;  ///< per vertex, 0..1 (COFF), else empty
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::size_t polygons = 0;  ///< faces of more than 3 corners (fan-triangulated)
};

/// Checks a text or binary OFF and, with `read`, reads it (else only `summary` is filled).
/// \throw InputError naming the file and the line (text) or element (binary) of the first fault.
OffContents read_off(const std::filesystem::path& file, bool read);

}  // namespace meshtour::off_detail
