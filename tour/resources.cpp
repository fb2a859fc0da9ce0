#include "tour/resources.h"

#include "mesh/ray_scene.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <thread>

#include "core/error.h"
#include "mesh/mesh.h"

namespace meshtour {
ResidentMemory resident_memory() {
  std::ifstream status("/proc/self/status");
  ResidentMemory m;
  for (std::string line; std::getline(status, line);) {
    std::istringstream words(line);
    std::string key;
    double kib = 0;
    words >> key >> kib;
    if (key == "VmRSS:") m.now = kib * 1024;
    if (key == "VmHWM:") m.peak = kib * 1024;
  }
  return m;
}


std::string format_bytes(double bytes) {
  const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB"};
  int u = 0;
  while (bytes >= 1024 && u < 5) {
    bytes /= 1024;
    ++u;
  }
  char text[32];
  std::snprintf(text, sizeof text, u == 0 ? "%.0f %s" : "%.1f %s", bytes, units[u]);
  return text;
}

std::uint64_t physical_memory() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  if (pages > 0 && page > 0) return static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page);
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  std::uint64_t kib = 0;
  while (meminfo >> key >> kib) {
    if (key == "MemTotal:") return kib * 1024;
    meminfo.ignore(1 << 10, '\n');
  }
  return 0;
}

MemoryBudget memory_budget(const ResourceArgs& args) {
  if (!args.max_memory.empty()) return {parse_memory_size(args.max_memory), "--max-memory " + args.max_memory};
  const std::uint64_t physical = physical_memory();
  if (physical == 0) return {UINT64_MAX, "unlimited (the machine's memory is unknown)"};
  return {physical / 4 * 3, "the default, 75% of the " + format_bytes(static_cast<double>(physical)) + " of this machine"};
}

// Bytes per element, measured with /usr/bin/time on the Stanford bunny (70k triangles) and a
// 1920x1080 tour and rounded up: the budget should refuse what cannot work, never what can.
double estimate_mesh_bytes(std::size_t triangles, std::size_t vertices) {
  return 400.0 * static_cast<double>(triangles) + 200.0 * static_cast<double>(vertices);
}
double estimate_path_bytes(std::size_t triangles) { return 1800.0 * static_cast<double>(triangles); }
double estimate_ray_scene_bytes(std::size_t triangles, std::size_t vertices) { return RayScene::estimated_bytes(triangles, vertices); }
// The renderer's copies of positions and triangles, normals (with the crease's vertex copies),
// UVs, materials and the crease pass's scratch. (With the BVH, which is now the ray-tracing scene's
// part, this was 250 bytes a face.)
double estimate_shading_bytes(std::size_t triangles) { return 140.0 * static_cast<double>(triangles); }
// The fixed part holds the 2^16 surface samples (with their trace copies, about 8 MB) and the views' bits.
double estimate_coverage_bytes(std::size_t triangles, std::size_t vertices) {
  return 150e6 + 50.0 * static_cast<double>(triangles) + 60.0 * static_cast<double>(vertices);
}
double estimate_frame_bytes(int width, int height, int extra_layers, bool denoise) {
  // The float image and its film, the 8-bit copy, and the encoder's look-ahead of about 40
  // YUV 4:2:0 frames; the denoiser's guides, planes and output (tracer/denoiser.h) about 170
  // bytes a pixel.
  return static_cast<double>(width) * height * (80.0 + 16.0 * extra_layers + 1.5 * 40 + (denoise ? 170.0 : 0.0));
}

MemoryEstimate estimate_job_memory(std::size_t triangles, std::size_t vertices, const std::vector<MemoryPart>& held,
                                   const std::optional<MemoryPart>& path, const std::vector<MemoryPart>& render) {
  MemoryEstimate e;
  e.parts = {{"runtime", 100e6}, {"mesh", estimate_mesh_bytes(triangles, vertices)}};
  double held_bytes = e.parts[0].second + e.parts[1].second;
  for (const MemoryPart& part : held) {
    e.parts.push_back(part);
    held_bytes += part.second;
  }
  if (path) e.parts.push_back(*path);
  double render_bytes = 0.0;
  for (const MemoryPart& part : render) {
    e.parts.push_back(part);
    render_bytes += part.second;
  }
  e.peak = held_bytes + std::max(path ? path->second : 0.0, render_bytes);
  return e;
}

double estimate_decoded_texture_bytes(const TriangleMesh& mesh) {
  double bytes = 0.0;
  for (const MeshMaterial& material : mesh.materials)
    for (const MeshTexture* map : material.maps()) {  // base colour and normal map alike
      try {
        const TextureSize size = probe_texture(*map, material.name);
        bytes += 4.0 / 3.0 * size.width * size.height * size.channels;
      } catch (const IoError&) {
        // An unreadable texture holds no memory; the loader or the renderer says what is wrong.
      }
    }
  return bytes;
}

double estimate_texture_cache_bytes(double decoded_texture_bytes) { return std::min(decoded_texture_bytes, 1024.0 * 1024 * 1024); }

void check_memory(const MemoryEstimate& estimate, const MemoryBudget& budget, const std::string& job) {
  if (estimate.peak <= static_cast<double>(budget.bytes)) return;
  std::string parts;
  for (const auto& [what, bytes] : estimate.parts) parts += (parts.empty() ? "" : ", ") + what + " " + format_bytes(bytes);
  const double suggestion = std::ceil(estimate.peak * 1.25 / (1024.0 * 1024 * 1024));
  throw InputError(job + " needs an estimated " + format_bytes(estimate.peak) + " of memory (" + parts +
                   ") but the memory budget is " + format_bytes(static_cast<double>(budget.bytes)) + " (" + budget.origin +
                   "); raise it with --max-memory " + std::to_string(static_cast<long long>(suggestion)) +
                   "G if the machine has it, or make the job smaller");
}

void StageLog::start(const std::string& name) {
  stop();
  announce(name);
  current_ = name;
  started_ = std::chrono::steady_clock::now();
}

void StageLog::stop() {
  if (current_.empty()) return;
  report(current_, std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count());
  current_.clear();
}

void StageLog::report(const std::string& name, double seconds) const {
  if (!verbose_) return;
  const auto [rss, peak] = resident_memory();
  std::fprintf(stderr, "meshtour: stage %-16s %8.3f s   memory %s, peak %s\n", name.c_str(), seconds,
               format_bytes(rss).c_str(), format_bytes(peak).c_str());
}

void StageLog::report_time(const std::string& name, double seconds) const {
  if (verbose_) std::fprintf(stderr, "meshtour: stage %-16s %8.3f s\n", name.c_str(), seconds);
}

}  // namespace meshtour
