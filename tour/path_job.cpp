#include "tour/path_job.h"

#include "tour/thread_limit.h"
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include "tour/mesh_warnings.h"
#include "tour/path_overview.h"
#include "tour/path_plot.h"
#include "core/error.h"
#include "mesh/convex_hull.h"
#include "mesh/mesh.h"
#include "mesh/up_axis.h"
#include "scenes/scene.h"
#include "pathgen/camera_export.h"
#include "pathgen/debug_output.h"
#include "pathgen/path_file.h"
#include "core/interrupt.h"
#include "tour/mesh_warnings.h"
#include "tour/path_overview.h"
#include "tour/path_plot.h"
#include "tour/progress.h"
#include "tour/tour.h"

namespace meshtour {
namespace {

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

void print_summary(const PaperPathResult& r, const PathJob& a, const LoadReport& load, std::ostream& out) {
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

}  // namespace

void run_path(PathJob& a) {
  install_interrupt_handlers();
  // --up auto needs the model: decided once it is loaded, below.
  const bool up_auto = a.up_auto;
  if (!up_auto) a.options.up = a.up;
  const ThreadLimit thread_limit(a.threads, a.quiet);
  a.threads = thread_limit.threads();
  a.options.surface.threads = a.threads;
  a.options.validate();

  const std::filesystem::path output =
      a.output.empty() ? std::filesystem::path(std::filesystem::path(a.mesh).stem().string() + ".path.json")
                       : std::filesystem::path(a.output);

  // Refuse what would not fit before allocating it: the counts come from the file's structure.
  StageLog log(a.resources.verbose);
  log.start("check");
  const MeshFileSummary counts = check_mesh_file(a.mesh);
  // The feature orbit searches against the model's ray-tracing scene, as in a tour.
  std::vector<MemoryPart> held;
  if (a.mode == PathMode::feature_orbit) held.push_back({"ray-tracing scene", estimate_ray_scene_bytes(counts.triangles(), counts.vertices)});
  const MemoryEstimate estimate =
      estimate_job_memory(counts.triangles(), counts.vertices, held, path_search_memory(a.mode, counts.triangles(), counts.vertices), {});
  check_memory(estimate, memory_budget(a.resources), "the camera path of " + a.mesh);

  log.start("load");
  LoadReport load;
  TriangleMesh loaded = load_mesh(a.mesh, &load, LoadOptions{.check_textures = false});  // the path needs no textures
  if (a.scene.model_transform) transform_mesh(loaded, *a.scene.model_transform);  // a Voyager document's pose
  const TriangleMesh& mesh = loaded;
  throw_if_interrupted();
  if (up_auto) {
    const UpChoice choice = choose_up_axis(mesh, a.mesh);
    a.up = UpDirection{};  // the axis the model's shape gives
    a.up.axis = choice.up;
    a.options.up = a.up;
    // Asked for, the choice is said; as the default, only where it is not the +y it used to be.
    if (!a.quiet && (a.scene.up_given || choice.up != Axis{1, false}))
      std::fprintf(stderr, "--up auto: %s (%s)\n", choice.up.name().c_str(), choice.reason.c_str());
    if (!choice.warning.empty()) std::fprintf(stderr, "meshtour: warning: --up auto: %s\n", choice.warning.c_str());
  }
  const bool paper = a.mode == PathMode::paper;
  if (!paper && (!a.plot.empty() || !a.debug_dir.empty()))
    throw InputError("--plot and --debug-dir describe the paper path; with --path " + std::string(path_mode_name(a.mode)) +
                     " use -o, --gltf, --camera-frames or --overview");
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
  Scene scene = a.scene;
  scene.path_mode = a.mode;
  Eigen::Vector3d up_vector = result ? result->up : Eigen::Vector3d::UnitY();
  const bool axis_up = !paper || a.options.up.kind == UpDirection::Kind::axis;
  if (!paper) {
    scene.up = a.up.axis;  // the other modes take a coordinate axis (checked where --up was read)
    up_vector = scene.up.vector();
  } else if (axis_up) {
    scene.up = a.options.up.axis;
  }
  Lens lens;
  lens.vertical_fov_deg = scene.vertical_fov_deg;
  lens.aspect = static_cast<double>(scene.render.width) / scene.render.height;
  std::unique_ptr<CameraPath> camera_path;
  double fov = lens.vertical_fov_deg;
  const bool exports = !a.gltf.empty() || !a.camera_frames.empty() || !a.overview.empty();
  // The path file: the paper path's full record, or the other modes' path as `tour` computes it
  // (written when -o is given), each with the settings it was made for.
  std::string path_text;
  if (exports || (!paper && !a.output.empty())) {
    // The paper path as computed here (its up direction may be a vector or pca), else the tour's.
    // Once per mesh: the framing fits read only the hull's vertices.
    const std::vector<Eigen::Vector3d> hull = convex_hull_vertices(mesh.positions);
    if (paper) {
      camera_path = std::make_unique<UniformTurnPath>(from_opening_view(std::make_unique<PaperCameraPath>(result->camera_path()), scene, mesh));
    } else {
      SearchedPath searched = search_path(scene, mesh, hull, lens, a.quiet);
      camera_path = std::move(searched.path);
      path_text = std::move(searched.file_text);
    }
    if (exports) fov = choose_fov(scene, *camera_path, mesh, hull, lens, true);
  }
  if (paper) {
    PathRecord record;
    record.source = a.mesh;
    record.made_for = path_settings(scene, PathMode::paper, mesh, lens);
    // A vector or pca up direction is no --up a render can give: only the search is recorded.
    if (!axis_up) std::erase_if(record.made_for, [](const auto& setting) { return setting.first == "up"; });
    path_text = path_file_text(*result, record);
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
    overview = render_overview(mesh, *camera_path, cylinder, a.overview_width, a.overview_height);
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
    if (!path_text.empty()) {
      write_text_file_atomically(output, path_text, "path file");
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
    else std::cout << "meshtour path: " << a.mesh << " (--path " << path_mode_name(a.mode) << ", up " << scene.up.name() << ")\n";
    if (exports) std::cout << "  lens       " << fixed(fov, 2) << " degrees vertical, " << scene.frames << " frames at " << scene.fps << " fps\n";
    for (const auto& f : written) std::cout << "  wrote      " << f.string() << "\n";
  }
}

}  // namespace meshtour
