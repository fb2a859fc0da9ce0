#pragma once
// The STL reader (private to mesh/): one pass over a binary or ASCII STL that checks it (the size a
// binary header announces, the ASCII grammar, finite corners; errors name the facet or the line)
// and, when asked, reads it. STL stores every facet's three corners, shared with no other facet;
// the reader merges bit-identical corners into one vertex as it goes (a hash table of the distinct
// corners), so the tracer's smooth normals see a connected surface, and numbers the vertices in
// the order they first appear. It replaced OpenMesh's reader, which merged through a std::map and
// then built half-edges the loader threw away: the bunny split to 4.5M faces as binary STL loaded
// in 6.8 s, now 0.55 s (bench/load_bench BM_LoadStl: 5.4 ms to 2.4 s from 70k to 17.8M faces).
//
// What STL cannot say is not invented: no colours (the attribute word's colour conventions
// disagree between writers, so it is ignored), no texture, no units.
#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "mesh/mesh.h"

namespace meshtour::stl_detail {

struct StlContents {
  MeshFileSummary summary;  ///< as stored: facets, and 3 corners (vertices) per facet
  bool binary = false;
  std::vector<Eigen::Vector3d> positions;  ///< the distinct corners, in order of first appearance
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::size_t polygons = 0;  ///< ASCII loops of more than 3 corners (fan-triangulated)
  std::vector<std::string> warnings;
};

/// Checks a binary or ASCII STL and, with `read`, reads it (else only `summary`, `binary` and
/// `warnings` are filled). The file must exist and not be empty.
/// \throw InputError naming the file and the facet (binary) or line (ASCII) of the first fault.
StlContents read_stl(const std::filesystem::path& file, bool read);

}  // namespace meshtour::stl_detail
