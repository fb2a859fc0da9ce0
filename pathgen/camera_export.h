#pragma once
// Exports of a tour's cameras for other tools: a glTF 2.0 file with an animated camera (Blender,
// three.js, f3d play it) and a plain per-frame table (CSV or JSON) of eye, target, up and fov.
#include <filesystem>
#include <span>
#include <string>

#include "pathgen/camera_path.h"

namespace meshtour {

/// The cameras of one tour: pose of every frame, one vertical field of view, the frame aspect
/// (width / height) and the frame rate.
struct TourCameras {
  std::vector<CameraPose> poses;
  double vertical_fov_deg = 35.0;
  double aspect = 16.0 / 9.0;
  double fps = 30.0;
};

/// The cameras of `frames` frames of `path` (frame k at t = k / frames).
TourCameras sample_tour(const CameraPath& path, int frames, double vertical_fov_deg, double aspect, double fps);

/// Rotation of a glTF camera node placed at `pose`: glTF cameras look down their local -Z with
/// +Y up, so the node's -Z axis becomes the view direction and its +Y the image's up.
/// Returned as (x, y, z, w), unit length.
Eigen::Vector4d gltf_camera_rotation(const CameraPose& pose);

/// Writes `file` (.gltf) and its buffer (same name with .bin, next to it): one scene with one
/// node carrying a perspective camera (yfov, aspectRatio) and one animation whose translation
/// and rotation samplers (LINEAR) have a key at every frame time k / fps.
/// \throw InputError if there are no frames or the name does not end in .gltf, IoError if a file
///        cannot be written.
void write_camera_gltf(const TourCameras& cameras, const std::filesystem::path& file);

/// Writes one row per frame: frame, time, eye, target, up (x y z each), vertical and horizontal
/// field of view in degrees. ".csv" gives CSV with a header row, ".json" an array of objects.
/// \throw InputError for another extension, IoError if the file cannot be written.
void write_camera_frames(const TourCameras& cameras, const std::filesystem::path& file);

}  // namespace meshtour
