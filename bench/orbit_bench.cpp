// The feature orbit at scan sizes: the shared bunny (70k faces) split 1-to-4 at edge midpoints
// 2, 3 and 4 times (1.1M, 4.5M, 17.8M faces; the same shape). Google Benchmark timings of the
// coverage model's stages and of the whole search, per size:
//
//   build-test/bench/orbit_bench --benchmark_filter=FeatureOrbit/3
//
// and, with --invariance[=LEVELS], the check that the same shape gives the same tour: the
// elevation of every level's orbit against level 0's (degrees, over 360 azimuths) and the
// evaluation figures of every level's 12 frames under every feature definition:
//
//   build-test/bench/orbit_bench --invariance=3 [--mesh=FILE] [--up=y]
//
// --features=LEVELS prints why the features would move: the proxy, w(f) on it, and the overlap of
// every level's feature samples with level 0's.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "bench_common.h"
#include "core/axis.h"
#include "evaluate/evaluate.h"
#include "mesh/mesh.h"
#include "pathgen/coverage.h"
#include "pathgen/feature_orbit.h"
#include "pathgen/features.h"
#include "pathgen/surface.h"

namespace {

std::filesystem::path g_source_mesh;
meshtour::Axis g_up{1, false};

const meshtour::TriangleMesh& mesh_at(int levels) { return meshtour::bench::split_mesh(g_source_mesh, levels); }

meshtour::FeatureOrbitOptions orbit_options() {
  meshtour::FeatureOrbitOptions o;
  o.up = g_up;
  o.frames = 12;
  return o;
}

void BM_CoverageModel(benchmark::State& state) {
  const auto& mesh = mesh_at(static_cast<int>(state.range(0)));
  std::vector<std::pair<std::string, double>> stages;
  for (auto _ : state) {
    const meshtour::CoverageModel model(mesh, orbit_options().coverage);
    stages = model.stage_seconds();
  }
  for (const auto& [name, s] : stages) state.counters[name + "_s"] = s;
  state.counters["faces"] = static_cast<double>(mesh.triangles.size());
}
BENCHMARK(BM_CoverageModel)->Arg(0)->Arg(2)->Arg(3)->Arg(4)->Unit(benchmark::kMillisecond)->Iterations(1)->UseRealTime();

// The whole search: coverage model, the grid of views, the curve search, the dolly and the start.
void BM_FeatureOrbit(benchmark::State& state) {
  const auto& mesh = mesh_at(static_cast<int>(state.range(0)));
  meshtour::FeatureOrbitResult result;
  for (auto _ : state) result = meshtour::compute_feature_orbit(mesh, orbit_options());
  state.counters["faces"] = static_cast<double>(mesh.triangles.size());
  state.counters["objective"] = result.scores.objective;
}
BENCHMARK(BM_FeatureOrbit)->Arg(0)->Arg(2)->Arg(3)->Arg(4)->Unit(benchmark::kMillisecond)->Iterations(1)->UseRealTime();

double elevation_deg(const meshtour::CameraPose& p, const Eigen::Vector3d& up) {
  return std::asin(std::clamp((p.eye - p.target).normalized().dot(up), -1.0, 1.0)) * 180.0 / std::numbers::pi;
}

int invariance(int levels) {
  const Eigen::Vector3d up = g_up.vector();
  std::vector<meshtour::FeatureOrbitPath> paths;
  std::printf("%-6s %10s %8s %9s %9s %10s %9s %9s %9s", "level", "faces", "orbit_s", "objective", "max_dElev", "start_deg", "frame_dEl",
              "frame_dAz", "ties c/s");
  for (const auto& d : meshtour::feature_definitions()) std::printf(" %20s", meshtour::CoverageOptions{}.key(d).c_str());
  std::printf("\n");
  for (int level = 0; level <= levels; ++level) {
    const auto& mesh = mesh_at(level);
    const auto start = std::chrono::steady_clock::now();
    const meshtour::FeatureOrbitResult r = meshtour::compute_feature_orbit(mesh, orbit_options());
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    paths.push_back(r.camera_path());
    double worst = 0.0;
    for (int k = 0; k < 360; ++k)
      worst = std::max(worst, std::abs(elevation_deg(paths.back().pose(k / 360.0), up) - elevation_deg(paths.front().pose(k / 360.0), up)));
    std::vector<meshtour::Camera> cameras;
    for (int k = 0; k < 12; ++k) cameras.push_back(meshtour::Camera::at(meshtour::frame_pose(paths.back(), k, 12), 35.0));
    const meshtour::PathEvaluator evaluator(mesh);
    const meshtour::PathEvaluation e = evaluator.evaluate(cameras, 16.0 / 9.0);
    // The must-show of the tour: every one of the 12 frames within 1 degree of elevation and 2 of
    // azimuth (around the up axis, of the eye about the target) of level 0's frame.
    double frame_elevation = 0.0, frame_azimuth = 0.0;
    for (int k = 0; k < 12; ++k) {
      const meshtour::CameraPose a = meshtour::frame_pose(paths.front(), k, 12), b = meshtour::frame_pose(paths.back(), k, 12);
      frame_elevation = std::max(frame_elevation, std::abs(elevation_deg(a, up) - elevation_deg(b, up)));
      const Eigen::Vector3d da = a.eye - a.target, db = b.eye - b.target;
      const Eigen::Vector3d pa = da - da.dot(up) * up, pb = db - db.dot(up) * up;
      frame_azimuth = std::max(frame_azimuth, std::abs(std::atan2(pa.cross(pb).dot(up), pa.dot(pb))) * 180.0 / std::numbers::pi);
    }
    char ties[32];
    std::snprintf(ties, sizeof ties, "%d/%d", r.curves_tied, r.starts_tied);
    std::printf("%-6d %10zu %8.2f %9.4f %9.2f %10.1f %9.2f %9.2f %9s", level, mesh.triangles.size(), seconds, r.scores.objective, worst,
                360.0 * r.geometry.start, frame_elevation, frame_azimuth, ties);
    for (const auto& f : e.by_definition) std::printf(" %19.2f%%", 100.0 * f.feature_coverage);
    // The leading curves (objective ×100; mean elevation / swing @ phase / ripple, degrees and
    // loop fractions): a flip between levels is a tie when the curves scored within the tie tolerance.
    std::printf("   leaders:");
    constexpr double deg = 180.0 / std::numbers::pi;
    for (std::size_t c = 0; c < std::min<std::size_t>(3, r.leaders.size()); ++c) {
      const meshtour::ElevationCurve& e = r.leaders[c].first;
      std::printf(" %.2f (%.0f/%.0f@%.3f/%.0f)", 100.0 * r.leaders[c].second, e.base * deg, e.swing * deg, e.swing_phase, e.ripple * deg);
    }
    std::printf("\n");
    std::fflush(stdout);
  }
  return 0;
}


// Why features move with the tessellation: per level, the proxy (vertices, faces, face area
// quantiles in cell areas), the patch density w(f) on it (patches, w quantiles) and the overlap
// (Jaccard) of each measure's feature samples with level 0's (sample i lies in the same level-0
// face at every level, as the split keeps the face order and the area).
double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const auto k = static_cast<std::ptrdiff_t>(q * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[static_cast<std::size_t>(k)];
}

int feature_diagnosis(int levels) {
  const meshtour::CoverageOptions options = orbit_options().coverage;
  std::vector<std::array<std::vector<std::uint8_t>, meshtour::kFeatureMeasures>> masks;
  std::printf("%-6s %9s %8s %8s %8s %8s %8s %7s %6s %6s %6s %6s %9s %9s %8s %8s\n", "level", "faces", "proxy_v", "proxy_f", "a10", "a50",
              "a90", "patches", "w10", "w50", "w90", "wmean", "J_patch", "J_salien", "proxy_cpu", "boundary");
  for (int level = 0; level <= levels; ++level) {
    const auto& mesh = mesh_at(level);
    double proxy_s = 1e30;  // CPU seconds (all threads), the least of three builds: the machine is shared
    meshtour::ClusteredMesh proxy;
    for (int run = 0; run < 3; ++run) {
      const std::clock_t start = std::clock();
      proxy = meshtour::coverage_proxy(mesh, options);
      proxy_s = std::min(proxy_s, static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC);
    }
    const double cell_area = proxy.cell_size * proxy.cell_size;
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> edge_faces;  // unordered edge → faces
    for (const auto& t : proxy.mesh.triangles)
      for (int e = 0; e < 3; ++e) ++edge_faces[std::minmax(t[e], t[(e + 1) % 3])];
    std::size_t boundary = 0;
    for (const auto& [edge, count] : edge_faces) boundary += count == 1;
    std::vector<double> area = meshtour::face_areas(proxy.mesh);
    for (double& a : area) a /= cell_area;
    const meshtour::SurfaceAnalysis surface = meshtour::analyze_surface(proxy.mesh, options.surface);
    const meshtour::CoverageModel model(mesh, options);
    masks.push_back({model.features(meshtour::FeatureMeasure::patch_density), model.features(meshtour::FeatureMeasure::saliency)});
    double wmean = 0.0;
    for (double w : surface.face_weight) wmean += w / static_cast<double>(surface.face_weight.size());
    std::array<double, meshtour::kFeatureMeasures> jaccard{};
    for (int m = 0; m < meshtour::kFeatureMeasures; ++m) {
      std::size_t both = 0, either = 0;
      for (std::size_t i = 0; i < masks[0][m].size(); ++i) {
        both += masks[0][m][i] && masks.back()[m][i];
        either += masks[0][m][i] || masks.back()[m][i];
      }
      jaccard[m] = either ? static_cast<double>(both) / static_cast<double>(either) : 1.0;
    }
    std::printf("%-6d %9zu %8zu %8zu %8.3f %8.3f %8.3f %7d %6.1f %6.1f %6.1f %6.2f %9.3f %9.3f %8.3f %8zu\n", level, mesh.triangles.size(),
                proxy.mesh.positions.size(), proxy.mesh.triangles.size(), quantile(area, 0.1), quantile(area, 0.5), quantile(area, 0.9),
                surface.patch_count, quantile(surface.face_weight, 0.1), quantile(surface.face_weight, 0.5),
                quantile(surface.face_weight, 0.9), wmean, jaccard[0], jaccard[1], proxy_s, boundary);
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  g_source_mesh = std::filesystem::path(MESHTOUR_SOURCE_DIR).parent_path() / "shared" / "meshes" / "bunny.ply";
  int invariance_levels = -1, feature_levels = -1;
  std::vector<char*> rest = {argv[0]};
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--mesh=", 7) == 0)
      g_source_mesh = argv[i] + 7;
    else if (std::strncmp(argv[i], "--up=", 5) == 0)
      g_up = meshtour::Axis::parse(argv[i] + 5);
    else if (std::strcmp(argv[i], "--invariance") == 0)
      invariance_levels = 3;
    else if (std::strncmp(argv[i], "--invariance=", 13) == 0)
      invariance_levels = std::atoi(argv[i] + 13);
    else if (std::strncmp(argv[i], "--features=", 11) == 0)
      feature_levels = std::atoi(argv[i] + 11);
    else
      rest.push_back(argv[i]);
  }
  if (invariance_levels >= 0) return invariance(invariance_levels);
  if (feature_levels >= 0) return feature_diagnosis(feature_levels);
  return meshtour::bench::run_benchmarks(rest);
}
