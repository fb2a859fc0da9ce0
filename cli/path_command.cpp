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
#include "tour/mesh_warnings.h"
#include "cli/path_options.h"
#include "tour/path_overview.h"
#include "tour/path_plot.h"
#include "cli/common_options.h"
#include "cli/scene_args.h"
#include "core/error.h"
#include "mesh/mesh.h"
#include "scenes/scene.h"
#include "pathgen/camera_export.h"
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
  std::string mode = "paper";
  options::Values values;  // registry rows of `path`: frames, threads, exports, path search
  std::string gltf, camera_frames, overview;
  std::string overview_size = "1200x900";
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
  a.options = path_search_options(a.values, a.options);
  a.options.up = UpDirection::parse(a.up);
  a.threads = int_value_or(a.values, "threads", 0);
  a.gltf = value_or(a.values, "gltf", "");
  a.camera_frames = value_or(a.values, "camera-frames", "");
  a.threads = thread_count(a.threads, a.quiet);
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
  const bool paper = a.mode == "paper";
  if (!paper && (!a.output.empty() || !a.plot.empty() || !a.debug_dir.empty()))
    throw InputError("-o, --plot and --debug-dir describe the paper path; with --path " + a.mode +
                     " use --gltf, --camera-frames or --overview");
  std::optional<PaperPathResult> result;
  if (paper) {
    log.start("path");
    result = with_file_name(a.mesh, [&] { return compute_paper_path(mesh, a.options); });
    log.stop();
    for (const auto& [stage, seconds] : result->stage_seconds) log.report_time("path/" + stage, seconds);
    if (!a.quiet) warn_if_flat(mesh, result->up, a.mesh);
  }
  throw_if_interrupted();

  // The cameras exactly as `meshtour tour MESH --path MODE --frames N` renders them (default
  // frame size and field of view "auto"), for the exports and the overview.
  Scene scene = default_scene();
  scene.source = a.mesh;
  scene.mesh_file = a.mesh;
  apply_options(scene, a.values);  // --frames and the path search, as `tour` applies them
  scene.path_mode = a.mode;
  Eigen::Vector3d up_vector = result ? result->up : Eigen::Vector3d::UnitY();
  if (!paper) {
    scene.up = Axis::parse(a.up);  // the other modes take a coordinate axis
    up_vector = scene.up.vector();
  } else if (a.options.up.kind == UpDirection::Kind::axis) {
    scene.up = a.options.up.axis;
  }
  Lens lens;
  lens.vertical_fov_deg = scene.vertical_fov_deg;
  lens.aspect = static_cast<double>(scene.render.width) / scene.render.height;
  std::unique_ptr<CameraPath> camera_path;
  double fov = lens.vertical_fov_deg;
  const bool exports = !a.gltf.empty() || !a.camera_frames.empty() || !a.overview.empty();
  if (exports) {
    // The paper path as computed here (its up direction may be a vector or pca), else the tour's.
    if (paper)
      camera_path = std::make_unique<PaperCameraPath>(result->camera_path());
    else
      camera_path = make_path(scene, mesh, lens, a.quiet);
    fov = choose_fov(scene, *camera_path, mesh, lens, true);
  }
  // Everything that can fail for a reason other than the file system happens before the first
  // output is written: the plot and the overview are drawn in memory first.
  std::optional<PlotImage> plot;
  if (!a.plot.empty()) plot = render_path_plot(*result);
  std::optional<Image> overview;
  if (!a.overview.empty()) {
    OverviewCylinder cylinder = bounding_cylinder(mesh, up_vector);
    if (paper) {
      // The paper's own cylinder (normalized units) in model units.
      const Cylinder& c = result->cylinder;
      const double scale = result->surface.scale;
      cylinder.up = c.up;
      cylinder.base_center = scale * c.axis_foot(c.base) + result->surface.offset;
      cylinder.radius = scale * c.radius;
      cylinder.height = scale * c.height;
    }
    int width = 0, height = 0;
    if (std::sscanf(a.overview_size.c_str(), "%dx%d", &width, &height) != 2 || width < 16 || height < 16 || width > 16384 || height > 16384)
      throw InputError("--overview-size '" + a.overview_size + "': give WIDTHxHEIGHT in pixels, e.g. 1200x900");
    overview = render_overview(mesh, *camera_path, cylinder, width, height);
  }
  throw_if_interrupted();

  std::vector<std::filesystem::path> written;
  try {
    if (!a.debug_dir.empty()) written = write_debug_outputs(*result, a.debug_dir);
    if (plot) {
      write_plot_image(*plot, a.plot);
      written.push_back(a.plot);
    }
    if (overview) {
      write_image(*overview, a.overview);
      written.push_back(a.overview);
    }
    if (exports && (!a.gltf.empty() || !a.camera_frames.empty())) {
      const TourCameras cameras = sample_tour(*camera_path, scene.frames, fov, lens.aspect, scene.fps);
      if (!a.gltf.empty()) {
        write_camera_gltf(cameras, a.gltf);
        written.push_back(a.gltf);
        written.push_back(std::filesystem::path(a.gltf).replace_extension(".bin"));
      }
      if (!a.camera_frames.empty()) {
        write_camera_frames(cameras, a.camera_frames);
        written.push_back(a.camera_frames);
      }
    }
    if (paper) {
      write_path_file(*result, output, a.mesh);
      written.push_back(output);
    }
  } catch (...) {
    // No partial outputs: undo the files this run completed.
    std::error_code ignored;
    for (const auto& f : written) std::filesystem::remove(f, ignored);
    throw;
  }
  if (!a.quiet) {
    if (paper) print_summary(*result, a, load, std::cout);
    else std::cout << "meshtour path: " << a.mesh << " (--path " << a.mode << ", up " << scene.up.name() << ")\n";
    if (exports) std::cout << "  lens       " << fixed(fov, 2) << " degrees vertical, " << scene.frames << " frames at " << scene.fps << " fps\n";
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
  cmd->add_option("--path", args->mode,
                  "Path mode: paper (this method; the path file, --plot and --debug-dir describe it), turntable or "
                  "feature-orbit (see 'meshtour evaluate --help'); the other modes need a coordinate --up axis")
      ->check(CLI::IsMember({"paper", "turntable", "feature-orbit"}))
      ->capture_default_str();
  cmd->add_option("--overview", args->overview,
                  "Also render a picture of the path (PNG): the model, its bounding cylinder (blue-grey), the camera "
                  "positions (magenta), the points looked at (cyan), sight lines (yellow) and the start (red)")
      ->type_name("PNG");
  cmd->add_option("--overview-size", args->overview_size, "Size of the --overview picture, WIDTHxHEIGHT")
      ->type_name("WxH")
      ->capture_default_str();
  cmd->add_option("--samples", args->options.samples,
                  "Samples per loop K in samples.csv (§13.3)")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  cmd->add_flag("-q,--quiet", args->quiet, "Print nothing on success");
  options::add_registered_options(*cmd, options::path, args->values);
  add_resource_options(*cmd, args->resources);
  cmd->callback([args] { run_path(*args); });
}

}  // namespace meshtour::cli
