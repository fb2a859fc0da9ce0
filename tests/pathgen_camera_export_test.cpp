// Camera exports: the glTF camera's orientation (glTF cameras look down -Z with +Y up), the
// layout of the .gltf/.bin pair, and the per-frame CSV/JSON tables.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <numbers>
#include <random>

#include "core/error.h"
#include "helpers.h"
#include "pathgen/camera_export.h"
#include "pathgen/turntable.h"
#include "test_meshes.h"

namespace {

using namespace meshtour;
namespace fs = std::filesystem;

Eigen::Quaterniond to_quaternion(const Eigen::Vector4d& xyzw) { return Eigen::Quaterniond(xyzw[3], xyzw[0], xyzw[1], xyzw[2]); }

TEST(CameraExport, GltfRotationTurnsMinusZIntoTheViewAndYIntoTheUp) {
  // Looking from +Z at the origin with +Y up is the glTF camera's rest pose: identity.
  const Eigen::Vector4d identity = gltf_camera_rotation(CameraPose{Eigen::Vector3d(0, 0, 5), Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY()});
  EXPECT_NEAR(std::abs(identity[3]), 1.0, 1e-12);
  // Looking from +X: the camera turned +90° about Y.
  const Eigen::Quaterniond side = to_quaternion(gltf_camera_rotation(CameraPose{Eigen::Vector3d(3, 0, 0), Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY()}));
  EXPECT_NEAR(std::abs(side.dot(Eigen::Quaterniond(Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitY())))), 1.0, 1e-12);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 100; ++i) {
    const auto draw = [&] { return u(rng); };
    const CameraPose pose{test_meshes::drawn_vector(draw) * 5, test_meshes::drawn_vector(draw),
                          test_meshes::drawn_vector(draw).normalized()};
    const Eigen::Quaterniond q = to_quaternion(gltf_camera_rotation(pose));
    EXPECT_NEAR(q.norm(), 1.0, 1e-12);
    const Eigen::Vector3d view = (pose.target - pose.eye).normalized();
    EXPECT_NEAR((q * Eigen::Vector3d(0, 0, -1) - view).norm(), 0.0, 1e-9);
    const Eigen::Vector3d image_up = q * Eigen::Vector3d::UnitY();
    EXPECT_NEAR(image_up.dot(view), 0.0, 1e-9);
    // The image's up is the requested up made perpendicular to the view (same side, same plane).
    const Eigen::Vector3d expected = (pose.up - pose.up.dot(view) * view).normalized();
    EXPECT_NEAR((image_up - expected).norm(), 0.0, 1e-9);
  }
}

TEST(CameraExport, GltfFileHoldsOneKeyPerFrameAndTheLens) {
  const fs::path dir = test::scratch_dir();
  const std::vector<Eigen::Vector3d> points = {{-1, -1, -1}, {1, 1, 1}};
  TurntableOptions options;
  const TurntablePath path(points, options);
  const TourCameras cameras = sample_tour(path, 24, 30.0, 1.5, 12.0);
  write_camera_gltf(cameras, dir / "tour.gltf");
  std::ifstream in(dir / "tour.gltf");
  const nlohmann::json doc = nlohmann::json::parse(in);
  EXPECT_EQ(doc["asset"]["version"], "2.0");
  EXPECT_NEAR(doc["cameras"][0]["perspective"]["yfov"].get<double>(), 30.0 * std::numbers::pi / 180.0, 1e-12);
  EXPECT_DOUBLE_EQ(doc["cameras"][0]["perspective"]["aspectRatio"].get<double>(), 1.5);
  EXPECT_EQ(doc["buffers"][0]["uri"], "tour.bin");
  const auto size = fs::file_size(dir / "tour.bin");
  EXPECT_EQ(size, doc["buffers"][0]["byteLength"].get<std::size_t>());
  EXPECT_EQ(size, 24u * (1 + 3 + 4) * sizeof(float));
  EXPECT_EQ(doc["accessors"][0]["count"], 24);
  EXPECT_NEAR(doc["accessors"][0]["max"][0].get<double>(), 23.0 / 12.0, 1e-6);
  // The translation of key 5 is the eye of frame 5; its rotation maps -Z to the view.
  std::ifstream bin(dir / "tour.bin", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(bin)), std::istreambuf_iterator<char>());
  auto read = [&](std::size_t index) {
    float f;
    std::memcpy(&f, bytes.data() + 4 * index, 4);
    return static_cast<double>(f);
  };
  const Eigen::Vector3d eye(read(24 + 15), read(24 + 16), read(24 + 17));
  EXPECT_LT((eye - cameras.poses[5].eye).norm(), 1e-5);
  const Eigen::Quaterniond q(read(96 + 23), read(96 + 20), read(96 + 21), read(96 + 22));  // after 24 times and 72 coordinates
  const Eigen::Vector3d view = (cameras.poses[5].target - cameras.poses[5].eye).normalized();
  EXPECT_LT((q * Eigen::Vector3d(0, 0, -1) - view).norm(), 1e-5);
  EXPECT_THROW(write_camera_gltf(cameras, dir / "tour.glb"), InputError);
}

TEST(CameraExport, FramesTablesListEyeTargetUpAndFov) {
  const fs::path dir = test::scratch_dir();
  const std::vector<Eigen::Vector3d> points = {{-1, -1, -1}, {1, 1, 1}};
  const TurntablePath path(points, TurntableOptions{});
  const TourCameras cameras = sample_tour(path, 10, 40.0, 2.0, 30.0);
  write_camera_frames(cameras, dir / "frames.csv");
  write_camera_frames(cameras, dir / "frames.json");
  std::ifstream csv(dir / "frames.csv");
  std::string header, line;
  std::getline(csv, header);
  EXPECT_EQ(header, "frame,time,eye_x,eye_y,eye_z,target_x,target_y,target_z,up_x,up_y,up_z,vertical_fov_deg,horizontal_fov_deg");
  int rows = 0;
  while (std::getline(csv, line)) ++rows;
  EXPECT_EQ(rows, 10);
  std::ifstream js(dir / "frames.json");
  const nlohmann::json doc = nlohmann::json::parse(js);
  ASSERT_EQ(doc.size(), 10u);
  EXPECT_NEAR(doc[3]["eye"][0].get<double>(), cameras.poses[3].eye.x(), 1e-6);
  EXPECT_DOUBLE_EQ(doc[3]["vertical_fov_deg"].get<double>(), 40.0);
  EXPECT_NEAR(doc[3]["horizontal_fov_deg"].get<double>(), 2.0 * std::atan(2.0 * std::tan(20.0 * std::numbers::pi / 180.0)) * 180.0 / std::numbers::pi, 1e-9);
  EXPECT_THROW(write_camera_frames(cameras, dir / "frames.txt"), InputError);
}

}  // namespace
