#include "tour/mesh_warnings.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace meshtour {

void warn_if_flat(const TriangleMesh& mesh, const Eigen::Vector3d& up, const std::string& file) {
  const auto normal = flat_plane_normal(mesh);
  if (!normal) return;
  // The angle between the plane and the up direction: 90 degrees would have been refused.
  const double tilt = std::asin(std::min(1.0, std::abs(normal->dot(up.normalized())))) * 180.0 / 3.14159265358979;
  std::fprintf(stderr,
               "meshtour: warning: %s is flat (every vertex lies in one plane, tilted %.0f degrees from the up "
               "direction); the camera circles it and sees it edge-on twice per loop\n",
               file.c_str(), tilt);
}

}  // namespace meshtour
