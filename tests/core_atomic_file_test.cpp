// The one atomic writer (core/atomic_file.h): a file appears complete under its final name or
// not at all, and no temporary survives a failure.
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/file_lock.h"
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
// Two holders of one name exclude each other (even in one process: the locks belong to the open
// file, not to the process); other names are free; closing releases.
TEST(FolderLock, OneNameOneHolderOtherNamesFreeReleasedOnClose) {
  const auto dir = test::scratch_dir();
  auto first = std::make_unique<FolderLock>(dir, "a.mp4");
  ASSERT_TRUE(first->try_lock());
  FolderLock same(dir, "a.mp4"), other(dir, "b.mp4");
  EXPECT_FALSE(same.try_lock());
  EXPECT_TRUE(other.try_lock());
  first.reset();
  EXPECT_TRUE(same.try_lock());
  EXPECT_TRUE(std::filesystem::exists(dir / kFolderLockFile));
  EXPECT_THROW(FolderLock(dir / "not-there", "a.mp4"), IoError);
}

}  // namespace meshtour
