#include <Eigen/Geometry>
#include <embree3/rtcore.h>
#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <numbers>
#include <string>

#include "core/error.h"
#include "tracer/color.h"
#include "tracer/tracer.h"

namespace meshtour {
namespace {

// Embree reports errors through a callback; keep the first message so the throwing site can
// quote it (exceptions must not cross Embree's C frames).
struct EmbreeErrorSink {
  std::mutex mutex;
  std::string message;
};

void embree_error(void* user, RTCError code, const char* text) {
  auto* sink = static_cast<EmbreeErrorSink*>(user);
  std::lock_guard lock(sink->mutex);
  if (sink->message.empty()) sink->message = "Embree error " + std::to_string(code) + ": " + (text ? text : "");
}

struct DeviceDeleter {
  void operator()(RTCDevice d) const { rtcReleaseDevice(d); }
};
struct SceneDeleter {
  void operator()(RTCScene s) const { rtcReleaseScene(s); }
};
using DevicePtr = std::unique_ptr<RTCDeviceTy, DeviceDeleter>;
using ScenePtr = std::unique_ptr<RTCSceneTy, SceneDeleter>;

constexpr int kTileSize = 32;

}  // namespace

struct Renderer::Impl {
  RenderOptions options;
  EmbreeErrorSink errors;
  DevicePtr device;
  ScenePtr scene;
  // The scene is stored relative to the model's centre in float; cameras are shifted the same
  // way, so models far from the origin (georeferenced scans) keep their precision.
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3f> normals;  // smooth, angle-weighted vertex normals
  std::vector<Eigen::Vector3f> colors;   // linear vertex colours, or empty
  std::vector<std::array<std::uint32_t, 3>> triangles;

  void check(const char* what) {
    std::lock_guard lock(errors.mutex);
    if (!errors.message.empty()) throw RuntimeFailure(std::string(what) + ": " + errors.message);
  }
};

namespace {

std::vector<Eigen::Vector3f> angle_weighted_normals(const std::vector<Eigen::Vector3f>& p,
                                                    const std::vector<std::array<std::uint32_t, 3>>& tris) {
  std::vector<Eigen::Vector3d> acc(p.size(), Eigen::Vector3d::Zero());
  for (const auto& t : tris) {
    const Eigen::Vector3d a = p[t[0]].cast<double>(), b = p[t[1]].cast<double>(), c = p[t[2]].cast<double>();
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double len = n.norm();
    if (!(len > 0.0)) continue;
    const Eigen::Vector3d unit = n / len;
    const Eigen::Vector3d corners[3] = {a, b, c};
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d e1 = corners[(k + 1) % 3] - corners[k], e2 = corners[(k + 2) % 3] - corners[k];
      const double angle = std::atan2(e1.cross(e2).norm(), e1.dot(e2));
      acc[t[k]] += angle * unit;
    }
  }
  std::vector<Eigen::Vector3f> out(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double len = acc[i].norm();
    out[i] = len > 0.0 ? Eigen::Vector3f((acc[i] / len).cast<float>()) : Eigen::Vector3f::UnitY();
  }
  return out;
}

}  // namespace

Renderer::Renderer(const TriangleMesh& mesh, const RenderOptions& options) : impl_(std::make_unique<Impl>()) {
  if (options.width <= 0 || options.height <= 0 || options.width > 16384 || options.height > 16384)
    throw InputError("image size must be between 1x1 and 16384x16384, got " + std::to_string(options.width) + "x" +
                     std::to_string(options.height));
  if (options.samples_per_pixel < 1 || options.samples_per_pixel > 4096)
    throw InputError("samples per pixel must be between 1 and 4096, got " + std::to_string(options.samples_per_pixel));
  if (mesh.triangles.empty()) throw InputError("the mesh has no triangles to render");

  Impl& s = *impl_;
  s.options = options;
  s.origin = mesh.bounds().center();
  s.positions.reserve(mesh.positions.size());
  for (const auto& p : mesh.positions) s.positions.push_back((p - s.origin).cast<float>());
  s.triangles = mesh.triangles;
  for (const auto& t : s.triangles)
    for (auto v : t)
      if (v >= s.positions.size()) throw InputError("the mesh has a triangle that refers to a missing vertex");
  s.normals = angle_weighted_normals(s.positions, s.triangles);
  if (mesh.has_colors() && options.shading.use_vertex_colors) {
    s.colors.reserve(mesh.colors.size());
    for (const auto& c : mesh.colors) s.colors.push_back(srgb_to_linear(c));
  }

  s.device.reset(rtcNewDevice(nullptr));
  if (!s.device) throw RuntimeFailure("cannot create the Embree device (error " + std::to_string(rtcGetDeviceError(nullptr)) + ")");
  rtcSetDeviceErrorFunction(s.device.get(), embree_error, &s.errors);

  s.scene.reset(rtcNewScene(s.device.get()));
  // Robust traversal: no cracks between triangles sharing an edge, which a turntable would show
  // as flickering pixels.
  rtcSetSceneFlags(s.scene.get(), RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(s.scene.get(), RTC_BUILD_QUALITY_HIGH);
  RTCGeometry geometry = rtcNewGeometry(s.device.get(), RTC_GEOMETRY_TYPE_TRIANGLE);
  // Shared buffers: Embree reads our arrays directly. The vertex buffer needs 16-byte padding at
  // its end, which the 3-float stride plus one spare vertex provides.
  s.positions.reserve(s.positions.size() + 1);
  s.positions.push_back(Eigen::Vector3f::Zero());
  rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, s.positions.data(), 0,
                             sizeof(Eigen::Vector3f), s.positions.size() - 1);
  rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, s.triangles.data(), 0,
                             sizeof(std::array<std::uint32_t, 3>), s.triangles.size());
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(s.scene.get(), geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(s.scene.get());
  s.check("building the ray-tracing scene");
}

Renderer::~Renderer() = default;

const RenderOptions& Renderer::options() const { return impl_->options; }

Image Renderer::render(const Camera& camera) const {
  const Impl& s = *impl_;
  const int width = s.options.width, height = s.options.height;
  Image image;
  image.width = width;
  image.height = height;
  image.rgba.assign(static_cast<std::size_t>(width) * height * 4, 0.0f);

  const Eigen::Vector3d forward_d = (camera.target - camera.eye).normalized();
  Eigen::Vector3d right_d = forward_d.cross(camera.up);
  if (!(right_d.norm() > 1e-9)) right_d = forward_d.unitOrthogonal();
  right_d.normalize();
  const Eigen::Vector3d up_d = right_d.cross(forward_d);
  const Eigen::Vector3f eye = (camera.eye - s.origin).cast<float>();
  const Eigen::Vector3f forward = forward_d.cast<float>(), right = right_d.cast<float>(), up = up_d.cast<float>();
  const float tan_half = static_cast<float>(std::tan(camera.vertical_fov_deg * std::numbers::pi / 360.0));
  const float aspect = static_cast<float>(width) / static_cast<float>(height);

  const Shading& sh = s.options.shading;
  const Eigen::Vector3f light_dir =
      (sh.light_from_camera.x() * right + sh.light_from_camera.y() * up - sh.light_from_camera.z() * forward).normalized();

  // Stratified samples: a rows x cols grid inside the pixel with rows*cols == spp.
  const int spp = s.options.samples_per_pixel;
  int rows = static_cast<int>(std::sqrt(static_cast<double>(spp)));
  while (spp % rows != 0) --rows;
  const int cols = spp / rows;

  const int tiles_x = (width + kTileSize - 1) / kTileSize, tiles_y = (height + kTileSize - 1) / kTileSize;
  tbb::parallel_for(tbb::blocked_range2d<int>(0, tiles_y, 0, tiles_x), [&](const tbb::blocked_range2d<int>& r) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    for (int ty = r.rows().begin(); ty != r.rows().end(); ++ty)
      for (int tx = r.cols().begin(); tx != r.cols().end(); ++tx)
        for (int y = ty * kTileSize; y < std::min(height, (ty + 1) * kTileSize); ++y)
          for (int x = tx * kTileSize; x < std::min(width, (tx + 1) * kTileSize); ++x) {
            Eigen::Vector4f sum = Eigen::Vector4f::Zero();
            for (int sy = 0; sy < rows; ++sy)
              for (int sx = 0; sx < cols; ++sx) {
                const float px = (static_cast<float>(x) + (static_cast<float>(sx) + 0.5f) / cols) / width;
                const float py = (static_cast<float>(y) + (static_cast<float>(sy) + 0.5f) / rows) / height;
                const Eigen::Vector3f dir =
                    (forward + (2.0f * px - 1.0f) * tan_half * aspect * right + (1.0f - 2.0f * py) * tan_half * up)
                        .normalized();
                RTCRayHit hit{};
                hit.ray.org_x = eye.x();
                hit.ray.org_y = eye.y();
                hit.ray.org_z = eye.z();
                hit.ray.dir_x = dir.x();
                hit.ray.dir_y = dir.y();
                hit.ray.dir_z = dir.z();
                hit.ray.tnear = 0.0f;
                hit.ray.tfar = std::numeric_limits<float>::infinity();
                hit.ray.mask = 0xFFFFFFFFu;
                hit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                rtcIntersect1(s.scene.get(), &context, &hit);
                if (hit.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
                  const float t = py;  // vertical gradient behind the model
                  const Eigen::Vector3f bg = (1.0f - t) * sh.background_top + t * sh.background_bottom;
                  sum += Eigen::Vector4f(bg.x(), bg.y(), bg.z(), 0.0f);
                  continue;
                }
                const auto& tri = s.triangles[hit.hit.primID];
                const float u = hit.hit.u, v = hit.hit.v, w = 1.0f - u - v;
                Eigen::Vector3f n = (w * s.normals[tri[0]] + u * s.normals[tri[1]] + v * s.normals[tri[2]]);
                n = n.norm() > 0.0f ? n.normalized() : Eigen::Vector3f(hit.hit.Ng_x, hit.hit.Ng_y, hit.hit.Ng_z).normalized();
                // Two-sided: open scans show their inside, which must be lit like the outside.
                if (n.dot(dir) > 0.0f) n = -n;
                const Eigen::Vector3f albedo = s.colors.empty()
                    ? sh.base_color
                    : Eigen::Vector3f(w * s.colors[tri[0]] + u * s.colors[tri[1]] + v * s.colors[tri[2]]);
                const float diffuse = std::max(0.0f, n.dot(light_dir));
                const Eigen::Vector3f half = (light_dir - dir).normalized();
                const float spec = diffuse > 0.0f ? sh.specular * std::pow(std::max(0.0f, n.dot(half)), sh.shininess) : 0.0f;
                const Eigen::Vector3f c = albedo * (sh.ambient + sh.light_intensity * diffuse) + Eigen::Vector3f::Constant(spec);
                sum += Eigen::Vector4f(c.x(), c.y(), c.z(), 1.0f);
              }
            const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 4;
            const Eigen::Vector4f avg = sum / static_cast<float>(spp);
            for (int k = 0; k < 4; ++k) image.rgba[i + k] = avg[k];
          }
  });
  return image;
}

}  // namespace meshtour
