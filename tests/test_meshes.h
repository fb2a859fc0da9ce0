#pragma once
// Generated test meshes of docs/METHOD.md §17.1 (no files needed) and the transforms §17.8 applies
// to them: similarity transforms, vertex/face permutations, corner rotations.
// Header-only: only tests/<part>_*test.cpp files are compiled into the runners.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

#include "mesh/mesh.h"
#include "pathgen/surface.h"

namespace meshtour::test_meshes {

using Triangle = std::array<std::uint32_t, 3>;

/// Uniform double in [0, 1) from a mt19937_64 (the standard fixes its output sequence; the
/// standard distributions are not portable between library implementations, so they are not used).
inline double uniform(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

/// Standard normal sample (Box–Muller), portable for the same reason.
inline double gaussian(std::mt19937_64& rng) {
  const double u1 = 1.0 - uniform(rng), u2 = uniform(rng);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

/// Three draws as a vector, in a fixed order. The order in which a call's arguments are evaluated
/// is unspecified (GCC goes right to left, clang left to right), so `Vector3d(g(rng), g(rng),
/// g(rng))` builds other points, and other test meshes, under each compiler. The draws go z, y, x:
/// GCC's order, the one the tests' expectations were set with.
template <class Draw>
Eigen::Vector3d drawn_vector(Draw&& draw) {
  const double z = draw();
  const double y = draw();
  const double x = draw();
  return {x, y, z};
}

/// Icosphere of subdivision `level` on the unit sphere: 20·4^level faces, outward orientation.
inline TriangleMesh icosphere(int level) {
  TriangleMesh m;
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  const double base[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                              {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (const auto& p : base) m.positions.push_back(Eigen::Vector3d(p[0], p[1], p[2]).normalized());
  m.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8},   {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                 {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoint;
    const auto mid = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      const auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      const auto index = static_cast<std::uint32_t>(m.positions.size());
      m.positions.push_back((m.positions[a] + m.positions[b]).normalized());
      midpoint.emplace(key, index);
      return index;
    };
    std::vector<Triangle> next;
    next.reserve(m.triangles.size() * 4);
    for (const auto& f : m.triangles) {
      const std::uint32_t a = mid(f[0], f[1]), b = mid(f[1], f[2]), c = mid(f[2], f[0]);
      next.push_back({f[0], a, c});
      next.push_back({f[1], b, a});
      next.push_back({f[2], c, b});
      next.push_back({a, b, c});
    }
    m.triangles = std::move(next);
  }
  return m;
}

/// Ring torus around +Z: centre-circle radius R, tube radius r, nu × nv vertices, outward faces.
/// Vertex (i, j) = index i·nv + j has angle u = 2πi/nu around the axis, v = 2πj/nv around the tube
/// (v = 0 is the outer equator).
inline TriangleMesh torus(double R = 0.3, double r = 0.1, int nu = 192, int nv = 64) {
  TriangleMesh m;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = 2.0 * std::numbers::pi * i / nu, v = 2.0 * std::numbers::pi * j / nv;
      m.positions.emplace_back((R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v));
    }
  const auto id = [&](int i, int j) { return static_cast<std::uint32_t>(((i + nu) % nu) * nv + (j + nv) % nv); };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

/// Open cylinder around +Y: radius, height, `around` × `along` quads split in two (outward).
inline TriangleMesh open_cylinder(double radius = 0.2, double height = 0.8, int around = 128, int along = 128) {
  TriangleMesh m;
  for (int k = 0; k <= along; ++k)
    for (int i = 0; i < around; ++i) {
      const double a = 2.0 * std::numbers::pi * i / around;
      m.positions.emplace_back(radius * std::sin(a), height * k / along - height / 2, radius * std::cos(a));
    }
  const auto id = [&](int k, int i) { return static_cast<std::uint32_t>(k * around + (i + around) % around); };
  for (int k = 0; k < along; ++k)
    for (int i = 0; i < around; ++i) {
      m.triangles.push_back({id(k, i), id(k, i + 1), id(k + 1, i + 1)});
      m.triangles.push_back({id(k, i), id(k + 1, i + 1), id(k + 1, i)});
    }
  return m;
}

/// Plane z = 0 over [−0.5, 0.5]², n × n quads, every quad split along the same diagonal, so every
/// interior vertex has valence 6 (a regular triangulation).
inline TriangleMesh plane(int n = 64) {
  TriangleMesh m;
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) m.positions.emplace_back(static_cast<double>(x) / n - 0.5, static_cast<double>(y) / n - 0.5, 0.0);
  const auto id = [&](int x, int y) { return static_cast<std::uint32_t>(y * (n + 1) + x); };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      m.triangles.push_back({id(x, y), id(x + 1, y), id(x + 1, y + 1)});
      m.triangles.push_back({id(x, y), id(x + 1, y + 1), id(x, y + 1)});
    }
  return m;
}

/// 40 bump centres in the sector x > 0, y > 0 (above the equator for up = +Y), fixed seed.
inline std::vector<Eigen::Vector3d> bump_centres(int count = 40, std::uint64_t seed = 2024) {
  std::mt19937_64 rng(seed);
  std::vector<Eigen::Vector3d> centres;
  while (static_cast<int>(centres.size()) < count) {
    const Eigen::Vector3d d = drawn_vector([&] { return gaussian(rng); });
    if (d.norm() < 1e-9 || d.x() <= 0.0 || d.y() <= 0.0) continue;
    centres.push_back(d.normalized());
  }
  return centres;
}

/// Bumpy sphere of §17.1: icosphere with radius 1 + Σ_k 0.03·exp(−(angle(p, c_k)/0.08)²), plus
/// Gaussian radial noise of standard deviation `noise` (model units) if noise > 0.
inline TriangleMesh bumpy_sphere(int level = 5, double noise = 0.0, std::uint64_t seed = 7) {
  TriangleMesh m = icosphere(level);
  const auto centres = bump_centres();
  std::mt19937_64 rng(seed);
  for (auto& p : m.positions) {
    double radius = 1.0;
    for (const auto& c : centres) {
      const double angle = std::acos(std::clamp(p.dot(c), -1.0, 1.0));
      radius += 0.03 * std::exp(-(angle / 0.08) * (angle / 0.08));
    }
    if (noise > 0.0) radius += noise * gaussian(rng);
    p *= radius;
  }
  return m;
}

/// p ← scale·Q·p + shift for every vertex.
inline TriangleMesh transformed(TriangleMesh m, double scale, const Eigen::Matrix3d& rotation, const Eigen::Vector3d& shift) {
  for (auto& p : m.positions) p = scale * (rotation * p) + shift;
  return m;
}

/// Random renumbering of vertices and faces and a random cyclic rotation of each face's corners.
/// `vertex_map[old] = new`, `face_map[old] = new` are returned for comparing results.
struct Permuted {
  TriangleMesh mesh;
  std::vector<std::uint32_t> vertex_map;
  std::vector<std::uint32_t> face_map;
};
inline Permuted permuted(const TriangleMesh& m, std::uint64_t seed, bool rotate_corners = true) {
  std::mt19937_64 rng(seed);
  const auto shuffle = [&](std::vector<std::uint32_t>& v) {
    for (std::size_t i = v.size(); i > 1; --i) std::swap(v[i - 1], v[rng() % i]);
  };
  Permuted out;
  out.vertex_map.resize(m.positions.size());
  out.face_map.resize(m.triangles.size());
  for (std::uint32_t i = 0; i < out.vertex_map.size(); ++i) out.vertex_map[i] = i;
  for (std::uint32_t i = 0; i < out.face_map.size(); ++i) out.face_map[i] = i;
  shuffle(out.vertex_map);
  shuffle(out.face_map);
  out.mesh.positions.resize(m.positions.size());
  for (std::size_t v = 0; v < m.positions.size(); ++v) out.mesh.positions[out.vertex_map[v]] = m.positions[v];
  out.mesh.triangles.resize(m.triangles.size());
  for (std::size_t f = 0; f < m.triangles.size(); ++f) {
    Triangle t{out.vertex_map[m.triangles[f][0]], out.vertex_map[m.triangles[f][1]], out.vertex_map[m.triangles[f][2]]};
    if (rotate_corners) std::rotate(t.begin(), t.begin() + static_cast<long>(rng() % 3), t.end());
    out.mesh.triangles[out.face_map[f]] = t;
  }
  return out;
}

/// The same surface as a triangle soup: every face has its own three vertex copies (STL style).
inline TriangleMesh soup(const TriangleMesh& m) {
  TriangleMesh out;
  for (const auto& t : m.triangles) {
    const auto base = static_cast<std::uint32_t>(out.positions.size());
    for (std::uint32_t v : t) out.positions.push_back(m.positions[v]);
    out.triangles.push_back({base, base + 1, base + 2});
  }
  return out;
}

/// Two meshes as one (the second's indices shifted).
inline TriangleMesh combined(const TriangleMesh& a, const TriangleMesh& b) {
  TriangleMesh out = a;
  const auto base = static_cast<std::uint32_t>(a.positions.size());
  out.positions.insert(out.positions.end(), b.positions.begin(), b.positions.end());
  for (const auto& t : b.triangles) out.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  return out;
}

/// One 1-to-4 split at edge midpoints: the same shape with four times the faces. The original
/// vertices keep their indices; face f becomes faces 4f..4f+3 (4f+3 the middle one). Edges are
/// numbered by sorting the corners' edge keys, which stays fast at benchmark sizes (17.8M faces).
inline TriangleMesh split_at_midpoints(const TriangleMesh& in) {
  const std::size_t corners = 3 * in.triangles.size();
  std::vector<std::pair<std::uint64_t, std::uint32_t>> edges(corners);
  for (std::size_t f = 0; f < in.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t a = in.triangles[f][k], b = in.triangles[f][(k + 1) % 3];
      edges[3 * f + k] = {std::min(a, b) << 32 | std::max(a, b), static_cast<std::uint32_t>(3 * f + k)};
    }
  std::sort(edges.begin(), edges.end());
  TriangleMesh out;
  out.positions = in.positions;
  std::vector<std::uint32_t> midpoint(corners);
  for (std::size_t i = 0; i < corners; ++i) {
    if (i == 0 || edges[i].first != edges[i - 1].first) {
      const std::uint64_t key = edges[i].first;
      out.positions.push_back(0.5 * (in.positions[key >> 32] + in.positions[key & 0xffffffffu]));
    }
    midpoint[edges[i].second] = static_cast<std::uint32_t>(out.positions.size() - 1);
  }
  out.triangles.reserve(4 * in.triangles.size());
  for (std::size_t f = 0; f < in.triangles.size(); ++f) {
    const auto& t = in.triangles[f];
    const std::uint32_t m0 = midpoint[3 * f], m1 = midpoint[3 * f + 1], m2 = midpoint[3 * f + 2];
    out.triangles.push_back({t[0], m0, m2});
    out.triangles.push_back({t[1], m1, m0});
    out.triangles.push_back({t[2], m2, m1});
    out.triangles.push_back({m0, m1, m2});
  }
  return out;
}

/// Share of a unit sphere's area seen well from distance `distance` (no occlusion but its own):
/// a point at angle θ from the camera axis is seen well when the angle between its normal and the
/// direction to the eye is below `angle_deg`, i.e. (D cos θ − 1) / |eye − p| > cos(angle); the cap
/// up to θmax holds (1 − cos θmax) / 2 of the area.
inline double sphere_seen_well_share(double distance, double angle_deg) {
  const double D = distance, limit = std::cos(angle_deg * std::numbers::pi / 180.0);
  double lo = 0.0, hi = std::numbers::pi / 2;
  for (int i = 0; i < 100; ++i) {
    const double th = 0.5 * (lo + hi);
    const double c = (D * std::cos(th) - 1.0) / std::sqrt(D * D - 2.0 * D * std::cos(th) + 1.0);
    (c > limit ? lo : hi) = th;
  }
  return 0.5 * (1.0 - std::cos(lo));
}

/// Rotation by `angle` (radians) about `axis`.
inline Eigen::Matrix3d rotation(const Eigen::Vector3d& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

/// A UV sphere of `radius` centred at the origin (poles on ±Y), for renderer tests; optionally
/// with per-vertex colours (sRGB values) varying with latitude and longitude.
inline TriangleMesh uv_sphere(double radius = 1.0, int segments = 64, int rings = 32, bool colored = false) {
  TriangleMesh m;
  for (int j = 0; j <= rings; ++j)
    for (int i = 0; i < segments; ++i) {
      const double th = std::numbers::pi * j / rings, ph = 2 * std::numbers::pi * i / segments;
      m.positions.emplace_back(radius * std::sin(th) * std::cos(ph), radius * std::cos(th), radius * std::sin(th) * std::sin(ph));
      if (colored)
        m.colors.emplace_back(0.5f + 0.5f * static_cast<float>(std::cos(ph)), static_cast<float>(j) / rings,
                              0.5f + 0.5f * static_cast<float>(std::sin(3 * ph)));
    }
  for (int j = 0; j < rings; ++j)
    for (int i = 0; i < segments; ++i) {
      const auto a = static_cast<std::uint32_t>(j * segments + i), b = static_cast<std::uint32_t>(j * segments + (i + 1) % segments);
      const auto c = a + static_cast<std::uint32_t>(segments), d = b + static_cast<std::uint32_t>(segments);
      m.triangles.push_back({a, c, b});
      m.triangles.push_back({b, c, d});
    }
  return m;
}

/// §3–§8 options with smoothing off, as most §17 checks are stated.
/// The specification's patch stage: ε in units of the bounding-box diagonal (the default is I-34's
/// 2.5 times tighter box-half-extent). The synthetic surfaces' expected counts are the
/// specification's: a clean icosphere is one patch only under its ε.
inline SurfaceOptions specification_units() {
  SurfaceOptions o;
  o.tolerance_unit = ToleranceUnit::diagonal;
  return o;
}

/// The specification's patch stage without smoothing.
inline SurfaceOptions no_smoothing() {
  SurfaceOptions o = specification_units();
  o.smoothing = SmoothingMethod::none;
  return o;
}

}  // namespace meshtour::test_meshes
