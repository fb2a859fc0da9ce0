#pragma once
// Access to the renderer's Embree scene and rays, for the benchmark that compares the renderer's
// ray throughput with bare Embree calls on the very same rays, and to its shading normals, for
// their test and benchmark. Not part of the public API.
#include <Eigen/Core>
#include <embree3/rtcore.h>

#include <array>
#include <cstdint>
#include <vector>

#include "tracer/tracer.h"

namespace meshtour {

/// Lanes of a 16-ray packet in use (-1) or not (0). Embree requires 64-byte alignment.
struct alignas(64) ValidMask {
  std::array<int, 16> lanes;
  int* data() { return lanes.data(); }
  int& operator[](std::size_t i) { return lanes[i]; }
};

/// Copies of the rays one render() traced, for the tiles whose index is a multiple of
/// `tile_stride` (all tiles would need gigabytes at 16 spp), packet by packet as the renderer
/// traced them: rtcIntersect16 on the camera rays, then rtcOccluded16 on the shadow rays and on
/// the occlusion rays (each only when some lane is in use).
struct RayRecording {
  int tile_stride = 8;
  struct Packet {
    RTCRayHit16 primary;  ///< camera rays, as traced (before intersection)
    ValidMask primary_valid;
    RTCRay16 shadow, sky;  ///< lanes not in use hold a harmless ray (tile_kernel.cpp, set_rays)
    ValidMask shadow_valid, sky_valid;
  };
  struct Tile {
    std::vector<Packet> packets;
  };
  std::vector<Tile> tiles;  ///< one entry per recorded tile
};

/// The renderer's shading normals, one per vertex, with creases (Material::crease_angle_deg): each
/// corner's normal averages the faces around its vertex that meet its own face at less than the
/// angle, weighted by their angles there. Where a vertex's corners get different normals, each one
/// after the first gets a copy of the vertex appended to `positions` (the same coordinates) and
/// its corners in `triangles` are re-pointed; `copied_from` receives each copy's source vertex.
/// A smooth surface gets no copies. Deterministic (the same bits on every CPU: no libm beyond
/// sqrt). Linear in the corners: bench/tracer_bench BM_CreaseNormals.
std::vector<Eigen::Vector3f> crease_normals(std::vector<Eigen::Vector3f>& positions, std::vector<std::array<std::uint32_t, 3>>& triangles,
                                            float crease_angle_deg, std::vector<std::uint32_t>& copied_from);

struct RendererAccess {
  static RTCScene scene(const Renderer& renderer);
  static Image render(const Renderer& renderer, const Camera& camera, std::uint64_t frame_index, RenderStats* stats,
                      RayRecording* recording);
};

}  // namespace meshtour
