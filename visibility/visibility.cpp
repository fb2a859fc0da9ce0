#include "visibility/visibility.h"

#include <embree3/rtcore.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/error.h"
#include "core/interrupt.h"
#include "core/triangle_geometry.h"

namespace meshtour {
namespace {

// Samples are tested in blocks of this many: one task, one result list, concatenated in order.
constexpr std::size_t kBlock = 2048;

}  // namespace

SurfaceSamples sample_surface(const TriangleMesh& mesh, std::size_t count) {
  if (count < 1) throw InputError("surface sampling needs at least one sample");
  const std::size_t faces = mesh.triangles.size();
  std::vector<double> area(faces);
  double total = 0.0;
  for (std::size_t f = 0; f < faces; ++f) {
    const auto& t = mesh.triangles[f];
    const Eigen::Vector3d &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
    area[f] = triangle_area(a, b, c);
    if (!std::isfinite(area[f])) area[f] = 0.0;
    total += area[f];
  }
  if (!(total > 0.0)) throw InputError("the mesh has no surface area to sample");

  SurfaceSamples s;
  s.area_per_sample = total / static_cast<double>(count);
  s.points.reserve(count);
  s.normals.reserve(count);
  s.faces.reserve(count);
  s.barycentric.reserve(count);
  // The R2 sequence (generalised golden ratio in 2-D) places the samples that fall in one face
  // evenly inside it; folding the unit square onto the triangle keeps the spread.
  constexpr double kPhi2 = 1.32471795724474602596;
  constexpr double kA1 = 1.0 / kPhi2, kA2 = 1.0 / (kPhi2 * kPhi2);
  double before = 0.0;  // area of the faces before f
  std::size_t next = 0;
  for (std::size_t f = 0; f < faces && next < count; ++f) {
    const double end = before + area[f];
    while (next < count && (static_cast<double>(next) + 0.5) * s.area_per_sample < end) {
      double u = std::fmod(0.5 + kA1 * static_cast<double>(next), 1.0);
      double v = std::fmod(0.5 + kA2 * static_cast<double>(next), 1.0);
      if (u + v > 1.0) {
        u = 1.0 - u;
        v = 1.0 - v;
      }
      const auto& t = mesh.triangles[f];
      const Eigen::Vector3d &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
      s.points.push_back(a + u * (b - a) + v * (c - a));
      s.normals.push_back(triangle_normal(a, b, c));
      s.faces.push_back(static_cast<std::uint32_t>(f));
      s.barycentric.emplace_back(u, v);
      ++next;
    }
    before = end;
  }
  // Rounding can leave the last sample or two past the running sum: they go to the last face with area.
  for (std::size_t f = faces; next < count && f-- > 0;) {
    if (!(area[f] > 0.0)) continue;
    const auto& t = mesh.triangles[f];
    const Eigen::Vector3d &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
    while (next < count) {
      s.points.push_back((a + b + c) / 3.0);
      s.normals.push_back(triangle_normal(a, b, c));
      s.faces.push_back(static_cast<std::uint32_t>(f));
      s.barycentric.emplace_back(1.0 / 3.0, 1.0 / 3.0);
      ++next;
    }
  }
  return s;
}

struct VisibilityScene::Impl {
  std::shared_ptr<const RayScene> rays;
};

VisibilityScene::VisibilityScene(const TriangleMesh& mesh) : VisibilityScene(std::make_shared<const RayScene>(mesh)) {}

VisibilityScene::VisibilityScene(std::shared_ptr<const RayScene> scene) : impl_(std::make_unique<Impl>()) {
  if (!scene) throw InputError("the visibility tests need a ray-tracing scene");
  impl_->rays = std::move(scene);
}

VisibilityScene::~VisibilityScene() = default;

double VisibilityScene::diagonal() const { return impl_->rays->diagonal(); }

VisibleSamples VisibilityScene::visible(const View& view, const SurfaceSamples& samples, double seen_angle_deg,
                                        std::size_t stride) const {
  if (!(seen_angle_deg > 0.0 && seen_angle_deg <= 90.0)) throw InputError("the seen-well angle must be in (0, 90] degrees");
  if (!(view.aspect > 0.0)) throw InputError("the frame's aspect ratio must be positive");
  if (stride < 1 || kBlock % stride != 0) throw InputError("the sample stride must divide 2048");
  const RayScene& s = *impl_->rays;
  const LookAtFrame frame = look_at(view.camera);
  const double tan_y = std::tan(view.camera.vertical_fov_deg * std::numbers::pi / 360.0), tan_x = tan_y * view.aspect;
  const double cos_limit = std::cos(seen_angle_deg * std::numbers::pi / 180.0);
  const Eigen::Vector3d eye = view.camera.eye;
  // A ray leaves its sample this far out, so the sample's own face (or a neighbour meeting it at
  // the sample, in float precision) does not hide it.
  const float clearance = static_cast<float>(1e-5 * s.diagonal());

  const std::size_t n = samples.size(), blocks = (n + kBlock - 1) / kBlock;
  std::vector<VisibleSamples> parts(blocks);
  std::atomic<bool> stopped{false};
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
    if (stopped.load(std::memory_order_relaxed) || interrupt_requested()) {
      stopped = true;
      return;
    }
    VisibleSamples& out = parts[b];
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    // The rays start at the samples and run towards the eye, one at a time: on big scans that
    // is about 1.6x quicker than 16-ray packets from the eye (whose rays fan out to samples
    // spread over the model, so the packet splits at once), because a ray that is not blocked
    // near its sample soon leaves the model's boxes.
    const std::size_t end = std::min(n, (b + 1) * kBlock);
    for (std::size_t i = b * kBlock; i < end; i += stride) {
      const Eigen::Vector3d d = samples.points[i] - eye;
      const double z = d.dot(frame.forward);
      if (!(z > 0.0) || std::abs(d.dot(frame.right)) > tan_x * z || std::abs(d.dot(frame.up)) > tan_y * z) continue;
      const double distance = d.norm();
      const double cosine = std::abs(samples.normals[i].dot(d)) / distance;
      if (!(cosine > cos_limit) || !(distance > 2.0 * clearance)) continue;
      const Eigen::Vector3f from = (samples.points[i] - s.origin()).cast<float>();
      const Eigen::Vector3f towards_eye = (-d / distance).cast<float>();
      RTCRay ray;
      ray.org_x = from.x();
      ray.org_y = from.y();
      ray.org_z = from.z();
      ray.dir_x = towards_eye.x();
      ray.dir_y = towards_eye.y();
      ray.dir_z = towards_eye.z();
      ray.tnear = clearance;
      ray.tfar = static_cast<float>(distance);
      ray.time = 0.0f;
      ray.mask = RayScene::kModelMask;
      ray.id = 0;
      ray.flags = 0;
      rtcOccluded1(s.scene(), &context, &ray);
      if (ray.tfar < 0.0f) continue;  // Embree sets tfar to -inf when something is in the way
      out.samples.push_back(static_cast<std::uint32_t>(i));
      out.cosines.push_back(static_cast<float>(cosine));
    }
  });
  if (stopped) throw_if_interrupted();
  VisibleSamples all;
  std::size_t total = 0;
  for (const auto& p : parts) total += p.samples.size();
  all.samples.reserve(total);
  all.cosines.reserve(total);
  for (const auto& p : parts) {
    all.samples.insert(all.samples.end(), p.samples.begin(), p.samples.end());
    all.cosines.insert(all.cosines.end(), p.cosines.begin(), p.cosines.end());
  }
  return all;
}

}  // namespace meshtour
