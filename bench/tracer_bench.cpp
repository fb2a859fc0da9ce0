// tracer_bench: the renderer's speed on the bunny (../shared/meshes/bunny.ply, Y up) at 1280x720
// and 640x360 (the benchmarks' argument is the width), 16 spp, studio preset, compared in the same
// run with bare Embree calls on the very same rays.
//
//   BM_RenderFrame    a whole frame: camera rays, shading, shadow and occlusion rays, filter,
//                     the frame's buffers. Counters: primary and shadow+AO rays per second,
//                     seconds per frame (wall clock) and CPU seconds per frame (all threads).
//   BM_BareEmbree     the same rays, recorded from one render of the same frame (the tiles whose
//                     index is a multiple of 8, to bound memory: ~1/8 of the frame's rays, spread
//                     over the whole frame), traced with the same calls and flags as the renderer,
//                     packet by packet (rtcIntersect16 on 16 camera rays with the COHERENT
//                     context, then rtcOccluded16 on their shadow rays and on their occlusion rays
//                     with the INCOHERENT context), over the same TBB tiling, with no ray
//                     generation, shading or output. Restoring the rays between iterations is not
//                     timed.
// The ratio (renderer rays/s) / (bare Embree rays/s) is printed at the end, from wall-clock time
// and from CPU time (the sum over threads; steadier when other processes share the machine):
// how close the renderer gets to what Embree alone delivers on the same rays. A ratio of 100 %
// would mean the renderer spends no time outside Embree.
//
// Also BM_CreaseNormals and BM_SceneSetup: the set-up's cost from 70k to 17.8M faces (below).
//
// Run from the repository root:  build-test/bench/tracer_bench
// (the set-up alone: build-test/bench/tracer_bench --benchmark_filter='Crease|Setup')
#include <benchmark/benchmark.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <memory>
#include <numbers>

#include "core/memory_policy.h"
#include "bench_common.h"
#include "studio_frame.h"
#include "mesh/mesh.h"
#include "tracer/renderer_internal.h"
#include "tracer/tracer.h"

namespace meshtour {
namespace {

struct Fixture {
  TriangleMesh mesh;
  RenderOptions options;
  Camera camera;
  std::unique_ptr<Renderer> renderer;
  RayRecording recording;
  std::uint64_t recorded_rays = 0;
};

// Rays per second of each benchmark, by wall-clock and by CPU time, by frame width.
struct Throughput {
  double wall = 0.0, cpu = 0.0;
};
std::map<int, Throughput> g_renderer, g_bare;

// The frame of `width` x (width * 9 / 16), set up once per width.
Fixture* fixture(int width) {
  static std::map<int, std::unique_ptr<Fixture>> fixtures;
  std::unique_ptr<Fixture>& f = fixtures[width];
  if (!f) f = [width] {
    auto fx = std::make_unique<Fixture>();
    const std::filesystem::path file = std::filesystem::path(MESHTOUR_SOURCE_DIR) / ".." / "shared" / "meshes" / "bunny.ply";
    fx->mesh = load_mesh(file);
    // The ray tracing only, as bare Embree does it: the denoiser's cost is
    // bench/denoise_quality.cpp's figure.
    const bench::StudioFrame frame = bench::studio_frame(fx->mesh, width);
    fx->options = frame.options;
    fx->camera = frame.camera;
    fx->renderer = std::make_unique<Renderer>(fx->mesh, fx->options);
    fx->recording.tile_stride = 8;
    RendererAccess::render(*fx->renderer, fx->camera, 0, nullptr, &fx->recording);
    auto lanes = [](const ValidMask& v) {
      std::uint64_t n = 0;
      for (int lane : v.lanes) n += lane != 0;
      return n;
    };
    for (const auto& t : fx->recording.tiles)
      for (const auto& p : t.packets) fx->recorded_rays += lanes(p.primary_valid) + lanes(p.shadow_valid) + lanes(p.sky_valid);
    return fx;
  }();
  return f.get();
}
int frame_width(const benchmark::State& state) { return static_cast<int>(state.range(0)); }

void BM_RenderFrame(benchmark::State& state) {
  Fixture* f = fixture(frame_width(state));
  RenderStats stats;
  for (auto _ : state) {
    stats = RenderStats{};
    Image image = f->renderer->render(f->camera, 0, &stats);
    benchmark::DoNotOptimize(image.rgba.data());
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["primary_rays/s"] = benchmark::Counter(static_cast<double>(stats.primary_rays) * n, benchmark::Counter::kIsRate);
  state.counters["shadow+AO_rays/s"] = benchmark::Counter(static_cast<double>(stats.secondary_rays) * n, benchmark::Counter::kIsRate);
  state.counters["rays/s"] = benchmark::Counter(static_cast<double>(stats.primary_rays + stats.secondary_rays) * n, benchmark::Counter::kIsRate);
  state.counters["s/frame"] = benchmark::Counter(n, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["rays/sample"] = static_cast<double>(stats.primary_rays + stats.secondary_rays) / static_cast<double>(stats.primary_rays);
  state.counters["rays/iteration"] = static_cast<double>(stats.primary_rays + stats.secondary_rays);
}

void BM_BareEmbree(benchmark::State& state) {
  Fixture* f = fixture(frame_width(state));
  RTCScene scene = RendererAccess::scene(*f->renderer);
  const auto& tiles = f->recording.tiles;
  // Working copies: intersection overwrites tfar and the hit, so every iteration starts afresh
  // (the copy is not timed).
  std::vector<RayRecording::Tile> work = tiles;
  for (auto _ : state) {
    state.PauseTiming();
    work = tiles;
    state.ResumeTiming();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, work.size(), 1), [&](const tbb::blocked_range<std::size_t>& r) {
      RTCIntersectContext coherent, incoherent;
      rtcInitIntersectContext(&coherent);
      coherent.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
      rtcInitIntersectContext(&incoherent);
      incoherent.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
      auto any = [](const ValidMask& v) {
        for (int lane : v.lanes)
          if (lane) return true;
        return false;
      };
      for (std::size_t i = r.begin(); i != r.end(); ++i)
        for (auto& p : work[i].packets) {
          rtcIntersect16(p.primary_valid.data(), scene, &coherent, &p.primary);
          if (any(p.shadow_valid)) rtcOccluded16(p.shadow_valid.data(), scene, &incoherent, &p.shadow);
          if (any(p.sky_valid)) rtcOccluded16(p.sky_valid.data(), scene, &incoherent, &p.sky);
        }
    });
    benchmark::DoNotOptimize(work.data());
  }
  state.counters["rays/s"] = benchmark::Counter(static_cast<double>(f->recorded_rays) * static_cast<double>(state.iterations()),
                                                benchmark::Counter::kIsRate);
  state.counters["rays/iteration"] = static_cast<double>(f->recorded_rays);
}

// The scene set-up's cost as the mesh grows (the bunny split 1-to-4 at edge midpoints 0, 2, 3 and
// 4 times: 70k, 1.1M, 4.5M, 17.8M faces): BM_CreaseNormals, the shading normals with their
// creases alone; BM_SceneSetup, a whole Renderer (those normals, the BVH build). Their ratio is the
// normals' share of the set-up.
const TriangleMesh& split_bunny(int levels) {
  return bench::split_mesh(std::filesystem::path(MESHTOUR_SOURCE_DIR) / ".." / "shared" / "meshes" / "bunny.ply", levels);
}

// range(1): the crease angle; 180 smooths every edge, which is the welding of coincident
// vertices and the smoothing pass alone: the ratio is the creases' own cost.
void BM_CreaseNormals(benchmark::State& state) {
  const TriangleMesh& mesh = split_bunny(static_cast<int>(state.range(0)));
  const auto crease = static_cast<float>(state.range(1));
  std::vector<Eigen::Vector3f> source;
  for (const auto& p : mesh.positions) source.push_back(p.cast<float>());
  std::size_t copies = 0;
  for (auto _ : state) {
    state.PauseTiming();
    std::vector<Eigen::Vector3f> positions = source;
    std::vector<std::array<std::uint32_t, 3>> triangles = mesh.triangles;
    std::vector<std::uint32_t> copied_from;
    state.ResumeTiming();
    const std::vector<Eigen::Vector3f> normals = crease_normals(positions, triangles, crease, copied_from);
    benchmark::DoNotOptimize(normals.data());
    copies = copied_from.size();
  }
  state.counters["faces"] = static_cast<double>(mesh.triangles.size());
  state.counters["vertex_copies"] = static_cast<double>(copies);
  state.counters["ns/face"] = benchmark::Counter(static_cast<double>(mesh.triangles.size()) * static_cast<double>(state.iterations()),
                                                 benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_SceneSetup(benchmark::State& state) {
  const TriangleMesh& mesh = split_bunny(static_cast<int>(state.range(0)));
  RenderOptions options;
  options.shading = look_preset("studio");
  for (auto _ : state) {
    Renderer renderer(mesh, options);
    benchmark::DoNotOptimize(&renderer);
  }
  state.counters["faces"] = static_cast<double>(mesh.triangles.size());
}

BENCHMARK(BM_CreaseNormals)->ArgsProduct({{0, 2, 3, 4}, {60, 180}})->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);
BENCHMARK(BM_SceneSetup)->Arg(0)->Arg(2)->Arg(3)->Arg(4)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);

BENCHMARK(BM_RenderFrame)->Arg(1280)->Arg(640)->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime()->MinTime(6.0);
BENCHMARK(BM_BareEmbree)->Arg(1280)->Arg(640)->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime()->MinTime(3.0);

// Collects the two throughputs from the results to print their ratio.
class RatioReporter : public benchmark::ConsoleReporter {
public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& run : runs) {
      const auto it = run.counters.find("rays/iteration");
      if (it == run.counters.end() || run.iterations <= 0) continue;
      const double n = static_cast<double>(run.iterations);
      const Throughput t{it->second.value * n / run.real_accumulated_time, it->second.value * n / run.cpu_accumulated_time};
      const std::string name = run.benchmark_name();
      const std::size_t slash = name.find('/');
      const int width = slash == std::string::npos ? 0 : std::atoi(name.c_str() + slash + 1);
      if (name.find("BM_RenderFrame") == 0) {
        g_renderer[width] = t;
        std::printf("renderer at width %d: %.3f s/frame wall clock, %.3f CPU s/frame (%d threads)\n", width, run.real_accumulated_time / n,
                    run.cpu_accumulated_time / n, tbb::this_task_arena::max_concurrency());
      }
      if (name.find("BM_BareEmbree") == 0) g_bare[width] = t;
    }
  }
};

}  // namespace
}  // namespace meshtour

int main(int argc, char** argv) {
  meshtour::keep_freed_frame_buffers();  // as the program does (core/memory_policy.h)
  benchmark::Initialize(&argc, argv);
  meshtour::RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();
  for (const auto& [width, renderer] : meshtour::g_renderer) {
    const auto bare = meshtour::g_bare.find(width);
    if (bare == meshtour::g_bare.end() || !(bare->second.wall > 0.0) || !(renderer.wall > 0.0)) continue;
    std::printf("%dx%d: renderer / bare Embree ray throughput, wall clock: %.1f Mrays/s / %.1f Mrays/s = %.0f %% (goal: >= 90 %%)\n", width,
                width * 9 / 16, renderer.wall * 1e-6, bare->second.wall * 1e-6, 100.0 * renderer.wall / bare->second.wall);
    std::printf("%dx%d: renderer / bare Embree ray throughput, CPU time:   %.1f Mrays/s / %.1f Mrays/s = %.0f %%\n", width, width * 9 / 16,
                renderer.cpu * 1e-6, bare->second.cpu * 1e-6, 100.0 * renderer.cpu / bare->second.cpu);
  }
  return 0;
}
