// The write order of every output kind (issue 38): core/atomic_file.h writes a file's data under a
// temporary name, fsyncs it, renames it to its final name and fsyncs the directory, so that a
// crash or a killed task leaves either the old file or the whole new one. The real `meshtour`
// runs under tests/write_trace_shim.c (LD_PRELOAD), which records open/fopen, fsync/fdatasync,
// rename and close; write_order_faults() checks the trace for every file the run left.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "core/file_lock.h"
#include "helpers.h"
#include "textured_cube.h"

namespace {

namespace fs = std::filesystem;
using meshtour::test::run_meshtour;


// What is wrong with how each file under `out_dir` was written, per the trace's lines (empty:
// every file was written to a temporary name, fsynced, renamed into place, its folder fsynced).
std::vector<std::string> write_order_faults(const std::vector<std::string>& trace, const fs::path& out_dir) {
  struct Event {
    std::string kind, path, to;  // path: of the fd for fsync; for open, its path; for rename, from
    bool writing = false;
  };
  std::vector<Event> events;
  std::map<int, std::string> fds;
  for (const std::string& line : trace) {
    std::istringstream in(line);
    Event e;
    in >> e.kind;
    if (e.kind == "open") {
      int fd = -1;
      char mode = 'R';
      in >> fd >> mode;
      std::getline(in >> std::ws, e.path);
      e.writing = mode == 'W';
      fds[fd] = e.path;
    } else if (e.kind == "fsync") {
      int fd = -1;
      in >> fd;
      e.path = fds.count(fd) ? fds[fd] : "";
    } else if (e.kind == "close") {
      int fd = -1;
      in >> fd;
      fds.erase(fd);
      continue;
    } else if (e.kind == "rename") {
      std::string rest;
      std::getline(in >> std::ws, rest);
      const auto tab = rest.find('\t');
      e.path = rest.substr(0, tab);
      e.to = tab == std::string::npos ? "" : rest.substr(tab + 1);
    } else {
      continue;
    }
    events.push_back(e);
  }
  std::vector<std::string> faults;
  for (const auto& entry : fs::recursive_directory_iterator(out_dir)) {
    if (!entry.is_regular_file()) continue;
    const std::string file = entry.path().string(), dir = entry.path().parent_path().string();
    const std::string name = entry.path().filename().string();
    if (name == meshtour::kFolderLockFile) continue;  // the batch's item locks (core/file_lock.h): empty, no output
    if (name[0] == '.') {
      faults.push_back(name + ": a temporary file left behind");
      continue;
    }
    std::ptrdiff_t renamed = -1;
    for (std::size_t i = 0; i < events.size(); ++i) {
      if (events[i].kind == "open" && events[i].writing && events[i].path == file)
        faults.push_back(name + ": opened for writing under its final name");
      if (events[i].kind == "rename" && events[i].to == file) renamed = static_cast<std::ptrdiff_t>(i);
    }
    if (renamed < 0) {
      faults.push_back(name + ": never renamed into place");
      continue;
    }
    const std::string temporary = events[static_cast<std::size_t>(renamed)].path;
    std::ptrdiff_t written = -1, synced = -1;
    for (std::ptrdiff_t i = 0; i < renamed; ++i) {
      const Event& e = events[static_cast<std::size_t>(i)];
      if (e.kind == "open" && e.writing && e.path == temporary) written = i;
      if (e.kind == "fsync" && e.path == temporary) synced = i;
    }
    if (written < 0) faults.push_back(name + ": its temporary " + temporary + " was never opened for writing");
    if (synced < 0 || synced < written) faults.push_back(name + ": its temporary was not fsynced before the rename");
    bool dir_synced = false;
    for (std::size_t i = static_cast<std::size_t>(renamed) + 1; i < events.size(); ++i)
      dir_synced = dir_synced || (events[i].kind == "fsync" && events[i].path == dir);
    if (!dir_synced) faults.push_back(name + ": its folder was not fsynced after the rename");
  }
  return faults;
}

std::vector<std::string> read_lines(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string out;
  for (const auto& l : lines) out += l + "\n";
  return out;
}

// The checker on recorded traces: the good order passes; each step removed is caught.
TEST(WriteOrderChecker, FindsEachMissingStep) {
  const fs::path dir = meshtour::test::scratch_dir();
  std::ofstream(dir / "v.mp4") << "data";
  const std::string d = dir.string(), t = d + "/.v.mp4.partial-1.mp4", f = d + "/v.mp4";
  const std::vector<std::string> open_tmp = {"open 5 W " + t, "write 5", "close 5"}, sync_tmp = {"open 5 R " + t, "fsync 5", "close 5"},
                                 rename = {"rename " + t + "\t" + f}, sync_dir = {"open 6 R " + d, "fsync 6", "close 6"};
  const auto trace = [](std::initializer_list<std::vector<std::string>> parts) {
    std::vector<std::string> out;
    for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
    return out;
  };
  EXPECT_TRUE(write_order_faults(trace({open_tmp, sync_tmp, rename, sync_dir}), dir).empty());
  const auto one = [&](const std::vector<std::string>& t, const std::string& words) {
    const auto faults = write_order_faults(t, dir);
    ASSERT_EQ(faults.size(), 1u) << joined(faults);
    EXPECT_NE(faults[0].find(words), std::string::npos) << faults[0];
  };
  one(trace({open_tmp, rename, sync_dir}), "not fsynced before the rename");
  one(trace({sync_tmp, open_tmp, rename, sync_dir}), "not fsynced before the rename");  // synced before the data
  one(trace({open_tmp, sync_tmp, rename}), "folder was not fsynced");
  one(trace({sync_dir, open_tmp, sync_tmp, rename}), "folder was not fsynced");  // folder synced before the rename
  const auto direct = joined(write_order_faults(trace({{"open 5 W " + f, "write 5", "fsync 5", "close 5"}, sync_dir}), dir));
  EXPECT_NE(direct.find("opened for writing under its final name"), std::string::npos) << direct;
  EXPECT_NE(direct.find("never renamed into place"), std::string::npos) << direct;
  std::ofstream(dir / ".w.png.partial-1.png") << "x";
  EXPECT_EQ(write_order_faults(trace({open_tmp, sync_tmp, rename, sync_dir}), dir).size(), 1u);
}

class WriteOrder : public ::testing::Test {
protected:
  void SetUp() override {
#ifdef MESHTOUR_SANITIZED_BUILD
    GTEST_SKIP() << "the sanitizer runtime must be the first library loaded: no LD_PRELOAD shim";
#endif
    dir_ = meshtour::test::scratch_dir();
    meshtour::test::write_textured_cube(dir_);
    std::ofstream(dir_ / "m.csv") << "mesh,caption,path\ncube.obj,Cube,turntable\n";
  }

  // Runs `args` under the shim; returns the trace's lines.
  std::vector<std::string> traced(const std::string& args, bool drop_fsync = false) {
    const fs::path trace = dir_ / ("trace-" + std::to_string(runs_++) + ".txt");
    const auto r = run_meshtour("--version >/dev/null && MESHTOUR_WRITE_TRACE=" + meshtour::test::shell_quoted(trace) +
                                (drop_fsync ? " MESHTOUR_WRITE_TRACE_DROP_FSYNC=1" : "") + " LD_PRELOAD=" + meshtour::test::shell_quoted(MESHTOUR_WRITE_TRACE_SHIM) +
                                " " + meshtour::test::shell_quoted(meshtour::test::meshtour_executable()) + " " + args);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return read_lines(trace);
  }

  // The tour's outputs: frames, frames manifest, video, poster, camera exports.
  std::string tour_args(const fs::path& out) const {
    fs::create_directories(out);
    return "tour " + meshtour::test::shell_quoted(dir_ / "cube.obj") + " --width 64 --height 36 --frames 2 --spp 1 --path turntable --threads 1 -q --frames-dir " +
           meshtour::test::shell_quoted(out / "frames") + " -o " + meshtour::test::shell_quoted(out / "v.mp4") + " --poster " + meshtour::test::shell_quoted(out / "poster.png") + " --camera-frames " +
           meshtour::test::shell_quoted(out / "camera.json") + " --gltf " + meshtour::test::shell_quoted(out / "camera.gltf");
  }

  fs::path dir_;
  int runs_ = 0;
};

TEST_F(WriteOrder, EveryOutputKindIsWrittenAtomically) {
  const fs::path tour = dir_ / "tour", path = dir_ / "path", batch = dir_ / "batch";
  const auto tour_trace = traced(tour_args(tour));
  fs::create_directories(path);
  const auto path_trace = traced("path " + meshtour::test::shell_quoted(dir_ / "cube.obj") + " --path paper --frames 2 --threads 1 -q -o " + meshtour::test::shell_quoted(path / "p.path.json"));
  const auto batch_trace = traced("batch " + meshtour::test::shell_quoted(dir_ / "m.csv") + " --out-dir " + meshtour::test::shell_quoted(batch) +
                                  " --web --frames 2 --width 64 --height 36 --spp 1 -q --progress none");
  // Every output kind is there, so that the check below covers it.
  for (const fs::path& f : {tour / "frames" / "frame_000000.png", tour / "frames" / "meshtour-frames.json", tour / "v.mp4",
                           tour / "poster.png", tour / "camera.json", tour / "camera.gltf", path / "p.path.json",
                           batch / "cube.mp4", batch / "cube.webm", batch / "cube.poster.png", batch / "index.html",
                           batch / "batch-summary.json"})
    EXPECT_TRUE(fs::exists(f)) << f;
  EXPECT_EQ(joined(write_order_faults(tour_trace, tour)), "");
  EXPECT_EQ(joined(write_order_faults(path_trace, path)), "");
  EXPECT_EQ(joined(write_order_faults(batch_trace, batch)), "");
}

// The test can fail: with every fsync dropped (as a writer that skipped the step would), each of
// the tour's files is reported, twice (its data and its folder).
TEST_F(WriteOrder, FailsWhenTheFsyncsAreDropped) {
  const fs::path out = dir_ / "dropped";
  const auto trace = traced(tour_args(out), /*drop_fsync=*/true);
  std::size_t files = 0;
  for (const auto& e : fs::recursive_directory_iterator(out)) files += e.is_regular_file();
  const auto faults = write_order_faults(trace, out);
  EXPECT_GE(files, 7u);
  EXPECT_EQ(faults.size(), 2 * files) << joined(faults);
}

}  // namespace
