#include "pathgen/camera_export.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>

#include "core/angles.h"
#include "core/error.h"
#include "pathgen/path_file.h"

namespace meshtour {
namespace {

void write_bytes(const std::filesystem::path& file, const std::string& bytes) {
  write_file_atomically(file, [&](const std::filesystem::path& temporary) {
    std::ofstream out(temporary, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) throw IoError(file.string() + ": cannot write the file (check the folder exists and is writable)");
  });
}

void append_float(std::string& bytes, double value) {
  const float f = static_cast<float>(value);
  char raw[sizeof f];
  std::memcpy(raw, &f, sizeof f);
  bytes.append(raw, sizeof f);
}

double horizontal_fov_deg(double vertical_fov_deg, double aspect) {
  return 2.0 * std::atan(std::tan(0.5 * vertical_fov_deg * kRadiansPerDegree) * aspect) / kRadiansPerDegree;
}

}  // namespace

TourCameras sample_tour(const CameraPath& path, int frames, double vertical_fov_deg, double aspect, double fps) {
  if (frames < 1) throw InputError("a tour needs at least one frame");
  TourCameras cameras;
  cameras.vertical_fov_deg = vertical_fov_deg;
  cameras.aspect = aspect;
  cameras.fps = fps;
  for (int k = 0; k < frames; ++k) cameras.poses.push_back(frame_pose(path, k, frames));
  return cameras;
}

Eigen::Vector4d gltf_camera_rotation(const CameraPose& pose) {
  const LookAtFrame frame = look_at(pose);
  const Eigen::Vector3d &forward = frame.forward, &right = frame.right, &up = frame.up;
  Eigen::Matrix3d rotation;
  rotation.col(0) = right;     // local +X
  rotation.col(1) = up;        // local +Y
  rotation.col(2) = -forward;  // local +Z points backwards: the camera looks down -Z
  const Eigen::Quaterniond q = Eigen::Quaterniond(rotation).normalized();
  return {q.x(), q.y(), q.z(), q.w()};
}

void write_camera_gltf(const TourCameras& cameras, const std::filesystem::path& file) {
  if (cameras.poses.empty()) throw InputError("the glTF export needs at least one frame");
  if (file.extension() != ".gltf") throw InputError(file.string() + ": the camera path is written as glTF 2.0 text; name it *.gltf");
  if (!(cameras.fps > 0.0) || !(cameras.aspect > 0.0)) throw InputError("the glTF export needs a positive frame rate and aspect");
  const std::size_t n = cameras.poses.size();
  std::filesystem::path bin_file = file;
  bin_file.replace_extension(".bin");

  // Buffer: times, then translations (VEC3), then rotations (VEC4); every view 4-byte aligned.
  std::string bytes;
  float t_min = std::numeric_limits<float>::infinity(), t_max = -t_min;
  for (std::size_t k = 0; k < n; ++k) {
    const float t = static_cast<float>(static_cast<double>(k) / cameras.fps);
    t_min = std::min(t_min, t);
    t_max = std::max(t_max, t);
    append_float(bytes, t);
  }
  const std::size_t translation_offset = bytes.size();
  double near = std::numeric_limits<double>::infinity(), far = 0.0;
  for (const CameraPose& p : cameras.poses) {
    for (int c = 0; c < 3; ++c) append_float(bytes, p.eye[c]);
    const double d = (p.target - p.eye).norm();
    near = std::min(near, d);
    far = std::max(far, d);
  }
  const std::size_t rotation_offset = bytes.size();
  Eigen::Vector4d previous = Eigen::Vector4d::Zero();
  for (const CameraPose& p : cameras.poses) {
    Eigen::Vector4d q = gltf_camera_rotation(p);
    // q and -q are the same rotation; keep neighbours in one hemisphere so interpolation takes
    // the short way.
    if (q.dot(previous) < 0.0) q = -q;
    previous = q;
    // Normalize in single precision, which the validator checks.
    Eigen::Vector4f qf = q.cast<float>();
    qf /= qf.norm();
    for (int c = 0; c < 4; ++c) append_float(bytes, qf[c]);
  }

  using nlohmann::ordered_json;
  ordered_json doc;
  doc["asset"] = {{"version", "2.0"}, {"generator", "meshtour"}};
  doc["scene"] = 0;
  doc["scenes"] = ordered_json::array({{{"name", "tour"}, {"nodes", {0}}}});
  const CameraPose& first = cameras.poses.front();
  const Eigen::Vector4d q0 = gltf_camera_rotation(first);
  doc["nodes"] = ordered_json::array({{{"name", "tour camera"},
                                       {"camera", 0},
                                       {"translation", {first.eye.x(), first.eye.y(), first.eye.z()}},
                                       {"rotation", {q0[0], q0[1], q0[2], q0[3]}}}});
  // Near and far planes from the distances to the point looked at: the model lies around it.
  const double znear = std::max(1e-6, 0.01 * near), zfar = std::max(100.0 * far, 2.0 * znear);
  doc["cameras"] = ordered_json::array({{{"name", "tour lens"},
                                         {"type", "perspective"},
                                         {"perspective",
                                          {{"yfov", cameras.vertical_fov_deg * kRadiansPerDegree},
                                           {"aspectRatio", cameras.aspect},
                                           {"znear", znear},
                                           {"zfar", zfar}}}}});
  doc["buffers"] = ordered_json::array({{{"uri", bin_file.filename().string()}, {"byteLength", bytes.size()}}});
  doc["bufferViews"] = ordered_json::array({
      {{"buffer", 0}, {"byteOffset", 0}, {"byteLength", translation_offset}},
      {{"buffer", 0}, {"byteOffset", translation_offset}, {"byteLength", rotation_offset - translation_offset}},
      {{"buffer", 0}, {"byteOffset", rotation_offset}, {"byteLength", bytes.size() - rotation_offset}},
  });
  constexpr int kFloat = 5126;
  doc["accessors"] = ordered_json::array({
      {{"bufferView", 0}, {"componentType", kFloat}, {"count", n}, {"type", "SCALAR"}, {"min", {t_min}}, {"max", {t_max}}},
      {{"bufferView", 1}, {"componentType", kFloat}, {"count", n}, {"type", "VEC3"}},
      {{"bufferView", 2}, {"componentType", kFloat}, {"count", n}, {"type", "VEC4"}},
  });
  doc["animations"] = ordered_json::array({{
      {"name", "tour"},
      {"channels", ordered_json::array({{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}},
                                        {{"sampler", 1}, {"target", {{"node", 0}, {"path", "rotation"}}}}})},
      {"samplers", ordered_json::array({{{"input", 0}, {"output", 1}, {"interpolation", "LINEAR"}},
                                        {{"input", 0}, {"output", 2}, {"interpolation", "LINEAR"}}})},
  }});
  write_bytes(bin_file, bytes);
  write_bytes(file, doc.dump(2) + "\n");
}

void write_camera_frames(const TourCameras& cameras, const std::filesystem::path& file) {
  const std::string ext = file.extension().string();
  if (ext != ".csv" && ext != ".json") throw InputError(file.string() + ": write the camera frames as .csv or .json");
  const double hfov = horizontal_fov_deg(cameras.vertical_fov_deg, cameras.aspect);
  std::ostringstream out;
  out.precision(9);
  if (ext == ".csv") {
    out << "frame,time,eye_x,eye_y,eye_z,target_x,target_y,target_z,up_x,up_y,up_z,vertical_fov_deg,horizontal_fov_deg\n";
    for (std::size_t k = 0; k < cameras.poses.size(); ++k) {
      const CameraPose& p = cameras.poses[k];
      out << k << ',' << static_cast<double>(k) / cameras.fps;
      for (const Eigen::Vector3d* v : {&p.eye, &p.target, &p.up})
        for (int c = 0; c < 3; ++c) out << ',' << (*v)[c];
      out << ',' << cameras.vertical_fov_deg << ',' << hfov << '\n';
    }
  } else {
    nlohmann::ordered_json rows = nlohmann::ordered_json::array();
    for (std::size_t k = 0; k < cameras.poses.size(); ++k) {
      const CameraPose& p = cameras.poses[k];
      rows.push_back({{"frame", k},
                      {"time", static_cast<double>(k) / cameras.fps},
                      {"eye", {p.eye.x(), p.eye.y(), p.eye.z()}},
                      {"target", {p.target.x(), p.target.y(), p.target.z()}},
                      {"up", {p.up.x(), p.up.y(), p.up.z()}},
                      {"vertical_fov_deg", cameras.vertical_fov_deg},
                      {"horizontal_fov_deg", hfov}});
    }
    out << rows.dump(2) << '\n';
  }
  write_bytes(file, out.str());
}

}  // namespace meshtour
