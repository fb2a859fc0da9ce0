#include "tour/path_overview.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/error.h"

namespace meshtour {
namespace {

constexpr double kPi = std::numbers::pi;

// Appends a tube of `radius` along `points` (closed: the last point joins the first).
void add_tube(TriangleMesh& out, const std::vector<Eigen::Vector3d>& points, bool closed, double radius,
              const Eigen::Vector3f& color, const Eigen::Vector3d& reference_up) {
  constexpr int kSides = 10;
  const std::size_t n = points.size();
  if (n < 2) return;
  const std::uint32_t first = static_cast<std::uint32_t>(out.positions.size());
  Eigen::Vector3d previous_normal = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector3d& prev = closed ? points[(k + n - 1) % n] : points[k == 0 ? 0 : k - 1];
    const Eigen::Vector3d& next = closed ? points[(k + 1) % n] : points[std::min(k + 1, n - 1)];
    Eigen::Vector3d tangent = next - prev;
    if (!(tangent.norm() > 0.0)) tangent = Eigen::Vector3d::UnitX();
    tangent.normalize();
    // Parallel transport of the previous ring's normal keeps the tube from twisting.
    Eigen::Vector3d normal = previous_normal.norm() > 0.0 ? previous_normal : reference_up;
    normal -= normal.dot(tangent) * tangent;
    if (!(normal.norm() > 1e-9)) normal = tangent.unitOrthogonal();
    normal.normalize();
    previous_normal = normal;
    const Eigen::Vector3d binormal = tangent.cross(normal);
    for (int s = 0; s < kSides; ++s) {
      const double a = 2.0 * kPi * s / kSides;
      out.positions.push_back(points[k] + radius * (std::cos(a) * normal + std::sin(a) * binormal));
      out.colors.push_back(color);
    }
  }
  const std::size_t rings = closed ? n : n - 1;
  for (std::size_t k = 0; k < rings; ++k) {
    const std::uint32_t a = first + static_cast<std::uint32_t>(k * kSides);
    const std::uint32_t b = first + static_cast<std::uint32_t>(((k + 1) % n) * kSides);
    for (int s = 0; s < kSides; ++s) {
      const std::uint32_t s1 = (s + 1) % kSides;
      out.triangles.push_back({a + s, b + s, b + s1});
      out.triangles.push_back({a + s, b + s1, a + s1});
    }
  }
}

void add_ball(TriangleMesh& out, const Eigen::Vector3d& center, double radius, const Eigen::Vector3f& color) {
  constexpr int kRings = 10, kSegments = 16;
  const std::uint32_t first = static_cast<std::uint32_t>(out.positions.size());
  for (int i = 0; i <= kRings; ++i) {
    const double theta = kPi * i / kRings;
    for (int j = 0; j < kSegments; ++j) {
      const double phi = 2.0 * kPi * j / kSegments;
      out.positions.push_back(center + radius * Eigen::Vector3d(std::sin(theta) * std::cos(phi), std::cos(theta),
                                                                std::sin(theta) * std::sin(phi)));
      out.colors.push_back(color);
    }
  }
  for (int i = 0; i < kRings; ++i)
    for (int j = 0; j < kSegments; ++j) {
      const std::uint32_t a = first + i * kSegments + j, b = first + i * kSegments + (j + 1) % kSegments;
      const std::uint32_t c = a + kSegments, d = b + kSegments;
      out.triangles.push_back({a, c, d});
      out.triangles.push_back({a, d, b});
    }
}

}  // namespace

OverviewCylinder bounding_cylinder(const TriangleMesh& mesh, const Eigen::Vector3d& up) {
  OverviewCylinder c;
  c.up = up.normalized();
  const Eigen::Vector3d center = mesh.bounds().center();
  double lo = std::numeric_limits<double>::infinity(), hi = -lo, radius = 0.0;
  for (const auto& t : mesh.triangles)
    for (std::uint32_t v : t) {
      const Eigen::Vector3d d = mesh.positions[v] - center;
      const double h = d.dot(c.up);
      lo = std::min(lo, h);
      hi = std::max(hi, h);
      radius = std::max(radius, (d - h * c.up).norm());
    }
  c.base_center = center + lo * c.up;
  c.height = hi - lo;
  c.radius = radius;
  return c;
}

TriangleMesh overview_scene(const TriangleMesh& mesh, const CameraPath& path, const OverviewCylinder& cylinder, int samples) {
  TriangleMesh scene = mesh;
  if (!scene.has_colors()) scene.colors.assign(scene.positions.size(), Eigen::Vector3f(0.78f, 0.78f, 0.76f));
  scene.corner_uvs.clear();
  scene.materials.clear();
  scene.triangle_materials.clear();

  std::vector<Eigen::Vector3d> eyes, targets;
  for (int k = 0; k < samples; ++k) {
    const CameraPose p = path.pose(static_cast<double>(k) / samples);
    eyes.push_back(p.eye);
    targets.push_back(p.target);
  }
  Eigen::Vector3d lo = eyes.front(), hi = eyes.front();
  for (const std::vector<Eigen::Vector3d>* set : std::array<const std::vector<Eigen::Vector3d>*, 3>{&eyes, &targets, &mesh.positions})
    for (const auto& p : *set) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  const double size = (hi - lo).norm();
  const double tube = 0.004 * size;

  // The cylinder: rims and sides every 30 degrees, thin so the model shows through.
  const Eigen::Vector3d e1 = cylinder.up.unitOrthogonal(), e2 = cylinder.up.cross(e1);
  const Eigen::Vector3f cylinder_color(0.55f, 0.62f, 0.75f);
  for (double h : {0.0, cylinder.height}) {
    std::vector<Eigen::Vector3d> rim;
    for (int k = 0; k < 96; ++k) {
      const double a = 2.0 * kPi * k / 96;
      rim.push_back(cylinder.base_center + h * cylinder.up + cylinder.radius * (std::cos(a) * e1 + std::sin(a) * e2));
    }
    add_tube(scene, rim, true, 0.5 * tube, cylinder_color, cylinder.up);
  }
  for (int k = 0; k < 12; ++k) {
    const double a = 2.0 * kPi * k / 12;
    const Eigen::Vector3d foot = cylinder.base_center + cylinder.radius * (std::cos(a) * e1 + std::sin(a) * e2);
    add_tube(scene, {foot, foot + cylinder.height * cylinder.up}, false, 0.5 * tube, cylinder_color, e1);
  }
  // Sight lines every 1/12 of the loop, then the two paths and the start.
  for (int k = 0; k < 12; ++k) {
    const CameraPose p = path.pose(k / 12.0);
    add_tube(scene, {p.eye, p.target}, false, 0.35 * tube, Eigen::Vector3f(0.95f, 0.85f, 0.2f), cylinder.up);
  }
  add_tube(scene, eyes, true, tube, Eigen::Vector3f(0.9f, 0.2f, 0.85f), cylinder.up);
  double gaze_extent = 0.0;
  for (const auto& t : targets) gaze_extent = std::max(gaze_extent, (t - targets.front()).norm());
  if (gaze_extent > 2.0 * tube)
    add_tube(scene, targets, true, tube, Eigen::Vector3f(0.1f, 0.85f, 0.9f), cylinder.up);
  else
    add_ball(scene, targets.front(), 2.5 * tube, Eigen::Vector3f(0.1f, 0.85f, 0.9f));  // a fixed gaze point
  add_ball(scene, eyes.front(), 3.0 * tube, Eigen::Vector3f(0.95f, 0.15f, 0.1f));
  return scene;
}

Image render_overview(const TriangleMesh& mesh, const CameraPath& path, const OverviewCylinder& cylinder, int width,
                      int height, int samples_per_pixel) {
  const TriangleMesh scene = overview_scene(mesh, path, cylinder);
  // Look from 35 degrees above the cylinder's mid-plane, turned 30 degrees from the path's start.
  const Bounds bounds = scene.bounds();
  const Eigen::Vector3d center = bounds.center();
  const CameraPose start = path.pose(0.0);
  Eigen::Vector3d front = start.eye - center;
  front -= front.dot(cylinder.up) * cylinder.up;
  if (!(front.norm() > 1e-12)) front = cylinder.up.unitOrthogonal();
  front.normalize();
  const Eigen::Vector3d side = cylinder.up.cross(front);
  const double azimuth = 30.0 * kPi / 180.0, elevation = 35.0 * kPi / 180.0;
  const Eigen::Vector3d direction =
      std::cos(elevation) * (std::cos(azimuth) * front + std::sin(azimuth) * side) + std::sin(elevation) * cylinder.up;
  Lens lens;
  lens.vertical_fov_deg = 30.0;
  lens.aspect = static_cast<double>(width) / height;
  lens.margin = 0.04;
  CameraPose pose{center + 1e-3 * bounds.diagonal() * direction, center, cylinder.up};
  pose.eye += fit_pullback(scene.positions, pose, lens) * direction;

  RenderOptions options;
  options.width = width;
  options.height = height;
  options.samples_per_pixel = samples_per_pixel;
  options.world_up = cylinder.up;
  const Renderer renderer(scene, options);
  return renderer.render(Camera::at(pose, lens.vertical_fov_deg));
}

}  // namespace meshtour
