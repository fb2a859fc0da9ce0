// tracer_bench: the renderer's speed on the bunny (../shared/meshes/bunny.ply, Y up) at 1280x720,
// 16 spp, studio preset, compared in the same run with bare Embree calls on the very same rays.
//
//   BM_RenderFrame    a whole frame: camera rays, shading, shadow and occlusion rays, filter.
//                     Counters: primary and secondary rays per second, seconds per frame.
//   BM_BareEmbree     the same rays, recorded from one render (every 8th tile, to bound memory),
//                     traced with the same calls (rtcIntersect16 packets, rtcOccluded1M) and the
//                     same TBB tiling, with no ray generation, shading or output.
// At the end the ratio (renderer rays/s) / (bare Embree rays/s) is printed: how close the
// renderer gets to what Embree alone can deliver.
//
// Run from the repository root:  build/bench/tracer_bench [--benchmark_min_time=3]
#include <benchmark/benchmark.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numbers>

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

double g_renderer_rays_per_s = 0.0, g_bare_rays_per_s = 0.0;

Fixture* fixture() {
  static std::unique_ptr<Fixture> f = [] {
    auto fx = std::make_unique<Fixture>();
    const std::filesystem::path file = std::filesystem::path(MESHTOUR_SOURCE_DIR) / ".." / "shared" / "meshes" / "bunny.ply";
    fx->mesh = load_mesh(file);
    fx->options.width = 1280;
    fx->options.height = 720;
    fx->options.samples_per_pixel = 16;
    fx->options.shading = look_preset("studio");
    fx->options.world_up = Eigen::Vector3d::UnitY();
    // The default tour's first frame: 18 degrees above the centre, the whole bunny in a 35 degree lens.
    const Bounds b = fx->mesh.bounds();
    const double fov = 35.0, elevation = 18.0 * std::numbers::pi / 180.0;
    const double distance = 0.55 * b.diagonal() / std::tan(fov * std::numbers::pi / 360.0);
    fx->camera.target = b.center();
    fx->camera.eye = b.center() + distance * Eigen::Vector3d(0.0, std::sin(elevation), std::cos(elevation));
    fx->camera.up = Eigen::Vector3d::UnitY();
    fx->camera.vertical_fov_deg = fov;
    fx->renderer = std::make_unique<Renderer>(fx->mesh, fx->options);
    fx->recording.tile_stride = 8;
    RendererAccess::render(*fx->renderer, fx->camera, 0, nullptr, &fx->recording);
    for (const auto& t : fx->recording.tiles) {
      for (const auto& v : t.valid)
        for (int lane : v.lanes) fx->recorded_rays += lane != 0;
      fx->recorded_rays += t.secondary.size();
    }
    return fx;
  }();
  return f.get();
}

void BM_RenderFrame(benchmark::State& state) {
  Fixture* f = fixture();
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
}

void BM_BareEmbree(benchmark::State& state) {
  Fixture* f = fixture();
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
      for (std::size_t i = r.begin(); i != r.end(); ++i) {
        auto& t = work[i];
        for (std::size_t p = 0; p < t.packets.size(); ++p) rtcIntersect16(t.valid[p].data(), scene, &coherent, &t.packets[p]);
        if (!t.secondary.empty())
          rtcOccluded1M(scene, &incoherent, t.secondary.data(), static_cast<unsigned>(t.secondary.size()), sizeof(RTCRay));
      }
    });
    benchmark::DoNotOptimize(work.data());
  }
  state.counters["rays/s"] = benchmark::Counter(static_cast<double>(f->recorded_rays) * static_cast<double>(state.iterations()),
                                                benchmark::Counter::kIsRate);
}

BENCHMARK(BM_RenderFrame)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3.0);
BENCHMARK(BM_BareEmbree)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);

// Collects the two throughputs from the results to print their ratio.
class RatioReporter : public benchmark::ConsoleReporter {
public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& run : runs) {
      const auto it = run.counters.find("rays/s");
      if (it == run.counters.end()) continue;
      // Counters arrive already divided by the measured time.
      if (run.benchmark_name().find("BM_RenderFrame") == 0) g_renderer_rays_per_s = it->second.value;
      if (run.benchmark_name().find("BM_BareEmbree") == 0) g_bare_rays_per_s = it->second.value;
    }
  }
};

}  // namespace
}  // namespace meshtour

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  meshtour::RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();
  if (meshtour::g_bare_rays_per_s > 0.0 && meshtour::g_renderer_rays_per_s > 0.0)
    std::printf("renderer / bare Embree ray throughput: %.1f Mrays/s / %.1f Mrays/s = %.0f %% (goal: >= 75 %%)\n",
                meshtour::g_renderer_rays_per_s * 1e-6, meshtour::g_bare_rays_per_s * 1e-6,
                100.0 * meshtour::g_renderer_rays_per_s / meshtour::g_bare_rays_per_s);
  return 0;
}
