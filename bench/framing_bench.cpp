// Framing on big meshes (issue 14): the convex hull's vertices (mesh/convex_hull.h) and the
// turntable framing, on bunny.ply subdivided 1-to-4 at edge midpoints 0, 2, 3 and 4 times (70k,
// 1.1M, 4.5M and 17.8M faces). In one run: the hull alone, the framing on every vertex (as
// before the hull) and the framing on the hull (the hull's time included), and whether the two
// framings agree (counter same_path = 1 when radius and centre are bit-identical); and the
// `--up auto` rule, which shares the hull (issue 15).
//
//   build-test/bench/framing_bench                                   # every size
//   build-test/bench/framing_bench --benchmark_filter='/4$'          # the 17.8M-face mesh only
//   build-test/bench/framing_bench --mesh=FILE --mesh-dir=DIR
//
// The source mesh is --mesh=FILE, else ../shared/meshes/bunny.ply next to the source tree. The
// subdivided meshes are also written, once, as binary PLY to --mesh-dir (default: bench-meshes/ in
// the build folder, never the repository), e.g. to time `meshtour tour` on them; the benchmark
// itself uses the meshes it subdivided in memory.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <iostream>
#include <map>
#include <numeric>
#include <string>
#include <vector>

#include "bench_common.h"
#include "mesh/convex_hull.h"
#include "mesh/mesh.h"
#include "mesh/up_axis.h"
#include "pathgen/turntable.h"

namespace {

std::filesystem::path g_source_mesh;
std::filesystem::path g_mesh_dir;

// The source mesh split `levels` times; each split level is also written to g_mesh_dir.
const meshtour::TriangleMesh& bunny(int levels) {
  return meshtour::bench::split_mesh(g_source_mesh, levels, [](const meshtour::TriangleMesh& mesh, int level) {
    const auto file = g_mesh_dir / (g_source_mesh.stem().string() + "-split" + std::to_string(level) + ".ply");
    if (!std::filesystem::exists(file)) meshtour::bench::write_ply(mesh, file);
  });
}

meshtour::TurntableOptions turntable_options() {
  meshtour::TurntableOptions options;
  options.up = meshtour::Axis{1, false};
  return options;
}

void size_counters(benchmark::State& state, const meshtour::TriangleMesh& mesh) {
  state.counters["faces"] = static_cast<double>(mesh.triangles.size());
  state.counters["vertices"] = static_cast<double>(mesh.positions.size());
}

void BM_Hull(benchmark::State& state) {
  const auto& mesh = bunny(static_cast<int>(state.range(0)));
  std::size_t kept = 0;
  for (auto _ : state) kept = meshtour::convex_hull_vertices(mesh.positions).size();
  size_counters(state, mesh);
  state.counters["hull_points"] = static_cast<double>(kept);
}

// The orbit fitted on every vertex, per size, kept for the comparison (computed once).
std::map<int, std::pair<double, Eigen::Vector3d>> g_every_vertex_orbit;

// The framing as before the hull: every vertex, 180 angles x 4 fits plus the balancing passes.
void BM_TurntableEveryVertex(benchmark::State& state) {
  const int levels = static_cast<int>(state.range(0));
  const auto& mesh = bunny(levels);
  for (auto _ : state) {
    const meshtour::TurntablePath path(mesh.positions, turntable_options());
    g_every_vertex_orbit[levels] = {path.radius(), path.center()};
  }
  size_counters(state, mesh);
}

// The framing now: the hull, then the same fits on its vertices; same_path = 1 when the orbit is
// bit-identical to the one fitted on every vertex.
void BM_TurntableOnHull(benchmark::State& state) {
  const auto& mesh = bunny(static_cast<int>(state.range(0)));
  double radius = 0.0;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  for (auto _ : state) {
    const std::vector<Eigen::Vector3d> hull = meshtour::convex_hull_vertices(mesh.positions);
    const meshtour::TurntablePath path(hull, turntable_options());
    radius = path.radius();
    center = path.center();
  }
  size_counters(state, mesh);
  const int levels = static_cast<int>(state.range(0));
  if (!g_every_vertex_orbit.count(levels)) {
    const meshtour::TurntablePath reference(mesh.positions, turntable_options());
    g_every_vertex_orbit[levels] = {reference.radius(), reference.center()};
  }
  const auto& [reference_radius, reference_center] = g_every_vertex_orbit[levels];
  state.counters["same_path"] = radius == reference_radius && center == reference_center ? 1.0 : 0.0;
  state.counters["radius_rel_diff"] = std::abs(radius - reference_radius) / reference_radius;
}

// `--up auto` (mesh/up_axis.h): the hull, the six rests, the flat ends, the mirror test, the
// holes (mesh/mesh_edges.h's tally) and the air under each side (one pass over the triangles
// each); against BM_Hull of the same run.
void BM_UpAxis(benchmark::State& state) {
  const auto& mesh = bunny(static_cast<int>(state.range(0)));
  meshtour::UpChoice choice;
  for (auto _ : state) choice = meshtour::choose_up_axis(mesh);
  size_counters(state, mesh);
  state.counters["up_is_plus_y"] = choice.up == meshtour::Axis{1, false} ? 1.0 : 0.0;
}

// The big sizes run once: the old framing of the 17.8M-face mesh takes tens of seconds.
void sizes(benchmark::internal::Benchmark* b) {
  for (int levels : {0, 2, 3, 4}) b->Arg(levels);
  b->Unit(benchmark::kMillisecond)->UseRealTime();
}
BENCHMARK(BM_Hull)->Apply(sizes)->Iterations(3);
BENCHMARK(BM_TurntableEveryVertex)->Apply(sizes)->Iterations(1);
BENCHMARK(BM_TurntableOnHull)->Apply(sizes)->Iterations(3);
BENCHMARK(BM_UpAxis)->Apply(sizes)->Iterations(3);

}  // namespace

int main(int argc, char** argv) {
  return meshtour::bench::run_benchmarks(
      meshtour::bench::take_mesh_flags(argc, argv, g_source_mesh, g_mesh_dir, MESHTOUR_SOURCE_DIR, MESHTOUR_BINARY_DIR));
}
