#pragma once
// Tangents for tangent-space normal maps, built the way MikkTSpace (Mikkelsen 2008, "Simulation
// of wrinkled surfaces revisited"; the glTF specification's rule for files without TANGENT)
// builds them, so that a map baked by Blender, Substance or xNormal reads as it was baked.
#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace meshtour {

/// One tangent per triangle corner (3 per triangle, in the order of `triangles`): xyz unit and
/// perpendicular to the corner's normal, w = +1 or -1 with the bitangent cross(normal, tangent) * w.
/// As MikkTSpace: each triangle's directions of increasing u and v (unit, their sign turned where
/// its UVs are mirrored) are projected onto each corner's tangent plane and averaged, weighted by
/// the corner's angle, over the corners that share a vertex, a normal, a UV and a UV orientation;
/// w is that orientation (+1 where u, v and the normal form a right-handed frame). Corners of
/// triangles without UV area take their group's tangent, or any perpendicular of the normal.
/// `corner_normals` and `corner_uvs` are per corner (unit normals; OBJ's UVs, v up the image).
std::vector<Eigen::Vector4f> corner_tangents(std::span<const Eigen::Vector3f> positions,
                                             std::span<const std::array<std::uint32_t, 3>> triangles,
                                             std::span<const Eigen::Vector3f> corner_normals, std::span<const Eigen::Vector2f> corner_uvs);

}  // namespace meshtour
