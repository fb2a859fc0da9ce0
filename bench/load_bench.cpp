// Loading big meshes (issue 15): meshtour::load_mesh on the same model as binary PLY, OBJ, binary
// STL and GLB, the bunny split 1-to-4 at edge midpoints 0, 2, 3 and 4 times (70k, 1.1M, 4.5M,
// 17.8M faces).
// The files are written once to --mesh-dir (default: bench-meshes/ in the build folder, never
// the repository); each benchmark then times reading its file back, so the formats are
// compared in one run on one machine.
//
//   build-test/bench/load_bench                                   # every size, every format
//   build-test/bench/load_bench --benchmark_filter='Glb/4/'       # the 17.8M-face GLB only
//   build-test/bench/load_bench --benchmark_filter=Instanced      # one mesh drawn 1, 16, 64 times
//   build-test/bench/load_bench --mesh=FILE --mesh-dir=DIR
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_common.h"
#include "mesh/mesh.h"

namespace {

std::filesystem::path g_source_mesh;
std::filesystem::path g_mesh_dir;

// The split mesh's file in `extension` (".ply", ".obj", ".off", ".stl" or ".glb"), written on first use.
std::filesystem::path mesh_file(int levels, const std::string& extension) {
  const auto file = g_mesh_dir / (g_source_mesh.stem().string() + "-split" + std::to_string(levels) + extension);
  if (!std::filesystem::exists(file)) {
    const meshtour::TriangleMesh& mesh = meshtour::bench::split_mesh(g_source_mesh, levels);
    if (extension == ".glb") meshtour::bench::write_glb(mesh, file);
    else if (extension == ".obj") meshtour::bench::write_obj(mesh, file);
    else if (extension == ".stl") meshtour::bench::write_stl(mesh, file);
    else if (extension == ".off") meshtour::bench::write_off(mesh, file);
    else meshtour::bench::write_ply(mesh, file);
  }
  return file;
}

void load(benchmark::State& state, const std::string& extension) {
  const auto file = mesh_file(static_cast<int>(state.range(0)), extension);
  std::size_t faces = 0, vertices = 0;
  for (auto _ : state) {
    const meshtour::TriangleMesh mesh = meshtour::load_mesh(file);
    faces = mesh.triangles.size();
    vertices = mesh.positions.size();
  }
  state.counters["faces"] = static_cast<double>(faces);
  state.counters["vertices"] = static_cast<double>(vertices);
  state.counters["MB"] = static_cast<double>(std::filesystem::file_size(file)) / 1e6;
}

void BM_LoadPly(benchmark::State& state) { load(state, ".ply"); }
void BM_LoadObj(benchmark::State& state) { load(state, ".obj"); }
// Text OFF: meshtour's reader (OpenMesh's before, 81 ms at 70k faces).
void BM_LoadOff(benchmark::State& state) { load(state, ".off"); }
// Binary STL: every corner stored, so the loader welds the corners back into vertices.
void BM_LoadStl(benchmark::State& state) { load(state, ".stl"); }
// GLB: tinygltf's parse, the accessor checks and the welding of bit-identical vertices.
void BM_LoadGlb(benchmark::State& state) { load(state, ".glb"); }

// A GLB whose one mesh (the bunny, 70k faces) is drawn by state.range(0) nodes, as written (plain
// accessors) or Draco-compressed by Debian's draco_transcoder (skipped without it): a catalogue
// model of repeated parts. The decoding is done once per mesh, the copying once per instance.
void load_instanced(benchmark::State& state, bool draco) {
  const int instances = static_cast<int>(state.range(0));
  const auto plain = g_mesh_dir / (g_source_mesh.stem().string() + "-x" + std::to_string(instances) + ".glb");
  if (!std::filesystem::exists(plain)) meshtour::bench::write_glb(meshtour::bench::split_mesh(g_source_mesh, 0), plain, instances);
  auto file = plain;
  if (draco) {
    file = g_mesh_dir / (plain.stem().string() + "-draco.glb");
    const std::string command = "draco_transcoder -i '" + plain.string() + "' -o '" + file.string() + "' >/dev/null 2>&1";
    if (!std::filesystem::exists(file) && std::system(command.c_str()) != 0) {
      state.SkipWithError("draco_transcoder is not installed (Debian package draco)");
      return;
    }
  }
  std::size_t faces = 0;
  for (auto _ : state) faces = meshtour::load_mesh(file).triangles.size();
  state.counters["faces"] = static_cast<double>(faces);
  state.counters["MB"] = static_cast<double>(std::filesystem::file_size(file)) / 1e6;
}
void BM_LoadInstancedGlb(benchmark::State& state) { load_instanced(state, false); }
void BM_LoadInstancedDracoGlb(benchmark::State& state) { load_instanced(state, true); }

void sizes(benchmark::internal::Benchmark* b) {
  for (int levels : {0, 2, 3, 4}) b->Arg(levels);
  b->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);
}

BENCHMARK(BM_LoadPly)->Apply(sizes);
BENCHMARK(BM_LoadObj)->Apply(sizes);
BENCHMARK(BM_LoadOff)->Apply(sizes);
BENCHMARK(BM_LoadStl)->Apply(sizes);
BENCHMARK(BM_LoadGlb)->Apply(sizes);
BENCHMARK(BM_LoadInstancedGlb)->Arg(1)->Arg(16)->Arg(64)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);
BENCHMARK(BM_LoadInstancedDracoGlb)->Arg(1)->Arg(16)->Arg(64)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);

}  // namespace

int main(int argc, char** argv) {
  return meshtour::bench::run_benchmarks(
      meshtour::bench::take_mesh_flags(argc, argv, g_source_mesh, g_mesh_dir, MESHTOUR_SOURCE_DIR, MESHTOUR_BINARY_DIR));
}
