#pragma once
// Access to the renderer's Embree scene and rays, for the benchmark that compares the renderer's
// ray throughput with bare Embree calls on the very same rays. Not part of the public API.
#include <embree3/rtcore.h>

#include <array>
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
    RTCRay16 shadow, sky;  ///< lanes not in use are uninitialised
    ValidMask shadow_valid, sky_valid;
  };
  struct Tile {
    std::vector<Packet> packets;
  };
  std::vector<Tile> tiles;  ///< one entry per recorded tile
};

struct RendererAccess {
  static RTCScene scene(const Renderer& renderer);
  static Image render(const Renderer& renderer, const Camera& camera, std::uint64_t frame_index, RenderStats* stats,
                      RayRecording* recording);
};

}  // namespace meshtour
