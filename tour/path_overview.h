#pragma once
// The --overview picture of `meshtour path`: the model with its bounding cylinder, the position
// path (where the camera is, magenta), the gaze path (what it looks at, cyan), a few sight lines
// (yellow) and the start (red), drawn in 3D as vertex-coloured tubes added to the model's mesh and
// ray traced with the tracer's public API, from a viewpoint that shows the whole path.
#include <Eigen/Core>
#include <filesystem>

#include "mesh/mesh.h"
#include "pathgen/camera_path.h"
#include "tracer/tracer.h"

namespace meshtour {

/// A cylinder around the up axis, in model units.
struct OverviewCylinder {
  Eigen::Vector3d base_center = Eigen::Vector3d::Zero();  ///< centre of the bottom disc
  Eigen::Vector3d up = Eigen::Vector3d::UnitY();          ///< unit axis
  double radius = 1.0;
  double height = 1.0;
};

/// The smallest cylinder around the axis through the bounding-box centre along `up` holding every vertex.
OverviewCylinder bounding_cylinder(const TriangleMesh& mesh, const Eigen::Vector3d& up);

/// The model plus tubes for the cylinder's rims and sides, the position and gaze paths of `path`
/// (sampled at `samples` points) and sight lines, with per-vertex colours.
TriangleMesh overview_scene(const TriangleMesh& mesh, const CameraPath& path, const OverviewCylinder& cylinder,
                            int samples = 360);

/// Renders overview_scene() from above and to the side, framed to show all of it.
Image render_overview(const TriangleMesh& mesh, const CameraPath& path, const OverviewCylinder& cylinder,
                      int width = 1200, int height = 900, int samples_per_pixel = 16);

}  // namespace meshtour
