#include "evaluate/evaluate.h"

#include <embree3/rtcore.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>

#include "core/error.h"
#include "core/interrupt.h"
#include "mesh/convex_hull.h"
#include "pathgen/motion.h"

namespace meshtour {
namespace {

struct DeviceRelease {
  void operator()(RTCDevice d) const { rtcReleaseDevice(d); }
};
struct SceneRelease {
  void operator()(RTCScene s) const { rtcReleaseScene(s); }
};
using DeviceHandle = std::unique_ptr<RTCDeviceTy, DeviceRelease>;
using SceneHandle = std::unique_ptr<RTCSceneTy, SceneRelease>;

// The camera frame the tracer uses (tracer/renderer.cpp): right = forward × up, up' = right × forward.
struct CameraFrame {
  Eigen::Vector3d forward, right, up;
  double tan_half = 0.0;
};

CameraFrame camera_frame(const Camera& camera) {
  CameraFrame f;
  const LookAtFrame view = look_at(camera);
  f.forward = view.forward;
  f.right = view.right;
  f.up = view.up;
  f.tan_half = std::tan(camera.vertical_fov_deg * std::numbers::pi / 360.0);
  return f;
}

}  // namespace

void EvaluationOptions::validate() const {
  if (long_side_pixels < 8 || long_side_pixels > 8192)
    throw InputError("the item buffer's long side must be 8 to 8192 pixels, got " + std::to_string(long_side_pixels));
  if (!(seen_angle_deg > 0.0 && seen_angle_deg <= 90.0))
    throw InputError("the seen-well angle must be above 0 and at most 90 degrees");
  if (!(region_seen_share > 0.0 && region_seen_share <= 1.0))
    throw InputError("the share of a feature region that must be seen must be above 0 and at most 1");
}

FeatureRegions feature_regions(const TriangleMesh& mesh, const std::vector<std::uint8_t>& feature_face) {
  if (feature_face.size() != mesh.triangles.size()) throw InputError("feature regions: one flag per face is needed");
  // Union-find over feature faces that share an edge (edges found by sorting (a, b, face) keys).
  std::vector<int> parent(mesh.triangles.size());
  for (std::size_t f = 0; f < parent.size(); ++f) parent[f] = static_cast<int>(f);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  struct EdgeKey {
    std::uint32_t a, b;
    int face;
  };
  std::vector<EdgeKey> edges;
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    if (!feature_face[f]) continue;
    const auto& t = mesh.triangles[f];
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t a = t[c], b = t[(c + 1) % 3];
      edges.push_back({std::min(a, b), std::max(a, b), static_cast<int>(f)});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const EdgeKey& x, const EdgeKey& y) {
    return x.a != y.a ? x.a < y.a : x.b != y.b ? x.b < y.b : x.face < y.face;
  });
  for (std::size_t k = 1; k < edges.size(); ++k)
    if (edges[k].a == edges[k - 1].a && edges[k].b == edges[k - 1].b) {
      const int x = find(edges[k].face), y = find(edges[k - 1].face);
      if (x != y) parent[std::max(x, y)] = std::min(x, y);
    }
  FeatureRegions regions;
  regions.face_region.assign(mesh.triangles.size(), -1);
  std::vector<int> id(mesh.triangles.size(), -1);
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    if (!feature_face[f]) continue;
    const int root = find(static_cast<int>(f));
    if (id[root] < 0) id[root] = regions.count++;
    regions.face_region[f] = id[root];
  }
  return regions;
}

struct PathEvaluator::Impl {
  EvaluationOptions options;
  DeviceHandle device;
  SceneHandle scene;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // the Embree scene is stored relative to this
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  // centre of the bounding box
  std::vector<Eigen::Vector3d> normals, centroids;
  std::vector<double> areas;
  // The convex hull's vertices of the vertices some face uses: whether every vertex is in frame
  // is decided by them (count_out_of_frame's test is a largest value of linear functions).
  std::vector<Eigen::Vector3d> hull_points;
  std::vector<std::uint8_t> feature_face;
  FeatureRegions regions;
  std::vector<double> region_area;

  std::vector<std::uint8_t> seen_well(const Camera& camera, double aspect) const {
    const CameraFrame f = camera_frame(camera);
    int width = options.long_side_pixels, height = options.long_side_pixels;
    if (aspect >= 1.0)
      height = std::max(1, static_cast<int>(std::lround(width / aspect)));
    else
      width = std::max(1, static_cast<int>(std::lround(height * aspect)));
    std::vector<std::uint32_t> item(static_cast<std::size_t>(width) * height, RTC_INVALID_GEOMETRY_ID);
    const Eigen::Vector3f eye = (camera.eye - origin).cast<float>();
    tbb::parallel_for(0, height, [&](int y) {
      RTCIntersectContext context;
      rtcInitIntersectContext(&context);
      for (int x = 0; x < width; ++x) {
        const double sx = (2.0 * (x + 0.5) / width - 1.0) * f.tan_half * (static_cast<double>(width) / height);
        const double sy = (1.0 - 2.0 * (y + 0.5) / height) * f.tan_half;
        const Eigen::Vector3f d = (f.forward + sx * f.right + sy * f.up).normalized().cast<float>();
        RTCRayHit rh{};
        rh.ray.org_x = eye.x();
        rh.ray.org_y = eye.y();
        rh.ray.org_z = eye.z();
        rh.ray.dir_x = d.x();
        rh.ray.dir_y = d.y();
        rh.ray.dir_z = d.z();
        rh.ray.tnear = 0.0f;
        rh.ray.tfar = std::numeric_limits<float>::infinity();
        rh.ray.mask = 0xFFFFFFFFu;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene.get(), &context, &rh);
        if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) item[static_cast<std::size_t>(y) * width + x] = rh.hit.primID;
      }
    });
    std::vector<std::uint8_t> seen(normals.size(), 0);
    const double cos_limit = std::cos(options.seen_angle_deg * std::numbers::pi / 180.0);
    for (std::uint32_t face : item) {
      if (face == RTC_INVALID_GEOMETRY_ID || seen[face]) continue;
      const Eigen::Vector3d to_eye = (camera.eye - centroids[face]).normalized();
      if (std::abs(normals[face].dot(to_eye)) > cos_limit) seen[face] = 1;
    }
    return seen;
  }
};

PathEvaluator::PathEvaluator(const TriangleMesh& mesh, std::vector<std::uint8_t> feature_face,
                             const EvaluationOptions& options)
    : impl_(std::make_unique<Impl>()) {
  options.validate();
  if (mesh.triangles.empty()) throw InputError("the mesh has no triangles to evaluate");
  if (feature_face.size() != mesh.triangles.size()) throw InputError("evaluation: one feature flag per face is needed");
  Impl& s = *impl_;
  s.options = options;
  s.feature_face = std::move(feature_face);
  const Bounds bounds = mesh.bounds();
  s.origin = s.center = bounds.center();

  const std::size_t faces = mesh.triangles.size();
  s.normals.resize(faces);
  s.centroids.resize(faces);
  s.areas.resize(faces);
  for (std::size_t f = 0; f < faces; ++f) {
    const auto& t = mesh.triangles[f];
    const Eigen::Vector3d &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
    const Eigen::Vector3d n = (b - a).cross(c - a);
    s.areas[f] = 0.5 * n.norm();
    s.normals[f] = s.areas[f] > 0.0 ? Eigen::Vector3d(n.normalized()) : Eigen::Vector3d::Zero();
    s.centroids[f] = (a + b + c) / 3.0;
  }
  s.hull_points = convex_hull_vertices(mesh);

  s.regions = feature_regions(mesh, s.feature_face);
  s.region_area.assign(static_cast<std::size_t>(s.regions.count), 0.0);
  for (std::size_t f = 0; f < faces; ++f)
    if (s.regions.face_region[f] >= 0) s.region_area[s.regions.face_region[f]] += s.areas[f];

  s.device.reset(rtcNewDevice("threads=0"));
  if (!s.device) throw RuntimeFailure("Embree could not create a device for the evaluation");
  s.scene.reset(rtcNewScene(s.device.get()));
  RTCGeometry geometry = rtcNewGeometry(s.device.get(), RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                               3 * sizeof(float), mesh.positions.size()));
  auto* indices = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                      3 * sizeof(std::uint32_t), faces));
  if (!vertices || !indices) {
    rtcReleaseGeometry(geometry);
    throw RuntimeFailure("Embree could not allocate the evaluation's geometry");
  }
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const Eigen::Vector3f p = (mesh.positions[v] - s.origin).cast<float>();
    vertices[3 * v] = p.x();
    vertices[3 * v + 1] = p.y();
    vertices[3 * v + 2] = p.z();
  }
  for (std::size_t f = 0; f < faces; ++f)
    for (int c = 0; c < 3; ++c) indices[3 * f + c] = mesh.triangles[f][c];
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(s.scene.get(), geometry);
  rtcReleaseGeometry(geometry);
  rtcSetSceneBuildQuality(s.scene.get(), RTC_BUILD_QUALITY_HIGH);
  rtcSetSceneProgressMonitorFunction(s.scene.get(), [](void*, double) { return !interrupt_requested(); }, nullptr);
  rtcCommitScene(s.scene.get());
  throw_if_interrupted();  // a cancelled build is an interrupt, not an Embree failure
  if (rtcGetDeviceError(s.device.get()) != RTC_ERROR_NONE) throw RuntimeFailure("Embree failed to build the evaluation's scene");
}

PathEvaluator::~PathEvaluator() = default;

const std::vector<std::uint8_t>& PathEvaluator::feature_face() const { return impl_->feature_face; }
const FeatureRegions& PathEvaluator::regions() const { return impl_->regions; }

std::vector<std::uint8_t> PathEvaluator::seen_well(const Camera& camera, double aspect) const {
  if (!(aspect > 0.0)) throw InputError("the frame's aspect ratio must be positive");
  return impl_->seen_well(camera, aspect);
}

PathEvaluation PathEvaluator::evaluate(std::span<const Camera> cameras, double aspect) const {
  if (cameras.empty()) throw InputError("evaluation: the tour has no frames");
  if (!(aspect > 0.0)) throw InputError("the frame's aspect ratio must be positive");
  const Impl& s = *impl_;
  const std::size_t faces = s.areas.size();
  std::vector<int> seen_frames(faces, 0);
  std::vector<int> region_frames(static_cast<std::size_t>(s.regions.count), 0);
  std::vector<double> region_seen(static_cast<std::size_t>(s.regions.count));
  for (const Camera& camera : cameras) {
    throw_if_interrupted();
    const std::vector<std::uint8_t> seen = s.seen_well(camera, aspect);
    std::fill(region_seen.begin(), region_seen.end(), 0.0);
    for (std::size_t f = 0; f < faces; ++f) {
      if (!seen[f]) continue;
      ++seen_frames[f];
      if (s.regions.face_region[f] >= 0) region_seen[s.regions.face_region[f]] += s.areas[f];
    }
    for (int r = 0; r < s.regions.count; ++r)
      if (region_seen[r] >= s.options.region_seen_share * s.region_area[r] && s.region_area[r] > 0.0) ++region_frames[r];
  }

  PathEvaluation out;
  out.frames = static_cast<int>(cameras.size());
  double total = 0.0, covered = 0.0, feature_total = 0.0, feature_covered = 0.0;
  for (std::size_t f = 0; f < faces; ++f) {
    total += s.areas[f];
    if (seen_frames[f] > 0) covered += s.areas[f];
    if (s.feature_face[f]) {
      feature_total += s.areas[f];
      if (seen_frames[f] > 0) feature_covered += s.areas[f];
    }
  }
  out.surface_coverage = total > 0.0 ? covered / total : 0.0;
  out.feature_coverage = feature_total > 0.0 ? feature_covered / feature_total : 0.0;
  if (!region_frames.empty()) {
    std::vector<int> sorted = region_frames;
    std::sort(sorted.begin(), sorted.end());
    out.feature_min_frames = sorted.front();
    const std::size_t n = sorted.size();
    out.feature_median_frames = n % 2 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
  }
  measure_motion(cameras, s.center, out);
  out.frames_out_of_frame = count_out_of_frame(cameras, s.hull_points, aspect);
  return out;
}

void measure_motion(std::span<const Camera> cameras, const Eigen::Vector3d& center, PathEvaluation& out) {
  std::vector<Eigen::Vector3d> position(cameras.size()), view(cameras.size()), up(cameras.size());
  for (std::size_t k = 0; k < cameras.size(); ++k) {
    position[k] = (cameras[k].eye - center).normalized();
    view[k] = (cameras[k].target - cameras[k].eye).normalized();
    up[k] = cameras[k].up;
  }
  std::tie(out.camera_max_angular_speed, out.camera_max_angular_acceleration) = angular_motion(position, up);
  std::tie(out.view_max_angular_speed, out.view_max_angular_acceleration) = angular_motion(view, up);
}

int count_out_of_frame(std::span<const Camera> cameras, const std::vector<Eigen::Vector3d>& points, double aspect) {
  int count = 0;
  for (const Camera& camera : cameras) {
    const CameraFrame f = camera_frame(camera);
    // A hair of tolerance: the fitted field of view puts the extreme vertex exactly on its margin.
    const double limit_y = f.tan_half * (1.0 + 1e-9), limit_x = f.tan_half * aspect * (1.0 + 1e-9);
    for (const Eigen::Vector3d& p : points) {
      const Eigen::Vector3d d = p - camera.eye;
      const double z = d.dot(f.forward);
      if (!(z > 0.0) || std::abs(d.dot(f.up)) > limit_y * z || std::abs(d.dot(f.right)) > limit_x * z) {
        ++count;
        break;
      }
    }
  }
  return count;
}

std::string evaluation_json(const std::vector<std::pair<std::string, PathEvaluation>>& modes) {
  nlohmann::ordered_json doc;
  nlohmann::ordered_json& by_mode = doc["modes"];
  by_mode = nlohmann::ordered_json::object();
  for (const auto& [name, e] : modes) {
    by_mode[name] = {
        {"feature_coverage", e.feature_coverage},
        {"surface_coverage", e.surface_coverage},
        {"feature_min_frames", e.feature_min_frames},
        {"feature_median_frames", e.feature_median_frames},
        {"camera_max_angular_speed", e.camera_max_angular_speed},
        {"view_max_angular_speed", e.view_max_angular_speed},
        {"view_max_angular_acceleration", e.view_max_angular_acceleration},
        {"frames_out_of_frame", e.frames_out_of_frame},
    };
  }
  return doc.dump(2) + "\n";
}

}  // namespace meshtour
