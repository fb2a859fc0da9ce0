// meshtour tour: the whole job on one machine. Model -> camera path -> frames -> video, with the
// encoder fed as frames finish, so memory stays flat however long the tour is.
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

#include "cli/commands.h"
#include "cli/mesh_warnings.h"
#include "cli/path_options.h"
#include "cli/progress.h"
#include "cli/resource_options.h"
#include "cli/render_options.h"
#include "core/error.h"
#include "encoder/video_encoder.h"
#include "pathgen/paper_path.h"
#include "pathgen/path_file.h"
#include "pathgen/turntable.h"
#include "scenes/scene.h"
#include "tracer/tracer.h"

namespace meshtour::cli {
namespace {

struct TourArgs {
  std::string input;  // mesh or .json scene; empty = built-in default scene
  std::string output;
  std::optional<int> width, height, fps, frames, crf;
  std::optional<double> seconds, elevation;
  std::optional<std::string> fov;  // degrees or "auto"
  std::optional<std::string> up, path_mode, path_file;
  PaperPathOptions paper;  // options of the toroidal-patch path (ALGORITHM.md §2)
  std::string frames_dir;
  std::string format = "png";
  int threads = 0;
  bool quiet = false;
  RenderArgs render;
  ResourceArgs resources;
};

bool is_scene_file(const std::filesystem::path& p) { return p.extension() == ".json"; }

Scene resolve_scene(const TourArgs& a) {
  Scene scene;
  if (a.input.empty()) {
    scene = default_scene();
  } else if (is_scene_file(a.input)) {
    scene = load_scene(a.input);
  } else {
    scene = default_scene();  // defaults for everything but the model
    scene.source = a.input;
    scene.mesh_file = a.input;
  }
  if (a.up) scene.up = Axis::parse(*a.up);
  if (a.width) scene.render.width = *a.width;
  if (a.height) scene.render.height = *a.height;
  if (a.fps) scene.fps = *a.fps;
  if (a.frames) scene.frames = *a.frames;
  if (a.seconds) {
    const double frames = *a.seconds * scene.fps;
    if (!(frames >= 1.0 && frames <= 1e6)) throw InputError("--seconds gives " + std::to_string(frames) + " frames; it must give 1 to 1000000");
    scene.frames = static_cast<int>(std::lround(frames));
  }
  if (a.crf) scene.crf = *a.crf;
  if (a.fov && *a.fov == "auto") {
    scene.auto_fov = true;
  } else if (a.fov) {
    scene.vertical_fov_deg = std::stod(*a.fov);
    scene.auto_fov = false;
  }
  if (a.elevation) scene.elevation_deg = *a.elevation;
  if (a.path_mode) scene.path_mode = *a.path_mode;
  if (a.path_file) scene.path_file = *a.path_file;
  apply_render_options(a.render, scene);
  return scene;
}

std::filesystem::path default_output(const TourArgs& a) {
  if (a.input.empty()) return "meshtour-default.mp4";
  return std::filesystem::path(a.input).stem().string() + ".mp4";
}

std::string frame_name(int frame, const char* ext) {
  char name[64];
  std::snprintf(name, sizeof name, "frame_%06d.%s", frame, ext);
  return name;
}

// The camera path of the scene. Geometry-driven paths are wrapped in FramedPath: the paper's
// 4r/6r distance rule frames typical models, but the renderer checks every vertex anyway (§16 L6).
std::unique_ptr<CameraPath> make_path(const Scene& scene, const TriangleMesh& mesh, const Lens& lens,
                                      PaperPathOptions paper, bool quiet) {
  if (scene.path_file) {
    auto path = read_path_file(*scene.path_file);
    if (!quiet) std::fprintf(stderr, "camera path: %s\n", scene.path_file->string().c_str());
    if (scene.auto_fov) return path;
    return std::make_unique<FramedPath>(std::move(path), mesh.positions, lens);
  }
  if (scene.path_mode == "turntable") {
    TurntableOptions options;
    options.up = scene.up;
    options.elevation_deg = scene.elevation_deg;
    options.lens = lens;
    return std::make_unique<TurntablePath>(mesh.positions, options);
  }
  paper.up = UpDirection{UpDirection::Kind::axis, scene.up, scene.up.vector()};
  const std::string model = scene.mesh_file ? scene.mesh_file->string() : scene.source;
  const PaperPathResult result = with_file_name(model, [&] { return compute_paper_path(mesh, paper); });
  if (!quiet) warn_if_flat(mesh, result.up, model);
  if (!quiet) {
    double seconds = 0;
    for (const auto& [stage, s] : result.stage_seconds) seconds += s;
    std::fprintf(stderr, "camera path (toroidal patches): %d patches (%.2f %% of faces), amplitude %.1f %%, %d extreme points, %.2f s\n",
                 result.surface.patch_count, 100.0 * result.surface.patch_count / std::max<std::size_t>(1, result.surface.triangles.size()),
                 100.0 * result.metrics.amplitude_gaze, result.metrics.extreme_points, seconds);
    for (const auto& note : result.surface.cleanup_notes) std::fprintf(stderr, "  clean-up: %s\n", note.c_str());
  }
  if (scene.auto_fov) return std::make_unique<PaperCameraPath>(result.camera_path());
  auto framed = std::make_unique<FramedPath>(std::make_unique<PaperCameraPath>(result.camera_path()), mesh.positions, lens);
  if (!quiet && framed->pullback() > 0.0)
    std::fprintf(stderr, "  camera moved back by %.4g model units to keep the whole model in frame\n", framed->pullback());
  return framed;
}

// The field of view to render with. With "auto", a geometry-driven path keeps the distances its
// method chose and the lens is fitted to the model over every frame of the tour (one fov for the
// whole tour, so the image does not pump); the turntable fitted its radius to the fixed lens.
double choose_fov(const Scene& scene, const CameraPath& path, const TriangleMesh& mesh, const Lens& lens, bool quiet) {
  if (!scene.auto_fov || (scene.path_mode == "turntable" && !scene.path_file)) return lens.vertical_fov_deg;
  std::vector<Camera> cameras;
  cameras.reserve(static_cast<std::size_t>(scene.frames));
  for (int k = 0; k < scene.frames; ++k) {
    const CameraPose pose = frame_pose(path, k, scene.frames);
    cameras.push_back(Camera{pose.eye, pose.target, pose.up, lens.vertical_fov_deg});
  }
  const double fov = fit_vertical_fov(cameras, mesh.positions, lens.aspect, lens.margin);
  if (fov > 120.0)
    throw InputError("the camera path passes too close to the model to frame it (it would need a " +
                     std::to_string(static_cast<int>(fov)) + " degree lens); give a fixed --fov to move the camera back instead");
  if (!quiet) std::fprintf(stderr, "field of view: %.1f degrees (fitted to the model over all %d frames)\n", fov, scene.frames);
  return fov;
}

void run_tour(const TourArgs& args) {
  install_interrupt_handlers();
  const Scene scene = resolve_scene(args);
  const std::filesystem::path output = args.output.empty() ? default_output(args) : std::filesystem::path(args.output);
  if (output.extension() != ".mp4") throw InputError(output.string() + ": the video is written as H.264 MP4; name it *.mp4");
  const bool keep_frames = !args.frames_dir.empty();
  const bool write_png = keep_frames && (args.format == "png" || args.format == "png+exr");
  const bool write_exr = keep_frames && (args.format == "exr" || args.format == "png+exr");

  const int threads = capped_threads(args.threads, args.quiet);
  tbb::global_control thread_limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));

  // Refuse what would not fit before allocating anything: the model's counts come from its file's
  // structure (or the procedural model's size), the rest from the options.
  StageLog log(args.resources.verbose);
  log.start("check");
  std::size_t triangles = 0, vertices = 0;
  if (scene.mesh_file) {
    const MeshFileSummary counts = check_mesh_file(*scene.mesh_file);
    triangles = counts.triangles();
    vertices = counts.vertices;
  } else {
    triangles = static_cast<std::size_t>(60000.0 * scene.procedural_detail * scene.procedural_detail) + 1000;
    vertices = triangles / 2 + 1000;
  }
  {
    const auto& layers = scene.render.layers;
    const int extra_layers = int(layers.albedo) + int(layers.normal) + int(layers.depth);
    const bool path_stages = !scene.path_file && scene.path_mode == "paper";
    MemoryEstimate e;
    e.parts = {{"runtime", 100e6}, {"mesh", estimate_mesh_bytes(triangles, vertices)}};
    if (path_stages) e.parts.push_back({"camera path", estimate_path_bytes(triangles)});
    e.parts.push_back({"ray-tracing BVH", estimate_bvh_bytes(triangles)});
    e.parts.push_back({"frame buffers", estimate_frame_bytes(scene.render.width, scene.render.height, extra_layers)});
    // The path's structures are freed before the BVH is built.
    e.peak = e.parts[0].second + e.parts[1].second +
             std::max(path_stages ? e.parts[2].second : 0.0, e.parts[e.parts.size() - 2].second + e.parts.back().second);
    check_memory(e, memory_budget(args.resources), "this tour");
  }

  // Fail on the output before the expensive work: the encoder opens its temporary file now.
  VideoOptions video;
  video.width = scene.render.width;
  video.height = scene.render.height;
  video.fps = scene.fps;
  video.crf = scene.crf;
  VideoEncoder encoder(output, video);

  log.start("load");
  LoadReport report;
  const TriangleMesh mesh = load_scene_model(scene, &report);
  const Bounds bounds = mesh.bounds();
  if (!args.quiet) {
    std::fprintf(stderr, "%s: %zu faces, %zu vertices%s, bounds (%.4g %.4g %.4g) - (%.4g %.4g %.4g), up %s\n",
                 scene.mesh_file ? scene.mesh_file->string().c_str() : "built-in sculpture", mesh.face_count(),
                 mesh.vertex_count(), mesh.has_colors() ? " with colours" : "", bounds.lo.x(), bounds.lo.y(),
                 bounds.lo.z(), bounds.hi.x(), bounds.hi.y(), bounds.hi.z(), scene.up.name().c_str());
    for (const auto& w : report.warnings) std::fprintf(stderr, "  reader: %s\n", w.c_str());
  }

  if (!args.frames_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(args.frames_dir, ec);
    if (ec) throw IoError(args.frames_dir + ": cannot create the frames directory: " + ec.message());
  }

  Lens lens;
  lens.vertical_fov_deg = scene.vertical_fov_deg;
  lens.aspect = static_cast<double>(scene.render.width) / scene.render.height;
  log.start("path");
  auto path = make_path(scene, mesh, lens, args.paper, args.quiet);
  const double fov = choose_fov(scene, *path, mesh, lens, args.quiet);
  log.start("bvh");
  const Renderer renderer(mesh, scene.render);
  log.stop();

  Progress progress("frame", scene.frames, args.quiet);
  using Clock = std::chrono::steady_clock;
  double render_seconds = 0.0, encode_seconds = 0.0;
  for (int k = 0; k < scene.frames; ++k) {
    throw_if_interrupted();
    const auto t0 = Clock::now();
    const CameraPose pose = frame_pose(*path, k, scene.frames);
    const Image image = renderer.render(Camera{pose.eye, pose.target, pose.up, fov}, static_cast<std::uint64_t>(k));
    if (write_png) write_image(image, std::filesystem::path(args.frames_dir) / frame_name(k, "png"));
    if (write_exr) write_image(image, std::filesystem::path(args.frames_dir) / frame_name(k, "exr"));
    const auto t1 = Clock::now();
    encoder.add_frame(image.to_srgb8());
    encode_seconds += std::chrono::duration<double>(Clock::now() - t1).count();
    render_seconds += std::chrono::duration<double>(t1 - t0).count();
    progress.update(k + 1);
  }
  throw_if_interrupted();
  log.report("render", render_seconds);
  const auto finish_start = Clock::now();
  encoder.finish();
  log.report("encode", encode_seconds + std::chrono::duration<double>(Clock::now() - finish_start).count());
  progress.finish();
  if (!args.quiet) std::fprintf(stderr, "wrote %s (%d frames, %dx%d, %d fps)\n", output.string().c_str(), scene.frames,
                                scene.render.width, scene.render.height, scene.fps);
}

}  // namespace

void add_tour_command(CLI::App& app) {
  auto args = std::make_shared<TourArgs>();
  CLI::App* cmd = app.add_subcommand("tour", "Render a tour video of a mesh or a scene (the whole job on this machine).");
  cmd->description(
      "Render a tour video: load the model, compute the camera path, render every frame with the\n"
      "ray tracer and encode them to an H.264 MP4. With no INPUT, renders the built-in default scene.\n"
      "Options given here override the scene file; a mesh file gets the default scene's settings.");
  cmd->add_option("input", args->input, "Mesh (" + supported_mesh_formats() + ") or scene file (.json); default: built-in scene");
  cmd->add_option("-o,--output", args->output, "Video file to write (.mp4); default: <input name>.mp4 in the current directory");
  cmd->add_option("--width", args->width, "Frame width in pixels, even (default 1280)")->check(CLI::Range(2, 16384));
  cmd->add_option("--height", args->height, "Frame height in pixels, even (default 720)")->check(CLI::Range(2, 16384));
  cmd->add_option("--fps", args->fps, "Frames per second (default 30)")->check(CLI::Range(1, 240));
  auto* frames = cmd->add_option("--frames", args->frames, "Frames in one loop of the path (default 120)")->check(CLI::Range(1, 1000000));
  cmd->add_option("--seconds", args->seconds, "Length of the video in seconds (sets --frames = seconds x fps)")
      ->check(CLI::PositiveNumber)->excludes(frames);
  cmd->add_option("--up", args->up, "The model's up axis: x, y, z, -x, -y or -z (default y)")
      ->check(CLI::IsMember({"x", "y", "z", "-x", "-y", "-z", "+x", "+y", "+z"}, CLI::ignore_case));
  cmd->add_option("--path", args->path_mode,
                  "Camera path: paper (default; computed from the geometry by the toroidal-patch method of Choi et al. 2024,\n"
                  "see 'meshtour path --help') or turntable (circular orbit around the up axis)")
      ->check(CLI::IsMember({"turntable", "paper"}));
  cmd->add_option("--path-file", args->path_file, "Use the camera path in this file, written by 'meshtour path -o' (overrides --path)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--fov", args->fov,
                  "Vertical field of view: degrees (5-120), or auto (default): the paper path keeps its camera distance\n"
                  "and the fov is fitted so every vertex stays in frame at every frame; the turntable uses 35 degrees\n"
                  "and fits its radius. A fixed fov moves the paper path's camera back where needed instead.")
      ->check(CLI::IsMember({"auto"}) | CLI::Range(5.0, 120.0));
  cmd->add_option("--elevation", args->elevation, "Turntable: camera elevation above the model's centre, degrees (default 18)")
      ->check(CLI::Range(-80.0, 80.0));
  add_render_options(*cmd, args->render);
  cmd->add_option("--crf", args->crf, "H.264 quality (x264 CRF): 18 looks lossless, 23 is x264's default, 51 worst; 0 is lossless but High 4:4:4, which browsers do not play (default 18)")->check(CLI::Range(0, 51));
  cmd->add_option("--frames-dir", args->frames_dir, "Also write every frame as an image into this directory (frame_000000.png, ...)");
  cmd->add_option("--format", args->format, "Frame image format for --frames-dir: png (8-bit sRGB), exr (half float, linear) or png+exr")
      ->check(CLI::IsMember({"png", "exr", "png+exr"}));
  cmd->add_option("--threads", args->threads, "Threads to render with (default: all cores); results do not depend on it")
      ->check(CLI::Range(1, 1024));
  cmd->add_flag("-q,--quiet", args->quiet, "Print nothing but errors");
  add_paper_path_options(*cmd, args->paper);
  add_resource_options(*cmd, args->resources);
  cmd->callback([args] { run_tour(*args); });
}

}  // namespace meshtour::cli
