// Timing of the toroidal-patch path (docs/METHOD.md §3–§14) on a large scanned mesh: bunny.ply
// Loop-subdivided twice (557k vertices, 1.1M faces). Targets (2 cores): every stage together
// under 3 s, the whole `meshtour path` command under 5 s and 1.5 GB peak memory.
//
//   build-path/bench/pathgen_bench                       # per-stage timings, as counters
//   build-path/bench/pathgen_bench --write-mesh=/tmp/bunny-1m.ply   # only write the big mesh
//   /usr/bin/time -v build-path/cli/meshtour path /tmp/bunny-1m.ply --up y -o /tmp/bunny-1m.json
//
// The source mesh is looked up as --mesh=FILE, else ../shared/meshes/bunny.ply next to the
// source tree.
#include <benchmark/benchmark.h>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "bench_common.h"
#include "mesh/mesh.h"
#include "pathgen/paper_path.h"
#include "pathgen/path_file.h"
#include "pathgen/surface.h"

namespace {

struct DoubleTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
};
using SubdivisionMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;

std::filesystem::path g_source_mesh;

meshtour::TriangleMesh loop_subdivide(const meshtour::TriangleMesh& in, int levels) {
  SubdivisionMesh om;
  std::vector<SubdivisionMesh::VertexHandle> handles;
  handles.reserve(in.positions.size());
  for (const auto& p : in.positions) handles.push_back(om.add_vertex({p.x(), p.y(), p.z()}));
  for (const auto& t : in.triangles) om.add_face(handles[t[0]], handles[t[1]], handles[t[2]]);
  OpenMesh::Subdivider::Uniform::LoopT<SubdivisionMesh, double> loop;
  loop.attach(om);
  loop(levels);
  loop.detach();
  meshtour::TriangleMesh out;
  out.positions.reserve(om.n_vertices());
  for (auto v : om.vertices()) {
    const auto& p = om.point(v);
    out.positions.emplace_back(p[0], p[1], p[2]);
  }
  out.triangles.reserve(om.n_faces());
  for (auto f : om.faces()) {
    std::array<std::uint32_t, 3> tri{};
    int k = 0;
    for (auto v : om.fv_range(f)) tri[k++] = static_cast<std::uint32_t>(v.idx());
    out.triangles.push_back(tri);
  }
  return out;
}

// Built once, on first use, so that benchmarks filtered out do not pay for it.
const meshtour::TriangleMesh& big_mesh() {
  static const meshtour::TriangleMesh mesh = [] {
    if (!std::filesystem::exists(g_source_mesh)) {
      std::cerr << "pathgen_bench: " << g_source_mesh << " not found; pass --mesh=FILE\n";
      std::exit(2);
    }
    return loop_subdivide(meshtour::load_mesh(g_source_mesh), 2);
  }();
  return mesh;
}

void report_stages(benchmark::State& state, const std::vector<std::pair<std::string, double>>& stages) {
  double total = 0.0;
  for (const auto& [name, seconds] : stages) {
    state.counters[name + "_s"] = seconds;
    total += seconds;
  }
  state.counters["stages_s"] = total;
}

meshtour::PaperPathOptions default_options() {
  meshtour::PaperPathOptions options;
  options.up = meshtour::UpDirection::parse("y");
  return options;
}

// §3–§14 together, as `meshtour path` runs them; every stage's time is a counter.
void BM_ComputePaperPath(benchmark::State& state) {
  const auto& mesh = big_mesh();
  std::vector<std::pair<std::string, double>> stages;
  for (auto _ : state) {
    const meshtour::PaperPathResult result = meshtour::compute_paper_path(mesh, default_options());
    stages = result.stage_seconds;
    benchmark::DoNotOptimize(result.metrics.weight_max);
  }
  report_stages(state, stages);
  state.counters["faces"] = static_cast<double>(mesh.triangles.size());
  state.counters["vertices"] = static_cast<double>(mesh.positions.size());
}
BENCHMARK(BM_ComputePaperPath)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();

// §9–§14 only (cylinder, grid, control points, curve, metrics) on the analysed surface.
void BM_PathStages(benchmark::State& state) {
  const meshtour::SurfaceAnalysis surface = meshtour::analyze_surface(big_mesh(), default_options().surface);
  std::vector<std::pair<std::string, double>> stages;
  for (auto _ : state) {
    meshtour::PaperPathResult result = meshtour::compute_paper_path(surface, default_options());
    stages.assign(result.stage_seconds.begin() + static_cast<std::ptrdiff_t>(surface.stage_seconds.size()),
                  result.stage_seconds.end());
    benchmark::DoNotOptimize(result.metrics.weight_max);
  }
  report_stages(state, stages);
}
BENCHMARK(BM_PathStages)->Unit(benchmark::kMillisecond)->Iterations(5)->UseRealTime();

// Writing the path file (JSON text) of the big mesh's result.
void BM_PathFileText(benchmark::State& state) {
  const meshtour::PaperPathResult result = meshtour::compute_paper_path(big_mesh(), default_options());
  for (auto _ : state) benchmark::DoNotOptimize(meshtour::path_file_text(result).size());
}
BENCHMARK(BM_PathFileText)->Unit(benchmark::kMicrosecond);

}  // namespace

int main(int argc, char** argv) {
  g_source_mesh = std::filesystem::path(MESHTOUR_SOURCE_DIR).parent_path() / "shared" / "meshes" / "bunny.ply";
  std::optional<std::filesystem::path> write_mesh;
  const std::vector<char*> rest = meshtour::bench::take_flags(
      argc, argv, {{"--mesh=", [](const char* v) { g_source_mesh = v; }}, {"--write-mesh=", [&](const char* v) { write_mesh = v; }}});
  if (write_mesh) {
    const auto& mesh = big_mesh();
    meshtour::save_mesh(mesh, *write_mesh);
    std::cout << "wrote " << *write_mesh << ": " << mesh.positions.size() << " vertices, " << mesh.triangles.size()
              << " faces\n";
    return 0;
  }
  return meshtour::bench::run_benchmarks(rest);
}
