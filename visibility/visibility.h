#pragma once
// What a camera sees of a surface, measured on sample points of the surface rather than on its
// faces, so that the answer does not depend on how finely the surface is tessellated: the same
// shape split into four times as many triangles gives the same samples' worth of visible area.
//
// The one visibility module of meshtour: the feature orbit's path search (pathgen) and
// `meshtour evaluate` both ask it what a view sees. It sits between mesh/ and pathgen/ and traces
// its occlusion rays against the mesh's RayScene (mesh/ray_scene.h), which a tour shares with the
// tracer: one BVH per job.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "core/camera.h"
#include "mesh/mesh.h"
#include "mesh/ray_scene.h"

namespace meshtour {

/// Points spread over a surface in proportion to area: every sample stands for the same area.
struct SurfaceSamples {
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector3d> normals;  ///< unit normal of the face the point lies on
  std::vector<std::uint32_t> faces;      ///< the face the point lies on
  /// Barycentric coordinates of the point in its face (weights of corners 1 and 2; corner 0 has the rest).
  std::vector<Eigen::Vector2d> barycentric;
  double area_per_sample = 0.0;  ///< total area / number of samples
  /// The order visibility rays are traced in: the samples along a Z-order (Morton) curve through
  /// the model's bounding box, so that consecutive rays start close together and walk the same
  /// BVH nodes (on a 17.8M-face scan the BVH is over a gigabyte: in face order, rays left one
  /// another's nodes out of cache). Only the speed depends on it: VisibilityScene::visible() lists
  /// its results by sample index either way. trace[k] holds the samples whose index is a multiple
  /// of 2^k (visible()'s stride), k = 0..6, with their points and normals, so the tracing reads
  /// them in order too; empty: index order. sample_surface() makes it: code that changes the
  /// points or normals afterwards clears it.
  struct TraceSample {
    Eigen::Vector3d point, normal;
    std::uint32_t index;
  };
  std::vector<std::vector<TraceSample>> trace;

  std::size_t size() const { return points.size(); }
};

/// `count` samples of the surface of `mesh`, deterministic: systematic sampling of the cumulative
/// face area (sample i at area (i + ½)·A/count) and a low-discrepancy position inside the face.
/// Faces without area get none. \throw InputError if the mesh has no area or count < 1.
SurfaceSamples sample_surface(const TriangleMesh& mesh, std::size_t count);

/// A view: the camera and the frame's aspect ratio (width / height).
struct View {
  Camera camera;
  double aspect = 16.0 / 9.0;
};

/// The samples a view sees: inside the frame, not hidden by the surface, and facing the camera
/// within `seen_angle_deg` (the angle between the surface normal and the direction to the eye;
/// either side of the surface counts, as scans are not reliably oriented). `cosines` holds
/// |cos| of that angle for each sample listed, so a stricter angle is a filter on the result, and
/// `front` which side the eye sees: 1 where it is the side the face's normal points to.
struct VisibleSamples {
  std::vector<std::uint32_t> samples;  ///< ascending
  std::vector<float> cosines;
  std::vector<std::uint8_t> front;
};

/// The model's outline seen along one direction, in parallel projection: its area (model units²)
/// counted on a square grid of rays, and the same count on each half of the grid's cells (the
/// two colours of a checkerboard, each scaled to the whole), whose difference measures how much
/// of the area is where the grid happens to fall.
struct ProjectedArea {
  double area = 0.0;
  std::array<double, 2> halves{};
};

/// The surface as Embree sees it, built once and asked for any number of views. Thread-safe for
/// concurrent queries. Results do not depend on the thread count.
class VisibilityScene {
public:
  /// \throw InputError for a mesh without triangles, RuntimeFailure if Embree fails,
  ///        Interrupted if Ctrl-C / SIGTERM arrives during the build.
  explicit VisibilityScene(const TriangleMesh& mesh);
  /// On a scene already built for the mesh (shared, e.g. with the tracer). \throw InputError if null.
  explicit VisibilityScene(std::shared_ptr<const RayScene> scene);
  ~VisibilityScene();
  VisibilityScene(const VisibilityScene&) = delete;
  VisibilityScene& operator=(const VisibilityScene&) = delete;

  /// The samples `view` sees within `seen_angle_deg` (0 < angle <= 90). With `stride` > 1 only
  /// every stride-th sample is tested (0, stride, 2·stride, ...): as the samples are systematic
  /// in area, that subset is itself an even sampling of the surface, for a quicker estimate.
  VisibleSamples visible(const View& view, const SurfaceSamples& samples, double seen_angle_deg,
                         std::size_t stride = 1) const;

  /// The model's outline seen along `direction` (need not be unit), in parallel projection: one
  /// ray per cell of a `resolution`² grid over the square that holds the bounding sphere across
  /// that direction. Independent of the eye's distance and of the tessellation (a point sampling
  /// of the outline). \throw InputError for a zero direction or a resolution outside 2..4096.
  ProjectedArea projected_area(const Eigen::Vector3d& direction, int resolution) const;

  /// Diagonal of the bounding box of the scene (model units).
  double diagonal() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace meshtour
