#pragma once
// Whole-or-nothing file creation, shared by every stage that writes files (path files, frames,
// manifests, plots): a reader, or a re-run after a crash, never sees a half-written file under
// the final name.
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "core/error.h"

namespace meshtour {

/// The temporary name write_file_atomically() uses for `file`: hidden, in the same folder (so the
/// rename is atomic), with the process id (two processes never share one) and the same extension
/// (so that writers choosing a format by extension still work).
inline std::filesystem::path temporary_name_for(const std::filesystem::path& file) {
  const std::filesystem::path dir = file.has_parent_path() ? file.parent_path() : std::filesystem::path(".");
  // Appending piece by piece (not "." + string) also avoids a GCC 12 -Wrestrict false positive.
  std::string name = ".";
  name += file.filename().string();
  name += ".tmp";
  name += std::to_string(::getpid());
  name += file.extension().string();
  return dir / name;
}

/// Creates `file` all at once: `write` receives a temporary path (temporary_name_for(file)), and
/// the temporary file is renamed over `file` only when `write` returns. On any exception the
/// temporary file is removed and the exception propagates; `file` is then untouched.
/// \throw IoError if the rename fails.
inline void write_file_atomically(const std::filesystem::path& file,
                                  const std::function<void(const std::filesystem::path& temporary)>& write) {
  const std::filesystem::path temporary = temporary_name_for(file);
  try {
    write(temporary);
    std::error_code ec;
    std::filesystem::rename(temporary, file, ec);
    if (ec) throw IoError("cannot write " + file.string() + ": " + ec.message());
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw;
  }
}

/// Writes `text` as the whole of `file`, atomically (see write_file_atomically).
/// \throw IoError naming `what` (e.g. "path file") and `file` if it cannot be written.
inline void write_text_file_atomically(const std::filesystem::path& file, const std::string& text, const std::string& what) {
  write_file_atomically(file, [&](const std::filesystem::path& temporary) {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) throw IoError("cannot write " + what + " " + file.string() + ": " + std::strerror(errno));
    out << text;
    out.close();
    if (!out) throw IoError("cannot write " + what + " " + file.string() + ": write failed (disk full?)");
  });
}

}  // namespace meshtour
