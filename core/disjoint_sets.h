#pragma once
// Disjoint sets over the indices 0..n-1 (union-find with path halving): connected components of
// mesh vertices, proxy cells and faces. Joining two sets makes the lower of their roots the root,
// so a set's root is always its smallest index: the same roots whatever the order of the joins,
// which keeps every numbering built from them deterministic.
#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

namespace meshtour {

class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0u); }

  /// The smallest index of the set holding v.
  std::uint32_t root(std::uint32_t v) {
    while (parent_[v] != v) v = parent_[v] = parent_[parent_[v]];
    return v;
  }

  /// Joins the sets of a and b.
  void join(std::uint32_t a, std::uint32_t b) {
    const std::uint32_t ra = root(a), rb = root(b);
    if (ra != rb) parent_[std::max(ra, rb)] = std::min(ra, rb);
  }

 private:
  std::vector<std::uint32_t> parent_;
};

}  // namespace meshtour
