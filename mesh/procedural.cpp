// The built-in sculpture. It is made here rather than shipped as a file so that the default tour
// needs no download, and it is built to exercise what the camera path looks for: flat faces and
// sharp rims (the pedestal), a hole (the ring), and localized bumps on one side (the sphere).
#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <map>
#include <numbers>

#include "mesh/mesh.h"

namespace meshtour {
namespace {

constexpr double kPi = std::numbers::pi;

class MeshBuilder {
public:
  explicit MeshBuilder(TriangleMesh& mesh) : mesh_(mesh) {}

  std::uint32_t vertex(const Eigen::Vector3d& p, const Eigen::Vector3f& color) {
    mesh_.positions.push_back(p);
    mesh_.colors.push_back(color);
    return static_cast<std::uint32_t>(mesh_.positions.size() - 1);
  }
  void triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c) { mesh_.triangles.push_back({a, b, c}); }
  void quad(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
    triangle(a, b, c);
    triangle(a, c, d);
  }

  /// A (u, v) grid, u in [0,1) periodic, v in [0,1] (closed in v too when periodic_v).
  /// `surface(u, v)` must be counter-clockwise-oriented for increasing u then v.
  void grid(int nu, int nv, bool periodic_v, const Eigen::Vector3f& color,
            const std::function<Eigen::Vector3d(double, double)>& surface) {
    const int rows = periodic_v ? nv : nv + 1;
    const auto base = static_cast<std::uint32_t>(mesh_.positions.size());
    for (int j = 0; j < rows; ++j)
      for (int i = 0; i < nu; ++i) vertex(surface(double(i) / nu, double(j) / nv), color);
    auto at = [&](int i, int j) { return base + static_cast<std::uint32_t>((j % rows) * nu + (i % nu)); };
    for (int j = 0; j < nv; ++j)
      for (int i = 0; i < nu; ++i) quad(at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
  }

private:
  TriangleMesh& mesh_;
};

// Flat disc at height y facing +Y (up) or -Y, as concentric rings so triangles stay well shaped.
void add_disc(MeshBuilder& b, const Eigen::Vector3d& center, double radius, int segments, int rings,
              bool facing_up, const Eigen::Vector3f& color) {
  const std::uint32_t c = b.vertex(center, color);
  std::vector<std::uint32_t> previous;
  for (int r = 1; r <= rings; ++r) {
    std::vector<std::uint32_t> ring;
    const double rr = radius * r / rings;
    for (int i = 0; i < segments; ++i) {
      const double a = 2 * kPi * i / segments;
      ring.push_back(b.vertex(center + Eigen::Vector3d(rr * std::cos(a), 0, rr * std::sin(a)), color));
    }
    for (int i = 0; i < segments; ++i) {
      const int k = (i + 1) % segments;
      if (r == 1) {
        facing_up ? b.triangle(c, ring[k], ring[i]) : b.triangle(c, ring[i], ring[k]);
      } else {
        facing_up ? b.quad(previous[i], previous[k], ring[k], ring[i])
                  : b.quad(previous[i], ring[i], ring[k], previous[k]);
      }
    }
    previous = std::move(ring);
  }
}

// Icosphere with radial displacement `radius(direction)`.
void add_icosphere(MeshBuilder& b, TriangleMesh& mesh, const Eigen::Vector3d& center, int levels,
                   const std::function<double(const Eigen::Vector3d&)>& radius, const Eigen::Vector3f& color) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> dirs = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                                       {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& d : dirs) d.normalize();
  std::vector<std::array<std::uint32_t, 3>> faces = {
      {0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
      {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoints;
    auto midpoint = [&](std::uint32_t a, std::uint32_t c) {
      const auto key = std::minmax(a, c);
      if (auto it = midpoints.find(key); it != midpoints.end()) return it->second;
      dirs.push_back((dirs[a] + dirs[c]).normalized());
      const auto id = static_cast<std::uint32_t>(dirs.size() - 1);
      midpoints.emplace(key, id);
      return id;
    };
    std::vector<std::array<std::uint32_t, 3>> next;
    next.reserve(faces.size() * 4);
    for (const auto& f : faces) {
      const auto ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
      next.push_back({f[0], ab, ca});
      next.push_back({f[1], bc, ab});
      next.push_back({f[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    faces = std::move(next);
  }
  const auto base = static_cast<std::uint32_t>(mesh.positions.size());
  for (const auto& d : dirs) b.vertex(center + radius(d) * d, color);
  for (const auto& f : faces) b.triangle(base + f[0], base + f[1], base + f[2]);
}

}  // namespace

TriangleMesh make_sculpture(double detail) {
  const double s = std::sqrt(std::max(detail, 0.05));  // detail scales the triangle count ~linearly
  auto count = [&](int n) { return std::max(8, static_cast<int>(std::lround(n * s))); };
  TriangleMesh mesh;
  MeshBuilder b(mesh);

  const Eigen::Vector3f stone(0.42f, 0.40f, 0.38f), bronze(0.72f, 0.48f, 0.26f), marble(0.88f, 0.87f, 0.84f);

  // Pedestal: a squat cylinder, flat top and bottom with sharp rims, curved side.
  const double pedestal_radius = 0.85, pedestal_height = 0.3;
  const int segments = count(160);
  b.grid(segments, count(10), false, stone, [&](double u, double v) {
    const double a = -2 * kPi * u;  // clockwise in u so the side faces outwards
    return Eigen::Vector3d(pedestal_radius * std::cos(a), pedestal_height * v, pedestal_radius * std::sin(a));
  });
  add_disc(b, {0, pedestal_height, 0}, pedestal_radius, segments, count(12), true, stone);
  add_disc(b, {0, 0, 0}, pedestal_radius, segments, count(12), false, stone);

  // Ring: a torus standing upright on the pedestal (the hole), with a gentle twist of ridges.
  const double ring_major = 0.45, ring_minor = 0.11;
  const Eigen::Vector3d ring_center(-0.28, pedestal_height + ring_major + ring_minor - 0.02, -0.05);
  b.grid(count(200), count(56), true, bronze, [&](double u, double v) {
    const double a = 2 * kPi * u, c = 2 * kPi * v;
    const double ridge = 1.0 + 0.12 * std::cos(7 * a + 2 * c) * 0.5;
    const double r = ring_minor * ridge;
    const double rr = ring_major + r * std::cos(c);
    return Eigen::Vector3d(ring_center.x() + rr * std::cos(a), ring_center.y() + rr * std::sin(a),
                           ring_center.z() + r * std::sin(c));
  });

  // Bumpy sphere: Gaussian bumps clustered on its upper front, smooth elsewhere.
  const double sphere_radius = 0.27;
  const Eigen::Vector3d sphere_center(0.42, pedestal_height + sphere_radius * 0.97, 0.18);
  std::vector<Eigen::Vector3d> bumps;
  for (int k = 0; k < 14; ++k) {
    const double phi = 0.25 + 0.9 * (k % 5) / 4.0, theta = -0.3 + 1.6 * (k / 5) / 2.0 + 0.15 * (k % 2);
    bumps.push_back(Eigen::Vector3d(std::cos(theta) * std::sin(phi), std::cos(phi), std::sin(theta) * std::sin(phi)));
  }
  const int levels = detail >= 0.6 ? 5 : 4;
  add_icosphere(b, mesh, sphere_center, levels, [&](const Eigen::Vector3d& d) {
    double r = 1.0;
    for (const auto& c : bumps) {
      const double angle = std::acos(std::clamp(d.dot(c.normalized()), -1.0, 1.0));
      r += 0.12 * std::exp(-std::pow(angle / 0.16, 2));
    }
    return sphere_radius * r;
  }, marble);

  return mesh;
}

}  // namespace meshtour
