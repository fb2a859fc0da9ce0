// Messages about the model (tour/mesh_warnings.h): a path stage's InputError names the file, other
// errors and results pass through; a flat model gets one warning with its tilt, a solid one none.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <string>

#include "core/error.h"
#include "test_meshes.h"
#include "tour/mesh_warnings.h"

namespace {

using namespace meshtour;
using testing::internal::CaptureStderr;
using testing::internal::GetCapturedStderr;

TEST(TourMeshWarnings, InputErrorsOfAPathStageNameTheFile) {
  EXPECT_EQ(with_file_name("bunny.ply", [] { return 42; }), 42);
  try {
    with_file_name("models/bunny.ply", []() -> int { throw InputError("the mesh has no surface area to sample"); });
    FAIL() << "the error was swallowed";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "models/bunny.ply: the mesh has no surface area to sample");
  }
  // Other failures are not the file's fault: they pass through unchanged.
  try {
    with_file_name("bunny.ply", [] { throw IoError("disk full"); });
    FAIL() << "the error was swallowed";
  } catch (const InputError&) {
    FAIL() << "an IoError became an InputError";
  } catch (const IoError& e) {
    EXPECT_STREQ(e.what(), "disk full");
  }
}

std::string warning_for(const TriangleMesh& mesh, const Eigen::Vector3d& up, const std::string& file) {
  CaptureStderr();
  warn_if_flat(mesh, up, file);
  return GetCapturedStderr();
}

TEST(TourMeshWarnings, AFlatModelIsWarnedAboutWithItsTilt) {
  // The plane z = 0 contains the up direction +Y: seen edge-on twice per loop.
  const TriangleMesh plane = test_meshes::plane(4);
  const std::string upright = warning_for(plane, Eigen::Vector3d::UnitY(), "sheet.obj");
  EXPECT_EQ(upright.rfind("meshtour: warning: sheet.obj is flat", 0), 0u) << upright;
  EXPECT_NE(upright.find("tilted 0 degrees from the up direction"), std::string::npos) << upright;
  EXPECT_EQ(upright.back(), '\n');
  EXPECT_EQ(upright.find('\n'), upright.size() - 1) << "one line";

  // Turned 30 degrees about X, its normal is 30 degrees from the plane's: the tilt says so.
  const Eigen::Matrix3d turn = test_meshes::rotation(Eigen::Vector3d::UnitX(), 30.0 * std::numbers::pi / 180.0);
  const TriangleMesh tilted = test_meshes::transformed(plane, 2.0, turn, Eigen::Vector3d(5, -1, 3));
  EXPECT_NE(warning_for(tilted, Eigen::Vector3d(0, 4, 0), "tilted.ply").find("tilted 30 degrees"), std::string::npos);

  // A solid is not flat.
  EXPECT_EQ(warning_for(test_meshes::icosphere(2), Eigen::Vector3d::UnitY(), "ball.ply"), "");
}

}  // namespace
