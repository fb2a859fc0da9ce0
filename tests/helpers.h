#pragma once
// Shared test helpers: locating the repository, ../shared meshes, and running the CLI.
#include <gtest/gtest.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace meshtour::test {

/// Root of the source tree.
std::filesystem::path source_dir();
/// A fresh, empty scratch directory under the build tree, named after the running test.
std::filesystem::path scratch_dir();
/// The ../shared/meshes folder next to the repository ("" when it is absent).
std::filesystem::path shared_meshes_dir();
/// True when MESHTOUR_REQUIRE_SHARED=1: a missing ../shared is then a failure, not a skip (CI).
bool shared_required();

/// `p` in single quotes, for run_meshtour's shell command line.
std::string shell_quoted(const std::filesystem::path& p);
/// The whole file as bytes ("" when it cannot be read).
std::string file_bytes(const std::filesystem::path& file);

/// Result of running the meshtour executable.
struct CommandResult {
  int exit_code = -1;
  std::string output;  ///< stdout and stderr, merged
};
/// Runs `meshtour <args>` through the shell from the repository root.
CommandResult run_meshtour(const std::string& args);
/// The meshtour executable under test (absolute), for tests that start it themselves.
std::filesystem::path meshtour_executable();

/// Starts `meshtour <args>` (no shell) in the background and returns its pid; its stderr goes to `log`.
int spawn_meshtour(const std::vector<std::string>& args, const std::filesystem::path& log);

/// Sets an environment variable for its lifetime, then restores the previous value.
class ScopedEnv {
public:
  ScopedEnv(const char* name, const char* value);
  ~ScopedEnv();
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

private:
  std::string name_;
  std::optional<std::string> previous_;
};

}  // namespace meshtour::test

/// Sets `var` to ../shared/meshes/<name>, or skips the test (fails it under MESHTOUR_REQUIRE_SHARED=1).
// Skips the test in the sanitizer build (MESHTOUR_SANITIZED_BUILD): for tests that repeat, process
// after process, renders and searches that lighter tests already run under the sanitizers, and
// that check properties (bytes equal across runs, a score, a deadline) the Release pass checks.
// They were a third of the sanitizer pass's time, which CI pays on every run.
#ifdef MESHTOUR_SANITIZED_BUILD
#define MESHTOUR_SKIP_UNDER_SANITIZERS(why) GTEST_SKIP() << "skipped under the sanitizers: " << (why)
#else
#define MESHTOUR_SKIP_UNDER_SANITIZERS(why) static_cast<void>(why)
#endif

#define MESHTOUR_SHARED_MESH(var, name)                                                          \
  const std::filesystem::path var = ::meshtour::test::shared_meshes_dir() / (name);              \
  if (!std::filesystem::exists(var)) {                                                           \
    if (::meshtour::test::shared_required())                                                     \
      FAIL() << "MESHTOUR_REQUIRE_SHARED=1 but " << var << " is missing";                        \
    GTEST_SKIP() << "skipped: " << var << " not found (the ../shared test data is not checked out)"; \
  }
