// A PLY header must not make the loader allocate what the file cannot hold.
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>

#include "core/error.h"
#include "helpers.h"
#include "mesh/mesh.h"

namespace meshtour {
namespace {

void expect_input_error(const std::filesystem::path& file, const std::string& words) {
  const auto start = std::chrono::steady_clock::now();
  try {
    load_mesh(file);
    ADD_FAILURE() << file << ": expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
  // Refused from the header alone, not after trying to allocate.
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0);
}

TEST(PlyHeader, HugeCountsOnATinyFileAreRefused) {
  const auto dir = test::scratch_dir();
  std::ofstream(dir / "huge.ply") << "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
                                     "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                     "end_header\n0123456789";
  expect_input_error(dir / "huge.ply", "4000000000 vertex");
  std::ofstream(dir / "noend.ply") << "ply\nformat binary_little_endian 1.0\nelement vertex 99999999\n";
  expect_input_error(dir / "noend.ply", "end_header");
  std::ofstream(dir / "badcount.ply") << "ply\nformat ascii 1.0\nelement vertex lots\nend_header\n";
  expect_input_error(dir / "badcount.ply", "invalid count");
}

}  // namespace
}  // namespace meshtour
