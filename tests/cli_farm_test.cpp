// End-to-end tests of the farm commands through the real executable: `render` in chunks by
// separate processes gives the bytes of one run (and of `tour`), a killed render resumes to the
// same frames and never shows a partial file under a frame name, resume skips what exists,
// `batch` survives a broken item, and the sbatch scripts of `farm slurm` run a chunk.
// (The real Slurm cluster is tests/slurm/run-slurm-test.sh.)
#include <gtest/gtest.h>
#include <OpenImageIO/imagebuf.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "encoder/video_encoder.h"
#include "core/file_lock.h"
#include "tracer/instruction_set.h"
#include "helpers.h"
#include "test_meshes.h"
#include "video_probe.h"

namespace meshtour {
namespace {

using test::run_meshtour;



// Every regular file of `dir` by name (hidden ones included).
std::map<std::string, std::filesystem::path> files_of(const std::filesystem::path& dir) {
  std::map<std::string, std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.is_regular_file()) files[e.path().filename().string()] = e.path();
  return files;
}

std::vector<std::string> frame_names(const std::filesystem::path& dir, const std::string& ext) {
  std::vector<std::string> names;
  for (const auto& [name, path] : files_of(dir))
    if (name.rfind("frame_", 0) == 0 && path.extension() == ext) names.push_back(name);
  return names;
}

// The pixels and header of an EXR frame, without the one attribute that is meant to differ
// between runs (meshtour:renderSeconds, the render time the header records).
std::string exr_content(const std::filesystem::path& file) {
  OIIO::ImageBuf image(file.string());
  EXPECT_TRUE(image.read(0, 0, true, OIIO::TypeDesc::FLOAT)) << file;
  const OIIO::ImageSpec& spec = image.spec();
  std::vector<float> pixels(spec.image_pixels() * static_cast<std::size_t>(spec.nchannels));
  image.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, pixels.data());
  std::string content(reinterpret_cast<const char*>(pixels.data()), pixels.size() * sizeof(float));
  for (const auto& attribute : spec.extra_attribs)
    if (attribute.name() != "meshtour:renderSeconds") content += "\n" + attribute.name().string() + "=" + spec.metadata_val(attribute);
  EXPECT_NE(spec.find_attribute("meshtour:renderSeconds"), nullptr) << file << " lacks its render time";
  return content;
}

// Expects the frame files (and the manifest) of two directories to be the same: PNG and manifest
// the same bytes, EXR the same pixels and header but for the render time.
void expect_same_frames(const std::filesystem::path& a, const std::filesystem::path& b, std::size_t expected_files) {
  const auto fa = files_of(a), fb = files_of(b);
  ASSERT_EQ(fa.size(), expected_files) << a;
  ASSERT_EQ(fb.size(), expected_files) << b;
  for (const auto& [name, path] : fa) {
    ASSERT_TRUE(fb.count(name)) << name << " missing in " << b;
    if (path.extension() == ".exr")
      EXPECT_TRUE(exr_content(path) == exr_content(fb.at(name))) << name << " differs";
    else
      EXPECT_TRUE(test::file_bytes(path) == test::file_bytes(fb.at(name))) << name << " differs";
  }
}

// A PNG frame is complete: OpenImageIO reads all its pixels at the expected size.
bool readable_png(const std::filesystem::path& file, int width, int height) {
  OIIO::ImageBuf image(file.string());
  if (!image.read(0, 0, true, OIIO::TypeDesc::UINT8)) return false;
  return image.spec().width == width && image.spec().height == height && !image.has_error();
}

// The video of a frames directory, made by `meshtour encode`, decoded.
test::VideoProbe encode_and_decode(const std::filesystem::path& frames, const std::filesystem::path& video, int count) {
  std::vector<int> all(count);
  for (int k = 0; k < count; ++k) all[k] = k;
  const auto r = run_meshtour("encode " + test::shell_quoted(frames) + " -o " + test::shell_quoted(video) + " --codec h264 --crf 18");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return test::probe_video(video, all);
}

// Waits until `dir` holds at least `count` frame PNGs (checking every one seen is complete), or
// the process ends. Returns false if a visible frame was ever unreadable.
bool wait_for_frames(const std::filesystem::path& dir, std::size_t count, pid_t pid, int width, int height) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (std::chrono::steady_clock::now() < deadline) {
    if (std::filesystem::is_directory(dir)) {
      const auto names = frame_names(dir, ".png");
      for (const auto& n : names)
        if (!readable_png(dir / n, width, height)) return false;
      if (names.size() >= count) return true;
    }
    int status = 0;
    if (::waitpid(pid, &status, WNOHANG) == pid) return true;  // finished already (a very fast machine)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

const std::string kTour = "--frame-count 12 --width 96 --height 72 --spp 2";

TEST(RenderCommand, ThreeUnevenChunksInSeparateProcessesGiveTheBytesOfOneRun) {
  MESHTOUR_SKIP_UNDER_SANITIZERS("bytes equal across processes; chunked renders run under the sanitizers in lighter tests");
  const auto dir = test::scratch_dir();
  // One run of every frame, and the same tour in three uneven chunks, each its own process.
  auto r = run_meshtour("render --out-dir " + test::shell_quoted(dir / "one") + " " + kTour + " --format png+exr --progress none");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* chunk : {"0-1", "2-8", "9-11"}) {
    r = run_meshtour("render --out-dir " + test::shell_quoted(dir / "chunks") + " " + kTour + " --format png+exr --progress none --frames " + chunk);
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  expect_same_frames(dir / "one", dir / "chunks", 25);  // 12 PNG + 12 EXR + manifest
  // `tour` is the same pipeline: its frames are the same bytes too.
  r = run_meshtour("tour -o " + test::shell_quoted(dir / "tour.mp4") + " --frames 12 --width 96 --height 72 --spp 2 --frames-dir " +
                   test::shell_quoted(dir / "tour") + " --format png+exr --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  expect_same_frames(dir / "one", dir / "tour", 25);

  // The videos of both directories decode to the same frames, and the frames differ from each
  // other (a moving camera), so the comparison can tell frames apart.
  const auto one = encode_and_decode(dir / "one", dir / "one.mp4", 12);
  const auto chunks = encode_and_decode(dir / "chunks", dir / "chunks.mp4", 12);
  ASSERT_EQ(one.decoded_frames, 12);
  ASSERT_EQ(chunks.decoded_frames, 12);
  for (int k = 0; k < 12; ++k) EXPECT_TRUE(one.rgb_frames[k] == chunks.rgb_frames[k]) << "decoded frame " << k;
  EXPECT_FALSE(one.rgb_frames[0] == one.rgb_frames[6]);
}

TEST(RenderCommand, KilledRenderResumesToTheSameFramesAndNeverShowsAPartialFrame) {
  MESHTOUR_SKIP_UNDER_SANITIZERS("kill and resume, bytes equal to a clean run; resume runs under the sanitizers in ResumeSkipsExistingFrames...");
  const auto dir = test::scratch_dir();
  const std::string tour = "--frame-count 24 --width 160 --height 120 --spp 8";
  const std::vector<std::string> args = {"render", "--out-dir", (dir / "killed").string(), "--frame-count", "24", "--width", "160",
                                         "--height", "120", "--spp", "8", "--threads", "1", "--progress", "none"};
  const pid_t pid = test::spawn_meshtour(args, dir / "killed.log");
  ASSERT_GT(pid, 0);
  // Every frame that ever appears is complete, also while the render writes the next ones.
  const bool complete = wait_for_frames(dir / "killed", 2, pid, 160, 120);
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  EXPECT_TRUE(complete) << "a frame under its final name was not a complete image";
  ASSERT_TRUE(WIFSIGNALED(status)) << "the render finished before it was killed; make it longer";
  const auto names = frame_names(dir / "killed", ".png");
  ASSERT_GE(names.size(), 2u);
  ASSERT_LT(names.size(), 24u);
  for (const auto& n : names) EXPECT_TRUE(readable_png(dir / "killed" / n, 160, 120)) << n;

  // Re-running completes the set; the result is the bytes of a clean run. (A temporary file of
  // the killed process may stay behind under its hidden name; it is not a frame.)
  auto r = run_meshtour("render --out-dir " + test::shell_quoted(dir / "killed") + " " + tour + " --progress none");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_meshtour("render --out-dir " + test::shell_quoted(dir / "clean") + " " + tour + " --progress none");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_EQ(frame_names(dir / "killed", ".png").size(), 24u);
  for (const auto& n : frame_names(dir / "clean", ".png"))
    EXPECT_TRUE(test::file_bytes(dir / "killed" / n) == test::file_bytes(dir / "clean" / n)) << n;
}

TEST(RenderCommand, SigtermStopsAfterTheCurrentFrameWithoutTemporaries) {
  const auto dir = test::scratch_dir();
  const pid_t pid = test::spawn_meshtour({"render", "--out-dir", (dir / "f").string(), "--frame-count", "24", "--width", "160", "--height",
                                    "120", "--spp", "8", "--threads", "1", "--format", "png+exr", "--progress", "none"},
                                   dir / "log.txt");
  ASSERT_GT(pid, 0);
  wait_for_frames(dir / "f", 1, pid, 160, 120);
  ::kill(pid, SIGTERM);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status)) << "the render did not exit by itself after SIGTERM";
  EXPECT_EQ(WEXITSTATUS(status), 130) << test::file_bytes(dir / "log.txt");
  EXPECT_NE(test::file_bytes(dir / "log.txt").find("interrupted"), std::string::npos);
  const auto files = files_of(dir / "f");
  for (const auto& [name, path] : files) EXPECT_NE(name[0], '.') << "temporary file left: " << name;
  const auto png = frame_names(dir / "f", ".png"), exr = frame_names(dir / "f", ".exr");
  EXPECT_LT(png.size(), 24u);
  EXPECT_EQ(png.size(), exr.size()) << "a frame was stopped between its PNG and its EXR";
}

TEST(RenderCommand, ResumeSkipsExistingFramesAndRendersOnlyMissingOnes) {
  const auto dir = test::scratch_dir();
  auto r = run_meshtour("render --out-dir " + test::shell_quoted(dir) + " " + kTour + " --progress none");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  struct stat before[12];
  for (int k = 0; k < 12; ++k) ASSERT_EQ(::stat((dir / frame_names(dir, ".png")[k]).c_str(), &before[k]), 0);

  // Nothing to do: no frame is touched.
  r = run_meshtour("render --out-dir " + test::shell_quoted(dir) + " " + kTour + " --progress json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("0 to render, 12 already there"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("{\"event\":\"summary\",\"what\":\"frame\",\"done\":0,\"total\":0,\"skipped\":12,"), std::string::npos) << r.output;

  // Two frames lost: exactly those are rendered again (one JSON line each), the rest untouched.
  std::filesystem::remove(dir / "frame_000003.png");
  std::filesystem::remove(dir / "frame_000007.png");
  r = run_meshtour("render --out-dir " + test::shell_quoted(dir) + " " + kTour + " --progress json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::vector<int> rendered;
  std::vector<std::string> stages;  // each announced as it starts, so a log shows where a task stopped
  std::istringstream lines(r.output);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("{", 0) != 0) continue;
    const auto j = nlohmann::json::parse(line);
    if (j["event"] == "stage") {
      stages.push_back(j["stage"]);
    } else if (j["event"] == "frame") {
      rendered.push_back(j["frame"].get<int>());
      EXPECT_GT(j["seconds"].get<double>(), 0.0);
      EXPECT_EQ(j["total"].get<int>(), 2);
    } else {
      EXPECT_EQ(j["event"], "summary");
      EXPECT_EQ(j["done"].get<int>(), 2);
      EXPECT_EQ(j["skipped"].get<int>(), 10);
    }
  }
  EXPECT_EQ(rendered, (std::vector<int>{3, 7}));
  EXPECT_EQ(stages, (std::vector<std::string>{"check", "load", "bvh", "path", "shading", "render"}));
  for (int k = 0; k < 12; ++k) {
    if (k == 3 || k == 7) continue;
    struct stat after {};
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06d.png", k);
    ASSERT_EQ(::stat((dir / name).c_str(), &after), 0);
    EXPECT_EQ(after.st_ino, before[k].st_ino) << name;
    EXPECT_EQ(after.st_mtim.tv_nsec, before[k].st_mtim.tv_nsec) << name;
    EXPECT_EQ(after.st_mtim.tv_sec, before[k].st_mtim.tv_sec) << name;
  }
}

TEST(RenderCommand, RefusesToMixAnotherTourIntoTheSameDirectory) {
  const auto dir = test::scratch_dir();
  auto r = run_meshtour("render --out-dir " + test::shell_quoted(dir) + " " + kTour + " --frames 0 --progress none");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_meshtour("render --out-dir " + test::shell_quoted(dir) + " --frame-count 12 --width 64 --height 72 --spp 2 --frames 1 --progress none");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("holds another tour"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "frame_000001.png"));
  r = run_meshtour("render --out-dir " + test::shell_quoted(dir) + " " + kTour + " --frames 5-x");
  EXPECT_EQ(r.exit_code, 2) << r.output;
}

// Writes `mesh` as an OBJ file.
void write_obj(const TriangleMesh& mesh, const std::filesystem::path& file) {
  std::ofstream out(file);
  out.precision(9);
  for (const auto& p : mesh.positions) out << "v " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  for (const auto& t : mesh.triangles) out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
}

TEST(BatchCommand, ThreeGoodMeshesAndABrokenOneGiveThreeVideosOneFailureAndExitCode5) {
  const auto dir = test::scratch_dir();
  write_obj(test_meshes::icosphere(2), dir / "ball.obj");
  write_obj(test_meshes::torus(0.3, 0.1, 48, 16), dir / "ring.obj");
  write_obj(test_meshes::open_cylinder(0.2, 0.8, 32, 8), dir / "tube.obj");
  std::ofstream(dir / "broken.ply") << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n0.5\n";
  std::ofstream(dir / "catalogue.csv") << "mesh,up,output,preset,path\n"
                                          "ball.obj,y,,studio,turntable\n"
                                          "broken.ply,y,broken.mp4,plain,turntable\n"
                                          "ring.obj,z,ring-video.mp4,plain,turntable\n"
                                          "tube.obj,y,,,turntable\n";
  const std::string cmd = "batch " + test::shell_quoted(dir / "catalogue.csv") + " --out-dir " + test::shell_quoted(dir / "videos") +
                          " --frames 6 --width 64 --height 48 --spp 1 --progress none";
  auto r = run_meshtour(cmd);
  EXPECT_EQ(r.exit_code, 5) << r.output;
  EXPECT_NE(r.output.find("4 items: 3 rendered, 0 skipped (video already there), 1 failed"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("FAILED"), std::string::npos) << r.output;
  for (const char* video : {"ball.mp4", "ring-video.mp4", "tube.mp4"}) {
    ASSERT_TRUE(std::filesystem::exists(dir / "videos" / video)) << video;
    const auto probe = test::probe_video(dir / "videos" / video);
    EXPECT_EQ(probe.decoded_frames, 6) << video;
    EXPECT_EQ(probe.width, 64) << video;
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "videos" / "broken.mp4"));
  for (const auto& [name, path] : files_of(dir / "videos")) {
    if (name == kFolderLockFile) continue;
    EXPECT_NE(name[0], '.') << "temporary left: " << name;
  }

  auto summary = nlohmann::json::parse(test::file_bytes(dir / "videos" / "batch-summary.json"));
  EXPECT_EQ(summary["rendered"], 3);
  EXPECT_EQ(summary["failed"], 1);
  ASSERT_EQ(summary["items"].size(), 4u);
  EXPECT_EQ(summary["items"][1]["status"], "failed");
  EXPECT_NE(summary["items"][1]["error"].get<std::string>().find("broken.ply"), std::string::npos) << summary.dump(2);
  EXPECT_EQ(summary["items"][2]["output"], "ring-video.mp4");

  // A re-run renders nothing new: the videos are untouched, the broken item fails again.
  struct stat before {}, after {};
  ASSERT_EQ(::stat((dir / "videos" / "ball.mp4").c_str(), &before), 0);
  r = run_meshtour(cmd);
  EXPECT_EQ(r.exit_code, 5) << r.output;
  EXPECT_NE(r.output.find("4 items: 0 rendered, 3 skipped (video already there), 1 failed"), std::string::npos) << r.output;
  ASSERT_EQ(::stat((dir / "videos" / "ball.mp4").c_str(), &after), 0);
  EXPECT_EQ(after.st_ino, before.st_ino);
  EXPECT_EQ(after.st_mtim.tv_nsec, before.st_mtim.tv_nsec);
  summary = nlohmann::json::parse(test::file_bytes(dir / "videos" / "batch-summary.json"));
  EXPECT_EQ(summary["skipped"], 3);
  EXPECT_EQ(summary["rendered"], 0);
}

TEST(BatchCommand, JsonManifestAndBadValuesFailOnlyTheirItem) {
  const auto dir = test::scratch_dir();
  write_obj(test_meshes::icosphere(1), dir / "ball.obj");
  std::ofstream(dir / "m.json") << R"({"items": [{"mesh": "ball.obj", "output": "a.mp4", "path": "turntable", "frames": 3},
                                                {"mesh": "ball.obj", "output": "b.mp4", "up": "w"},
                                                {"mesh": "ball.obj", "output": "a.mp4"}]})";
  const auto r = run_meshtour("batch " + test::shell_quoted(dir / "m.json") + " --out-dir " + test::shell_quoted(dir / "v") + " --width 32 --height 24 --spp 1 --progress none");
  EXPECT_EQ(r.exit_code, 5) << r.output;
  EXPECT_EQ(test::probe_video(dir / "v" / "a.mp4").decoded_frames, 3);
  EXPECT_NE(r.output.find("up 'w' is not one of"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("already used by item 0"), std::string::npos) << r.output;
  // Not a manifest at all: exit 2 with the reason.
  std::ofstream(dir / "bad.csv") << "model,up\nball.obj,y\n";
  const auto bad = run_meshtour("batch " + test::shell_quoted(dir / "bad.csv") + " --out-dir " + test::shell_quoted(dir / "v"));
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("unknown column 'model'"), std::string::npos) << bad.output;
}

TEST(FarmSlurm, WritesScriptsWhoseArrayTaskRendersItsChunk) {
  const auto dir = test::scratch_dir();
  const auto out = dir / "farm";
  // The path is computed once into a path file (for every mode: the default one below).
  auto r = run_meshtour("farm slurm --out-dir " + test::shell_quoted(out) + " --path paper --frames 12 --width 64 --height 48 --spp 1 --chunk-size 5 --cpus-per-task 1 --partition debug --time 10");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string render = test::file_bytes(out / "render.sbatch");
  EXPECT_NE(render.find("#SBATCH --array=0-2\n"), std::string::npos) << render;  // 12 frames, chunks of 5
  EXPECT_NE(render.find("#SBATCH --partition=debug\n"), std::string::npos) << render;
  EXPECT_NE(render.find("#SBATCH --time=10\n"), std::string::npos) << render;
  EXPECT_NE(render.find("'" + test::meshtour_executable().string() + "' 'render'"), std::string::npos) << render;
  EXPECT_NE(render.find("'--path-file' '" + (out / "path.json").string() + "'"), std::string::npos) << render;
  EXPECT_TRUE(std::filesystem::exists(out / "path.json"));
  const std::string encode = test::file_bytes(out / "encode.sbatch");
  EXPECT_NE(encode.find("'encode' '" + (out / "frames").string() + "' '-o' '" + (out / "meshtour-default.mp4").string() + "' '--codec' 'h264'"),
            std::string::npos) << encode;
  EXPECT_NE(test::file_bytes(out / "submit.sh").find("--dependency=afterok:$render"), std::string::npos);

  // Run the last array task's script as Slurm would: it renders frames 10-11 only (the chunk
  // 10-14 clamped), with the thread count of SLURM_CPUS_PER_TASK.
  r = run_meshtour("--version && SLURM_ARRAY_TASK_ID=2 SLURM_CPUS_PER_TASK=1 bash " + test::shell_quoted(out / "render.sbatch"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("rendering with 1 threads"), std::string::npos) << r.output;
  EXPECT_EQ(frame_names(out / "frames", ".png"), (std::vector<std::string>{"frame_000010.png", "frame_000011.png"}));
  // And they are the frames a single `render` of the whole tour makes (same path, same fov).
  r = run_meshtour("render --out-dir " + test::shell_quoted(dir / "one") + " --path paper --frame-count 12 --width 64 --height 48 --spp 1 --progress none");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(test::file_bytes(out / "frames" / "frame_000011.png") == test::file_bytes(dir / "one" / "frame_000011.png"));

  // The default mode (feature orbit) too, and the turntable: the tasks read the file.
  for (const std::string mode : {"feature-orbit", "turntable"}) {
    r = run_meshtour("farm slurm --out-dir " + test::shell_quoted(dir / mode) + " --path " + mode + " --frames 12 --width 64 --height 48 --spp 1 --chunk-size 5");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(test::file_bytes(dir / mode / "render.sbatch").find("'--path-file' '" + (dir / mode / "path.json").string() + "'"), std::string::npos);
    EXPECT_EQ(nlohmann::json::parse(test::file_bytes(dir / mode / "path.json"))["mode"], mode);
  }
}

int count_of(const std::string& text, const std::string& word) {
  int n = 0;
  for (auto at = text.find(word); at != std::string::npos; at = text.find(word, at + word.size())) ++n;
  return n;
}

// The instruction sets this CPU runs the tile kernel in (MESHTOUR_TILE_KERNEL names them).
std::vector<std::string> kernels_of_this_cpu() {
  std::vector<std::string> kernels = {"baseline"};
  if (cpu_runs(InstructionSet::x86_64_v3)) kernels.push_back("x86-64-v3");
  if (cpu_runs(InstructionSet::x86_64_v4)) kernels.push_back("x86-64-v4");
  return kernels;
}

// A farm job of the default path (the feature orbit): the path search runs once, at submission
// (counted in the output of every process), the array tasks, each forced onto another
// instruction set, render frames of that one path, and the encode job's video is the bytes of
// `tour`'s.
TEST(FarmSlurm, DefaultPathIsSearchedOnceAndTasksOnEveryKernelGiveTheToursVideo) {
  MESHTOUR_SKIP_UNDER_SANITIZERS("the same tasks on three instruction sets, bytes compared; the Release pass checks them");
  const auto dir = test::scratch_dir();
  write_obj(test_meshes::bumpy_sphere(3), dir / "bumpy.obj");
  const std::string tour = test::shell_quoted(dir / "bumpy.obj") + " --frames 6 --width 64 --height 36 --spp 1 --crf 18";
  auto r = run_meshtour("farm slurm --out-dir " + test::shell_quoted(dir / "farm") + " " + tour + " --chunk-size 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  int searches = count_of(r.output, "path search:");
  EXPECT_EQ(searches, 1) << "submission: " << r.output;
  EXPECT_EQ(nlohmann::json::parse(test::file_bytes(dir / "farm" / "path.json"))["mode"], "feature-orbit");
  const std::vector<std::string> kernels = kernels_of_this_cpu();
  for (int task = 0; task < 3; ++task) {
    const std::string& kernel = kernels[static_cast<std::size_t>(task) % kernels.size()];
    r = run_meshtour("--version && MESHTOUR_TILE_KERNEL=" + kernel + " SLURM_ARRAY_TASK_ID=" + std::to_string(task) +
                     " SLURM_CPUS_PER_TASK=1 bash " + test::shell_quoted(dir / "farm" / "render.sbatch"));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    searches += count_of(r.output, "path search:");
    EXPECT_EQ(count_of(r.output, "\"event\":\"frame\""), 2) << "task " << task << " (" << kernel << "): " << r.output;
  }
  EXPECT_EQ(searches, 1) << "a render task searched the path again";
  r = run_meshtour("--version && bash " + test::shell_quoted(dir / "farm" / "encode.sbatch"));
  ASSERT_EQ(r.exit_code, 0) << r.output;

  r = run_meshtour("tour " + tour + " -o " + test::shell_quoted(dir / "tour.mp4") + " --frames-dir " + test::shell_quoted(dir / "tour") + " --progress none");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(count_of(r.output, "path search:"), 1) << r.output;  // the count is seen where a search runs
  for (int k = 0; k < 6; ++k) {
    const std::string frame = "frame_00000" + std::to_string(k) + ".png";
    EXPECT_TRUE(test::file_bytes(dir / "farm" / "frames" / frame) == test::file_bytes(dir / "tour" / frame)) << frame;
  }
  const std::string farm_video = test::file_bytes(dir / "farm" / "bumpy.mp4"), tour_video = test::file_bytes(dir / "tour.mp4");
  EXPECT_FALSE(farm_video.empty());
  EXPECT_TRUE(farm_video == tour_video) << "the farm's video (" << farm_video.size() << " bytes) is not tour's (" << tour_video.size() << " bytes)";
}

// Every option that changes the path or the pixels reaches the array tasks: with non-default
// path-search and look options, the tasks render the frames `tour` renders with the same options
// (and those differ from the default options' frames, so the comparison can tell).
TEST(FarmSlurm, TasksRenderTheTourOfNonDefaultPathAndLookOptions) {
  MESHTOUR_SKIP_UNDER_SANITIZERS("bytes equal to tour for non-default options; the farm scripts run under the sanitizers in lighter tests");
  const auto dir = test::scratch_dir();
  write_obj(test_meshes::bumpy_sphere(3), dir / "bumpy.obj");  // small, with features the path search sees
  const std::string tour = test::shell_quoted(dir / "bumpy.obj") + " --frames 4 --width 64 --height 48 --spp 1";
  const std::string custom = " --smoothing none --tolerance 0.004 --seed-order index --preset plain --exposure 0.5";
  auto r = run_meshtour("farm slurm --out-dir " + test::shell_quoted(dir / "farm") + " " + tour + custom + " --chunk-size 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* task : {"0", "1"}) {
    r = run_meshtour("--version && SLURM_ARRAY_TASK_ID=" + std::string(task) + " SLURM_CPUS_PER_TASK=1 bash " +
                     test::shell_quoted(dir / "farm" / "render.sbatch"));
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  r = run_meshtour("tour -o " + test::shell_quoted(dir / "t.mp4") + " " + tour + custom + " --frames-dir " + test::shell_quoted(dir / "tour") + " --progress none");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_meshtour("tour -o " + test::shell_quoted(dir / "d.mp4") + " " + tour + " --preset plain --exposure 0.5 --frames-dir " + test::shell_quoted(dir / "default") +
                   " --progress none");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  bool differs_from_default = false;
  for (const char* frame : {"frame_000000.png", "frame_000001.png", "frame_000002.png", "frame_000003.png"}) {
    EXPECT_TRUE(test::file_bytes(dir / "farm" / "frames" / frame) == test::file_bytes(dir / "tour" / frame)) << frame;
    differs_from_default = differs_from_default || test::file_bytes(dir / "tour" / frame) != test::file_bytes(dir / "default" / frame);
  }
  EXPECT_TRUE(differs_from_default) << "the path options changed no frame; the test cannot tell forwarded options from dropped ones";
}

// Each failed item says how `tour` would have ended: the exit class and code (input 2, io 3, ...),
// in the summary and on the contact sheet; an item whose estimate is over --max-memory fails
// before it allocates, the others are made; every item records the process's peak memory.
TEST(BatchCommand, FailedItemsCarryTheirExitClassAndMaxMemoryRefusesOnlyTheBigItem) {
  const auto dir = test::scratch_dir();
  write_obj(test_meshes::icosphere(1), dir / "ball.obj");
  write_obj(test_meshes::uv_sphere(1.0, 400, 200), dir / "big.obj");  // 160k faces: ~340 MiB estimated
  std::ofstream(dir / "broken.ply") << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n0.5\n";
  std::ofstream(dir / "textured.obj") << "mtllib t.mtl\nusemtl skin\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n";
  std::ofstream(dir / "t.mtl") << "newmtl skin\nmap_Kd gone.png\n";
  std::ofstream(dir / "m.csv") << "mesh,output\nball.obj,ball.mp4\nbig.obj,big.mp4\nbroken.ply,broken.mp4\ntextured.obj,textured.mp4\n";
  const auto r = run_meshtour("batch " + test::shell_quoted(dir / "m.csv") + " --out-dir " + test::shell_quoted(dir / "v") +
                              " --web --max-memory 300M --frames 3 --width 32 --height 24 --spp 1 --progress none");
  EXPECT_EQ(r.exit_code, 5) << r.output;
  const auto summary = nlohmann::json::parse(test::file_bytes(dir / "v" / "batch-summary.json"));
  ASSERT_EQ(summary["items"].size(), 4u) << summary.dump(2);
  const auto& items = summary["items"];
  EXPECT_EQ(items[0]["status"], "rendered") << summary.dump(2);
  EXPECT_FALSE(items[0].contains("exit_class"));
  EXPECT_GT(items[0]["peak_resident_bytes"].get<double>(), 1e6);
  EXPECT_EQ(items[1]["status"], "failed");
  EXPECT_NE(items[1]["error"].get<std::string>().find("--max-memory 300M"), std::string::npos) << items[1].dump();
  EXPECT_EQ(items[1]["exit_class"], "input");
  EXPECT_EQ(items[1]["exit_code"], 2);
  EXPECT_EQ(items[2]["exit_class"], "input");
  EXPECT_EQ(items[3]["exit_class"], "io") << items[3].dump();
  EXPECT_EQ(items[3]["exit_code"], 3);
  // The same classes as `tour` of the same files exits with.
  const auto tour_of = [&](const char* mesh) {
    return run_meshtour("tour " + test::shell_quoted(dir / mesh) + " -o " + test::shell_quoted(dir / "t.mp4") +
                        " --max-memory 300M --frames 3 --width 32 --height 24 --spp 1 -q").exit_code;
  };
  EXPECT_EQ(tour_of("big.obj"), 2);
  EXPECT_EQ(tour_of("textured.obj"), 3);
  const std::string page = test::file_bytes(dir / "v" / "index.html");
  EXPECT_NE(page.find("io error: "), std::string::npos) << page;
  EXPECT_NE(page.find("input error: "), std::string::npos);
}

// Two runs of one job on one folder at once (two operators, a re-submitted array): each item is
// made once, by whichever run takes its lock first; the other finds it done.
TEST(BatchCommand, TwoRunsOnOneFolderAtOnceMakeEachItemOnce) {
  const auto dir = test::scratch_dir();
  std::ofstream manifest(dir / "m.csv");
  manifest << "mesh,output\n";
  const auto stem = [](int i) { return std::string(1, 's') + std::to_string(i); };  // not "s" + ...: a GCC 12 -Wrestrict false positive
  for (int i = 0; i < 4; ++i) {
    write_obj(test_meshes::bumpy_sphere(2, 0.05, 10 + i), dir / (stem(i) + ".obj"));
    manifest << stem(i) << ".obj," << stem(i) << ".mp4\n";
  }
  manifest.close();
  const std::string cmd = "batch " + test::shell_quoted(dir / "m.csv") + " --out-dir " + test::shell_quoted(dir / "v") +
                          " --path turntable --frames 8 --width 64 --height 48 --spp 4 --progress none";
  test::CommandResult a, b;
  std::thread first([&] { a = run_meshtour(cmd); });
  std::thread second([&] { b = run_meshtour(cmd); });
  first.join();
  second.join();
  EXPECT_EQ(a.exit_code, 0) << a.output;
  EXPECT_EQ(b.exit_code, 0) << b.output;
  const auto starts = [](const std::string& text) {  // "== item N: MESH -> DIR/NAME.mp4" as an item is begun
    std::istringstream lines(text);
    int n = 0;
    for (std::string line; std::getline(lines, line);) n += line.starts_with("== item ") && line.find(" -> ") != std::string::npos;
    return n;
  };
  EXPECT_EQ(starts(a.output) + starts(b.output), 4) << a.output << "\n----\n" << b.output;
  for (int i = 0; i < 4; ++i) EXPECT_EQ(test::probe_video(dir / "v" / (stem(i) + ".mp4")).decoded_frames, 8);
}

// What a killed run (SIGKILL: no clean-up) leaves, hidden temporaries of an item's outputs and of
// the summary, the next run removes once it holds their locks.
TEST(BatchCommand, TemporariesOfAKilledRunAreRemovedByTheNextRun) {
  const auto dir = test::scratch_dir();
  write_obj(test_meshes::icosphere(1), dir / "ball.obj");
  std::ofstream(dir / "m.csv") << "mesh,output\nball.obj,ball.mp4\n";
  std::filesystem::create_directories(dir / "v");
  const std::vector<std::string> left = {".ball.mp4.partial-999999.mp4", ".ball.poster.png.partial-999999.png",
                                         ".batch-summary.json.partial-999999.json"};
  for (const auto& name : left) std::ofstream(dir / "v" / name) << "half";
  std::ofstream(dir / "v" / ".other.mp4.partial-999999.mp4") << "not this job's item";
  const auto r = run_meshtour("batch " + test::shell_quoted(dir / "m.csv") + " --out-dir " + test::shell_quoted(dir / "v") +
                              " --path turntable --frames 3 --width 32 --height 24 --spp 1 --progress none");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const auto& name : left) EXPECT_FALSE(std::filesystem::exists(dir / "v" / name)) << name;
  EXPECT_TRUE(std::filesystem::exists(dir / "v" / ".other.mp4.partial-999999.mp4"));
  EXPECT_TRUE(std::filesystem::exists(dir / "v" / "ball.mp4"));
}

TEST(FarmSlurm, MaxMemoryIsEveryTasksBudgetAndSlurmsReservation) {
  const auto dir = test::scratch_dir();
  std::ofstream(dir / "m.csv") << "mesh,output\na.obj,a.mp4\n";
  const auto r = run_meshtour("farm slurm --manifest " + test::shell_quoted(dir / "m.csv") + " --out-dir " +
                              test::shell_quoted(dir / "farm") + " --max-memory 1536M");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string script = test::file_bytes(dir / "farm" / "batch.sbatch");
  EXPECT_NE(script.find("#SBATCH --mem=1536M\n"), std::string::npos) << script;
  EXPECT_NE(script.find("'--max-memory' '1536M'"), std::string::npos) << script;
}

TEST(FarmSlurm, ManifestGivesOneArrayTaskPerItem) {
  const auto dir = test::scratch_dir();
  std::ofstream(dir / "m.csv") << "mesh,output\na.obj,a.mp4\nb.obj,b.mp4\nc.obj,c.mp4\n";
  const auto r = run_meshtour("farm slurm --manifest " + test::shell_quoted(dir / "m.csv") + " --out-dir " + test::shell_quoted(dir / "farm") + " --frames 6");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string script = test::file_bytes(dir / "farm" / "batch.sbatch");
  EXPECT_NE(script.find("#SBATCH --array=0-2\n"), std::string::npos) << script;
  EXPECT_NE(script.find("'batch' '" + (dir / "m.csv").string() + "'"), std::string::npos) << script;
  EXPECT_NE(script.find("--item \"$SLURM_ARRAY_TASK_ID\""), std::string::npos) << script;
  EXPECT_NE(script.find("'--frames' '6'"), std::string::npos) << script;
}

// --web: per item an MP4, a WebM, the poster and the glTF camera, and one contact sheet listing
// every item, the failed one with its error; captions come from the manifest.
TEST(BatchCommand, WebWritesBothVideosThePosterAndAContactSheet) {
  const auto dir = test::scratch_dir();
  write_obj(test_meshes::icosphere(2), dir / "ball.obj");
  std::ofstream(dir / "broken.ply") << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n0.5\n";
  std::ofstream(dir / "m.csv") << "mesh,caption,path,poster\n"
                                  "ball.obj,Ball — Kugel <1>,turntable,\n"
                                  "broken.ply,Broken,turntable,\n"
                                  "ball.obj,Second ball,turntable,second.png\n";
  // (the third item would reuse ball.mp4: it fails with that reason, and the page shows it)
  const auto r = run_meshtour("batch " + test::shell_quoted(dir / "m.csv") + " --out-dir " + test::shell_quoted(dir / "web") +
                              " --web --frames 6 --width 160 --height 96 --spp 1 -q");
  EXPECT_EQ(r.exit_code, 5) << r.output;
  for (const char* f : {"ball.mp4", "ball.webm", "ball.poster.png", "ball.gltf", "index.html", "batch-summary.json"})
    EXPECT_TRUE(std::filesystem::exists(dir / "web" / f)) << f;
  EXPECT_EQ(test::probe_video(dir / "web" / "ball.webm").codec, "vp9");
  const auto summary = nlohmann::json::parse(test::file_bytes(dir / "web" / "batch-summary.json"));
  EXPECT_EQ(summary["items"][0]["poster"], "ball.poster.png");
  EXPECT_EQ(summary["items"][0]["webm"], "ball.webm");
  EXPECT_EQ(summary["items"][0]["faces"], 320);
  EXPECT_EQ(summary["items"][0]["caption"], "Ball — Kugel <1>");
  const std::string page = test::file_bytes(dir / "web" / "index.html");
  EXPECT_NE(page.find("Ball — Kugel &lt;1&gt;"), std::string::npos) << "caption missing or not escaped";
  EXPECT_NE(page.find("<source src=\"ball.webm\" type=\"video/webm\"><source src=\"ball.mp4\" type=\"video/mp4\">"),
            std::string::npos);
  EXPECT_NE(page.find("poster=\"ball.poster.png\""), std::string::npos);
  EXPECT_NE(page.find("preload=\"none\""), std::string::npos);
  EXPECT_NE(page.find("broken.ply"), std::string::npos);
  EXPECT_NE(page.find("already used by item 0"), std::string::npos) << "the failed item's error line";
  EXPECT_EQ(page.find("http"), std::string::npos) << "the page must not reach the network";
}

TEST(FarmSlurm, ManifestWithWebAddsTheContactSheetJob) {
  const auto dir = test::scratch_dir();
  std::ofstream(dir / "m.csv") << "mesh,caption\na.obj,A\nb.obj,B\n";
  const auto r = run_meshtour("farm slurm --manifest " + test::shell_quoted(dir / "m.csv") + " --out-dir " + test::shell_quoted(dir / "farm") + " --web");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(test::file_bytes(dir / "farm" / "batch.sbatch").find("'--web'"), std::string::npos);
  const std::string page = test::file_bytes(dir / "farm" / "page.sbatch");
  EXPECT_NE(page.find("'--web' '--page-only'"), std::string::npos) << page;
  EXPECT_NE(test::file_bytes(dir / "farm" / "submit.sh").find("--dependency=afterany:"), std::string::npos);
}

// The render tasks write clean frames; the encode job captions them and writes the poster (its
// file named absolutely, as the job runs elsewhere).
TEST(FarmSlurm, CaptionAndPosterGoToTheEncodeJobOnly) {
  const auto dir = test::scratch_dir();
  const auto r = run_meshtour("farm slurm --out-dir " + test::shell_quoted(dir / "farm") + " --frames 6 --width 160 --height 90 --caption 'Ä — 1' --poster p.png");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string render = test::file_bytes(dir / "farm" / "render.sbatch"), encode = test::file_bytes(dir / "farm" / "encode.sbatch");
  EXPECT_EQ(render.find("--caption"), std::string::npos) << render;
  EXPECT_EQ(render.find("--poster"), std::string::npos) << render;
  EXPECT_NE(encode.find("'--caption' 'Ä — 1'"), std::string::npos) << encode;
  EXPECT_NE(encode.find("'--poster' '" + (test::source_dir() / "p.png").string() + "'"), std::string::npos) << encode;
}

// --size reaches the path searched at submission, the frames manifest and every render task (a
// named size, checked without rendering at 1080x1080); --alpha reaches the encode job, whose
// ProRes 4444 video keeps the frames' alpha; what the encode job would refuse is refused at
// submission.
TEST(FarmSlurm, SizeReachesTheTasksAndAlphaTheEncodeJob) {
  const auto dir = test::scratch_dir();
  auto r = run_meshtour("farm slurm --out-dir " + test::shell_quoted(dir / "square") + " --path turntable --frames 4 --size square -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(test::file_bytes(dir / "square" / "render.sbatch").find("'--size' 'square'"), std::string::npos);
  const auto frames = nlohmann::json::parse(test::file_bytes(dir / "square" / "frames" / "meshtour-frames.json"));
  EXPECT_EQ(frames["width"], 1080);
  EXPECT_EQ(frames["height"], 1080);
  EXPECT_EQ(nlohmann::json::parse(test::file_bytes(dir / "square" / "path.json"))["made_for"]["aspect"], "1");
  std::ofstream(dir / "m.csv") << "mesh\na.obj\n";
  r = run_meshtour("farm slurm --manifest " + test::shell_quoted(dir / "m.csv") + " --out-dir " + test::shell_quoted(dir / "batch") + " --size vertical -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(test::file_bytes(dir / "batch" / "batch.sbatch").find("'--size' 'vertical'"), std::string::npos);

  const std::string tour = " --path turntable --frames 4 --width 64 --height 48 --spp 1 --background transparent";
  r = run_meshtour("farm slurm --out-dir " + test::shell_quoted(dir / "alpha") + tour + " --alpha --codec prores --chunk-size 4 -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string render = test::file_bytes(dir / "alpha" / "render.sbatch"), encode = test::file_bytes(dir / "alpha" / "encode.sbatch");
  EXPECT_NE(render.find("'--background' 'transparent'"), std::string::npos) << render;
  EXPECT_EQ(render.find("--alpha"), std::string::npos) << render;
  EXPECT_NE(encode.find("'--codec' 'prores' '--alpha'"), std::string::npos) << encode;
  r = run_meshtour("--version && SLURM_ARRAY_TASK_ID=0 SLURM_CPUS_PER_TASK=1 bash " + test::shell_quoted(dir / "alpha" / "render.sbatch") +
                   " && bash " + test::shell_quoted(dir / "alpha" / "encode.sbatch"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto video = test::probe_video(dir / "alpha" / "meshtour-default.mov", {3});
  EXPECT_NE(video.decoded_pixel_format.find("yuva444p"), std::string::npos) << video.decoded_pixel_format;
  OIIO::ImageBuf frame((dir / "alpha" / "frames" / "frame_000003.png").string());
  ASSERT_TRUE(frame.read(0, 0, true, OIIO::TypeDesc::UINT8));
  ASSERT_EQ(frame.spec().nchannels, 4);
  std::vector<std::uint8_t> png(64 * 48 * 4);
  ASSERT_TRUE(frame.get_pixels(frame.roi(), OIIO::TypeDesc::UINT8, png.data()));
  const auto& rgba = video.rgba_frames.at(0);
  ASSERT_EQ(rgba.size(), png.size());
  double alpha_error = 0, clear = 0;
  for (std::size_t p = 0; p < png.size() / 4; ++p) {
    alpha_error += std::abs(rgba[p * 4 + 3] - png[p * 4 + 3]);
    clear += png[p * 4 + 3] == 0;
  }
  alpha_error /= static_cast<double>(png.size() / 4);
  EXPECT_GT(clear / static_cast<double>(png.size() / 4), 0.3) << "the frame has clear background to keep";
  EXPECT_LT(alpha_error, 0.5) << "the encode job's video lost the frames' alpha";

  struct Refused {
    std::string args, expected;
  };
  for (const Refused& c : {Refused{tour + " --alpha", "h264 (.mp4) cannot carry alpha"},
                           Refused{" --path turntable --frames 4 --alpha --codec vp9", "--alpha needs a transparent background"},
                           Refused{tour + " --alpha --codec ffv1 --format exr", "--alpha encodes the PNG frames"}}) {
    r = run_meshtour("farm slurm --out-dir " + test::shell_quoted(dir / "refused") + c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << c.args << "\n" << r.output;
  }
  r = run_meshtour("farm slurm --manifest " + test::shell_quoted(dir / "m.csv") + " --out-dir " + test::shell_quoted(dir / "refused") +
                   " --background transparent --alpha --codec prores");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("cannot carry alpha"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "refused" / "encode.sbatch"));
}

}  // namespace
}  // namespace meshtour
