// The per-tile hot loop of the renderer. This file is compiled once per instruction set (see
// tracer/CMakeLists.txt: MESHTOUR_TILE_KERNEL names the copy) and the renderer picks the widest
// the CPU has; they all give the same bits (simd.h says why). A separate compilation rather than
// GCC's target_clones: in a clone GCC 12 lowers 16-lane comparisons lane by lane, which cost a
// third of the kernel's speed.
#include <OpenImageIO/texture.h>
#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "tracer/color.h"
#include "tracer/denoiser.h"
#include "tracer/film.h"
#include "tracer/random.h"
#include "tracer/renderer_impl.h"
#include "tracer/sampler.h"
#include "tracer/simd.h"

#ifndef MESHTOUR_TILE_KERNEL
#define MESHTOUR_TILE_KERNEL render_tile_baseline
#endif

namespace meshtour {
namespace {

using simd::F16;
using simd::I16;

// A vector of three 16-lane components.
struct V3 {
  F16 x, y, z;
};
MESHTOUR_SIMD_INLINE F16 dot(const V3& a, const V3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
MESHTOUR_SIMD_INLINE V3 broadcast(const Eigen::Vector3f& v) { return {simd::broadcast(v.x()), simd::broadcast(v.y()), simd::broadcast(v.z())}; }
MESHTOUR_SIMD_INLINE V3 select(I16 m, const V3& a, const V3& b) { return {simd::select(m, a.x, b.x), simd::select(m, a.y, b.y), simd::select(m, a.z, b.z)}; }

// The orthonormal basis of Duff et al. 2017 ("Building an orthonormal basis, revisited"), 16 at once.
MESHTOUR_SIMD_INLINE void basis(const V3& n, V3& t, V3& b) {
  const F16 sign = simd::select(simd::lt(n.z, 0.0f), simd::broadcast(-1.0f), simd::broadcast(1.0f));
  const F16 a = -1.0f / (sign + n.z);
  const F16 c = n.x * n.y * a;
  t = {1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x};
  b = {c, sign + n.y * n.y * a, -n.y};
}

// The per-lane parameters of one light out of several.
struct LaneLight {
  V3 direction, tangent, bitangent, radiance;
  F16 one_minus_cos_half_angle, cos_half_angle, sin_half_angle;
};
MESHTOUR_SIMD_INLINE LaneLight lane_light(const std::vector<FrameLight>& lights, I16 chosen) {
  LaneLight l{};
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const I16 m = simd::eq(chosen, static_cast<int>(i));
    const FrameLight& f = lights[i];
    l.direction = select(m, broadcast(f.direction), l.direction);
    l.tangent = select(m, broadcast(f.tangent), l.tangent);
    l.bitangent = select(m, broadcast(f.bitangent), l.bitangent);
    l.radiance = select(m, broadcast(f.radiance), l.radiance);
    l.one_minus_cos_half_angle = simd::select(m, simd::broadcast(f.one_minus_cos_half_angle), l.one_minus_cos_half_angle);
    l.cos_half_angle = simd::select(m, simd::broadcast(f.cos_half_angle), l.cos_half_angle);
    l.sin_half_angle = simd::select(m, simd::broadcast(f.sin_half_angle), l.sin_half_angle);
  }
  return l;
}

// Picks light i with probability weights[i] / total per lane (u in [0, 1), total > 0 where it
// matters): the first light whose running sum exceeds u * total; rounding at the very top falls
// back to the last light with a weight. `reused` is where u falls inside the chosen light's
// share, stretched to [0, 1): a fresh number for sampling that light, and, u being one coordinate
// of a 2D net, the samples that pick a light keep the net's stratification with the other
// coordinate on its disc (the samples of a pixel that pick the key light cover the key light's
// disc evenly, which an independent pair, of which they would be a random subset, does not).
template <typename Weight>
MESHTOUR_SIMD_INLINE I16 choose(const Weight* weights, std::size_t n, F16 total, F16 u, F16& reused) {
  const F16 target = u * total;
  F16 acc = simd::broadcast(0.0f), before = acc, width = acc, last_before = acc, last_width = acc;
  I16 chosen = simd::broadcast_int(-1), last = simd::broadcast_int(0);
  for (std::size_t i = 0; i < n; ++i) {
    const F16 w = simd::broadcast(0.0f) + weights[i];
    const I16 has = simd::gt(w, 0.0f);
    const F16 next = acc + simd::select(has, w, simd::broadcast(0.0f));
    const I16 i_vec = simd::broadcast_int(static_cast<int>(i));
    const I16 picked = simd::both(has, simd::both(simd::lt(chosen, 0), simd::lt(target, next)));
    chosen = simd::select_int(picked, i_vec, chosen);
    before = simd::select(picked, acc, before);
    width = simd::select(picked, w, width);
    last = simd::select_int(has, i_vec, last);
    last_before = simd::select(has, acc, last_before);
    last_width = simd::select(has, w, last_width);
    acc = next;
  }
  const I16 fallback = simd::lt(chosen, 0);
  before = simd::select(fallback, last_before, before);
  width = simd::select(fallback, last_width, width);
  const I16 sized = simd::gt(width, 0.0f);
  const F16 stretched = (target - before) / simd::select(sized, width, simd::broadcast(1.0f));
  reused = simd::select(sized, simd::min(simd::max(stretched, simd::broadcast(0.0f)), simd::broadcast(0x1.fffffep-1f)), u);
  return simd::select_int(fallback, last, chosen);
}

// A direction uniform over a light's disc (a spherical cap), from numbers (u, v) in (0, 1).
MESHTOUR_SIMD_INLINE V3 light_direction(const LaneLight& l, F16 u, F16 v) {
  const F16 cos_t = 1.0f - u * l.one_minus_cos_half_angle;
  const F16 sin_t = simd::sqrt(simd::max(simd::broadcast(0.0f), 1.0f - cos_t * cos_t));
  F16 sin_phi, cos_phi;
  simd::sincos_turns(v, sin_phi, cos_phi);
  const F16 a = sin_t * cos_phi, b = sin_t * sin_phi;
  return {cos_t * l.direction.x + a * l.tangent.x + b * l.bitangent.x, cos_t * l.direction.y + a * l.tangent.y + b * l.bitangent.y,
          cos_t * l.direction.z + a * l.tangent.z + b * l.bitangent.z};
}

// A cosine-weighted direction over the hemisphere around n (tangents t1, t2): the fraction of
// unblocked rays is then exactly the occlusion of a diffuse surface's sky light.
MESHTOUR_SIMD_INLINE V3 sky_direction(const V3& n, const V3& t1, const V3& t2, F16 u, F16 v) {
  const F16 rad = simd::sqrt(u);
  F16 sin_phi, cos_phi;
  simd::sincos_turns(v, sin_phi, cos_phi);
  const F16 a = rad * cos_phi, b = rad * sin_phi, h = simd::sqrt(simd::max(simd::broadcast(0.0f), 1.0f - u));
  return {a * t1.x + b * t2.x + h * n.x, a * t1.y + b * t2.y + h * n.y, a * t1.z + b * t2.z + h * n.z};
}

// Fills a 16-ray packet's rays (RTCRay16 or the ray part of RTCRayHit16). Lanes outside `lanes`
// get a harmless ray (from the origin along +z): Embree must ignore them, but on CPUs without
// AVX-512 it splits a 16-ray packet into two of 8, and Debian's build then asserts that every
// ray of a half is valid, aborting on the infinite origins of camera rays that missed.
template <typename Packet>
MESHTOUR_SIMD_INLINE void set_rays(Packet& p, I16 lanes, const V3& org, const V3& dir, float tfar, unsigned mask) {
  const F16 zero = simd::broadcast(0.0f), one = simd::broadcast(1.0f);
  simd::store(p.org_x, simd::select(lanes, org.x, zero));
  simd::store(p.org_y, simd::select(lanes, org.y, zero));
  simd::store(p.org_z, simd::select(lanes, org.z, zero));
  simd::store(p.dir_x, simd::select(lanes, dir.x, zero));
  simd::store(p.dir_y, simd::select(lanes, dir.y, zero));
  simd::store(p.dir_z, simd::select(lanes, dir.z, one));
  simd::store(p.tnear, simd::broadcast(0.0f));
  simd::store(p.tfar, simd::broadcast(tfar));
  simd::store(p.time, simd::broadcast(0.0f));
  simd::store_int(p.mask, simd::broadcast_int(static_cast<std::int32_t>(mask)));
  simd::store_int(p.id, simd::broadcast_int(0));
  simd::store_int(p.flags, simd::broadcast_int(0));
}

MESHTOUR_SIMD_INLINE int popcount(I16 mask) {
  int n = 0;
  for (int i = 0; i < simd::kLanes; ++i) n += mask[i] != 0;
  return n;
}

// The sums over one pixel's 16 samples (a packet) of wx[i] wy[j] (values, 1) for every tap, taps
// in rows (Values + 1 floats each), 16 sums per lane-sum tree; then the lanes' sums of `Extras`
// more values in the last tree's spare slots.
template <int Reach, int Values, int Extras>
struct PixelPacketSums {
  static constexpr int kTaps = 2 * Reach + 1, kFloats = Values + 1, kSums = kTaps * kTaps * kFloats,
                       kTrees = (kSums + simd::kLanes - 1) / simd::kLanes;
  static_assert(kSums + Extras <= kTrees * simd::kLanes, "the extras must fit the last tree's spare slots");
  alignas(64) float totals[kTrees * simd::kLanes];

  MESHTOUR_SIMD_INLINE PixelPacketSums(const F16 (&values)[Values], const F16* wx, const F16* wy, const F16* extras) {
    F16 products[kTrees * simd::kLanes];
    for (int j = 0; j < kTaps; ++j) {
      F16 weighted[kFloats];
      for (int c = 0; c < Values; ++c) weighted[c] = wy[j] * values[c];
      weighted[Values] = wy[j];
      for (int i = 0; i < kTaps; ++i)
        for (int c = 0; c < kFloats; ++c) products[(j * kTaps + i) * kFloats + c] = wx[i] * weighted[c];
    }
    for (int e = 0; e < Extras; ++e) products[kSums + e] = extras[e];
    for (int k = kSums + Extras; k < kTrees * simd::kLanes; ++k) products[k] = simd::broadcast(0.0f);
    for (int t = 0; t < kTrees; ++t) simd::store(totals + t * simd::kLanes, simd::sum_lanes(products + t * simd::kLanes));
  }
};

// Splats one packet's samples (`Values` floats per lane: premultiplied RGBA, and for the
// denoiser the unshadowed light's RGB) onto the tile's buffer (Values + 1 floats per pixel, the
// weight last): lanes of the same pixel are summed first, then added to the pixels around it.
//
// With `extras` (as many as the last tree's spare slots hold), the fast path also sums their
// lanes into `extra_sums` in the last tree's spare slots and returns true; otherwise (lanes of several pixels) it
// returns false and the caller sums them itself.
template <int Reach, int Values, int Extras = 0>
MESHTOUR_SIMD_INLINE bool splat_packet(const F16 (&values)[Values], const F16* wx, const F16* wy, const int* buffer_pixel, int lanes,
                                       float* sums, int stride, const F16* extras = nullptr, float* extra_sums = nullptr) {
  constexpr int kTaps = 2 * Reach + 1, kFloats = Values + 1;
  if (lanes == simd::kLanes && buffer_pixel[0] == buffer_pixel[simd::kLanes - 1]) {
    // All 16 samples in one pixel (lanes are in sample order, so first = last means all).
    const PixelPacketSums<Reach, Values, Extras> packet(values, wx, wy, extras);
    const float* totals = packet.totals;
    for (int e = 0; e < Extras; ++e) extra_sums[e] = totals[packet.kSums + e];
    // A row of taps is contiguous both here and in the buffer (kFloats per pixel).
    const int x = buffer_pixel[0] % stride, y = buffer_pixel[0] / stride;
    for (int j = 0; j < kTaps; ++j) {
      float* dst = sums + (static_cast<std::size_t>(y + j - Reach) * stride + (x - Reach)) * kFloats;
      for (int k = 0; k < kTaps * kFloats; ++k) dst[k] += totals[j * kTaps * kFloats + k];
    }
    return true;
  }
  using Splat = PixelSplat<Reach, Values>;
  Splat acc;
  int current = buffer_pixel[0];
  for (int l = 0; l < lanes; ++l) {
    if (buffer_pixel[l] != current) {
      acc.flush(sums, stride, current % stride, current / stride);
      acc = Splat{};
      current = buffer_pixel[l];
    }
    typename Splat::Vector v{};
    for (int c = 0; c < Values; ++c) v[c] = values[c][l];
    acc.add(wx, wy, l, v);
  }
  acc.flush(sums, stride, current % stride, current / stride);
  return false;
}

// The denoiser's splat (RGBA, unshadowed RGB, weight per buffer pixel) of a packet whose 16
// samples are all one pixel's and none sees the model: their unshadowed light is then one colour
// (the background's at the pixel's centre row, white in transparent frames), so its sums are that
// colour times the sums of the weights, and only the beauty's products are formed (5 floats a tap
// instead of 8). Most packets of a frame are background or ground. With `extras`, their lanes'
// sums go to `extra_sums` as in splat_packet.
template <int Reach, int Extras>
MESHTOUR_SIMD_INLINE void splat_uniform_light_packet(const F16 (&rgba)[4], const float (&light)[3], const F16* wx, const F16* wy,
                                                     int buffer_pixel, float* sums, int stride, const F16* extras = nullptr,
                                                     float* extra_sums = nullptr) {
  constexpr int kTaps = 2 * Reach + 1, kIn = 5, kOut = 8;
  const PixelPacketSums<Reach, 4, Extras> packet(rgba, wx, wy, extras);
  const float* totals = packet.totals;
  for (int e = 0; e < Extras; ++e) extra_sums[e] = totals[packet.kSums + e];
  const int x = buffer_pixel % stride, y = buffer_pixel / stride;
  for (int j = 0; j < kTaps; ++j)
    for (int i = 0; i < kTaps; ++i) {
      float* dst = sums + (static_cast<std::size_t>(y + j - Reach) * stride + (x + i - Reach)) * kOut;
      const float* t = totals + (j * kTaps + i) * kIn;
      for (int c = 0; c < 4; ++c) dst[c] += t[c];
      for (int c = 0; c < 3; ++c) dst[4 + c] += light[c] * t[4];
      dst[7] += t[4];
    }
}

// The backdrop's colour at height t (0 at the frame's top row, 1 at its bottom): a vertical gradient.
MESHTOUR_SIMD_INLINE V3 backdrop_colour(const Eigen::Vector3f& top, const Eigen::Vector3f& bottom, F16 t) {
  return {(1.0f - t) * top.x() + t * bottom.x(), (1.0f - t) * top.y() + t * bottom.y(), (1.0f - t) * top.z() + t * bottom.z()};
}

// The nearest of a one-pixel packet's depths.
MESHTOUR_SIMD_INLINE float nearest_depth(F16 depth) {
  float nearest = depth[0];
  for (int l = 1; l < simd::kLanes; ++l) nearest = std::min(nearest, depth[l]);
  return nearest;
}

MESHTOUR_SIMD_INLINE F16 luminance(F16 r, F16 g, F16 b) { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }

// What the denoiser gathers per pixel besides the splatted unshadowed light (denoiser.h): normal
// sums, the moments of each sample's visibility (its light divided by its unshadowed light: the
// variance estimate) and the nearest depth. The five sums of a packet whose 16 samples are one
// pixel's ride in splat_packet's spare slots; other packets add lane by lane.
constexpr int kGuideSums = 5;
MESHTOUR_SIMD_INLINE void guide_values(bool transparent, const F16 (&rgba)[4], const V3& unshadowed, const V3& normal, F16 (&out)[kGuideSums]) {
  const F16 unshadowed_luma = simd::max(luminance(unshadowed.x, unshadowed.y, unshadowed.z), simd::broadcast(1e-4f));
  const F16 signal = luminance(rgba[0], rgba[1], rgba[2]) / unshadowed_luma + (transparent ? rgba[3] : simd::broadcast(0.0f));
  out[0] = normal.x;
  out[1] = normal.y;
  out[2] = normal.z;
  out[3] = signal;
  out[4] = signal * signal;
}
MESHTOUR_SIMD_INLINE void add_pixel_guides(DenoiseGuides& g, std::size_t p, const float (&sums)[kGuideSums], float nearest) {
  for (int c = 0; c < 3; ++c) g.normal[p * 3 + c] += sums[c];
  g.moments[p * 2 + 0] += sums[3];
  g.moments[p * 2 + 1] += sums[4];
  g.depth[p] = std::min(g.depth[p], nearest);
}
MESHTOUR_SIMD_INLINE void add_lane_guides(DenoiseGuides& g, const int* image_pixel, int lanes, const F16 (&values)[kGuideSums], F16 depth) {
  for (int l = 0; l < lanes; ++l) {
    const float sums[kGuideSums] = {values[0][l], values[1][l], values[2][l], values[3][l], values[4][l]};
    add_pixel_guides(g, static_cast<std::size_t>(image_pixel[l]), sums, depth[l]);
  }
}

}  // namespace

// The hot loop: a tile's samples, 16 at a time (one packet; one pixel at 16 spp). Each packet
// goes through every stage before the next starts, so its data stay in registers and L1: camera
// rays, rtcIntersect16, shading (everything but the visibility of the chosen light and the sky),
// one rtcOccluded16 for the shadow rays and one for the occlusion rays, the filter's weights,
// and the splat.
void Renderer::Impl::MESHTOUR_TILE_KERNEL(const Frame& f, Scratch& scratch, const FilmTile& film, RayRecording::Tile* recorded,
                                          TileCounts& counts) const {
  RTCIntersectContext coherent;
  rtcInitIntersectContext(&coherent);
  coherent.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  RTCIntersectContext incoherent;
  rtcInitIntersectContext(&incoherent);
  incoherent.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;

  const int x0 = film.x0, y0 = film.y0, x1 = film.x1, y1 = film.y1;
  float* const sums = film.sums;
  const int tile_w = x1 - x0;
  const int spp = f.spp;
  const int nsamples = tile_w * (y1 - y0) * spp;
  const std::size_t nlights = f.lights.size();
  const V3 eye = broadcast(f.eye);
  const F16 zero = simd::broadcast(0.0f), one = simd::broadcast(1.0f);
  I16 lane_index;
  for (int l = 0; l < simd::kLanes; ++l) lane_index.set(l, l);

  // The sample after the last one set up: its pixel (within the tile) and index in the pixel,
  // the random key of the pixel's block, and the pixel's first index in the block's sequence.
  int next_pixel = 0, next_sample = 0;
  std::uint32_t block_key = 0, pixel_base = 0;
  int pixel_x = 0, pixel_y = 0;
  int log2_spp = 0;
  while ((1 << log2_spp) < spp) ++log2_spp;

  for (int k0 = 0; k0 < nsamples; k0 += simd::kLanes) {
    const int lanes = std::min(simd::kLanes, nsamples - k0);
    // Lane set-up (scalar): pixel, sample index, random key.
    alignas(64) float px[16] = {}, py[16] = {};
    alignas(64) std::uint32_t lane_key[16] = {}, lane_sample[16] = {};
    alignas(64) int buffer_pixel[16] = {};
    alignas(64) int image_pixel[16] = {};
    for (int l = 0; l < lanes; ++l) {
      if (next_sample == 0) {
        pixel_x = x0 + next_pixel % tile_w;
        pixel_y = y0 + next_pixel / tile_w;
        const std::uint64_t key = rng::pixel_key(f.index ^ f.seed, sampler::block_of(pixel_x, pixel_y));
        block_key = static_cast<std::uint32_t>(key ^ (key >> 32));
        pixel_base = sampler::first_index(pixel_x, pixel_y, log2_spp);
      }
      px[l] = static_cast<float>(pixel_x);
      py[l] = static_cast<float>(pixel_y);
      buffer_pixel[l] = film.sums_pixel(pixel_x, pixel_y);
      image_pixel[l] = film.layer_pixel(pixel_x, pixel_y);
      lane_key[l] = block_key;
      lane_sample[l] = pixel_base | static_cast<std::uint32_t>(next_sample);
      if (++next_sample == spp) {
        next_sample = 0;
        ++next_pixel;
      }
    }
    const I16 valid = simd::lt(lane_index, lanes);
    // Sample numbers: Owen-scrambled Sobol points, one shuffled 2D sequence per pair of
    // dimensions (sampler.h).
    const simd::U16 key = simd::load_uint(lane_key), sample_reversed = sampler::reverse_bits(simd::load_uint(lane_sample));
    F16 u_cam, v_cam, u_light, v_light, u_sky, v_sky;
    sampler::pair(sample_reversed, sampler::pair_seeds(key, 0), u_cam, v_cam);
    sampler::pair(sample_reversed, sampler::pair_seeds(key, 1), u_light, v_light);
    sampler::pair(sample_reversed, sampler::pair_seeds(key, 2), u_sky, v_sky);

    // 1. Camera rays, spread over the pixel by the sampler.
    const F16 offset_x = u_cam, offset_y = v_cam;
    const F16 fx = simd::load(px) + offset_x, fy = simd::load(py) + offset_y;
    V3 dir{f.corner.x() + fx * f.step_x.x() + fy * f.step_y.x(), f.corner.y() + fx * f.step_x.y() + fy * f.step_y.y(),
           f.corner.z() + fx * f.step_x.z() + fy * f.step_y.z()};
    const F16 inv_len = 1.0f / simd::sqrt(dot(dir, dir));
    dir = {dir.x * inv_len, dir.y * inv_len, dir.z * inv_len};
    RTCRayHit16& primary = scratch.primary;
    set_rays(primary.ray, valid, eye, dir, std::numeric_limits<float>::infinity(), f.camera_mask);
    simd::store_int(primary.hit.geomID, simd::broadcast_int(static_cast<std::int32_t>(RTC_INVALID_GEOMETRY_ID)));
    simd::store_int(primary.hit.instID[0], simd::broadcast_int(static_cast<std::int32_t>(RTC_INVALID_GEOMETRY_ID)));
    ValidMask primary_valid;
    simd::store_int(primary_valid.data(), valid);
    RayRecording::Packet* rec = nullptr;
    if (recorded) {
      rec = &recorded->packets.emplace_back();
      rec->primary = primary;
      rec->primary_valid = primary_valid;
    }
    rtcIntersect16(primary_valid.data(), scene.get(), &coherent, &primary);
    counts.primary += static_cast<std::uint64_t>(lanes);

    // 2. Shading.
    const I16 geom = simd::load_int(primary.hit.geomID);
    const I16 on_model = simd::both(valid, simd::eq(geom, static_cast<int>(kModelGeometry)));
    const I16 on_ground = simd::both(valid, simd::eq(geom, static_cast<int>(kGroundGeometry)));
    const F16 t_bg = simd::min(one, simd::max(zero, fy * f.inv_height));
    V3 bg{zero, zero, zero};
    if (!f.transparent)
      bg = backdrop_colour(f.background_top, f.background_bottom, t_bg);
    // What a sample contributes: base + (shadow ray unblocked ? with_light : 0) +
    // (occlusion ray unblocked ? with_sky : 0); RGBA each.
    F16 base[4] = {bg.x, bg.y, bg.z, zero}, with_light[4] = {zero, zero, zero, zero}, with_sky[4] = {zero, zero, zero, zero};
    I16 shadow_valid = simd::broadcast_int(0), sky_valid = simd::broadcast_int(0);
    V3 shadow_dir{zero, zero, one}, sky_dir{zero, zero, one}, org = eye;
    // What the sample tells the denoiser (denoiser.h): the shading normal, the depth, and the
    // light it would get if no shadow or occlusion ray were blocked (the background's colour, or
    // white in transparent frames, for the ground and the background: their "lighting" is the
    // shadow): the frame is divided by it, so that the denoiser filters only the visibility of
    // the lights and the sky (the shading's detail, normals, textures and highlights, is
    // noise-free and stays sharp).
    V3 guide_normal{zero, zero, zero};
    V3 guide_unshadowed = f.transparent ? V3{one, one, one} : bg;
    F16 guide_depth = simd::broadcast(std::numeric_limits<float>::infinity());

    const bool any_hit = simd::any(simd::either(on_model, on_ground));
    if (any_hit) {
      const F16 t = simd::load(primary.ray.tfar);
      guide_depth = simd::select(simd::either(on_model, on_ground), t * dot(dir, broadcast(f.forward)), guide_depth);
      V3 ng{simd::load(primary.hit.Ng_x), simd::load(primary.hit.Ng_y), simd::load(primary.hit.Ng_z)};
      const F16 ng_len2 = dot(ng, ng);
      // Two-sided: open scans show their inside.
      const F16 ng_scale = simd::select(simd::gt(dot(ng, dir), 0.0f), -one, one) / simd::select(simd::gt(ng_len2, 0.0f), simd::sqrt(ng_len2), one);
      ng = {ng.x * ng_scale, ng.y * ng_scale, ng.z * ng_scale};
      org = {eye.x + t * dir.x + f.eps * ng.x, eye.y + t * dir.y + f.eps * ng.y, eye.z + t * dir.z + f.eps * ng.z};

      if (simd::any(on_model)) {
        // Smooth normal and colour: interpolated from the hit triangle's vertices (gathers).
        alignas(64) float nx[16] = {}, ny[16] = {}, nz[16] = {}, ar[16], ag[16], ab[16];
        for (int l = 0; l < simd::kLanes; ++l) {
          ar[l] = f.base_color.x();
          ag[l] = f.base_color.y();
          ab[l] = f.base_color.z();
          if (!on_model[l]) continue;
          const std::size_t prim = primary.hit.primID[l];
          const auto& tri = triangles[prim];
          const float bu = primary.hit.u[l], bv = primary.hit.v[l], bw = 1.0f - bu - bv;
          const Eigen::Vector3f n = bw * normals[tri[0]] + bu * normals[tri[1]] + bv * normals[tri[2]];
          nx[l] = n.x();
          ny[l] = n.y();
          nz[l] = n.z();
          Eigen::Vector3f c(ar[l], ag[l], ab[l]);
          if (!colors.empty()) c = bw * colors[tri[0]] + bu * colors[tri[1]] + bv * colors[tri[2]];
          if (!surfaces.empty()) {
            const Surface& surface = surfaces[triangle_surface.empty() ? 0 : triangle_surface[prim]];
            if (surface.texture) {
              const Eigen::Vector2f uv = bw * corner_uvs[3 * prim] + bu * corner_uvs[3 * prim + 1] + bv * corner_uvs[3 * prim + 2];
              // Isotropic footprint of one sample in texture space: the pixel's width at this
              // distance, stretched by the slant, divided by sqrt(spp) because the samples already
              // average over the pixel.
              const float slant = std::max(0.2f, std::abs(ng.x[l] * dir.x[l] + ng.y[l] * dir.y[l] + ng.z[l] * dir.z[l]));
              const float width_uv = uv_scale[prim] * t[l] * f.pixel_angle / slant / std::sqrt(static_cast<float>(spp));
              OIIO::TextureOpt opt;
              opt.swrap = surface.wrap_s;
              opt.twrap = surface.wrap_t;
              float rgb[3] = {0, 0, 0};
              // OBJ's v runs upwards; OpenImageIO's t runs down the image.
              if (textures->texture(surface.texture, scratch.texture_thread, opt, uv.x(), 1.0f - uv.y(), width_uv, 0.0f, 0.0f,
                                    width_uv, 3, rgb)) {
                const Eigen::Vector3f texel = surface.texture_srgb ? srgb_to_linear(Eigen::Vector3f(rgb[0], rgb[1], rgb[2]))
                                                                   : Eigen::Vector3f(rgb[0], rgb[1], rgb[2]);
                c = surface.texture_times_vertex_colors && !colors.empty() ? Eigen::Vector3f(texel.cwiseProduct(c)) : texel;
              }
              c = c.cwiseProduct(surface.factor);
            } else if (surface.replaces_base_color) {
              c = colors.empty() ? surface.factor : Eigen::Vector3f(c.cwiseProduct(surface.factor));
            }
          }
          ar[l] = c.x();
          ag[l] = c.y();
          ab[l] = c.z();
        }
        V3 n{simd::load(nx), simd::load(ny), simd::load(nz)};
        const F16 n_len2 = dot(n, n);
        const F16 inv_n = 1.0f / simd::sqrt(simd::select(simd::gt(n_len2, 0.0f), n_len2, one));
        n = select(simd::gt(n_len2, 0.0f), V3{n.x * inv_n, n.y * inv_n, n.z * inv_n}, ng);
        n = select(simd::gt(dot(n, dir), 0.0f), V3{-n.x, -n.y, -n.z}, n);
        const V3 albedo{simd::load(ar), simd::load(ag), simd::load(ab)};
        guide_normal = select(on_model, n, guide_normal);
        const V3 view{-dir.x, -dir.y, -dir.z};
        // Unshadowed Blinn-Phong light from a light (cos_l = cosine of its incidence, > 0).
        auto reflected = [&](const V3& light_dir, const V3& radiance, F16 cos_l) __attribute__((always_inline)) {
          const V3 half{light_dir.x + view.x, light_dir.y + view.y, light_dir.z + view.z};
          const F16 cos_h = dot(n, half) / simd::sqrt(dot(half, half));
          const F16 spec = simd::select(simd::gt(cos_h, f.spec_cutoff), f.spec_scale * simd::pow_unit(simd::max(cos_h, simd::broadcast(1e-30f)), f.shininess), zero);
          return V3{radiance.x * (albedo.x + spec) * cos_l, radiance.y * (albedo.y + spec) * cos_l, radiance.z * (albedo.z + spec) * cos_l};
        };
        // What each light would bring here unshadowed (diffuse and highlight; 0 from behind).
        V3 contributions[8];
        for (std::size_t i = 0; i < nlights; ++i) {
          const F16 cos_i = dot(n, broadcast(f.lights[i].direction));
          const V3 c = reflected(broadcast(f.lights[i].direction), broadcast(f.lights[i].radiance), cos_i);
          const I16 lit = simd::gt(cos_i, 0.0f);
          contributions[i] = {simd::select(lit, c.x, zero), simd::select(lit, c.y, zero), simd::select(lit, c.z, zero)};
        }
        V3 model_base{zero, zero, zero};
        V3 model_light{zero, zero, zero};
        I16 model_shadow = simd::broadcast_int(0);
        if (f.shadows) {
          // One shadow ray to one light, chosen in proportion to the light it brings here
          // unshadowed (the luminance of its whole contribution, highlight included) and weighted
          // by 1/probability: unbiased, exact in luminance wherever no light is blocked, and the
          // light that matters most here gets most of the rays.
          F16 weights[8];
          F16 total = zero;
          for (std::size_t i = 0; i < nlights; ++i) {
            weights[i] = luminance(contributions[i].x, contributions[i].y, contributions[i].z);
            total += weights[i];
          }
          F16 u_disc;
          const I16 chosen = choose(weights, nlights, total, u_light, u_disc);
          F16 chosen_weight = zero;
          V3 c{zero, zero, zero};
          for (std::size_t i = 0; i < nlights; ++i) {
            const I16 m = simd::eq(chosen, static_cast<int>(i));
            chosen_weight = simd::select(m, weights[i], chosen_weight);
            c = select(m, contributions[i], c);
          }
          model_shadow = simd::both(on_model, simd::gt(total, 0.0f));
          const LaneLight light = lane_light(f.lights, chosen);
          const F16 inverse_probability = total / simd::select(model_shadow, chosen_weight, one);
          model_light = {c.x * inverse_probability, c.y * inverse_probability, c.z * inverse_probability};
          shadow_dir = light_direction(light, u_disc, v_light);
        } else {
          for (std::size_t i = 0; i < nlights; ++i)
            model_base = {model_base.x + contributions[i].x, model_base.y + contributions[i].y, model_base.z + contributions[i].z};
        }
        const V3 sky{albedo.x * f.ambient.x(), albedo.y * f.ambient.y(), albedo.z * f.ambient.z()};
        if (film.guides) {
          V3 unshadowed = sky;
          for (std::size_t i = 0; i < nlights; ++i)
            unshadowed = {unshadowed.x + contributions[i].x, unshadowed.y + contributions[i].y, unshadowed.z + contributions[i].z};
          guide_unshadowed = select(on_model, unshadowed, guide_unshadowed);
        }
        V3 model_sky{zero, zero, zero};
        if (f.ambient_occlusion) {
          model_sky = sky;
          V3 t1, t2;
          basis(n, t1, t2);
          sky_dir = select(on_model, sky_direction(n, t1, t2, u_sky, v_sky), sky_dir);
          sky_valid = simd::either(sky_valid, on_model);
        } else {
          model_base = {model_base.x + sky.x, model_base.y + sky.y, model_base.z + sky.z};
        }
        shadow_valid = simd::either(shadow_valid, model_shadow);
        base[0] = simd::select(on_model, model_base.x, base[0]);
        base[1] = simd::select(on_model, model_base.y, base[1]);
        base[2] = simd::select(on_model, model_base.z, base[2]);
        base[3] = simd::select(on_model, one, base[3]);
        with_light[0] = simd::select(model_shadow, model_light.x, with_light[0]);
        with_light[1] = simd::select(model_shadow, model_light.y, with_light[1]);
        with_light[2] = simd::select(model_shadow, model_light.z, with_light[2]);
        with_sky[0] = simd::select(on_model, model_sky.x, with_sky[0]);
        with_sky[1] = simd::select(on_model, model_sky.y, with_sky[1]);
        with_sky[2] = simd::select(on_model, model_sky.z, with_sky[2]);

        // Extra layers: averaged over the pixel's own samples (no filter: they are data, not light).
        if (film.albedo || film.normal || film.depth)
          for (int l = 0; l < simd::kLanes; ++l) {
            if (!on_model[l]) continue;
            const std::size_t pixel = static_cast<std::size_t>(image_pixel[l]);
            if (film.albedo) {
              film.albedo[pixel * 3 + 0] += albedo.x[l] / static_cast<float>(spp);
              film.albedo[pixel * 3 + 1] += albedo.y[l] / static_cast<float>(spp);
              film.albedo[pixel * 3 + 2] += albedo.z[l] / static_cast<float>(spp);
            }
            if (film.normal) {
              film.normal[pixel * 3 + 0] += n.x[l];
              film.normal[pixel * 3 + 1] += n.y[l];
              film.normal[pixel * 3 + 2] += n.z[l];
            }
            if (film.depth) {
              const float depth = t[l] * (dir.x[l] * f.forward.x() + dir.y[l] * f.forward.y() + dir.z[l] * f.forward.z());
              film.depth[pixel] = std::min(film.depth[pixel], depth);
            }
          }
      }

      if (simd::any(on_ground)) {
        guide_normal = select(on_ground, broadcast(f.up), guide_normal);
        // The ground shows the background, darkened by the share of light and sky the model
        // takes away from it (a shadow catcher); transparent frames get the shadow as alpha. The
        // share whose ray is traced comes back if the ray is unblocked.
        F16 unshadowed = simd::broadcast(1.0f - f.ground_shadow);
        const F16 alpha_sign = simd::broadcast(f.transparent ? -1.0f : 0.0f);
        // Only the model casts shadows on the ground: a ray that misses the model's bounding
        // sphere is known to be unblocked and is not traced (most of the visible ground).
        const F16 dist2 = dot(org, org), dist = simd::sqrt(dist2);
        const float radius2 = f.model_radius * f.model_radius;
        const F16 sin_r = simd::min(one, f.model_radius / dist), cos_r = simd::sqrt(1.0f - sin_r * sin_r);
        const I16 inside = simd::le(dist2, radius2);
        // The same test for a light's whole disc, before sampling a direction in it: the cone
        // around the light's centre misses the sphere when the angle between its axis and the
        // sphere's centre exceeds the cone's half angle plus the sphere's angular radius.
        auto disc_may_hit_model = [&](const V3& light_dir, F16 cos_half, F16 sin_half) __attribute__((always_inline)) {
          const F16 cos_limit = cos_half * cos_r - sin_half * sin_r;  // cos(half angle + radius)
          const F16 cos_axis = -dot(org, light_dir) / dist;
          return simd::either(inside, simd::ge(cos_axis, cos_limit - 1e-4f));  // margin for rounding
        };
        if (f.ground_light_share > 0.0f) {
          I16 shadow_possible = simd::broadcast_int(0);  // from some light with a share of the ground's light
          if (f.shadows)
            for (std::size_t i = 0; i < nlights; ++i)
              if (f.ground_weights[i] > 0.0f)
                shadow_possible = simd::either(shadow_possible, disc_may_hit_model(broadcast(f.lights[i].direction), simd::broadcast(f.lights[i].cos_half_angle),
                                                      simd::broadcast(f.lights[i].sin_half_angle)));
          F16 u_disc;
          const I16 chosen = choose(f.ground_weights, nlights, simd::broadcast(f.ground_light_total), u_light, u_disc);
          const LaneLight light = lane_light(f.lights, chosen);
          const V3 d = light_direction(light, u_disc, v_light);
          const F16 b = dot(org, d), c = dist2 - radius2;
          const I16 may_hit = simd::either(simd::lt(c, 0.0f), simd::both(simd::lt(b, 0.0f), simd::ge(b * b, c)));
          const I16 traced = simd::both(simd::both(on_ground, shadow_possible), simd::both(disc_may_hit_model(light.direction, light.cos_half_angle, light.sin_half_angle), may_hit));
          unshadowed += simd::select(traced, zero, simd::broadcast(f.ground_light_share));
          for (int ch = 0; ch < 3; ++ch)
            with_light[ch] = simd::select(traced, (ch == 0 ? bg.x : ch == 1 ? bg.y : bg.z) * f.ground_light_share, with_light[ch]);
          with_light[3] = simd::select(traced, alpha_sign * f.ground_light_share, with_light[3]);
          shadow_dir = select(traced, d, shadow_dir);
          shadow_valid = simd::either(shadow_valid, traced);
        }
        if (f.ground_sky_share > 0.0f) {
          // Beyond the AO length from the model's bounding sphere nothing can occlude the sky.
          const I16 traced = f.ambient_occlusion ? simd::both(on_ground, simd::lt(dist2, f.ground_ao_reach2)) : simd::broadcast_int(0);
          unshadowed += simd::select(traced, zero, simd::broadcast(f.ground_sky_share));
          for (int ch = 0; ch < 3; ++ch)
            with_sky[ch] = simd::select(traced, (ch == 0 ? bg.x : ch == 1 ? bg.y : bg.z) * f.ground_sky_share, with_sky[ch]);
          with_sky[3] = simd::select(traced, alpha_sign * f.ground_sky_share, with_sky[3]);
          const V3 up = broadcast(f.up);
          sky_dir = select(traced, sky_direction(up, broadcast(f.up_t1), broadcast(f.up_t2), u_sky, v_sky), sky_dir);
          sky_valid = simd::either(sky_valid, traced);
        }
        base[0] = simd::select(on_ground, bg.x * unshadowed, base[0]);
        base[1] = simd::select(on_ground, bg.y * unshadowed, base[1]);
        base[2] = simd::select(on_ground, bg.z * unshadowed, base[2]);
        base[3] = simd::select(on_ground, f.transparent ? 1.0f - unshadowed : zero, base[3]);
      }
    }

    // 3. Shadow and occlusion rays: Embree stops at the first hit.
    ValidMask shadow_lanes, sky_lanes;
    simd::store_int(shadow_lanes.data(), shadow_valid);
    simd::store_int(sky_lanes.data(), sky_valid);
    const bool any_shadow = simd::any(shadow_valid), any_sky = simd::any(sky_valid);
    if (any_shadow) set_rays(scratch.shadow, shadow_valid, org, shadow_dir, std::numeric_limits<float>::infinity(), kModelMask | kGroundMask);
    if (any_sky) set_rays(scratch.sky, sky_valid, org, sky_dir, f.ao_length, kModelMask | kGroundMask);
    if (rec) {
      if (any_shadow) rec->shadow = scratch.shadow;
      if (any_sky) rec->sky = scratch.sky;
      rec->shadow_valid = shadow_lanes;
      rec->sky_valid = sky_lanes;
    }
    if (any_shadow) rtcOccluded16(shadow_lanes.data(), scene.get(), &incoherent, &scratch.shadow);
    if (any_sky) rtcOccluded16(sky_lanes.data(), scene.get(), &incoherent, &scratch.sky);
    counts.secondary += static_cast<std::uint64_t>(popcount(shadow_valid) + popcount(sky_valid));
    // rtcOccluded16 sets tfar to -inf where the ray is blocked.
    const I16 light_seen = any_shadow ? simd::both(shadow_valid, simd::ge(simd::load(scratch.shadow.tfar), 0.0f)) : shadow_valid;
    const I16 sky_seen = any_sky ? simd::both(sky_valid, simd::ge(simd::load(scratch.sky.tfar), 0.0f)) : sky_valid;
    F16 rgba[4];
    for (int ch = 0; ch < 4; ++ch)
      rgba[ch] = base[ch] + simd::select(light_seen, with_light[ch], zero) + simd::select(sky_seen, with_sky[ch], zero);

    // 4. Reconstruction filter: every sample is splatted onto the pixels within the radius.
    F16 wx[5], wy[5];
    filter.weights(offset_x, wx);
    filter.weights(offset_y, wy);
    const bool one_pixel = lanes == simd::kLanes && buffer_pixel[0] == buffer_pixel[simd::kLanes - 1];
    // The unshadowed light splatted off the model: the background's colour at the pixel's centre
    // row rather than each sample's own (they differ by a thousandth at most), one colour for
    // all of a pixel's samples, so that a pixel of ground and background needs no sums of its own
    // for it (splat_uniform_light_packet). The moments keep each sample's own: there the far
    // ground's visibility is exactly 1, without noise, and is not filtered.
    V3 splat_light = guide_unshadowed;
    if (film.guides && !f.transparent) {
      const F16 t_centre = simd::min(one, simd::max(zero, (simd::load(py) + 0.5f) * f.inv_height));
      splat_light = select(on_model, guide_unshadowed, backdrop_colour(f.background_top, f.background_bottom, t_centre));
    }
    if (film.guides && one_pixel && !any_hit) {
      // One pixel's samples, all on the background: its guides stay as the tile cleared them (no
      // normal, no depth: the denoiser passes the pixel through).
      const float light[3] = {splat_light.x[0], splat_light.y[0], splat_light.z[0]};
      switch (filter.reach()) {
        case 0: splat_uniform_light_packet<0, 0>(rgba, light, wx, wy, buffer_pixel[0], sums, film.stride); break;
        case 1: splat_uniform_light_packet<1, 0>(rgba, light, wx, wy, buffer_pixel[0], sums, film.stride); break;
        default: splat_uniform_light_packet<2, 0>(rgba, light, wx, wy, buffer_pixel[0], sums, film.stride); break;
      }
    } else if (film.guides && one_pixel && !simd::any(on_model)) {
      // One pixel's samples on the ground and the background: the normal is the ground's for
      // every sample on it, and only the visibility's moments are summed.
      const float light[3] = {splat_light.x[0], splat_light.y[0], splat_light.z[0]};
      F16 values[kGuideSums];
      guide_values(f.transparent, rgba, guide_unshadowed, guide_normal, values);
      const F16 moments[2] = {values[3], values[4]};
      float moment_sums[2];
      switch (filter.reach()) {
        case 0: splat_uniform_light_packet<0, 2>(rgba, light, wx, wy, buffer_pixel[0], sums, film.stride, moments, moment_sums); break;
        case 1: splat_uniform_light_packet<1, 2>(rgba, light, wx, wy, buffer_pixel[0], sums, film.stride, moments, moment_sums); break;
        default: splat_uniform_light_packet<2, 2>(rgba, light, wx, wy, buffer_pixel[0], sums, film.stride, moments, moment_sums); break;
      }
      const float on_ground_samples = static_cast<float>(popcount(on_ground));
      const float pixel_sums[kGuideSums] = {f.up.x() * on_ground_samples, f.up.y() * on_ground_samples, f.up.z() * on_ground_samples,
                                            moment_sums[0], moment_sums[1]};
      add_pixel_guides(*film.guides, static_cast<std::size_t>(image_pixel[0]), pixel_sums, nearest_depth(guide_depth));
    } else if (film.guides) {
      // The denoiser divides the frame by the unshadowed light: splatted with the very same
      // weights, so that the ratio is the visibility also at silhouettes and colour edges.
      const F16 values[7] = {rgba[0], rgba[1], rgba[2], rgba[3], splat_light.x, splat_light.y, splat_light.z};
      F16 extras[kGuideSums];
      guide_values(f.transparent, rgba, guide_unshadowed, guide_normal, extras);
      float extra_sums[kGuideSums];
      bool summed = false;
      switch (filter.reach()) {
        case 0: summed = splat_packet<0, 7, kGuideSums>(values, wx, wy, buffer_pixel, lanes, sums, film.stride, extras, extra_sums); break;
        case 1: summed = splat_packet<1, 7, kGuideSums>(values, wx, wy, buffer_pixel, lanes, sums, film.stride, extras, extra_sums); break;
        default: summed = splat_packet<2, 7, kGuideSums>(values, wx, wy, buffer_pixel, lanes, sums, film.stride, extras, extra_sums); break;
      }
      if (summed) {
        add_pixel_guides(*film.guides, static_cast<std::size_t>(image_pixel[0]), extra_sums, nearest_depth(guide_depth));
      } else {
        add_lane_guides(*film.guides, image_pixel, lanes, extras, guide_depth);
      }
    } else {
      switch (filter.reach()) {
        case 0: splat_packet<0>(rgba, wx, wy, buffer_pixel, lanes, sums, film.stride); break;
        case 1: splat_packet<1>(rgba, wx, wy, buffer_pixel, lanes, sums, film.stride); break;
        default: splat_packet<2>(rgba, wx, wy, buffer_pixel, lanes, sums, film.stride); break;
      }
    }
  }
}

}  // namespace meshtour
