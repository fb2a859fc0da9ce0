#pragma once
// Merging vertices at bit-identical places (private to mesh/): STL repeats every corner per facet,
// glTF splits a vertex wherever its texture coordinates change; the tracer's smooth normals need
// the shared vertex back. One open-addressing hash table of vertex numbers over the distinct keys
// (a place's bits, and its colour's where colours count): linear in the vertices, memory for the
// distinct ones only, and the vertices numbered in the order they first appear, so the same file
// gives the same model on any machine. It replaced a parallel sort of every vertex (the glTF
// weld; 10 % of loading a 4.5M-face GLB) and OpenMesh's std::map (STL).
#include <array>
#include <bit>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/error.h"

namespace meshtour::weld_detail {

/// The bits of a coordinate as a key: -0 and +0 are one place.
inline std::uint32_t key_bits(float value) { return std::bit_cast<std::uint32_t>(value == 0.0f ? 0.0f : value); }
inline std::uint64_t key_bits(double value) { return std::bit_cast<std::uint64_t>(value == 0.0 ? 0.0 : value); }

/// Numbers keys (N 32-bit words; NaN-free coordinates' bits) by first appearance.
template <std::size_t N>
class VertexWelder {
public:
  using Key = std::array<std::uint32_t, N>;

  /// `expected` distinct keys are held without growing the table.
  explicit VertexWelder(std::size_t expected) {
    std::size_t capacity = 1024;
    while (capacity < 2 * expected) capacity *= 2;  // at most half full
    table_.assign(capacity, kEmpty);
    keys_.reserve(expected);
  }

  /// The number `key` got when first seen, or the next number.
  std::uint32_t vertex(const Key& key) {
    if (2 * (keys_.size() + 1) > table_.size()) grow();
    const std::uint64_t h = hash(key);
    const auto tag = static_cast<std::uint32_t>(h >> 32);  // most other keys are told apart without reading them
    const std::size_t mask = table_.size() - 1;
    for (std::size_t slot = static_cast<std::size_t>(h) & mask;; slot = (slot + 1) & mask) {
      const std::uint64_t entry = table_[slot];
      if (entry == kEmpty) {
        if (keys_.size() >= kMaxVertices) throw InputError("more than 4294967294 distinct vertices: too many to index");
        const auto number = static_cast<std::uint32_t>(keys_.size());
        table_[slot] = std::uint64_t{tag} << 32 | number;
        keys_.push_back(key);
        return number;
      }
      const auto number = static_cast<std::uint32_t>(entry);
      if (static_cast<std::uint32_t>(entry >> 32) == tag && same(keys_[number], key)) return number;
    }
  }

  /// The distinct keys, in vertex order.
  const std::vector<Key>& keys() const { return keys_; }

private:
  // A table entry: the key's tag (its hash's high half) above its number; no number is all ones.
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};
  static constexpr std::size_t kMaxVertices = std::numeric_limits<std::uint32_t>::max() - 1;

  static std::uint64_t hash(const Key& key) {
    std::uint64_t h = 0x9E3779B97F4A7C15ull;
    for (const std::uint32_t word : key) h = (h ^ word) * 0xBF58476D1CE4E5B9ull;
    return h ^ (h >> 29);
  }

  static bool same(const Key& a, const Key& b) {
    std::uint32_t differ = 0;
    for (std::size_t i = 0; i < N; ++i) differ |= a[i] ^ b[i];  // no call to memcmp for a few words
    return differ == 0;
  }

  void grow() {
    std::vector<std::uint64_t> table(2 * table_.size(), kEmpty);
    const std::size_t mask = table.size() - 1;
    for (std::size_t i = 0; i < keys_.size(); ++i) {
      const std::uint64_t h = hash(keys_[i]);
      std::size_t slot = static_cast<std::size_t>(h) & mask;
      while (table[slot] != kEmpty) slot = (slot + 1) & mask;
      table[slot] = (h >> 32) << 32 | i;
    }
    table_ = std::move(table);
  }

  std::vector<std::uint64_t> table_;
  std::vector<Key> keys_;
};

}  // namespace meshtour::weld_detail
