#pragma once
// Resource limits shared by the commands: a memory budget checked against an estimate of the job
// BEFORE anything big is allocated, and --verbose reports of time
// and memory per stage. The command line gives them as the registry rows --max-memory and --verbose.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/memory_size.h"  // parse_memory_size: --max-memory
#include "tour/progress.h"

namespace meshtour {

struct TriangleMesh;

struct ResourceArgs {
  std::string max_memory;  ///< as given ("512M", "8G"); empty = default budget
  bool verbose = false;
};


/// Bytes as "1.5 GiB", "512 MiB".
std::string format_bytes(double bytes);
/// Physical memory of the machine (sysconf, else /proc/meminfo), 0 if unknown.
std::uint64_t physical_memory();

/// The memory a job may use, and why (for messages).
struct MemoryBudget {
  std::uint64_t bytes = 0;
  std::string origin;  ///< "--max-memory 8G" or "the default, 75% of the 16 GiB of this machine"
};
/// --max-memory when given, else 75% of physical memory. \throw InputError for a bad SIZE.
MemoryBudget memory_budget(const ResourceArgs& args);

/// A part of a job's memory: what it is and its bytes.
using MemoryPart = std::pair<std::string, double>;

/// What a job will hold in memory at its peak, by part, in bytes.
struct MemoryEstimate {
  std::vector<MemoryPart> parts;  ///< e.g. {"mesh (70000 triangles)", 3.1e7}
  double peak = 0.0;
};

/// The estimate of a job on a mesh of `triangles` and `vertices` (as its file announces them): the
/// runtime, the loaded mesh and `held` (the ray-tracing scene, which the path search and the
/// renderer share), held throughout; the camera path's structures (`path`, when the job computes a
/// path), freed before the renderer's parts (`render`: its shading data and the frame buffers;
/// none when the job does not render) are made. The peak holds the larger of those two phases.
MemoryEstimate estimate_job_memory(std::size_t triangles, std::size_t vertices, const std::vector<MemoryPart>& held,
                                   const std::optional<MemoryPart>& path, const std::vector<MemoryPart>& render);

/// Estimates (deliberately generous; calibrated on the Stanford bunny, see docs/USAGE.md, "Resource limits").
double estimate_mesh_bytes(std::size_t triangles, std::size_t vertices);  ///< loading: OpenMesh + arrays
double estimate_path_bytes(std::size_t triangles);                        ///< toroidal-patch path stages
/// The model's ray-tracing scene (mesh/ray_scene.h: Embree's buffers and BVH), one per job.
double estimate_ray_scene_bytes(std::size_t triangles, std::size_t vertices);
double estimate_shading_bytes(std::size_t triangles);  ///< the renderer's own per-face and per-vertex data
/// The feature orbit's coverage model (pathgen/coverage.h) besides the ray-tracing scene: the
/// surface samples, the clustering's arrays and the proxy's analysis.
double estimate_coverage_bytes(std::size_t triangles, std::size_t vertices);
double estimate_frame_bytes(int width, int height, int extra_layers, bool denoise);     ///< frame buffers + encoder
/// The textures' texels as the renderer decodes them (8 bits a channel, plus a third for the MIP
/// levels), from their files' headers. 0 for an untextured model.
double estimate_decoded_texture_bytes(const TriangleMesh& mesh);
/// The renderer's texture cache: OpenImageIO keeps at most 1 GiB of 64x64 tiles (its default),
/// whatever the atlases' size (8 x 16k JPEG atlases measured 1.6 GB peak for a whole render).
double estimate_texture_cache_bytes(double decoded_texture_bytes);

/// Refuses (InputError, exit 2) a job whose estimated peak exceeds the budget, naming the budget,
/// the estimate by part and how to raise the budget.
void check_memory(const MemoryEstimate& estimate, const MemoryBudget& budget, const std::string& job);

/// This process's resident memory now and at its peak so far (VmRSS, VmHWM of /proc/self/status),
/// bytes; 0 where /proc is not there.
struct ResidentMemory {
  double now = 0.0, peak = 0.0;
};
ResidentMemory resident_memory();

/// --verbose: one line per stage on stderr with its wall time, the resident memory at its end and
/// the peak so far (VmRSS / VmHWM of /proc/self/status).
class StageLog {
public:
  explicit StageLog(bool verbose, ProgressMode stage_events = ProgressMode::none)
      : verbose_(verbose), stage_events_(stage_events) {}
  /// Ends the previous stage (if any) and starts `name` (a JSON stage event where the progress is JSON).
  void start(const std::string& name);
  /// Announces a stage timed elsewhere as it starts (report() gives its time when it ends).
  void announce(const std::string& name) const { report_stage(stage_events_, name); }
  /// Ends the current stage and reports it.
  void stop();
  /// Reports a stage timed elsewhere (seconds), with the memory figures of now.
  void report(const std::string& name, double seconds) const;
  /// Reports a part of a stage timed elsewhere, without memory figures (they belong to the stage).
  void report_time(const std::string& name, double seconds) const;
  bool verbose() const { return verbose_; }

private:
  bool verbose_;
  ProgressMode stage_events_;
  std::string current_;
  std::chrono::steady_clock::time_point started_;
};

}  // namespace meshtour
