#pragma once
// Points along a Morton (Z-order) curve: neighbours in the order are neighbours in space, which
// keeps what walks the points in order (a mesh's vertex renumbering, visibility rays) in cache.
#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace meshtour {

/// The indices of `positions` sorted along a Morton curve through their bounding box (21 bits
/// per axis, interleaved); ties (same cell) by index, so the order is a function of the
/// geometry and of the input order only. Empty for no positions.
std::vector<std::uint32_t> morton_order(const std::vector<Eigen::Vector3d>& positions);

}  // namespace meshtour
