#pragma once
// The model as rays see it: one Embree BVH per mesh, built once and shared by everything that
// traces rays against the model in a job: the visibility module (the feature orbit's search,
// `evaluate`) and the tracer (camera, shadow and occlusion rays; its ground is a plane it
// intersects itself). A tour of a 17.8M-face scan used to build two BVHs of the whole mesh,
// about 9-10 s and a few GB each.
#include <embree3/rtcore.h>

#include <Eigen/Core>
#include <cstdint>
#include <memory>

#include "mesh/mesh.h"

namespace meshtour {

class RayScene {
public:
  /// The model's triangles are geometry kModelGeometry with mask kModelMask.
  static constexpr unsigned kModelGeometry = 0, kModelMask = 1;

  /// Builds the BVH: Embree's high-quality build with robust traversal (no cracks between
  /// triangles sharing an edge, which a turntable would show as flickering pixels). Vertices are
  /// stored in float relative to the bounding box's centre (origin()).
  /// \throw InputError for a mesh without triangles or a triangle that refers to a missing vertex,
  ///        RuntimeFailure if Embree fails (out of memory), Interrupted if Ctrl-C / SIGTERM arrives
  ///        during the build.
  explicit RayScene(const TriangleMesh& mesh);
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  /// The committed scene; thread-safe for concurrent queries (rtcIntersect*, rtcOccluded*).
  RTCScene scene() const;
  /// The point the vertices are stored relative to: the mesh's bounding box's centre.
  const Eigen::Vector3d& origin() const;
  /// The bounding box's diagonal (model units).
  double diagonal() const;
  std::size_t triangle_count() const;

  /// Bytes a scene of this size holds: Embree's vertex and index buffers and its BVH (measured on
  /// the bunny split up to 17.8M faces; see docs/PERFORMANCE.md), rounded up.
  static double estimated_bytes(std::size_t triangles, std::size_t vertices);

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace meshtour
