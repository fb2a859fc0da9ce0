#include "mesh/morton_order.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <utility>

namespace meshtour {

std::vector<std::uint32_t> morton_order(const std::vector<Eigen::Vector3d>& positions) {
  if (positions.empty()) return {};
  const auto spread = [](std::uint64_t x) {  // 21 bits → every third bit of 63
    x &= 0x1fffff;
    x = (x | x << 32) & 0x1f00000000ffffULL;
    x = (x | x << 16) & 0x1f0000ff0000ffULL;
    x = (x | x << 8) & 0x100f00f00f00f00fULL;
    x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
    x = (x | x << 2) & 0x1249249249249249ULL;
    return x;
  };
  Eigen::Vector3d lo = positions.front(), hi = positions.front();
  for (const auto& p : positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const Eigen::Vector3d extent = (hi - lo).cwiseMax(Eigen::Vector3d::Constant(1e-300));
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keys(positions.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, keys.size(), 1 << 14), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t v = range.begin(); v < range.end(); ++v) {
      std::uint64_t code = 0;
      for (int axis = 0; axis < 3; ++axis) {
        const double t = std::clamp((positions[v](axis) - lo(axis)) / extent(axis), 0.0, 1.0);
        code |= spread(static_cast<std::uint64_t>(t * 2097151.0)) << (2 - axis);
      }
      keys[v] = {code, static_cast<std::uint32_t>(v)};
    }
  });
  tbb::parallel_sort(keys.begin(), keys.end());  // keys are distinct (the index breaks ties): any sort gives one order
  std::vector<std::uint32_t> order(keys.size());
  for (std::size_t i = 0; i < keys.size(); ++i) order[i] = keys[i].second;
  return order;
}

}  // namespace meshtour
