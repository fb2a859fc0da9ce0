#include "helpers.h"

#include <array>
#include <fstream>
#include <iterator>
#include <cstdio>
#include <cstdlib>
#include <sys/wait.h>
#include <unistd.h>

namespace meshtour::test {

std::filesystem::path source_dir() { return MESHTOUR_SOURCE_DIR; }

std::filesystem::path scratch_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = info ? std::string(info->test_suite_name()) + "." + info->name() : "global";
  for (char& c : name)
    if (c == '/') c = '_';
  const auto dir = std::filesystem::path(MESHTOUR_BINARY_DIR) / "test-scratch" / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

std::filesystem::path shared_meshes_dir() {
  const auto dir = source_dir().parent_path() / "shared" / "meshes";
  return std::filesystem::is_directory(dir) ? dir : std::filesystem::path();
}

bool shared_required() {
  const char* v = std::getenv("MESHTOUR_REQUIRE_SHARED");
  return v && std::string(v) == "1";
}

std::filesystem::path meshtour_executable() { return MESHTOUR_EXECUTABLE; }

CommandResult run_meshtour(const std::string& args) {
  const std::string cmd = "cd '" + source_dir().string() + "' && '" + MESHTOUR_EXECUTABLE + "' " + args + " 2>&1";
  CommandResult result;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return result;
  std::array<char, 4096> buf{};
  while (std::size_t n = fread(buf.data(), 1, buf.size(), pipe)) result.output.append(buf.data(), n);
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

ScopedEnv::ScopedEnv(const char* name, const char* value) : name_(name) {
  if (const char* old = std::getenv(name)) previous_ = old;
  ::setenv(name, value, 1);
}

ScopedEnv::~ScopedEnv() {
  if (previous_)
    ::setenv(name_.c_str(), previous_->c_str(), 1);
  else
    ::unsetenv(name_.c_str());
}

int spawn_meshtour(const std::vector<std::string>& args, const std::filesystem::path& log) {
  const std::string exe = meshtour_executable().string();
  std::vector<std::string> argv_storage = {exe};
  argv_storage.insert(argv_storage.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : argv_storage) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    if (FILE* f = std::freopen(log.c_str(), "w", stderr)) (void)f;
    ::execv(exe.c_str(), argv.data());
    ::_exit(127);
  }
  return pid;
}

std::string shell_quoted(const std::filesystem::path& p) {
  std::string quoted = "'";
  quoted += p.string();
  quoted += "'";
  return quoted;
}

std::string file_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace meshtour::test
