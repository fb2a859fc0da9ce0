// meshtour path: the camera path of a mesh by the toroidal-patch method (ALGORITHM.md), written
// as a JSON path file, with an optional plot and debug outputs. No rendering.
#include <tbb/global_control.h>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include "cli/commands.h"
#include "cli/mesh_warnings.h"
#include "cli/path_options.h"
#include "cli/path_plot.h"
#include "cli/resource_options.h"
#include "core/error.h"
#include "mesh/mesh.h"
#include "pathgen/debug_output.h"
#include "pathgen/path_file.h"

namespace meshtour::cli {
namespace {

struct PathArgs {
  std::string mesh;
  std::string up = "y";
  std::string output;
  std::string plot;
  std::string debug_dir;
  int threads = 0;
  bool quiet = false;
  PaperPathOptions options;
  ResourceArgs resources;
};

std::string fixed(double value, int digits) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", digits, value);
  return text;
}

std::string general(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%.4g", value);
  return text;
}

void print_summary(const PaperPathResult& r, const PathArgs& a, const LoadReport& load, std::ostream& out) {
  const SurfaceAnalysis& s = r.surface;
  const PathMetrics& m = r.metrics;
  const double faces = static_cast<double>(s.triangles.size());
  out << "meshtour path: " << a.mesh << " (up " << r.options.up.name();
  if (r.options.up.kind != UpDirection::Kind::axis)
    out << " = " << general(r.up.x()) << "," << general(r.up.y()) << "," << general(r.up.z());
  out << ")\n";
  out << "  mesh       " << s.triangles.size() << " faces, " << s.positions.size() << " vertices\n";
  out << "  patches    T = " << s.patch_count << " (T/F = " << fixed(100.0 * s.patch_count / faces, 2)
      << "%; grown " << s.grown_patches << ", single-face " << s.single_face_patches << ", largest "
      << s.largest_patch << "), orphans " << s.orphans << "\n";
  out << "  cylinder   r = " << fixed(r.cylinder.radius, 4) << ", h = " << fixed(r.cylinder.height, 4)
      << " (diagonal = 1), h/r = " << fixed(m.height_over_radius, 3) << ", k_r = " << m.radius_factor << "\n";
  out << "  path       A = " << fixed(100.0 * m.amplitude_gaze, 1) << "% of h (curve "
      << fixed(100.0 * m.amplitude_curve, 1) << "%), E = " << m.extreme_points << ", start cell (row "
      << r.start.row << ", column " << r.start.column << "), t0 = " << general(r.start.parameter) << "\n";
  out << "  weights    Wmax = " << fixed(m.weight_max, 2) << ", Wavg = " << fixed(m.weight_avg, 2)
      << " (non-empty " << fixed(m.weight_avg_nonempty, 2) << "), empty cells " << m.empty_cells << " of "
      << r.grid.rows * r.grid.columns << "\n";
  out << "  rows       ";
  for (int row : r.control.rows) out << row << ' ';
  out << "\n  times      ";
  double total = 0.0;
  for (std::size_t k = 0; k < r.stage_seconds.size(); ++k) {
    out << (k ? ", " : "") << r.stage_seconds[k].first << " " << fixed(r.stage_seconds[k].second, 3);
    total += r.stage_seconds[k].second;
  }
  out << " (total " << fixed(total, 3) << " s)\n";
  for (const auto& note : load.warnings) out << "  loader     " << note << "\n";
  for (const auto& note : s.cleanup_notes) out << "  cleanup    " << note << "\n";
}

void run_path(PathArgs& a) {
  install_interrupt_handlers();
  a.options.up = UpDirection::parse(a.up);
  if (a.threads > 0) a.threads = capped_threads(a.threads, a.quiet);
  a.options.surface.threads = a.threads;
  a.options.validate();
  std::optional<tbb::global_control> thread_limit;
  if (a.threads > 0) thread_limit.emplace(tbb::global_control::max_allowed_parallelism, a.threads);

  const std::filesystem::path output =
      a.output.empty() ? std::filesystem::path(std::filesystem::path(a.mesh).stem().string() + ".path.json")
                       : std::filesystem::path(a.output);

  // Refuse what would not fit before allocating it: the counts come from the file's structure.
  StageLog log(a.resources.verbose);
  log.start("check");
  const MeshFileSummary counts = check_mesh_file(a.mesh);
  MemoryEstimate estimate;
  estimate.parts = {{"runtime", 100e6},
                    {"mesh", estimate_mesh_bytes(counts.triangles(), counts.vertices)},
                    {"camera path", estimate_path_bytes(counts.triangles())}};
  for (const auto& part : estimate.parts) estimate.peak += part.second;
  check_memory(estimate, memory_budget(a.resources), "the camera path of " + a.mesh);

  log.start("load");
  LoadReport load;
  const TriangleMesh mesh = load_mesh(a.mesh, &load);
  throw_if_interrupted();
  log.start("path");
  const PaperPathResult result = with_file_name(a.mesh, [&] { return compute_paper_path(mesh, a.options); });
  log.stop();
  for (const auto& [stage, seconds] : result.stage_seconds) log.report_time("path/" + stage, seconds);
  throw_if_interrupted();
  if (!a.quiet) warn_if_flat(mesh, result.up, a.mesh);
  // Everything that can fail for a reason other than the file system happens before the first
  // output is written: the plot is drawn in memory first.
  std::optional<PlotImage> plot;
  if (!a.plot.empty()) plot = render_path_plot(result);

  std::vector<std::filesystem::path> written;
  try {
    if (!a.debug_dir.empty()) written = write_debug_outputs(result, a.debug_dir);
    if (plot) {
      write_plot_image(*plot, a.plot);
      written.push_back(a.plot);
    }
    write_path_file(result, output, a.mesh);
    written.push_back(output);
  } catch (...) {
    // No partial outputs: undo the files this run completed.
    std::error_code ignored;
    for (const auto& f : written) std::filesystem::remove(f, ignored);
    throw;
  }
  if (!a.quiet) {
    print_summary(result, a, load, std::cout);
    for (const auto& f : written) std::cout << "  wrote      " << f.string() << "\n";
  }
}

}  // namespace

void add_path_command(CLI::App& app) {
  auto args = std::make_shared<PathArgs>();
  CLI::App* cmd = app.add_subcommand(
      "path",
      "Computes the camera path of a mesh by the toroidal-patch method of Choi et al. 2024 "
      "(see ALGORITHM.md) and writes it as a JSON path file; no rendering. The mesh is "
      "normalized (bounding-box diagonal = 1) and smoothed, split into toroidal patches; faces "
      "where many small patches meet are 'interesting'. A cylinder around the up axis is cut "
      "into a grid, each column's most interesting cell becomes a control point, and a closed "
      "B-spline through them gives the height of the camera as it circles the model. Lengths "
      "in options are in units of the bounding-box diagonal; I-n refers to the interpretations "
      "in ALGORITHM.md §15.");
  cmd->option_defaults()->always_capture_default();
  cmd->add_option("mesh", args->mesh, "Mesh file (" + supported_mesh_formats() + ")")
      ->required()
      ->type_name("MESH");
  cmd->add_option("--up", args->up, kPaperUpHelp)
      ->check(up_direction_validator())
      ->type_name("AXIS")
      ->capture_default_str();
  cmd->add_option("-o,--output", args->output,
                  "Path file to write (JSON, normalized units plus the transform back to model "
                  "units). Default: <mesh name>.path.json in the current folder")
      ->type_name("FILE");
  cmd->add_option("--plot", args->plot,
                  "Also draw a PNG of the grid weights over the (angle, height) domain with the "
                  "control points (white discs), the base (white), gaze (cyan) and position "
                  "(magenta) curves and the start cell (red)")
      ->type_name("PNG");
  cmd->add_option("--debug-dir", args->debug_dir,
                  "Also write the debug outputs of §14 into this folder: patches.ply, "
                  "face_weights.ply, cell_weights.ply (the smoothed mesh in model units, faces "
                  "coloured by patch / by w(f) / by the weight of their cell, green = low, red = "
                  "high) and samples.csv (the sampled curves and camera poses)")
      ->type_name("DIR");
  cmd->add_option("--samples", args->options.samples,
                  "Samples per loop K in samples.csv (§13.3)")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  cmd->add_option("--threads", args->threads, "Worker threads; 0 = all cores. Results do not depend on it")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_flag("-q,--quiet", args->quiet, "Print nothing on success");
  add_paper_path_options(*cmd, args->options);
  add_resource_options(*cmd, args->resources);
  cmd->callback([args] { run_path(*args); });
}

}  // namespace meshtour::cli
