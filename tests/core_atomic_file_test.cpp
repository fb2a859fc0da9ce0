// The one atomic writer (core/atomic_file.h): a file appears complete under its final name or
// not at all, and no temporary survives a failure.
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "helpers.h"

namespace meshtour {
namespace {

namespace fs = std::filesystem;

std::string read_all(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::size_t entries(const fs::path& dir) {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++n;
  return n;
}

TEST(AtomicFile, TemporaryIsHiddenBesideTheTargetWithItsExtension) {
  const PendingFile pending("/some/dir/frame_000001.png");
  EXPECT_EQ(pending.temporary().parent_path(), fs::path("/some/dir"));
  const std::string name = pending.temporary().filename().string();
  EXPECT_EQ(name, ".frame_000001.png.partial-" + std::to_string(::getpid()) + ".png");
  EXPECT_EQ(PendingFile("v.mp4", ".mkv").temporary().extension(), ".mkv");
}

TEST(AtomicFile, CommitGivesTheWholeFileItsNameAndLeavesNoTemporary) {
  const fs::path dir = test::scratch_dir();
  const std::string text(1 << 20, 'x');
  write_text_file_atomically(dir / "a.json", "old", "test file");
  write_text_file_atomically(dir / "a.json", text, "test file");
  EXPECT_EQ(read_all(dir / "a.json"), text);
  EXPECT_EQ(entries(dir), 1u);
}

TEST(AtomicFile, AFailedWriteLeavesTheOldFileAndNoTemporary) {
  const fs::path dir = test::scratch_dir();
  write_text_file_atomically(dir / "a.json", "old", "test file");
  EXPECT_THROW(write_file_atomically(dir / "a.json",
                                     [](const fs::path& temporary) {
                                       std::ofstream(temporary) << "half of the new";
                                       throw std::runtime_error("disk full");
                                     }),
               std::runtime_error);
  EXPECT_EQ(read_all(dir / "a.json"), "old");
  EXPECT_EQ(entries(dir), 1u);
  // Into a folder that does not exist: an IoError, nothing created.
  EXPECT_THROW(write_text_file_atomically(dir / "missing" / "b.json", "x", "test file"), IoError);
}

TEST(AtomicFile, UncommittedIsRemovedButNotWhatSquatsOnItsName) {
  const fs::path dir = test::scratch_dir();
  {
    PendingFile pending(dir / "v.mp4");
    std::ofstream(pending.temporary()) << "frames";
    EXPECT_EQ(entries(dir), 1u);
  }
  EXPECT_EQ(entries(dir), 0u);
  PendingFile squatted(dir / "w.mp4");
  fs::create_directory(squatted.temporary());
  squatted.discard();
  EXPECT_TRUE(fs::is_directory(squatted.temporary()));
  EXPECT_THROW(squatted.commit(), IoError);  // a directory cannot become the video
  EXPECT_FALSE(fs::exists(dir / "w.mp4"));
}

}  // namespace
}  // namespace meshtour
