// GCC 12 reports OpenMesh's default-constructed colour properties (VectorT<unsigned char, 3>,
// uninitialised by design and filled by the reader) as "may be used uninitialized" depending on
// its inlining choices for this file; the warning is about OpenMesh's code, not this file's.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include "mesh/mesh.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/interrupt.h"
#include "core/triangle_geometry.h"
#include "mesh/openmesh_log.h"

namespace meshtour {
namespace {

struct LoaderTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  VertexAttributes(OpenMesh::Attributes::Status);
  FaceAttributes(OpenMesh::Attributes::Status);
};
using LoaderMesh = OpenMesh::TriMesh_ArrayKernelT<LoaderTraits>;

}  // namespace

bool TriangleMesh::has_texture() const {
  return corner_uvs.size() == 3 * triangles.size() && !triangles.empty() &&
         std::any_of(materials.begin(), materials.end(), [](const MeshMaterial& m) { return !m.maps().empty(); });
}

void transform_mesh(TriangleMesh& mesh, const Eigen::Matrix4d& m) {
  const Eigen::Matrix3d linear = m.topLeftCorner<3, 3>();
  const double det = linear.determinant();
  if (!std::isfinite(det) || std::abs(det) < 1e-300 || m.row(3) != Eigen::RowVector4d(0, 0, 0, 1))
    throw InputError("the model's transform is singular or not affine (determinant " + std::to_string(det) + ")");
  const Eigen::Vector3d shift = m.topRightCorner<3, 1>();
  for (Eigen::Vector3d& p : mesh.positions) p = linear * p + shift;
  // The file's normals turn by the inverse transpose, its tangents with the surface; a mirror
  // turns the bitangent cross(n, t) the other way, so w flips.
  const Eigen::Matrix3f normal_matrix = linear.inverse().transpose().cast<float>(), tangent_matrix = linear.cast<float>();
  for (Eigen::Vector3f& n : mesh.corner_normals)
    if (n.squaredNorm() > 0.0f) n = (normal_matrix * n).normalized();
  for (Eigen::Vector4f& t : mesh.corner_tangents)
    if (t.head<3>().squaredNorm() > 0.0f) {
      const Eigen::Vector3f turned = (tangent_matrix * Eigen::Vector3f(t.x(), t.y(), t.z())).normalized();
      t = {turned.x(), turned.y(), turned.z(), det < 0.0 ? -t.w() : t.w()};
    }
  if (det < 0.0) {
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
    // Per-corner attributes follow their corners.
    const auto follow = [&](auto& corners) {
      if (corners.size() == 3 * mesh.triangles.size())
        for (std::size_t f = 0; f < mesh.triangles.size(); ++f) std::swap(corners[3 * f + 1], corners[3 * f + 2]);
    };
    follow(mesh.corner_uvs);
    follow(mesh.corner_normals);
    follow(mesh.corner_tangents);
  }
}

Bounds TriangleMesh::bounds() const {
  // The used vertices are marked first, then read in order: a byte per vertex stays in cache where
  // reading each triangle's corners' positions jumped through all of them (9 % of loading a
  // 17.8M-face GLB).
  std::vector<unsigned char> used(positions.size(), 0);
  for (const auto& t : triangles)
    for (const auto vi : t) used[vi] = 1;
  Bounds b;
  bool first = true;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    if (!used[i]) continue;
    const Eigen::Vector3d& p = positions[i];
    if (first) {
      b.lo = b.hi = p;
      first = false;
    } else {
      b.lo = b.lo.cwiseMin(p);
      b.hi = b.hi.cwiseMax(p);
    }
  }
  return b;
}

std::optional<Eigen::Vector3d> flat_plane_normal(const TriangleMesh& mesh) {
  // The largest triangle gives the most reliable normal; all used vertices must lie in its plane.
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d n = triangle_cross(mesh.positions, t);
    if (n.squaredNorm() > normal.squaredNorm()) normal = n;
  }
  if (normal.squaredNorm() == 0.0 || mesh.triangles.empty()) return std::nullopt;
  normal.normalize();
  const Eigen::Vector3d origin = mesh.positions[mesh.triangles.front()[0]];
  const double tolerance = 1e-9 * mesh.bounds().diagonal();
  for (const auto& t : mesh.triangles)
    for (auto v : t)
      if (std::abs((mesh.positions[v] - origin).dot(normal)) > tolerance) return std::nullopt;
  return normal;
}

std::vector<double> face_areas(const std::vector<Eigen::Vector3d>& positions, const std::vector<std::array<std::uint32_t, 3>>& triangles) {
  std::vector<double> area(triangles.size());
  // Every chunk looks at the interrupt flag (a 17.8M-face model takes a while even here).
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, area.size(), 1024), [&](const tbb::blocked_range<std::size_t>& r) {
    throw_if_interrupted();
    for (std::size_t f = r.begin(); f < r.end(); ++f) area[f] = triangle_area(positions, triangles[f]);
  });
  return area;
}

void save_mesh(const TriangleMesh& mesh, const std::filesystem::path& file) {
  LoaderMesh om;
  const bool colors = mesh.has_colors();
  if (colors) om.request_vertex_colors();
  std::vector<LoaderMesh::VertexHandle> handles;
  handles.reserve(mesh.positions.size());
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const auto& p = mesh.positions[i];
    handles.push_back(om.add_vertex(LoaderMesh::Point(p.x(), p.y(), p.z())));
    if (colors) {
      const auto& c = mesh.colors[i];
      auto to8 = [](float v) { return static_cast<unsigned char>(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f); };
      om.set_color(handles.back(), LoaderMesh::Color(to8(c.x()), to8(c.y()), to8(c.z())));
    }
  }
  OpenMeshLogCapture log;
  for (const auto& t : mesh.triangles) om.add_face(handles[t[0]], handles[t[1]], handles[t[2]]);
  OpenMesh::IO::Options options = OpenMesh::IO::Options::Binary;
  if (colors) options += OpenMesh::IO::Options::VertexColor;
  if (!OpenMesh::IO::write_mesh(om, file.string(), options))
    throw IoError(file.string() + ": cannot write mesh");
}

}  // namespace meshtour
