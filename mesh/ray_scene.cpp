#include "mesh/ray_scene.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <mutex>
#include <string>

#include "core/error.h"
#include "core/interrupt.h"

namespace meshtour {
// Named, not anonymous: RayScene::Impl (external linkage) holds these types as members.
namespace ray_scene_detail {

struct DeviceDeleter {
  void operator()(RTCDevice d) const { rtcReleaseDevice(d); }
};
struct SceneDeleter {
  void operator()(RTCScene s) const { rtcReleaseScene(s); }
};
struct GeometryDeleter {
  void operator()(RTCGeometry g) const { rtcReleaseGeometry(g); }
};

// Embree reports errors through a callback; the first message is kept so that the throwing site
// can quote it (exceptions must not cross Embree's C frames).
struct ErrorSink {
  std::mutex mutex;
  std::string message;
};
void record_error(void* user, RTCError code, const char* text) {
  auto* sink = static_cast<ErrorSink*>(user);
  std::lock_guard lock(sink->mutex);
  if (sink->message.empty()) sink->message = std::string(text ? text : "unknown error") + " (Embree error " + std::to_string(code) + ")";
}

}  // namespace ray_scene_detail
using namespace ray_scene_detail;

struct RayScene::Impl {
  ErrorSink errors;  // before the device, which reports into it until released
  std::unique_ptr<RTCDeviceTy, DeviceDeleter> device;
  std::unique_ptr<RTCSceneTy, SceneDeleter> scene;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  double diagonal = 0.0;
  std::size_t triangles = 0;

  void check(const std::string& what) {
    std::lock_guard lock(errors.mutex);
    if (!errors.message.empty()) throw RuntimeFailure(what + ": " + errors.message);
  }
};

RayScene::RayScene(const TriangleMesh& mesh) : impl_(std::make_unique<Impl>()) {
  if (mesh.triangles.empty()) throw InputError("the mesh has no triangles to trace rays against");
  const std::size_t vertices = mesh.positions.size(), faces = mesh.triangles.size();
  for (const auto& t : mesh.triangles)
    for (const std::uint32_t v : t)
      if (v >= vertices) throw InputError("the mesh has a triangle that refers to a missing vertex");
  Impl& s = *impl_;
  const Bounds bounds = mesh.bounds();
  s.origin = bounds.center();
  s.diagonal = bounds.diagonal();
  s.triangles = faces;

  s.device.reset(rtcNewDevice(nullptr));
  if (!s.device) throw RuntimeFailure("cannot create the Embree device (error " + std::to_string(rtcGetDeviceError(nullptr)) + ")");
  rtcSetDeviceErrorFunction(s.device.get(), record_error, &s.errors);
  s.scene.reset(rtcNewScene(s.device.get()));
  // A material with alpha or a single side lets the tracer pass a filter in its rays' context
  // (the renderer decides per hit); a scene without one keeps Embree's plain traversal.
  const bool filtered = std::any_of(mesh.materials.begin(), mesh.materials.end(), [](const MeshMaterial& m) { return m.rays_filtered(); });
  rtcSetSceneFlags(s.scene.get(), filtered ? RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION : RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(s.scene.get(), RTC_BUILD_QUALITY_HIGH);

  const std::unique_ptr<RTCGeometryTy, GeometryDeleter> geometry(rtcNewGeometry(s.device.get(), RTC_GEOMETRY_TYPE_TRIANGLE));
  // Embree's own buffers (it pads them as it needs): the scene does not depend on the caller
  // keeping the mesh's arrays alive or unchanged.
  auto* vertex = static_cast<float*>(
      rtcSetNewGeometryBuffer(geometry.get(), RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), vertices));
  auto* index = static_cast<std::uint32_t*>(
      rtcSetNewGeometryBuffer(geometry.get(), RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), faces));
  if (!vertex || !index) throw RuntimeFailure("Embree could not allocate the ray-tracing scene of " + std::to_string(faces) + " faces (out of memory?)");
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, vertices, 1 << 16), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t v = r.begin(); v < r.end(); ++v) {
      const Eigen::Vector3f p = (mesh.positions[v] - s.origin).cast<float>();
      for (int c = 0; c < 3; ++c) vertex[3 * v + c] = p[c];
    }
  });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, faces, 1 << 16), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t f = r.begin(); f < r.end(); ++f)
      for (int c = 0; c < 3; ++c) index[3 * f + c] = mesh.triangles[f][c];
  });
  rtcSetGeometryMask(geometry.get(), kModelMask);
  rtcCommitGeometry(geometry.get());
  rtcAttachGeometryByID(s.scene.get(), geometry.get(), kModelGeometry);
  // A BVH build of millions of faces takes seconds: Ctrl-C or SIGTERM cancels it.
  rtcSetSceneProgressMonitorFunction(s.scene.get(), [](void*, double) { return !interrupt_requested(); }, nullptr);
  rtcCommitScene(s.scene.get());
  throw_if_interrupted();  // a cancelled build is an interrupt, not an Embree failure
  s.check("building the ray-tracing scene of " + std::to_string(faces) + " faces");
}

RayScene::~RayScene() = default;

RTCScene RayScene::scene() const { return impl_->scene.get(); }
const Eigen::Vector3d& RayScene::origin() const { return impl_->origin; }
double RayScene::diagonal() const { return impl_->diagonal; }
std::size_t RayScene::triangle_count() const { return impl_->triangles; }

double RayScene::estimated_bytes(std::size_t triangles, std::size_t vertices) {
  return 110.0 * static_cast<double>(triangles) + 16.0 * static_cast<double>(vertices);
}

}  // namespace meshtour
