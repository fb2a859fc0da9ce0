#pragma once
// Whole-or-nothing file creation, the one way every stage writes an output (frames, videos, path
// files, manifests, summaries, farm scripts, plots): a reader, or a re-run after a crash of the
// program or of the machine, never sees a half-written file under the final name.
//
// The data go to a hidden temporary in the same folder (so the rename is atomic), which is
// flushed to the disk (fsync) before it is renamed over the final name, and the folder is flushed
// after the rename: without the first fsync a machine crash can leave the final name pointing at
// an empty or truncated file (the rename reached the disk before the data); without the second,
// the rename itself can be lost.
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <string_view>
#include <system_error>

#include "core/error.h"
#include "core/interrupt.h"

namespace meshtour {

/// A file being written: its temporary name, and the commit that gives it its final name.
/// Destroyed without commit() (an exception, an interrupt), it removes the temporary.
class PendingFile {
public:
  /// `temporary_extension` ("" = the target's own) is the temporary's extension, for writers
  /// that pick a format by it. The temporary is `.<name>.partial-<pid><extension>` beside the
  /// target: hidden, never a final name, and two processes never share one.
  explicit PendingFile(std::filesystem::path target, const std::string& temporary_extension = "")
      : target_(std::move(target)) {
    const std::filesystem::path dir = target_.has_parent_path() ? target_.parent_path() : std::filesystem::path(".");
    // Appending piece by piece (not "." + string) avoids a GCC 12 -Wrestrict false positive.
    std::string name = ".";
    name += target_.filename().string();
    name += ".partial-";
    name += std::to_string(::getpid());
    name += temporary_extension.empty() ? target_.extension().string() : temporary_extension;
    temporary_ = dir / name;
    register_temporary(temporary_.string());
  }
  ~PendingFile() {
    discard();
    unregister_temporary(temporary_.string());
  }
  PendingFile(const PendingFile&) = delete;
  PendingFile& operator=(const PendingFile&) = delete;

  const std::filesystem::path& temporary() const { return temporary_; }
  const std::filesystem::path& target() const { return target_; }

  /// Flushes the temporary to the disk, renames it to the target and flushes the folder.
  /// \throw IoError naming the target if any step fails (the temporary is then removed).
  void commit() {
    std::error_code status;
    if (!std::filesystem::is_regular_file(std::filesystem::symlink_status(temporary_, status)))
      throw IoError("cannot write " + target_.string() + ": its temporary " + temporary_.string() + " is not a file the writer made");
    sync_path(temporary_, O_RDONLY);
    std::error_code ec;
    std::filesystem::rename(temporary_, target_, ec);
    if (ec) throw IoError("cannot write " + target_.string() + ": " + ec.message());
    committed_ = true;
    sync_path(target_.has_parent_path() ? target_.parent_path() : std::filesystem::path("."), O_RDONLY | O_DIRECTORY);
  }

  /// Removes the temporary unless committed. Only a regular file is removed: a failure to create
  /// the temporary must not delete whatever else holds its name.
  void discard() noexcept {
    if (committed_) return;
    std::error_code ec;  // best effort: nothing useful to do if removal fails during clean-up
    if (std::filesystem::is_regular_file(std::filesystem::symlink_status(temporary_, ec))) std::filesystem::remove(temporary_, ec);
  }

private:
  void sync_path(const std::filesystem::path& path, int flags) const {
    const int fd = ::open(path.c_str(), flags | O_CLOEXEC);
    if (fd < 0 || ::fsync(fd) != 0) {
      const std::string why = std::strerror(errno);
      if (fd >= 0) ::close(fd);
      throw IoError("cannot write " + target_.string() + ": flushing " + path.string() + " to the disk failed: " + why);
    }
    ::close(fd);
  }

  std::filesystem::path target_, temporary_;
  bool committed_ = false;
};

/// Creates `file` all at once: `write` receives the temporary path, and the file gets its final
/// name (flushed to the disk, see PendingFile) only when `write` returns. On any exception the
/// temporary is removed and the exception propagates; `file` is then untouched.
/// \throw IoError if flushing or the rename fails.
inline void write_file_atomically(const std::filesystem::path& file,
                                  const std::function<void(const std::filesystem::path& temporary)>& write) {
  PendingFile pending(file);
  write(pending.temporary());
  pending.commit();
}

/// Writes `text` (any bytes) as the whole of `file`, atomically (see write_file_atomically).
/// \throw IoError naming `what` (e.g. "path file") and `file` if it cannot be written.
inline void write_text_file_atomically(const std::filesystem::path& file, std::string_view text, const std::string& what) {
  write_file_atomically(file, [&](const std::filesystem::path& temporary) {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) throw IoError("cannot write " + what + " " + file.string() + ": " + std::strerror(errno));
    out << text;
    out.close();
    if (!out) throw IoError("cannot write " + what + " " + file.string() + ": write failed (disk full?)");
  });
}

}  // namespace meshtour
