#include "tour/tour.h"

#include "tour/mesh_warnings.h"

#include "pathgen/feature_orbit.h"

#include "tour/thread_limit.h"

#include <algorithm>
#include <numeric>
#include <thread>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "core/interrupt.h"
#include "encoder/video_encoder.h"
#include "mesh/convex_hull.h"
#include "pathgen/camera_export.h"
#include "core/error.h"
#include "pathgen/opening_view.h"
#include "pathgen/path_file.h"
#include "pathgen/turntable.h"

namespace meshtour {

FrameFormats parse_frame_formats(std::string_view text) {
  for (const FrameFormats f : {FrameFormats::png, FrameFormats::exr, FrameFormats::png_and_exr})
    if (frame_formats_name(f) == text) return f;
  throw InputError("unknown frame format '" + std::string(text) + "'; use png, exr or png+exr");
}

std::string_view frame_formats_name(FrameFormats formats) {
  switch (formats) {
    case FrameFormats::png: return "png";
    case FrameFormats::exr: return "exr";
    case FrameFormats::png_and_exr: return "png+exr";
  }
  return "png";
}

std::vector<std::string> frame_extensions(FrameFormats formats) {
  switch (formats) {
    case FrameFormats::png: return {"png"};
    case FrameFormats::exr: return {"exr"};
    case FrameFormats::png_and_exr: return {"png", "exr"};
  }
  return {"png"};
}

PaperPathResult compute_scene_paper_path(const Scene& scene, const TriangleMesh& mesh) {
  PaperPathOptions paper = scene.path_search;
  paper.up = UpDirection{UpDirection::Kind::axis, scene.up, scene.up.vector()};
  return compute_paper_path(mesh, paper);
}

namespace {

// With "fov": "auto" a geometry-driven path keeps its distances (the lens is fitted later); with a
// fixed fov it is wrapped in FramedPath, which moves the camera back where the model would not fit.
std::unique_ptr<CameraPath> frame_for_lens(std::unique_ptr<CameraPath> path, const Scene& scene,
                                           std::span<const Eigen::Vector3d> hull, const Lens& lens) {
  if (scene.auto_fov) return path;
  return std::make_unique<FramedPath>(std::move(path), hull, lens);
}

}  // namespace

PathSettings path_settings(const Scene& scene, PathMode mode, const TriangleMesh& mesh, const Lens& lens) {
  PathSettings settings = {{"up", scene.up.name()}, {"faces", std::to_string(mesh.face_count())}};
  const std::string fov = scene.auto_fov ? std::string("auto") : setting_text(lens.vertical_fov_deg);
  switch (mode) {
    case PathMode::paper:
      settings.emplace_back("path-search", search_options_text(scene.path_search));
      break;
    case PathMode::feature_orbit:
      // The orbit plans its distances for the frame's aspect and, when fixed, for the lens.
      settings.emplace_back("path-search", search_options_text(scene.path_search.surface));
      settings.emplace_back("aspect", setting_text(lens.aspect));
      settings.emplace_back("fov", fov);
      // The frame scores the file records are for this frame count.
      settings.emplace_back("frames", std::to_string(scene.frames));
      settings.emplace_back("first-view", std::string(orbit_start_name(scene.orbit_start)));
      break;
    case PathMode::turntable:
      settings.emplace_back("elevation", setting_text(scene.elevation_deg));
      settings.emplace_back("aspect", setting_text(lens.aspect));
      settings.emplace_back("fov", setting_text(lens.vertical_fov_deg));
      break;
  }
  return settings;
}

std::unique_ptr<CameraPath> from_opening_view(std::unique_ptr<CameraPath> path, const Scene& scene, const TriangleMesh& mesh) {
  if (!scene.opening_view) return path;
  return std::make_unique<OpeningViewPath>(std::move(path), mesh.bounds().center(), scene.up, *scene.opening_view);
}

namespace {

// A searched or read path as the tour moves along it: turned to the opening view (if any), at an
// even turning rate, framed for the lens.
std::unique_ptr<CameraPath> turned_and_framed(std::unique_ptr<CameraPath> path, const Scene& scene, const TriangleMesh& mesh,
                                              std::span<const Eigen::Vector3d> hull, const Lens& lens) {
  return frame_for_lens(std::make_unique<UniformTurnPath>(from_opening_view(std::move(path), scene, mesh)), scene, hull, lens);
}

// The turntable as made for the lens; with an opening view, turned and framed like the other paths.
std::unique_ptr<CameraPath> turntable_for(std::unique_ptr<CameraPath> turntable, const Scene& scene, const TriangleMesh& mesh,
                                          std::span<const Eigen::Vector3d> hull, const Lens& lens) {
  if (!scene.opening_view) return turntable;
  return turned_and_framed(std::move(turntable), scene, mesh, hull, lens);
}

}  // namespace

SearchedPath search_path(const Scene& scene, const TriangleMesh& mesh, std::span<const Eigen::Vector3d> hull, const Lens& lens,
                         bool quiet, std::shared_ptr<const RayScene> rays) {
  SearchedPath out;
  PathRecord record;
  record.source = scene.source;
  record.made_for = path_settings(scene, scene.path_mode, mesh, lens);
  const std::string model = scene.mesh_file ? scene.mesh_file->string() : std::string("the built-in model");
  // Each search announces itself once (a farm job counts them in its logs: one, at submission).
  const auto announce = [&] {
    if (!quiet)
      std::fprintf(stderr, "meshtour: path search: %s of %s (%zu faces)\n", std::string(path_mode_name(scene.path_mode)).c_str(),
                   model.c_str(), mesh.face_count());
  };
  if (scene.path_mode == PathMode::feature_orbit) {
    announce();
    FeatureOrbitOptions orbit;
    orbit.coverage.surface = scene.path_search.surface;
    orbit.coverage.ray_scene = std::move(rays);
    orbit.up = scene.up;
    orbit.aspect = lens.aspect;
    // A fixed --fov is the lens the distances are planned for; auto keeps the orbit's long lens
    // (FeatureOrbitOptions::vertical_fov_deg), and choose_fov() fits the tour's fov to it.
    if (!scene.auto_fov) orbit.vertical_fov_deg = scene.vertical_fov_deg;
    orbit.frames = scene.frames;
    orbit.start = scene.orbit_start;
    const FeatureOrbitResult result = compute_feature_orbit(mesh, orbit);
    // The scores are of the frames as searched; an opening view turns them to other views.
    if (!scene.opening_view) out.view_scores = result.frame_scores;
    if (!quiet) {
      const ElevationCurve& e = result.geometry.elevation;
      constexpr double deg = 180.0 / 3.14159265358979323846;
      std::fprintf(stderr, "camera path (feature orbit): elevation %.1f%+.1f cos(2pi(t-%.2f))%+.1f cos(4pi(t-%.2f)) degrees, "
                   "starting at the %s view (%.0f degrees around, preference %.3f); its views see %.1f %% of the "
                   "feature area (objective %.3f over patch density and saliency at four angles)\n", e.base * deg, e.swing * deg,
                   e.swing_phase, e.ripple * deg, e.ripple_phase, std::string(orbit_start_name(scene.orbit_start)).c_str(),
                   360.0 * result.geometry.start, result.start_preference.score,
                   100.0 * result.feature_share_seen, result.scores.objective);
      // Where the scores could not tell candidates apart (within twice their measured noise), the
      // fixed rule chose: the plainest curve nearest the band's middle, the start nearest the front.
      std::fprintf(stderr, "  ties: %d of the leading curves within %.2f points (noise %.2f), %d starts within %.2f points (noise %.2f)%s\n",
                   result.curves_tied, 100.0 * result.curve_tie_band, 100.0 * result.curve_noise, result.starts_tied,
                   100.0 * result.start_tie_band, 100.0 * result.start_noise,
                   result.curves_tied > 1 || result.starts_tied > 1 ? ": the tie rule chose" : "");
    }
    record.frames = scene.frames;
    record.frame_scores = result.frame_scores;
    out.file_text = path_file_text(result.geometry, record);
    out.path = turned_and_framed(std::make_unique<FeatureOrbitPath>(result.camera_path()), scene, mesh, hull, lens);
    return out;
  }
  if (scene.path_mode == PathMode::turntable) {
    TurntableOptions options;
    options.up = scene.up;
    options.elevation_deg = scene.elevation_deg;
    options.lens = lens;
    auto turntable = std::make_unique<TurntablePath>(hull, options);
    out.file_text = path_file_text(turntable->geometry(), record);
    out.path = turntable_for(std::move(turntable), scene, mesh, hull, lens);
    return out;
  }
  announce();
  const PaperPathResult result = with_file_name(model, [&] { return compute_scene_paper_path(scene, mesh); });
  if (!quiet) warn_if_flat(mesh, result.up, model);
  if (!quiet) {
    double seconds = 0;
    for (const auto& [stage, s] : result.stage_seconds) seconds += s;
    std::fprintf(stderr, "camera path (toroidal patches): %d patches (%.2f %% of faces), amplitude %.1f %%, %d extreme points, %.2f s\n",
                 result.surface.patch_count, 100.0 * result.surface.patch_count / std::max<std::size_t>(1, result.surface.triangles.size()),
                 100.0 * result.metrics.amplitude_gaze, result.metrics.extreme_points, seconds);
    for (const auto& note : result.surface.cleanup_notes) std::fprintf(stderr, "  clean-up: %s\n", note.c_str());
  }
  out.file_text = path_file_text(result, record);
  if (scene.auto_fov) {
    out.path = std::make_unique<UniformTurnPath>(from_opening_view(std::make_unique<PaperCameraPath>(result.camera_path()), scene, mesh));
    return out;
  }
  auto framed = std::make_unique<FramedPath>(
      std::make_unique<UniformTurnPath>(from_opening_view(std::make_unique<PaperCameraPath>(result.camera_path()), scene, mesh)), hull, lens);
  if (!quiet && framed->pullback() > 0.0)
    std::fprintf(stderr, "  camera moved back by %.4g model units to keep the whole model in frame\n", framed->pullback());
  out.path = std::move(framed);
  return out;
}

std::unique_ptr<CameraPath> make_path(const Scene& scene, const TriangleMesh& mesh, std::span<const Eigen::Vector3d> hull,
                                      const Lens& lens, bool quiet, std::vector<double>* view_scores,
                                      std::shared_ptr<const RayScene> rays) {
  if (view_scores) view_scores->clear();
  if (scene.path_file) {
    // Never a search: the path as the file holds it, for the settings it was made for.
    PathFile file = load_path_file(*scene.path_file);
    const PathMode mode = parse_path_mode(file.mode);
    check_path_settings(file, path_settings(scene, mode, mesh, lens), *scene.path_file);
    if (!quiet) std::fprintf(stderr, "camera path (%s): %s\n", file.mode.c_str(), scene.path_file->string().c_str());
    if (view_scores && file.record.frames == scene.frames && !scene.opening_view) *view_scores = file.record.frame_scores;
    // The turntable was fitted to its lens when it was made; the others are framed as when searched.
    if (mode == PathMode::turntable) return turntable_for(std::move(file.path), scene, mesh, hull, lens);
    return turned_and_framed(std::move(file.path), scene, mesh, hull, lens);
  }
  SearchedPath searched = search_path(scene, mesh, hull, lens, quiet, std::move(rays));
  if (view_scores) *view_scores = std::move(searched.view_scores);
  return std::move(searched.path);
}

double choose_fov(const Scene& scene, const CameraPath& path, const TriangleMesh& mesh, std::span<const Eigen::Vector3d> hull,
                  const Lens& lens, bool quiet) {
  // The turntable is fitted to its lens (whether computed here or read from a path file).
  if (!scene.auto_fov || dynamic_cast<const TurntablePath*>(&path)) return lens.vertical_fov_deg;
  // All frames of the tour, never just the ones this process renders: a farm chunk must use the
  // fov of the whole tour.
  std::vector<Camera> cameras;
  cameras.reserve(static_cast<std::size_t>(scene.frames));
  for (int k = 0; k < scene.frames; ++k) {
    const CameraPose pose = frame_pose(path, k, scene.frames);
    cameras.push_back(Camera::at(pose, lens.vertical_fov_deg));
  }
  const double fov = fit_vertical_fov(cameras, mesh.positions, hull, lens.aspect, lens.margin);
  if (fov > 120.0)
    throw InputError("the camera path passes too close to the model to frame it (it would need a " +
                     std::to_string(static_cast<int>(fov)) + " degree lens); give a fixed --fov to move the camera back instead");
  if (!quiet) std::fprintf(stderr, "field of view: %.1f degrees (fitted to the model over all %d frames)\n", fov, scene.frames);
  return fov;
}

Image PreparedTour::render_frame(int k) const {
  const CameraPose pose = frame_pose(*path, k, scene.frames);
  return renderer->render(Camera::at(pose, fov), static_cast<std::uint64_t>(k));
}

std::optional<MemoryPart> path_search_memory(PathMode mode, std::size_t triangles, std::size_t vertices) {
  if (mode == PathMode::turntable) return std::nullopt;
  return MemoryPart{"camera path", mode == PathMode::paper ? estimate_path_bytes(triangles) : estimate_coverage_bytes(triangles, vertices)};
}

TourMemoryCheck check_tour_memory(const Scene& scene, const ResourceArgs& resources) {
  std::size_t triangles = 0, vertices = 0;
  if (scene.mesh_file) {
    const MeshFileSummary counts = check_mesh_file(*scene.mesh_file);
    triangles = counts.triangles();
    vertices = counts.vertices;
  } else {
    triangles = static_cast<std::size_t>(60000.0 * scene.procedural_detail * scene.procedural_detail) + 1000;
    vertices = triangles / 2 + 1000;
  }
  const auto& layers = scene.render.layers;
  const int extra_layers = int(layers.albedo) + int(layers.normal) + int(layers.depth);
  std::optional<MemoryPart> path;
  if (!scene.path_file) path = path_search_memory(scene.path_mode, triangles, vertices);
  const MemoryEstimate e = estimate_job_memory(
      triangles, vertices, {{"ray-tracing scene", estimate_ray_scene_bytes(triangles, vertices)}}, path,
      {{"shading data", estimate_shading_bytes(triangles)},
       {"frame buffers", estimate_frame_bytes(scene.render.width, scene.render.height, extra_layers, scene.render.denoise)}});
  TourMemoryCheck check{e, memory_budget(resources)};
  check_memory(check.estimate, check.budget, "this tour");
  return check;
}

namespace {

// The textures' part, known once the model is loaded (their files' headers give their sizes),
// checked before the renderer's texture cache exists.
void check_texture_memory(TourMemoryCheck memory, const TriangleMesh& mesh) {
  const double decoded = estimate_decoded_texture_bytes(mesh);
  if (!(decoded > 0.0)) return;
  const double cache = estimate_texture_cache_bytes(decoded);
  memory.estimate.parts.push_back({"texture cache", cache});
  memory.estimate.peak += cache;
  check_memory(memory.estimate, memory.budget, "this tour");
}

}  // namespace

PreparedTour prepare_tour(const Scene& requested, bool quiet, StageLog* log, const TourMemoryCheck* memory) {
  const auto stage = [&](const char* name) {
    if (log) log->start(name);
  };
  // On a big model the stages before the first frame take seconds each (a 17.8M-face scan: load
  // 3 s, path 15 s, BVH 9 s): each is announced as it starts, so a long wait says what it is.
  constexpr std::uintmax_t kBigFileBytes = 100u << 20;
  constexpr std::size_t kBigModelFaces = 1'000'000;
  std::error_code size_error;
  const std::uintmax_t file_bytes = requested.mesh_file ? std::filesystem::file_size(*requested.mesh_file, size_error) : 0;
  if (!quiet && !size_error && file_bytes >= kBigFileBytes)
    std::fprintf(stderr, "reading %s (%.0f MB)...\n", requested.mesh_file->string().c_str(), static_cast<double>(file_bytes) / 1e6);
  stage("load");
  PreparedTour tour;
  tour.scene = requested;
  LoadReport report;
  tour.mesh = load_scene_model(requested, &report);
  // --up auto needs the model; from here on everything reads the decided axis.
  resolve_auto_up(tour.scene, tour.mesh, quiet);
  if (memory) check_texture_memory(*memory, tour.mesh);
  const Scene& scene = tour.scene;
  const TriangleMesh& mesh = tour.mesh;
  const Bounds bounds = mesh.bounds();
  if (!quiet) {
    std::fprintf(stderr, "%s: %zu faces, %zu vertices%s, bounds (%.4g %.4g %.4g) - (%.4g %.4g %.4g), up %s\n",
                 scene.mesh_file ? scene.mesh_file->string().c_str() : "built-in sculpture", mesh.face_count(),
                 mesh.vertex_count(), mesh.has_colors() ? " with colours" : "", bounds.lo.x(), bounds.lo.y(),
                 bounds.lo.z(), bounds.hi.x(), bounds.hi.y(), bounds.hi.z(), scene.up.name().c_str());
    for (const auto& w : report.warnings) std::fprintf(stderr, "  reader: %s\n", w.c_str());
    if (!scene.voyager_summary.empty()) std::fprintf(stderr, "  %s\n", scene.voyager_summary.c_str());
  }
  Lens lens;
  lens.vertical_fov_deg = scene.vertical_fov_deg;
  lens.aspect = static_cast<double>(scene.render.width) / scene.render.height;
  const bool big = !quiet && mesh.face_count() >= kBigModelFaces;
  // One BVH for the job: the feature orbit's visibility tests and the renderer share it.
  if (big) std::fprintf(stderr, "building the ray-tracing BVH of %zu faces...\n", mesh.face_count());
  stage("bvh");
  const auto rays = std::make_shared<const RayScene>(mesh);
  if (big && !scene.path_file) std::fprintf(stderr, "choosing the camera path...\n");
  stage("path");
  // Once per mesh: every framing fit of the path and the lens reads only the hull's vertices.
  const std::vector<Eigen::Vector3d> hull = convex_hull_vertices(mesh.positions);
  tour.path = make_path(scene, mesh, hull, lens, quiet, &tour.view_scores, rays);
  tour.fov = choose_fov(scene, *tour.path, mesh, hull, lens, quiet);
  stage("shading");
  tour.renderer = std::make_unique<Renderer>(mesh, scene.render, rays);
  if (log) log->stop();
  return tour;
}

int thread_count(int requested, bool quiet) {
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  if (requested <= 0) {
    requested = cores;
    if (const char* slurm = std::getenv("SLURM_CPUS_PER_TASK")) {
      char* end = nullptr;
      const long n = std::strtol(slurm, &end, 10);
      if (end != slurm && *end == '\0' && n >= 1 && n <= 4096) requested = static_cast<int>(n);
    }
  }
  if (requested > cores) {
    // Results never depend on the thread count, so capping changes only speed.
    if (!quiet)
      std::fprintf(stderr, "meshtour: note: --threads %d capped to the %d cores of this machine (results do not depend on it)\n",
                   requested, cores);
    return cores;
  }
  return requested;
}

FrameDirInfo frame_dir_info(const Scene& scene, const std::vector<std::string>& formats, const std::vector<double>& view_scores) {
  FrameDirInfo info;
  info.frame_count = scene.frames;
  info.fps = scene.fps;
  info.width = scene.render.width;
  info.height = scene.render.height;
  info.image_formats = formats;
  info.denoise = scene.render.denoise;
  info.source = scene.source;
  if (scene.path_file) info.path_file = std::filesystem::absolute(*scene.path_file).string();
  if (static_cast<int>(view_scores.size()) == scene.frames && !view_scores.empty()) {
    info.view_scores = view_scores;
    info.best_view_frame = best_view_frame(view_scores);
  }
  return info;
}

int best_view_frame(const std::vector<double>& view_scores) {
  if (view_scores.empty()) return -1;
  // The first of equal maxima, as the path search picks its start.
  return static_cast<int>(std::max_element(view_scores.begin(), view_scores.end()) - view_scores.begin());
}

void render_frames(const PreparedTour& tour, const std::vector<int>& frames,
                   const std::function<void(int frame, const Image& image, double seconds)>& done) {
  for (const int k : frames) {
    throw_if_interrupted();  // SIGINT/SIGTERM: stop between frames; outputs never leave a temporary
    const auto start = std::chrono::steady_clock::now();
    const Image image = tour.render_frame(k);
    done(k, image, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
}

VideoCodec tour_video_codec(const std::filesystem::path& output) {
  if (const std::optional<VideoCodec> codec = codec_for_extension(output.extension().string())) return *codec;
  std::string list;
  for (const auto& info : video_codecs())
    list += (list.empty() ? "" : ", ") + std::string(info.extension) + " (" + std::string(info.name) + ")";
  throw InputError(output.string() + ": the video's type follows its name; name it *.mp4 (H.264), or one of " + list);
}

TourVideoResult render_tour_video(const Scene& scene, const TourVideoJob& job) {
  const std::filesystem::path& output = job.output;
  const VideoCodec codec = tour_video_codec(output);
  const bool transparent = scene.render.shading.background == BackgroundKind::transparent;
  if (job.alpha) require_alpha_codec(codec);
  if (job.alpha && !transparent)
    throw InputError("--alpha needs a transparent background: add --background transparent (over the gradient the "
                     "frames have no alpha to keep)");
  const bool keep_frames = !job.frames_dir.empty();
  const bool write_png = keep_frames && job.format != FrameFormats::exr;
  const bool write_exr = keep_frames && job.format != FrameFormats::png;

  const ThreadLimit thread_limit(job.threads, job.quiet);

  // Refuse what would not fit before allocating anything.
  StageLog log(job.resources.verbose, job.quiet ? ProgressMode::none : job.progress);
  log.start("check");
  const TourMemoryCheck memory = check_tour_memory(scene, job.resources);

  // Fail on the output before the expensive work: the encoder opens its temporary file now.
  VideoOptions video;
  video.width = scene.render.width;
  video.height = scene.render.height;
  video.fps = scene.fps;
  video.codec = codec;
  if (codec == VideoCodec::h264 || job.crf_given) video.crf = scene.crf;
  video.alpha = job.alpha;
  VideoEncoder encoder(output, video);
  // The caption is measured now: one that does not fit fails before the model is even loaded.
  CaptionArgs caption = job.caption;
  std::optional<CaptionedVideo> captioned;
  try {
    captioned.emplace(encoder, video, caption);
  } catch (const InputError& e) {
    if (!caption.caption_by_default) throw;
    if (!job.quiet) std::fprintf(stderr, "meshtour: note: the document's title is not captioned: %s\n", e.what());
    caption.caption.reset();
    captioned.emplace(encoder, video, caption);
  }
  // The web copy: VP9 at its own default quality (the crf given is H.264's).
  std::optional<VideoEncoder> web_encoder;
  std::optional<CaptionedVideo> web_captioned;
  if (!job.webm.empty()) {
    VideoOptions web = video;
    web.alpha = false;  // batch --web: the page's WebM is over black (a caption may be burned in)
    web.codec = VideoCodec::vp9;
    web.crf.reset();
    web_encoder.emplace(job.webm, web);
    web_captioned.emplace(*web_encoder, web, caption);
  }
  check_poster_output(job.poster);

  const PreparedTour tour = prepare_tour(scene, job.quiet, &log, &memory);
  // The frames directory and its manifest only once the tour could be prepared: a bad model or
  // path file leaves nothing behind.
  if (keep_frames) {
    // The same frames directory `meshtour render` writes: `meshtour encode` can read it too.
    std::vector<std::string> formats;
    if (write_png) formats.push_back("png");
    if (write_exr) formats.push_back("exr");
    const FrameDirInfo info = frame_dir_info(scene, formats, tour.view_scores);
    prepare_frame_dir(job.frames_dir, info);
  }

  if (!job.gltf.empty() || !job.camera_frames.empty()) {
    const double aspect = static_cast<double>(scene.render.width) / scene.render.height;
    const TourCameras cameras = sample_tour(*tour.path, scene.frames, tour.fov, aspect, scene.fps);
    if (!job.gltf.empty()) write_camera_gltf(cameras, job.gltf);
    if (!job.camera_frames.empty()) write_camera_frames(cameras, job.camera_frames);
  }

  // The poster: frame 0, the preferred view. The title card opens on it, so then it is rendered
  // before the tour; else it is kept as the loop passes it.
  const int poster_k = kPosterFrame;
  std::optional<Image> poster;
  if (captioned->needs_poster()) {
    poster = tour.render_frame(poster_k);
    captioned->start(job.alpha ? poster->to_srgba8() : poster->to_srgb8());
    if (web_captioned) web_captioned->start(poster->to_srgb8());
  }

  log.stop();
  log.announce("render");
  Progress progress("frame", scene.frames, job.progress);
  using Clock = std::chrono::steady_clock;
  double render_seconds = 0.0, encode_seconds = 0.0;
  std::vector<int> frames(static_cast<std::size_t>(scene.frames));
  std::iota(frames.begin(), frames.end(), 0);
  render_frames(tour, frames, [&](int k, const Image& image, double seconds) {
    const auto start = Clock::now();
    if (write_png) write_image(image, frame_file(job.frames_dir, k, "png"));
    if (write_exr) write_image(image, frame_file(job.frames_dir, k, "exr"));
    if (k == poster_k && !job.poster.file.empty() && !poster) poster = image;
    const auto written = Clock::now();
    if (job.alpha) {
      captioned->add(image.to_srgba8());  // straight alpha, as in the PNG frames
      if (web_captioned) web_captioned->add(image.to_srgb8());
    } else {
      const std::vector<std::uint8_t> rgb = image.to_srgb8();
      captioned->add(rgb);
      if (web_captioned) web_captioned->add(rgb);
    }
    encode_seconds += std::chrono::duration<double>(Clock::now() - written).count();
    render_seconds += seconds + std::chrono::duration<double>(written - start).count();
    progress.step_done(k, seconds + std::chrono::duration<double>(Clock::now() - start).count(), k + 1);
  });
  throw_if_interrupted();
  log.report("render", render_seconds);
  log.announce("encode");
  const auto finish_start = Clock::now();
  captioned->finish();
  if (web_captioned) web_captioned->finish();
  log.report("encode", encode_seconds + std::chrono::duration<double>(Clock::now() - finish_start).count());
  progress.finish();
  // After the video: a failed tour leaves no poster either.
  if (poster && !job.poster.file.empty()) {
    log.announce("poster");
    write_poster(*poster, job.poster);
    if (!job.quiet) std::fprintf(stderr, "wrote %s (poster: frame %d, the preferred view)\n", job.poster.file.string().c_str(), poster_k);
  }
  if (!job.quiet) std::fprintf(stderr, "wrote %s (%d frames, %dx%d, %d fps)\n", output.string().c_str(), scene.frames,
                               scene.render.width, scene.render.height, scene.fps);
  TourVideoResult result;
  result.faces = tour.mesh.face_count();
  result.video_frames = encoder.frames_written();
  result.fps = scene.fps;
  result.poster_frame = poster_k;
  return result;
}

}  // namespace meshtour
