#pragma once
// The tour library: what every front end that renders a tour needs (the `meshtour` commands tour,
// render, batch, farm, path and evaluate are thin wrappers around it): given a Scene (typed
// settings, resolved at the edge: scenes/scene_options.h), the camera path of each mode, the
// field of view, the memory check, the thread policy, the one frame loop, the frames directory's
// description and the whole tour-to-video job. One implementation, so that a frame rendered by `render` in a farm chunk is
// the frame `tour` renders.

#include <filesystem>
#include <functional>
#include <string_view>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "encoder/video_codecs.h"
#include "jobs/frame_dir.h"
#include "tour/captioned_video.h"
#include "tour/poster.h"
#include "tour/progress.h"
#include "tour/resources.h"
#include "pathgen/camera_path.h"
#include "pathgen/paper_path.h"
#include "pathgen/path_file.h"
#include "scenes/scene.h"
#include "tracer/tracer.h"

namespace meshtour {

/// The image files of a frames directory's frames (--format).
enum class FrameFormats { png, exr, png_and_exr };
/// "png", "exr" or "png+exr": the --format value. \throw InputError for anything else.
FrameFormats parse_frame_formats(std::string_view text);
std::string_view frame_formats_name(FrameFormats formats);
/// The file extensions, PNG first: {"png"}, {"exr"} or {"png", "exr"}.
std::vector<std::string> frame_extensions(FrameFormats formats);

/// A scene document's opening view (a Voyager document's, scenes/voyager.h) as frame 0: `path`
/// (as searched or read from its path file, before UniformTurnPath) turned and blended to start
/// there (pathgen/opening_view.h). Without an opening view, `path` itself.
std::unique_ptr<CameraPath> from_opening_view(std::unique_ptr<CameraPath> path, const Scene& scene, const TriangleMesh& mesh);

/// The toroidal-patch path of the scene's model (deterministic: the same for any thread count).
PaperPathResult compute_scene_paper_path(const Scene& scene, const TriangleMesh& mesh);

/// The settings a path of `mode` depends on, as the scene, the mesh and the lens give them: what a
/// path file records (made_for) and what make_path() compares a path file with.
PathSettings path_settings(const Scene& scene, PathMode mode, const TriangleMesh& mesh, const Lens& lens);

/// A path computed from the model (a search for the paper path and the feature orbit, a fit for
/// the turntable), with the text of its path file, from which make_path() rebuilds the same path
/// bit for bit without searching.
struct SearchedPath {
  std::unique_ptr<CameraPath> path;  ///< as make_path() returns it (framed for a fixed fov)
  std::vector<double> view_scores;   ///< per frame of scene.frames (feature orbit), else empty
  std::string file_text;
};
/// The scene's path mode on `mesh` (scene.path_file is not read). A search announces itself on
/// stderr unless quiet ("meshtour: path search: MODE of MODEL (N faces)"). Arguments as make_path().
SearchedPath search_path(const Scene& scene, const TriangleMesh& mesh, std::span<const Eigen::Vector3d> hull, const Lens& lens,
                         bool quiet, std::shared_ptr<const RayScene> rays = nullptr);

/// The camera path of the scene: read from scene.path_file when given (never a search; refused
/// with InputError when the file was made for other settings, path_settings()), else
/// search_path()'s. Geometry-driven paths are wrapped in FramedPath when the fov is
/// fixed: the paper's 4r/6r distance rule frames typical models, but every vertex is checked.
/// `hull` is convex_hull_vertices(mesh.positions) (mesh/convex_hull.h), computed once per mesh by
/// the caller: the framing fits read its few vertices instead of every vertex, with the same result.
/// When the path search scores each frame's view (the feature orbit), the scores are stored in
/// `view_scores` if given (one per frame of scene.frames), else it is left empty. `rays`, the
/// mesh's ray-tracing scene when the caller has one (a tour shares it with its renderer), serves
/// the feature orbit's visibility tests; null builds one for them.
std::unique_ptr<CameraPath> make_path(const Scene& scene, const TriangleMesh& mesh, std::span<const Eigen::Vector3d> hull,
                                      const Lens& lens, bool quiet, std::vector<double>* view_scores = nullptr,
                                      std::shared_ptr<const RayScene> rays = nullptr);

/// The field of view to render with. With "auto", a geometry-driven path keeps its distances and
/// the lens is fitted to the model over EVERY frame of the tour (one fov for the whole tour, so
/// the image does not pump, and every farm chunk of the tour gets the same one).
/// `hull` as for make_path().
double choose_fov(const Scene& scene, const CameraPath& path, const TriangleMesh& mesh, std::span<const Eigen::Vector3d> hull,
                  const Lens& lens, bool quiet);

/// A tour ready to render frames: model, path, fov and renderer (its BVH built).
struct PreparedTour {
  Scene scene;
  TriangleMesh mesh;
  std::unique_ptr<CameraPath> path;
  double fov = 0.0;
  std::unique_ptr<Renderer> renderer;
  std::vector<double> view_scores;  ///< per frame, when the path search measured them (else empty)

  /// Frame `k` of the tour (k in 0 .. scene.frames-1); the same pixels in any process.
  Image render_frame(int k) const;
};

/// What check_tour_memory() estimated, and the budget it checked the estimate against.
struct TourMemoryCheck {
  MemoryEstimate estimate;
  MemoryBudget budget;
};

/// The camera path's own structures while `mode` searches it (the paper path's stages, or the
/// coverage model of the other modes), for the memory estimates of `tour` and `path`. The
/// turntable searches nothing; callers that read a path file skip this part too.
std::optional<MemoryPart> path_search_memory(PathMode mode, std::size_t triangles, std::size_t vertices);

/// Refuses (InputError) a tour of `scene` whose estimated memory exceeds the budget, before
/// anything big is allocated: the model's counts come from its file's structure (or the
/// procedural model's size), the rest from the options. Textures are not known yet: give the
/// result to prepare_tour(), which adds them once the model is loaded.
TourMemoryCheck check_tour_memory(const Scene& scene, const ResourceArgs& resources);

/// Loads the model (printing a summary unless `quiet`), computes the path and the fov and builds
/// the renderer; each of these is a stage of `log` (--verbose) when given. With `memory`, the
/// model's textures (their texture cache) join its estimate once the model is loaded, and a tour
/// that no longer fits is refused before the path and the renderer are made.
PreparedTour prepare_tour(const Scene& scene, bool quiet, StageLog* log = nullptr, const TourMemoryCheck* memory = nullptr);

/// The one thread policy: `requested` when > 0, else SLURM_CPUS_PER_TASK when set (a farm task
/// must not take the whole node), else every core of the machine; capped to the machine's cores,
/// with a note on stderr when capped (unless quiet). Results never depend on it.
int thread_count(int requested, bool quiet);

/// The frames directory of `scene` holding `formats` ("png", "exr"): the description `render`,
/// `tour --frames-dir` and `farm` write as its manifest (so `encode` reads any of them).
/// `view_scores` (one per frame, or empty) go into it with the best frame's index.
FrameDirInfo frame_dir_info(const Scene& scene, const std::vector<std::string>& formats,
                            const std::vector<double>& view_scores = {});

/// The best-covering frame of `view_scores` (the first of equal maxima), or -1 when there are
/// none: the frames manifest's best_view_frame (the poster is frame 0, the loop's first view).
int best_view_frame(const std::vector<double>& view_scores);

/// The one frame loop: renders `frames` of the tour in order, checking for an interrupt before
/// each, and hands each image to `done` with its render time in seconds.
void render_frames(const PreparedTour& tour, const std::vector<int>& frames,
                   const std::function<void(int frame, const Image& image, double seconds)>& done);

/// The tour pipeline on one machine: path, frames, and the video encoded as frames finish; `tour`
/// runs it once, `batch` for every item.
struct TourVideoJob {
  std::filesystem::path output;      // .mp4 (H.264); .mov, .mkv, .webm or .gif: that codec (encoder/video_codecs.h)
  /// The output keeps the frames' alpha (straight): needs a transparent background and a codec
  /// that carries alpha (prores, ffv1, vp9).
  bool alpha = false;
  /// --crf was given: codecs other than h264 then use scene.crf, else their own default (a scene's
  /// output.crf, 18 in the default scene, is H.264's).
  bool crf_given = false;
  std::filesystem::path webm;        // also a VP9 WebM of the same frames ("" = no), at VP9's default crf
  std::filesystem::path frames_dir;  // also write the frames here ("" = no)
  FrameFormats format = FrameFormats::png;  // for frames_dir
  std::filesystem::path gltf;           // also export the camera path as glTF 2.0 ("" = no)
  std::filesystem::path camera_frames;  // also write every frame's camera as .csv or .json ("" = no)
  int threads = 0;                   // 0 = render_threads' default
  ProgressMode progress = ProgressMode::automatic;
  ResourceArgs resources;  // --max-memory, --verbose
  PosterJob poster;         // --poster, --poster-size: the best frame as a PNG (written after the video)
  CaptionArgs caption;      // --caption ..., --title-card: burned into the video only
  bool quiet = false;
};
/// What a finished tour video holds, for summaries and contact sheets.
struct TourVideoResult {
  std::size_t faces = 0;
  std::int64_t video_frames = 0;  ///< title card included
  int fps = 0;
  int poster_frame = 0;
  double seconds() const { return fps > 0 ? static_cast<double>(video_frames) / fps : 0.0; }
};
TourVideoResult render_tour_video(const Scene& scene, const TourVideoJob& job);
/// The codec a tour's video file is written with: the one its extension names (.mp4: h264).
/// \throw InputError for another extension, listing them.
VideoCodec tour_video_codec(const std::filesystem::path& output);

}  // namespace meshtour
