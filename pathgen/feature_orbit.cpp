#include "pathgen/feature_orbit.h"

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/error.h"
#include "core/interrupt.h"
#include "pathgen/features.h"
#include "pathgen/motion.h"

namespace meshtour {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

// The conventional front of a model (as the turntable's): +Z for Y-up and X-up, -Y for Z-up.
Eigen::Vector3d front_direction(const Axis& up) {
  return up.index == 2 ? Eigen::Vector3d(-Eigen::Vector3d::UnitY()) : Eigen::Vector3d(Eigen::Vector3d::UnitZ());
}


std::vector<Eigen::Vector3d> used_points(const TriangleMesh& mesh) {
  std::vector<std::uint8_t> used(mesh.positions.size(), 0);
  for (const auto& t : mesh.triangles)
    for (std::uint32_t v : t) used[v] = 1;
  std::vector<Eigen::Vector3d> points;
  for (std::size_t v = 0; v < used.size(); ++v)
    if (used[v]) points.push_back(mesh.positions[v]);
  return points;
}

// Sets g.distance to a smooth envelope of the distance each direction of the orbit needs to keep
// every vertex in frame: least-squares two-harmonic fit, raised until it is nowhere too close.
void plan_dolly(const TriangleMesh& mesh, const FeatureOrbitOptions& options, FeatureOrbitGeometry& g) {
  const std::vector<Eigen::Vector3d> points = used_points(mesh);
  Lens lens;
  lens.vertical_fov_deg = options.vertical_fov_deg;
  lens.aspect = options.aspect;
  constexpr int kSamples = 72;
  const double start = 1e-6 * g.distance[0];
  Eigen::MatrixXd basis(kSamples, 5);
  Eigen::VectorXd needed(kSamples);
  for (int k = 0; k < kSamples; ++k) {
    const double a = static_cast<double>(k) / kSamples, x = 2.0 * std::numbers::pi * a;
    const Eigen::Vector3d dir = g.direction(a);
    const CameraPose near_center{g.center + start * dir, g.center, g.up};
    needed[k] = start + fit_pullback(points, near_center, lens);
    basis.row(k) << 1.0, std::cos(x), std::sin(x), std::cos(2.0 * x), std::sin(2.0 * x);
  }
  Eigen::VectorXd c = basis.colPivHouseholderQr().solve(needed);
  const Eigen::VectorXd residual = needed - basis * c;
  c[0] += std::max(0.0, residual.maxCoeff());
  for (int i = 0; i < 5; ++i) g.distance[i] = c[i];
}

}  // namespace

void FeatureOrbitOptions::validate() const {
  auto check = [](bool ok, const char* what) {
    if (!ok) throw InputError(std::string("feature orbit: ") + what);
  };
  check(base_min_deg <= base_max_deg && base_step_deg > 0.0, "the mean elevations need min <= max and a positive step");
  check(swing_max_deg >= 0.0 && swing_step_deg > 0.0, "the swing amplitudes need max >= 0 and a positive step");
  check(ripple_max_deg >= 0.0 && ripple_step_deg > 0.0, "the ripple amplitudes need max >= 0 and a positive step");
  check(phases >= 1 && phases <= 360, "phases must be 1 to 360");
  check(lowest_deg > -85.0 && highest_deg < 85.0 && lowest_deg < highest_deg, "elevations must stay within (-85, 85) degrees");
  check(max_angular_speed > 0.0 && max_angular_acceleration > 0.0, "the smoothness limits must be positive");
  check(surface_weight >= 0.0, "the surface weight must not be negative");
  check(azimuth_samples >= 4 && azimuth_samples <= 720, "azimuth samples must be 4 to 720");
  check(elevation_grid_deg > 0.0, "the elevation grid spacing must be positive");
  check(view_pixels >= 16 && view_pixels <= 2048, "view pixels must be 16 to 2048");
  check(seen_angle_deg > 0.0 && seen_angle_deg <= 90.0, "the seen-well angle must be in (0, 90]");
  check(feature_quantile >= 0.0 && feature_quantile <= 1.0, "the feature quantile must be in [0, 1]");
  check(vertical_fov_deg >= 5.0 && vertical_fov_deg <= 120.0, "the field of view must be 5 to 120 degrees");
  check(aspect > 0.0, "the aspect ratio must be positive");
}

double ElevationCurve::operator()(double a) const {
  constexpr double two_pi = 2.0 * std::numbers::pi;
  return base + swing * std::cos(two_pi * (a - swing_phase)) + ripple * std::cos(2.0 * two_pi * (a - ripple_phase));
}

Eigen::Vector3d FeatureOrbitGeometry::direction(double a) const {
  const double azimuth = 2.0 * std::numbers::pi * (a - std::floor(a));
  const double e = elevation(a - std::floor(a));
  return std::cos(e) * (std::cos(azimuth) * front + std::sin(azimuth) * side) + std::sin(e) * up;
}

double FeatureOrbitGeometry::distance_at(double a) const {
  const double x = 2.0 * std::numbers::pi * a;
  return distance[0] + distance[1] * std::cos(x) + distance[2] * std::sin(x) + distance[3] * std::cos(2.0 * x) +
         distance[4] * std::sin(2.0 * x);
}

CameraPose FeatureOrbitPath::pose(double t) const {
  return CameraPose{geometry_.center + geometry_.distance_at(t) * geometry_.direction(t), geometry_.center, geometry_.up};
}

std::pair<double, double> loop_angular_extremes(const std::function<Eigen::Vector3d(double)>& direction,
                                                const Eigen::Vector3d& up, int samples) {
  std::vector<Eigen::Vector3d> u(static_cast<std::size_t>(samples)), ups(u.size(), up);
  for (int k = 0; k < samples; ++k) u[k] = direction(static_cast<double>(k) / samples).normalized();
  const auto [speed, acceleration] = angular_motion(u, ups);
  return {speed * samples, acceleration * samples * samples};
}

std::vector<std::uint32_t> faces_seen_well(const TriangleMesh& mesh, const Eigen::Vector3d& eye,
                                           const Eigen::Vector3d& target, const Eigen::Vector3d& up, double fov_deg,
                                           int pixels, double seen_angle_deg) {
  const LookAtFrame frame = look_at(eye, target, up);
  const Eigen::Vector3d &forward = frame.forward, &right = frame.right, &cam_up = frame.up;
  const double tan_half = std::tan(0.5 * fov_deg * kDegree);
  const double size = static_cast<double>(pixels);

  struct Projected {
    double x, y, inv_z;
    bool valid;
  };
  std::vector<Projected> projected(mesh.positions.size());
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const Eigen::Vector3d d = mesh.positions[v] - eye;
    const double z = d.dot(forward);
    if (!(z > 1e-12)) {
      projected[v] = {0, 0, 0, false};
      continue;
    }
    const double sx = d.dot(right) / (z * tan_half), sy = d.dot(cam_up) / (z * tan_half);
    projected[v] = {0.5 * (sx + 1.0) * size, 0.5 * (1.0 - sy) * size, 1.0 / z, true};
  }

  const std::size_t pixel_count = static_cast<std::size_t>(pixels) * pixels;
  std::vector<double> depth(pixel_count, 0.0);  // 1/z of the nearest face, 0 = nothing
  std::vector<std::uint32_t> item(pixel_count, std::numeric_limits<std::uint32_t>::max());
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    if ((f & 0xffff) == 0) throw_if_interrupted();  // one view of a big mesh takes a while
    const auto& t = mesh.triangles[f];
    const Projected &a = projected[t[0]], &b = projected[t[1]], &c = projected[t[2]];
    if (!a.valid || !b.valid || !c.valid) continue;  // crosses the eye plane: cannot happen outside the model
    const double area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (!(std::abs(area) > 1e-12)) continue;
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x, b.x, c.x}) - 0.5)));
    const int x1 = std::min(pixels - 1, static_cast<int>(std::ceil(std::max({a.x, b.x, c.x}) - 0.5)));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y, b.y, c.y}) - 0.5)));
    const int y1 = std::min(pixels - 1, static_cast<int>(std::ceil(std::max({a.y, b.y, c.y}) - 0.5)));
    for (int py = y0; py <= y1; ++py) {
      for (int px = x0; px <= x1; ++px) {
        const double x = px + 0.5, y = py + 0.5;
        const double wa = ((b.x - x) * (c.y - y) - (b.y - y) * (c.x - x)) / area;
        const double wb = ((c.x - x) * (a.y - y) - (c.y - y) * (a.x - x)) / area;
        const double wc = 1.0 - wa - wb;
        if (wa < 0.0 || wb < 0.0 || wc < 0.0) continue;
        const double inv_z = wa * a.inv_z + wb * b.inv_z + wc * c.inv_z;
        const std::size_t p = static_cast<std::size_t>(py) * pixels + px;
        if (inv_z > depth[p]) {
          depth[p] = inv_z;
          item[p] = static_cast<std::uint32_t>(f);
        }
      }
    }
  }

  std::sort(item.begin(), item.end());
  item.erase(std::unique(item.begin(), item.end()), item.end());
  if (!item.empty() && item.back() == std::numeric_limits<std::uint32_t>::max()) item.pop_back();
  const double cos_limit = std::cos(seen_angle_deg * kDegree);
  std::vector<std::uint32_t> seen;
  for (std::uint32_t f : item) {
    const auto& t = mesh.triangles[f];
    const Eigen::Vector3d &p0 = mesh.positions[t[0]], &p1 = mesh.positions[t[1]], &p2 = mesh.positions[t[2]];
    const Eigen::Vector3d n = (p1 - p0).cross(p2 - p0);
    const Eigen::Vector3d to_eye = eye - (p0 + p1 + p2) / 3.0;
    const double norms = n.norm() * to_eye.norm();
    if (norms > 0.0 && std::abs(n.dot(to_eye)) > cos_limit * norms) seen.push_back(f);
  }
  return seen;
}

FeatureOrbitResult compute_feature_orbit(const TriangleMesh& mesh, const FeatureOrbitOptions& options) {
  options.validate();
  const SurfaceAnalysis surface = analyze_surface(mesh, options.surface);
  const std::vector<double> weights = input_face_weights(surface, mesh.triangles.size());
  return compute_feature_orbit(mesh, feature_faces(weights, face_areas(mesh), options.feature_quantile), options);
}

FeatureOrbitResult compute_feature_orbit(const TriangleMesh& mesh, const std::vector<std::uint8_t>& feature_face,
                                         const FeatureOrbitOptions& options) {
  options.validate();
  if (mesh.triangles.empty()) throw InputError("feature orbit: the mesh has no triangles");
  if (feature_face.size() != mesh.triangles.size()) throw InputError("feature orbit: one feature flag per face is needed");

  FeatureOrbitGeometry g;
  const Bounds bounds = mesh.bounds();
  g.center = bounds.center();
  g.up = options.up.vector();
  g.front = front_direction(options.up);
  g.side = g.up.cross(g.front);
  double radius = 0.0;
  for (const auto& t : mesh.triangles)
    for (std::uint32_t v : t) radius = std::max(radius, (mesh.positions[v] - g.center).norm());
  if (!(radius > 0.0)) throw InputError("feature orbit: all vertices coincide; nothing to look at");
  // The bounding sphere just fills the lens: every view of the orbit frames the whole model.
  const double sphere_distance = radius / std::sin(0.5 * options.vertical_fov_deg * kDegree);
  g.distance = {sphere_distance, 0.0, 0.0, 0.0, 0.0};

  // What is worth seeing: feature area counts 1, other area surface_weight, in shares of the feature area.
  const std::vector<double> areas = face_areas(mesh);
  double feature_area = 0.0, total_area = 0.0;
  for (std::size_t f = 0; f < areas.size(); ++f) {
    total_area += areas[f];
    if (feature_face[f]) feature_area += areas[f];
  }
  if (!(total_area > 0.0)) throw InputError("feature orbit: the mesh has no area");
  const double unit = feature_area > 0.0 ? feature_area : total_area;
  std::vector<double> value(areas.size());
  for (std::size_t f = 0; f < areas.size(); ++f) value[f] = areas[f] * (feature_face[f] ? 1.0 : options.surface_weight) / unit;

  const std::vector<Eigen::Vector3d> points = used_points(mesh);
  Lens lens;
  lens.vertical_fov_deg = options.vertical_fov_deg;
  lens.aspect = options.aspect;

  // Views on a grid of azimuths × elevations; a curve is scored with the view nearest to it at
  // each sampled azimuth.
  const int n = options.azimuth_samples;
  const int m = static_cast<int>(std::floor((options.highest_deg - options.lowest_deg) / options.elevation_grid_deg + 1e-9)) + 1;
  std::vector<std::vector<std::uint32_t>> views(static_cast<std::size_t>(n) * m);
  tbb::parallel_for(0, n * m, [&](int k) {
    throw_if_interrupted();
    const int j = k / m, e = k % m;
    const double azimuth = 2.0 * std::numbers::pi * j / n;
    const double elevation = (options.lowest_deg + e * options.elevation_grid_deg) * kDegree;
    const Eigen::Vector3d dir = std::cos(elevation) * (std::cos(azimuth) * g.front + std::sin(azimuth) * g.side) + std::sin(elevation) * g.up;
    // With the dolly each view is as close as framing the model allows, as the tour will be.
    double distance = sphere_distance;
    if (options.dolly) {
      const double start = 1e-6 * sphere_distance;
      distance = start + fit_pullback(points, CameraPose{g.center + start * dir, g.center, g.up}, lens);
    }
    views[k] = faces_seen_well(mesh, g.center + distance * dir, g.center, g.up, options.vertical_fov_deg,
                               options.view_pixels, options.seen_angle_deg);
  });

  std::vector<std::uint32_t> stamp(areas.size(), 0);
  std::uint32_t current = 0;
  auto score = [&](const ElevationCurve& curve, double* feature_share, double* surface_share) {
    ++current;
    double covered = 0.0, features = 0.0, surface = 0.0;
    for (int j = 0; j < n; ++j) {
      const double e = curve(static_cast<double>(j) / n) / kDegree;
      const int row = std::clamp(static_cast<int>(std::lround((e - options.lowest_deg) / options.elevation_grid_deg)), 0, m - 1);
      for (std::uint32_t f : views[static_cast<std::size_t>(j) * m + row]) {
        if (stamp[f] == current) continue;
        stamp[f] = current;
        covered += value[f];
        surface += areas[f];
        if (feature_face[f]) features += areas[f];
      }
    }
    if (feature_share) *feature_share = feature_area > 0.0 ? features / feature_area : 0.0;
    if (surface_share) *surface_share = surface / total_area;
    return covered;
  };
  auto feasible = [&](const ElevationCurve& curve) {
    const double lo = curve.base - std::abs(curve.swing) - std::abs(curve.ripple);
    const double hi = curve.base + std::abs(curve.swing) + std::abs(curve.ripple);
    if (lo < options.lowest_deg * kDegree - 1e-9 || hi > options.highest_deg * kDegree + 1e-9) return false;
    FeatureOrbitGeometry trial = g;
    trial.elevation = curve;
    const auto [speed, acceleration] = loop_angular_extremes([&](double a) { return trial.direction(a); }, g.up);
    return speed <= options.max_angular_speed && acceleration <= options.max_angular_acceleration;
  };

  // Search: mean elevation × swing × phase, then a ripple on top of the best. A level orbit at the
  // lowest mean elevation is always a candidate, so there is always a feasible curve.
  FeatureOrbitResult result;
  ElevationCurve best;
  best.base = std::clamp(0.0, options.base_min_deg, options.base_max_deg) * kDegree;
  double best_score = -1.0;
  auto consider = [&](const ElevationCurve& curve) {
    throw_if_interrupted();
    if (!feasible(curve)) return;
    ++result.candidates;
    const double s = score(curve, nullptr, nullptr);
    if (s > best_score + 1e-12) {
      best_score = s;
      best = curve;
    }
  };
  for (double base = options.base_min_deg; base <= options.base_max_deg + 1e-9; base += options.base_step_deg)
    for (double swing = 0.0; swing <= options.swing_max_deg + 1e-9; swing += options.swing_step_deg)
      for (int p = 0; p < (swing > 0.0 ? options.phases : 1); ++p)
        consider(ElevationCurve{base * kDegree, swing * kDegree, static_cast<double>(p) / options.phases, 0.0, 0.0});
  const ElevationCurve swing_only = best;
  for (double ripple = options.ripple_step_deg; ripple <= options.ripple_max_deg + 1e-9; ripple += options.ripple_step_deg)
    for (int p = 0; p < options.phases; ++p) {
      ElevationCurve curve = swing_only;
      curve.ripple = ripple * kDegree;
      curve.ripple_phase = 0.5 * p / options.phases;  // the ripple repeats every half loop
      consider(curve);
    }
  if (best_score < 0.0) throw InputError("feature orbit: no elevation curve meets the smoothness limits; raise them");

  g.elevation = best;
  score(best, &result.feature_share_seen, &result.surface_share_seen);
  if (options.dolly) plan_dolly(mesh, options, g);
  std::tie(result.angular_speed, result.angular_acceleration) = loop_angular_extremes([&](double a) { return g.direction(a); }, g.up);
  result.geometry = std::move(g);
  return result;
}

}  // namespace meshtour
