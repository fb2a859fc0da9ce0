#pragma once
// What the benchmarks share: the bunny split 1-to-4 at edge midpoints (the same shape at 70k, 1.1M,
// 4.5M, 17.8M faces; the split is tests/test_meshes.h's) and the hand-over of the command line
// to Google Benchmark once a benchmark has taken its own flags.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <vector>

#include "mesh/mesh.h"
#include "test_meshes.h"

namespace meshtour::bench {

/// `source` split `levels` times, built once per level on first use (sizes a filter leaves out
/// cost nothing). `written(mesh, levels)`, when given, runs once for each new split level (to keep
/// the meshes as files). Exits with 2 and a message if `source` does not exist.
inline const TriangleMesh& split_mesh(const std::filesystem::path& source, int levels,
                                      const std::function<void(const TriangleMesh&, int)>& written = {}) {
  static std::map<int, TriangleMesh> cache;
  if (const auto it = cache.find(levels); it != cache.end()) return it->second;
  TriangleMesh mesh;
  if (levels == 0) {
    if (!std::filesystem::exists(source)) {
      std::cerr << source << " not found; pass --mesh=FILE\n";
      std::exit(2);
    }
    mesh = load_mesh(source);
  } else {
    mesh = test_meshes::split_at_midpoints(split_mesh(source, levels - 1, written));
    if (written) written(mesh, levels);
  }
  return cache.emplace(levels, std::move(mesh)).first->second;
}

/// Runs the benchmarks selected by `args` (argv[0] first, then the flags the benchmark did not take).
inline int run_benchmarks(std::vector<char*> args) {
  int count = static_cast<int>(args.size());
  benchmark::Initialize(&count, args.data());
  if (benchmark::ReportUnrecognizedArguments(count, args.data())) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

}  // namespace meshtour::bench
