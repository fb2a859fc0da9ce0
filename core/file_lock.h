#pragma once
// Named locks between processes that share an output folder: two runs of the same catalogue job on
// one --out-dir (two operators, a re-submitted farm array) must not make the same item twice. One
// hidden file in the folder holds every lock of the folder as a one-byte range chosen by the name;
// the locks are open-file-description locks (F_OFD_SETLK), so they belong to this open file, not to
// the process: they work between threads, never merge with another lock of the process, and the
// kernel drops them when the process ends, however it ends (SIGKILL, a dead node on NFS aside).
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>
#include <thread>

#include "core/error.h"
#include "core/interrupt.h"

namespace meshtour {

/// The hidden file of a folder's locks: empty, left in place (removing it could split the holders
/// of one lock between two files).
inline constexpr const char* kFolderLockFile = ".meshtour-locks";

class FolderLock {
public:
  /// The lock named `name` among those of `folder`. Nothing is locked yet.
  /// \throw IoError when the folder's lock file cannot be opened (the folder is not writable).
  FolderLock(const std::filesystem::path& folder, std::string_view name) : offset_(offset_of(name)) {
    const std::filesystem::path file = folder / kFolderLockFile;
    fd_ = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) throw IoError("cannot open the lock file " + file.string() + ": " + std::strerror(errno));
  }
  ~FolderLock() {
    if (fd_ >= 0) ::close(fd_);  // closing the description releases its locks
  }
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

  /// Takes the lock if no other holder has it; false when another has.
  bool try_lock() { return set(F_OFD_SETLK, F_WRLCK); }

  /// Waits until the lock is free and takes it. An interrupt (SIGINT/SIGTERM) ends the wait with
  /// Interrupted. (A poll, not F_OFD_SETLKW: the signal handlers restart that call, so it would
  /// not see an interrupt.)
  void lock() {
    while (!try_lock()) {
      throw_if_interrupted();
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  }

private:
  // The name's byte in the lock file: FNV-1a, 31 bits. Two names on one byte only wait for each
  // other; they never run together.
  static off_t offset_of(std::string_view name) {
    std::uint64_t h = 14695981039346656037ull;
    for (unsigned char c : name) h = (h ^ c) * 1099511628211ull;
    return static_cast<off_t>(h & 0x7fffffffu);
  }

  bool set(int command, short type) {  // true: set; false: another holder has it
    struct flock region{};
    region.l_type = type;
    region.l_whence = SEEK_SET;
    region.l_start = offset_;
    region.l_len = 1;
    if (::fcntl(fd_, command, &region) == 0) return true;
    if (errno == EAGAIN || errno == EACCES) return false;
    throw IoError(std::string("cannot lock an item in the output folder: ") + std::strerror(errno));
  }

  int fd_ = -1;
  off_t offset_;
};

}  // namespace meshtour
