// The integrator: the per-tile hot loop of the renderer, which the sampler feeds and which feeds
// the Film (film.h), in named stages: camera rays, intersection, shading, shadow and occlusion
// rays, splat. Every stage is forced inline, so the loop compiles as one body.
// This file is compiled once per instruction set (instruction_set.h: each copy specialises
// Renderer::Impl::render_tile for its set) and the renderer picks the widest the CPU has; they all
// give the same bits (simd.h says why). A separate compilation rather than GCC's target_clones: in a clone GCC 12
// lowers 16-lane comparisons lane by lane, which cost a third of the kernel's speed.
#include <OpenImageIO/texture.h>
#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "tracer/color.h"
#include "tracer/denoiser.h"
#include "tracer/film.h"
#include "tracer/instruction_set.h"
#include "tracer/random.h"
#include "tracer/renderer_impl.h"
#include "tracer/sampler.h"
#include "tracer/simd.h"

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

// One shadow ray to one light, chosen in proportion to `weights` (the luminance of the light
// each brings unshadowed) and weighted by 1/probability: unbiased, exact in luminance wherever no
// light is blocked, and the light that matters most gets most of the rays. `valid`: the lanes
// that trace it (in `lanes` and with some light).
struct OneLightSample {
  V3 light;  // the chosen light's contribution over its probability
  V3 dir;    // towards a point on its disc
  I16 valid;
};
MESHTOUR_SIMD_INLINE OneLightSample sample_one_light(const std::vector<FrameLight>& lights, const V3 (&contributions)[8], const F16 (&weights)[8],
                                                     F16 total, I16 lanes, F16 u_light, F16 v_light) {
  const F16 zero = simd::broadcast(0.0f);
  F16 u_disc;
  const I16 chosen = choose(weights, lights.size(), total, u_light, u_disc);
  F16 chosen_weight = zero;
  V3 c{zero, zero, zero};
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const I16 m = simd::eq(chosen, static_cast<int>(i));
    chosen_weight = simd::select(m, weights[i], chosen_weight);
    c = select(m, contributions[i], c);
  }
  OneLightSample out;
  out.valid = simd::both(lanes, simd::gt(total, 0.0f));
  const F16 inverse_probability = total / simd::select(out.valid, chosen_weight, simd::broadcast(1.0f));
  out.light = {c.x * inverse_probability, c.y * inverse_probability, c.z * inverse_probability};
  out.dir = light_direction(lane_light(lights, chosen), u_disc, v_light);
  return out;
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

// ---- The stages of a packet: 16 samples (one pixel's at 16 spp) through every stage before the
// next packet starts, so that its data stay in registers and L1.

using Impl = Renderer::Impl;

// Sampling: which pixel each lane's sample belongs to and its random numbers.
struct PacketSamples {
  int lanes = 0;  // lanes in use (the tile's last packet may have fewer)
  I16 valid;      // the lanes in use
  alignas(64) float px[16], py[16];             // the pixel's corner on the film
  alignas(64) int sums_pixel[16], layer_pixel[16];  // the pixel in the tile's sums, in the layers
  simd::U16 sample_reversed;                    // each lane's index in its block's sequence, bit-reversed
  F16 u_cam, v_cam;                             // the point on the film
  F16 u_light, v_light, u_sky, v_sky;           // set by TileSampler::secondary, where a ray hit something
};

// A tile's samples in order: pixel by pixel along the tile's rows, each pixel's samples one after
// another. Owen-scrambled Sobol points, one shuffled 2D sequence per pair of dimensions (sampler.h).
// A tile lies inside one of the sampler's blocks (kTileSize divides the block's size), so the
// pairs' seeds are the tile's, computed once; the light's and the sky's pairs are computed only for
// packets whose camera rays hit something (most of a frame is backdrop), the same numbers either way.
class TileSampler {
  static_assert((1 << sampler::kBlockBits) % kTileSize == 0, "a tile must lie inside one sampler block");

public:
  MESHTOUR_SIMD_INLINE TileSampler(const Frame& f, const FilmTile& film)
      : film_(film), spp_(f.spp), tile_w_(film.x1 - film.x0), sample_count_(tile_w_ * (film.y1 - film.y0) * f.spp) {
    while ((1 << log2_spp_) < spp_) ++log2_spp_;
    for (int l = 0; l < simd::kLanes; ++l) lane_index_.set(l, l);
    const std::uint64_t key = rng::pixel_key(f.index ^ f.seed, sampler::block_of(film.x0, film.y0));
    const simd::U16 block_key = simd::U16{} + static_cast<std::uint32_t>(key ^ (key >> 32));
    for (std::uint32_t pair = 0; pair < 3; ++pair) seeds_[pair] = sampler::pair_seeds(block_key, pair);
    for (int pair = 0; pair < 2 * f.bounces; ++pair) bounce_seeds_[pair] = sampler::pair_seeds(block_key, 3 + static_cast<std::uint32_t>(pair));
  }
  int sample_count() const { return sample_count_; }

  // The next `lanes` samples: their pixels and sample indices, and the point on the film.
  MESHTOUR_SIMD_INLINE void next(int lanes, PacketSamples& s) {
    alignas(64) std::uint32_t lane_sample[16];
    s.lanes = lanes;
    if (lanes == simd::kLanes && next_sample_ + simd::kLanes <= spp_) {
      // All 16 samples in one pixel (at 16 spp and more, every packet).
      start_pixel_if_due();
      const float px = static_cast<float>(pixel_x_), py = static_cast<float>(pixel_y_);
      const int sums = film_.sums_pixel(pixel_x_, pixel_y_), layer = film_.layer_pixel(pixel_x_, pixel_y_);
      for (int l = 0; l < simd::kLanes; ++l) {
        s.px[l] = px, s.py[l] = py, s.sums_pixel[l] = sums, s.layer_pixel[l] = layer;
        lane_sample[l] = pixel_base_ | static_cast<std::uint32_t>(next_sample_ + l);
      }
      if ((next_sample_ += simd::kLanes) == spp_) {
        next_sample_ = 0;
        ++next_pixel_;
      }
    } else {
      for (int l = 0; l < simd::kLanes; ++l) {
        if (l >= lanes) {  // unused lanes: any pixel of the tile, never splatted
          s.px[l] = s.px[0], s.py[l] = s.py[0], s.sums_pixel[l] = s.sums_pixel[0], s.layer_pixel[l] = s.layer_pixel[0];
          lane_sample[l] = 0;
          continue;
        }
        start_pixel_if_due();
        s.px[l] = static_cast<float>(pixel_x_);
        s.py[l] = static_cast<float>(pixel_y_);
        s.sums_pixel[l] = film_.sums_pixel(pixel_x_, pixel_y_);
        s.layer_pixel[l] = film_.layer_pixel(pixel_x_, pixel_y_);
        lane_sample[l] = pixel_base_ | static_cast<std::uint32_t>(next_sample_);
        if (++next_sample_ == spp_) {
          next_sample_ = 0;
          ++next_pixel_;
        }
      }
    }
    s.valid = simd::lt(lane_index_, lanes);
    s.sample_reversed = sampler::reverse_bits(simd::load_uint(lane_sample));
    sampler::pair(s.sample_reversed, seeds_[0], s.u_cam, s.v_cam);
  }

  // The numbers of the light's and the sky's rays of the packet `next` set up.
  MESHTOUR_SIMD_INLINE void secondary(PacketSamples& s) const {
    sampler::pair(s.sample_reversed, seeds_[1], s.u_light, s.v_light);
    sampler::pair(s.sample_reversed, seeds_[2], s.u_sky, s.v_sky);
  }

  // The numbers of interreflection `bounce`'s (0 first) light and sky rays: two more pairs of
  // dimensions per bounce, after the three above.
  MESHTOUR_SIMD_INLINE void bounce(const PacketSamples& s, int bounce, F16& u_light, F16& v_light, F16& u_sky, F16& v_sky) const {
    sampler::pair(s.sample_reversed, bounce_seeds_[2 * bounce], u_light, v_light);
    sampler::pair(s.sample_reversed, bounce_seeds_[2 * bounce + 1], u_sky, v_sky);
  }

private:
  MESHTOUR_SIMD_INLINE void start_pixel_if_due() {
    if (next_sample_ != 0) return;
    pixel_x_ = film_.x0 + next_pixel_ % tile_w_;
    pixel_y_ = film_.y0 + next_pixel_ / tile_w_;
    pixel_base_ = sampler::first_index(pixel_x_, pixel_y_, log2_spp_);
  }

  const FilmTile& film_;
  int spp_, tile_w_, sample_count_, log2_spp_ = 0;
  I16 lane_index_;
  sampler::PairSeeds seeds_[3];  // the tile's block's seeds of the three pairs (camera, light, sky)
  sampler::PairSeeds bounce_seeds_[2 * kMaxBounces];  // and of the interreflections' pairs
  // The sample after the last one set up: its pixel (within the tile) and index in the pixel,
  // and the pixel's first index in the block's sequence.
  int next_pixel_ = 0, next_sample_ = 0;
  std::uint32_t pixel_base_ = 0;
  int pixel_x_ = 0, pixel_y_ = 0;
};

// 1. Camera rays through the samples' points on the film, spread over the pixel by the sampler.
struct CameraRays {
  V3 dir;      // unit directions
  F16 film_y;  // the points' row on the film (pixels, from the top)
};
MESHTOUR_SIMD_INLINE CameraRays camera_rays(const Frame& f, const PacketSamples& s) {
  const F16 fx = simd::load(s.px) + s.u_cam, fy = simd::load(s.py) + s.v_cam;
  V3 dir{f.corner.x() + fx * f.step_x.x() + fy * f.step_y.x(), f.corner.y() + fx * f.step_x.y() + fy * f.step_y.y(),
         f.corner.z() + fx * f.step_x.z() + fy * f.step_y.z()};
  const F16 inv_len = 1.0f / simd::sqrt(dot(dir, dir));
  dir = {dir.x * inv_len, dir.y * inv_len, dir.z * inv_len};
  return {dir, fy};
}

// 2. Intersection: the camera rays through rtcIntersect16 (coherent: neighbouring rays), and
// what they hit. Returns the packet's recording (RendererAccess), or null.
MESHTOUR_SIMD_INLINE RayRecording::Packet* intersect(const Impl& r, RTCIntersectContext& coherent, RTCRayHit16& primary,
                                                   const PacketSamples& s, const V3& eye, const V3& dir, RayRecording::Tile* recorded,
                                                   TileCounts& counts) {
  set_rays(primary.ray, s.valid, eye, dir, std::numeric_limits<float>::infinity(), kModelMask);
  simd::store_int(primary.hit.geomID, simd::broadcast_int(static_cast<std::int32_t>(RTC_INVALID_GEOMETRY_ID)));
  simd::store_int(primary.hit.instID[0], simd::broadcast_int(static_cast<std::int32_t>(RTC_INVALID_GEOMETRY_ID)));
  ValidMask primary_valid;
  simd::store_int(primary_valid.data(), s.valid);
  RayRecording::Packet* rec = nullptr;
  if (recorded) {
    rec = &recorded->packets.emplace_back();
    rec->primary = primary;
    rec->primary_valid = primary_valid;
  }
  rtcIntersect16(primary_valid.data(), r.rays->scene(), &coherent, &primary);
  counts.primary += static_cast<std::uint64_t>(s.lanes);
  return rec;
}

// What the camera rays hit.
struct Hits {
  I16 on_model, on_ground;
  bool any = false;  // some lane hit the model or the ground; t and ng are set only then
  F16 t = simd::broadcast(0.0f);  // distance along the ray
  V3 ng{t, t, t};                 // unit geometric normal, facing the camera (two-sided)
  V3 org;  // where the secondary rays start: the hit, a hair off the surface (the eye elsewhere)
};
// Where rays from `org` along `dir` (unit) meet the ground's square within (0, tfar): the ground
// is a plane the kernel intersects itself rather than two huge triangles in the BVH, whose boxes
// every ray near the floor would have to open; the BVH holds the model alone and is shared with
// the visibility module (mesh/ray_scene.h). `t` is set where the result is true.
MESHTOUR_SIMD_INLINE I16 ground_hit(const Frame& f, const V3& org, const V3& dir, F16 tfar, F16& t) {
  const V3 up = broadcast(f.up);
  const F16 along = dot(dir, up), height = dot(org, up) - f.ground_height;
  // From above going down, or from below going up: the plane is two-sided for occlusion.
  const I16 towards = simd::either(simd::both(simd::gt(height, 0.0f), simd::lt(along, 0.0f)), simd::both(simd::lt(height, 0.0f), simd::gt(along, 0.0f)));
  t = -height / simd::select(towards, along, simd::broadcast(1.0f));
  const V3 p{org.x + t * dir.x, org.y + t * dir.y, org.z + t * dir.z};
  const F16 a = dot(p, broadcast(f.up_t1)), b = dot(p, broadcast(f.up_t2)), half = simd::broadcast(f.ground_half);
  const I16 inside = simd::both(simd::both(simd::le(a, half), simd::ge(a, -half)), simd::both(simd::le(b, half), simd::ge(b, -half)));
  return simd::both(simd::both(towards, inside), simd::both(simd::gt(t, 0.0f), simd::lt(t, tfar)));
}

// The unit geometric normal of the hits in `hit`, turned to face the rays (along `dir`) that
// met it: two-sided, open scans show their inside.
MESHTOUR_SIMD_INLINE V3 facing_normal(const RTCHit16& hit, const V3& dir) {
  const F16 one = simd::broadcast(1.0f);
  const V3 ng{simd::load(hit.Ng_x), simd::load(hit.Ng_y), simd::load(hit.Ng_z)};
  const F16 ng_len2 = dot(ng, ng);
  const F16 ng_scale = simd::select(simd::gt(dot(ng, dir), 0.0f), -one, one) / simd::select(simd::gt(ng_len2, 0.0f), simd::sqrt(ng_len2), one);
  return {ng.x * ng_scale, ng.y * ng_scale, ng.z * ng_scale};
}

MESHTOUR_SIMD_INLINE Hits read_hits(const Frame& f, const RTCRayHit16& primary, const PacketSamples& s, const V3& eye, const V3& dir) {
  Hits h;
  const I16 geom = simd::load_int(primary.hit.geomID);
  h.on_model = simd::both(s.valid, simd::eq(geom, static_cast<int>(kModelGeometry)));
  F16 t = simd::load(primary.ray.tfar);  // +inf where the ray missed the model
  h.on_ground = simd::broadcast_int(0);
  F16 t_ground = t;
  if (f.ground_visible) {
    h.on_ground = simd::both(s.valid, ground_hit(f, eye, dir, t, t_ground));
    h.on_model = simd::both(h.on_model, ~h.on_ground);
  }
  h.any = simd::any(simd::either(h.on_model, h.on_ground));
  h.org = eye;
  if (h.any) {
    h.t = simd::select(h.on_ground, t_ground, t);
    h.ng = select(h.on_ground, broadcast(f.up), facing_normal(primary.hit, dir));
    h.org = {eye.x + h.t * dir.x + f.eps * h.ng.x, eye.y + h.t * dir.y + f.eps * h.ng.y, eye.z + h.t * dir.z + f.eps * h.ng.z};
  }
  return h;
}

// 3. Shading: everything about a sample but the visibility of its chosen light and of the sky,
// which the shadow and occlusion rays decide. Its RGBA is base + (shadow ray unblocked ?
// with_light : 0) + (occlusion ray unblocked ? with_sky : 0).
struct ShadedSamples {
  F16 base[4], with_light[4], with_sky[4];
  I16 shadow_valid, sky_valid;  // the lanes that trace a shadow ray, an occlusion ray
  V3 shadow_dir, sky_dir;       // from Hits::org
  // What the sample tells the denoiser (denoiser.h): the shading normal, the depth, and the
  // light it would get if no shadow or occlusion ray were blocked (the background's colour, or
  // white in transparent frames, for the ground and the background: their "lighting" is the
  // shadow): the frame is divided by it, so that the denoiser filters only the visibility of
  // the lights and the sky (the shading's detail, normals, textures and highlights, is
  // noise-free and stays sharp).
  V3 guide_normal, guide_unshadowed;
  F16 guide_depth;
  // Interreflections (Frame::bounces): the lanes whose occlusion ray, where the model blocks
  // it, brings back the light of the point it meets, and the factor on that light (the BRDF
  // times cos over the density of the ray's direction, the occlusion map's factor included).
  I16 bounce_valid;
  V3 bounce_weight;
};

// The backdrop behind the samples (none in transparent frames), and the shading of a sample
// that hits nothing: the backdrop, no rays.
MESHTOUR_SIMD_INLINE V3 backdrop(const Frame& f, const PacketSamples& s, const CameraRays& camera) {
  const F16 zero = simd::broadcast(0.0f), one = simd::broadcast(1.0f);
  if (!f.backdrop_rgb.empty()) {  // the environment, per pixel
    alignas(64) float r[16], g[16], b[16];
    for (int l = 0; l < simd::kLanes; ++l) {
      const float* p = &f.backdrop_rgb[(static_cast<std::size_t>(s.py[l]) * f.width + static_cast<std::size_t>(s.px[l])) * 3];
      r[l] = p[0], g[l] = p[1], b[l] = p[2];
    }
    return {simd::load(r), simd::load(g), simd::load(b)};
  }
  const F16 t_bg = simd::min(one, simd::max(zero, camera.film_y * f.inv_height));
  V3 bg{zero, zero, zero};
  if (!f.transparent) bg = backdrop_colour(f.background_top, f.background_bottom, t_bg);
  return bg;
}
MESHTOUR_SIMD_INLINE void shade_background(const Frame& f, const V3& bg, ShadedSamples& sh) {
  const F16 zero = simd::broadcast(0.0f), one = simd::broadcast(1.0f);
  sh.base[0] = bg.x, sh.base[1] = bg.y, sh.base[2] = bg.z, sh.base[3] = zero;
  for (int ch = 0; ch < 4; ++ch) sh.with_light[ch] = zero, sh.with_sky[ch] = zero;
  sh.shadow_valid = simd::broadcast_int(0), sh.sky_valid = simd::broadcast_int(0);
  sh.shadow_dir = {zero, zero, one}, sh.sky_dir = {zero, zero, one};
  sh.guide_normal = {zero, zero, zero};
  sh.guide_unshadowed = f.transparent ? V3{one, one, one} : bg;
  sh.guide_depth = simd::broadcast(std::numeric_limits<float>::infinity());
  sh.bounce_valid = simd::broadcast_int(0);
  sh.bounce_weight = {zero, zero, zero};
}

// One lookup of a map at `uv` (OBJ's convention, v up) with a footprint of `width_uv`: RGB, or
// false where OpenImageIO has no value (then `rgb` is untouched).
MESHTOUR_SIMD_INLINE bool look_up(const Impl& r, Scratch& scratch, const Impl::Map& map, const Eigen::Vector2f& uv, float width_uv,
                                  float (&rgb)[3]) {
  OIIO::TextureOpt opt;
  opt.swrap = map.wrap_s;
  opt.twrap = map.wrap_t;
  const bool magnified = width_uv * map.texels_across <= 1.0f;
  opt.interpmode = magnified ? map.mag_interp : map.min_interp;
  opt.mipmode = magnified ? OIIO::TextureOpt::MipModeNoMIP : map.mip;
  // OBJ's v runs upwards; OpenImageIO's t runs down the image.
  if (!r.textures->texture(map.handle, scratch.texture_thread, opt, uv.x(), 1.0f - uv.y(), width_uv, 0.0f, 0.0f, width_uv, map.grey ? 1 : 3,
                           rgb))
    return false;
  if (map.grey) rgb[1] = rgb[2] = rgb[0];
  return true;
}

// The model's surface at the hits: the shading normal (facing the camera) and the albedo, from the
// hit triangle's corners (gathers), its material and its maps.
struct SurfacePoint {
  V3 n, albedo;
  F16 sky_occlusion;  // the occlusion map's factor on the sky's light (1: none)
  // The file's own shading (Surface): where `metallic_roughness`, glTF's BRDF with these
  // parameters replaces the look's highlight; `emission` is added as it is; `unlit` lanes show
  // their albedo alone.
  I16 metallic_roughness, unlit;
  F16 metallic, roughness;
  V3 emission;
  bool any_metallic_roughness = false, any_unlit = false, any_emission = false;
};
// `footprint_angle`: the width of a sample's footprint per unit of distance along its ray
// (radians), which picks the maps' mip level.
MESHTOUR_SIMD_INLINE SurfacePoint surface_at(const Impl& r, const Frame& f, Scratch& scratch, const RTCRayHit16& primary, const Hits& h,
                                            const V3& dir, float footprint_angle) {
  const F16 one = simd::broadcast(1.0f);
  alignas(64) float nx[16] = {}, ny[16] = {}, nz[16] = {}, ar[16], ag[16], ab[16];
  // The normal before its normal map: which of its sides faces the camera decides the side of
  // the mapped one too (a mapped normal may lean away from the camera on a surface that faces it).
  alignas(64) float sx[16] = {}, sy[16] = {}, sz[16] = {};
  alignas(64) float occlusion[16];
  alignas(64) float metallic[16], roughness[16], er[16], eg[16], eb[16];
  alignas(64) std::int32_t pbr_lane[16], unlit_lane[16];
  // Per lane, what the maps need: the surface, the UV and footprint, the barycentrics.
  const Impl::Surface* lane_surface[16] = {};
  Eigen::Vector2f lane_uv[16];
  float lane_width[16] = {}, lane_b[16][3] = {};
  for (int l = 0; l < simd::kLanes; ++l) {
    ar[l] = f.base_color.x();
    ag[l] = f.base_color.y();
    ab[l] = f.base_color.z();
    occlusion[l] = 1.0f;
    metallic[l] = 0.0f, roughness[l] = 1.0f, er[l] = eg[l] = eb[l] = 0.0f;
    pbr_lane[l] = unlit_lane[l] = 0;
    if (!h.on_model[l]) continue;
    const std::size_t prim = primary.hit.primID[l];
    const auto& tri = r.triangles[prim];
    const float bu = primary.hit.u[l], bv = primary.hit.v[l], bw = 1.0f - bu - bv;
    const Eigen::Vector3f n = r.corner_normals.empty()
                                  ? Eigen::Vector3f(bw * r.normals[tri[0]] + bu * r.normals[tri[1]] + bv * r.normals[tri[2]])
                                  : Eigen::Vector3f(bw * r.corner_normals[3 * prim] + bu * r.corner_normals[3 * prim + 1] + bv * r.corner_normals[3 * prim + 2]);
    sx[l] = nx[l] = n.x();
    sy[l] = ny[l] = n.y();
    sz[l] = nz[l] = n.z();
    Eigen::Vector3f c(ar[l], ag[l], ab[l]);
    if (!r.colors.empty()) c = bw * r.colors[tri[0]] + bu * r.colors[tri[1]] + bv * r.colors[tri[2]];
    if (!r.surfaces.empty()) {
      const Impl::Surface& surface = r.surfaces[r.triangle_surface.empty() ? 0 : r.triangle_surface[prim]];
      pbr_lane[l] = surface.metallic_roughness ? -1 : 0;
      unlit_lane[l] = surface.unlit ? -1 : 0;
      metallic[l] = surface.metallic, roughness[l] = surface.roughness;
      er[l] = surface.emissive.x(), eg[l] = surface.emissive.y(), eb[l] = surface.emissive.z();
      if (surface.texture.handle || surface.normal_map.handle || surface.occlusion_map.handle || surface.metallic_roughness_map.handle ||
          surface.emissive_map.handle) {
        lane_surface[l] = &surface;
        lane_uv[l] = bw * r.corner_uvs[3 * prim] + bu * r.corner_uvs[3 * prim + 1] + bv * r.corner_uvs[3 * prim + 2];
        // Isotropic footprint of one sample in texture space: the footprint's width at this
        // distance, stretched by the slant.
        const float slant = std::max(0.2f, std::abs(h.ng.x[l] * dir.x[l] + h.ng.y[l] * dir.y[l] + h.ng.z[l] * dir.z[l]));
        lane_width[l] = r.uv_scale[prim] * h.t[l] * footprint_angle / slant;
        lane_b[l][0] = bw, lane_b[l][1] = bu, lane_b[l][2] = bv;
      }
      if (!surface.texture.handle && surface.replaces_base_color)
        c = r.colors.empty() ? surface.factor : Eigen::Vector3f(c.cwiseProduct(surface.factor));
    }
    ar[l] = c.x();
    ag[l] = c.y();
    ab[l] = c.z();
  }
  // The maps one after another over the packet's lanes (mostly one pixel's samples, so one tile
  // of each image): OpenImageIO's per-thread cache keeps the last tile, which looking up three
  // maps per lane in turn missed every time (9 % of a normal-mapped frame in its main cache).
  for (int l = 0; l < simd::kLanes; ++l) {
    const Impl::Surface* surface = lane_surface[l];
    if (!surface || !surface->texture.handle) continue;
    Eigen::Vector3f c(ar[l], ag[l], ab[l]);
    float rgb[3] = {0, 0, 0};
    if (look_up(r, scratch, surface->texture, lane_uv[l], lane_width[l], rgb)) {
      const Eigen::Vector3f texel = surface->texture.srgb ? srgb_to_linear(Eigen::Vector3f(rgb[0], rgb[1], rgb[2]))
                                                          : Eigen::Vector3f(rgb[0], rgb[1], rgb[2]);
      c = surface->texture_times_vertex_colors && !r.colors.empty() ? Eigen::Vector3f(texel.cwiseProduct(c)) : texel;
    }
    c = c.cwiseProduct(surface->factor);
    ar[l] = c.x();
    ag[l] = c.y();
    ab[l] = c.z();
  }
  for (int l = 0; l < simd::kLanes; ++l) {
    const Impl::Surface* surface = lane_surface[l];
    float rgb[3];
    if (surface && surface->occlusion_map.handle && look_up(r, scratch, surface->occlusion_map, lane_uv[l], lane_width[l], rgb))
      occlusion[l] = 1.0f + surface->occlusion_strength * (std::clamp(rgb[0], 0.0f, 1.0f) - 1.0f);
  }
  for (int l = 0; l < simd::kLanes; ++l) {
    const Impl::Surface* surface = lane_surface[l];
    float rgb[3];
    if (surface && surface->metallic_roughness_map.handle &&
        look_up(r, scratch, surface->metallic_roughness_map, lane_uv[l], lane_width[l], rgb)) {
      roughness[l] *= std::clamp(rgb[1], 0.0f, 1.0f);  // glTF: green is roughness, blue metalness
      metallic[l] *= std::clamp(rgb[2], 0.0f, 1.0f);
    }
  }
  for (int l = 0; l < simd::kLanes; ++l) {
    const Impl::Surface* surface = lane_surface[l];
    float rgb[3];
    if (surface && surface->emissive_map.handle && look_up(r, scratch, surface->emissive_map, lane_uv[l], lane_width[l], rgb)) {
      const Eigen::Vector3f e = surface->emissive_map.srgb ? srgb_to_linear(Eigen::Vector3f(rgb[0], rgb[1], rgb[2]))
                                                           : Eigen::Vector3f(rgb[0], rgb[1], rgb[2]);
      er[l] *= e.x(), eg[l] *= e.y(), eb[l] *= e.z();
    }
  }
  for (int l = 0; l < simd::kLanes; ++l) {
    const Impl::Surface* surface = lane_surface[l];
    float rgb[3];
    if (!surface || !surface->normal_map.handle || !look_up(r, scratch, surface->normal_map, lane_uv[l], lane_width[l], rgb)) continue;
    // The map's (x, y, z) in the corner frame (tangent, bitangent, normal), glTF's rule:
    // normalize((2 value - 1) * (scale, scale, 1)), the frame's tangent made perpendicular.
    const float k = surface->normal_scale;
    const Eigen::Vector3f m((2.0f * rgb[0] - 1.0f) * k, (2.0f * rgb[1] - 1.0f) * k, 2.0f * rgb[2] - 1.0f);
    const Eigen::Vector4f* ct = &r.corner_tangents[3 * static_cast<std::size_t>(primary.hit.primID[l])];
    const Eigen::Vector3f along = lane_b[l][0] * ct[0].head<3>() + lane_b[l][1] * ct[1].head<3>() + lane_b[l][2] * ct[2].head<3>();
    const Eigen::Vector3f n(nx[l], ny[l], nz[l]);
    const float n_len = n.norm();
    if (!(n_len > 0.0f)) continue;
    const Eigen::Vector3f unit_n = n / n_len;
    Eigen::Vector3f t = along - unit_n * unit_n.dot(along);
    if (!(t.squaredNorm() > 0.0f)) continue;
    t.normalize();
    const Eigen::Vector3f b = unit_n.cross(t) * (ct[0].w() < 0.0f ? -1.0f : 1.0f);
    const Eigen::Vector3f mapped_n = m.x() * t + m.y() * b + m.z() * unit_n;
    if (!(mapped_n.squaredNorm() > 0.0f)) continue;
    nx[l] = mapped_n.x();
    ny[l] = mapped_n.y();
    nz[l] = mapped_n.z();
  }
  V3 n{simd::load(nx), simd::load(ny), simd::load(nz)};
  const F16 n_len2 = dot(n, n);
  const F16 inv_n = 1.0f / simd::sqrt(simd::select(simd::gt(n_len2, 0.0f), n_len2, one));
  n = select(simd::gt(n_len2, 0.0f), V3{n.x * inv_n, n.y * inv_n, n.z * inv_n}, h.ng);
  const V3 side{simd::load(sx), simd::load(sy), simd::load(sz)};
  const I16 faces_away = simd::select_int(simd::gt(n_len2, 0.0f), simd::gt(dot(side, dir), 0.0f), simd::gt(dot(n, dir), 0.0f));
  n = select(faces_away, V3{-n.x, -n.y, -n.z}, n);
  SurfacePoint p;
  p.n = n;
  p.albedo = {simd::load(ar), simd::load(ag), simd::load(ab)};
  p.sky_occlusion = simd::load(occlusion);
  p.metallic_roughness = simd::load_int(pbr_lane);
  p.unlit = simd::load_int(unlit_lane);
  p.metallic = simd::load(metallic);
  p.roughness = simd::load(roughness);
  p.emission = {simd::load(er), simd::load(eg), simd::load(eb)};
  p.any_metallic_roughness = simd::any(p.metallic_roughness);
  p.any_unlit = simd::any(p.unlit);
  p.any_emission = simd::any(simd::gt(p.emission.x + p.emission.y + p.emission.z, 0.0f));
  return p;
}

// ---- glTF's metallic-roughness BRDF (the specification's Appendix B): the Trowbridge-Reitz
// (GGX) distribution, Smith's height-correlated masking-shadowing, Schlick's Fresnel, and the mix
// by metalness of a dielectric (F0 0.04 over the diffuse base colour) and a metal (F0 the base
// colour). Values are pi times the BRDF: the kernel's unit, in which a white diffuse surface
// reflects the irradiance it gets. alpha = roughness^2.

// (1 - cos)^5, Schlick's weight.
MESHTOUR_SIMD_INLINE F16 schlick_weight(F16 cos) {
  const F16 x = 1.0f - simd::min(simd::max(cos, simd::broadcast(0.0f)), simd::broadcast(1.0f));
  const F16 x2 = x * x;
  return x2 * x2 * x;
}
// Smith's Lambda of GGX for a direction at cosine c (> 0) to the normal.
MESHTOUR_SIMD_INLINE F16 smith_lambda(F16 alpha2, F16 c) {
  const F16 c2 = simd::max(c * c, simd::broadcast(1e-12f));
  const F16 tan2 = simd::max(simd::broadcast(0.0f), 1.0f - c2) / c2;
  return 0.5f * (simd::sqrt(1.0f + alpha2 * tan2) - 1.0f);
}
// One lane group's parameters of the BRDF.
struct GgxLobe {
  F16 metallic, alpha2, n_dot_v, lambda_v;
  V3 base;
};
MESHTOUR_SIMD_INLINE GgxLobe ggx_lobe(const SurfacePoint& p, const V3& view) {
  const F16 rough = simd::max(p.roughness, simd::broadcast(0.03f));  // a mirror is a very sharp lobe
  const F16 alpha = rough * rough;
  GgxLobe g{p.metallic, alpha * alpha, simd::max(dot(p.n, view), simd::broadcast(1e-4f)), simd::broadcast(0.0f), p.albedo};
  g.lambda_v = smith_lambda(g.alpha2, g.n_dot_v);
  return g;
}
// The Fresnel-weighted specular colour (1 - m) F_dielectric + m F_metal at weight w, and the
// diffuse colour (1 - m)(1 - F_dielectric) base.
MESHTOUR_SIMD_INLINE void ggx_colours(const GgxLobe& g, F16 w, V3& specular, V3& diffuse) {
  const F16 dielectric = 0.04f + 0.96f * w, m = g.metallic, d = (1.0f - m) * (1.0f - dielectric);
  const F16 s = (1.0f - m) * dielectric;
  specular = {s + m * (g.base.x + (1.0f - g.base.x) * w), s + m * (g.base.y + (1.0f - g.base.y) * w), s + m * (g.base.z + (1.0f - g.base.z) * w)};
  diffuse = {d * g.base.x, d * g.base.y, d * g.base.z};
}
// What a distant disc light of irradiance `radiance` from unit direction l (cos_l > 0 to the
// normal) reflects towards the viewer. The disc's angular radius widens the distribution
// (alpha^2 + sin^2 of the half angle: a mirror shows the disc, not a point).
MESHTOUR_SIMD_INLINE V3 ggx_reflected(const GgxLobe& g, const V3& n, const V3& view, const V3& l, const V3& radiance, F16 cos_l,
                                      float sin_half_angle) {
  const V3 sum{l.x + view.x, l.y + view.y, l.z + view.z};
  const F16 inv = 1.0f / simd::sqrt(simd::max(dot(sum, sum), simd::broadcast(1e-12f)));
  const V3 h{sum.x * inv, sum.y * inv, sum.z * inv};
  const F16 n_dot_h = simd::max(dot(n, h), simd::broadcast(0.0f)), v_dot_h = dot(view, h);
  const F16 a2 = g.alpha2 + sin_half_angle * sin_half_angle;
  const F16 q = n_dot_h * n_dot_h * (a2 - 1.0f) + 1.0f;
  const F16 distribution = a2 / (std::numbers::pi_v<float> * q * q);
  const F16 cos_l_pos = simd::max(cos_l, simd::broadcast(1e-4f));
  // pi D G2 / (4 cos_v): the 1 / cos_l of the BRDF cancels against the irradiance's cos_l.
  const F16 spec = std::numbers::pi_v<float> * distribution / (4.0f * g.n_dot_v * (1.0f + g.lambda_v + smith_lambda(g.alpha2, cos_l_pos)));
  V3 specular, diffuse;
  ggx_colours(g, schlick_weight(v_dot_h), specular, diffuse);
  return {radiance.x * (diffuse.x * cos_l + specular.x * spec), radiance.y * (diffuse.y * cos_l + specular.y * spec),
          radiance.z * (diffuse.z * cos_l + specular.z * spec)};
}
// A direction of reflection sampled from the distribution of visible normals (Heitz 2018,
// "Sampling the GGX distribution of visible normals"), numbers (u, v) in [0, 1), about the
// normal n with tangents t1, t2; `weight` is the BRDF times cos over the density, per channel
// (F G2 / G1), 0 below the surface.
MESHTOUR_SIMD_INLINE V3 ggx_sample(const GgxLobe& g, const V3& n, const V3& t1, const V3& t2, const V3& view, F16 u, F16 v, V3& weight) {
  const F16 zero = simd::broadcast(0.0f), one = simd::broadcast(1.0f);
  const F16 alpha = simd::sqrt(g.alpha2);
  // The view in the normal's frame, stretched to the unit-roughness configuration.
  V3 vh{alpha * dot(view, t1), alpha * dot(view, t2), g.n_dot_v};
  const F16 inv_vh = 1.0f / simd::sqrt(dot(vh, vh));
  vh = {vh.x * inv_vh, vh.y * inv_vh, vh.z * inv_vh};
  const F16 len2 = vh.x * vh.x + vh.y * vh.y;
  const I16 tilted = simd::gt(len2, 1e-12f);
  const F16 inv_len = 1.0f / simd::sqrt(simd::select(tilted, len2, one));
  const V3 a{simd::select(tilted, -vh.y * inv_len, one), simd::select(tilted, vh.x * inv_len, zero), zero};
  const V3 b{vh.y * a.z - vh.z * a.y, vh.z * a.x - vh.x * a.z, vh.x * a.y - vh.y * a.x};
  F16 sin_phi, cos_phi;
  simd::sincos_turns(v, sin_phi, cos_phi);
  const F16 rad = simd::sqrt(u), p1 = rad * cos_phi;
  const F16 mix = 0.5f * (1.0f + vh.z);
  const F16 p2 = (1.0f - mix) * simd::sqrt(simd::max(zero, 1.0f - p1 * p1)) + mix * (rad * sin_phi);
  const F16 p3 = simd::sqrt(simd::max(zero, 1.0f - p1 * p1 - p2 * p2));
  V3 m{alpha * (p1 * a.x + p2 * b.x + p3 * vh.x), alpha * (p1 * a.y + p2 * b.y + p3 * vh.y), simd::max(p1 * a.z + p2 * b.z + p3 * vh.z, simd::broadcast(1e-6f))};
  const F16 inv_m = 1.0f / simd::sqrt(dot(m, m));
  const V3 h{(m.x * t1.x + m.y * t2.x + m.z * n.x) * inv_m, (m.x * t1.y + m.y * t2.y + m.z * n.y) * inv_m,
             (m.x * t1.z + m.y * t2.z + m.z * n.z) * inv_m};
  const F16 v_dot_h = dot(view, h);
  const V3 l{2.0f * v_dot_h * h.x - view.x, 2.0f * v_dot_h * h.y - view.y, 2.0f * v_dot_h * h.z - view.z};
  const F16 cos_l = dot(n, l);
  const I16 above = simd::gt(cos_l, 0.0f);
  const F16 g2_over_g1 = simd::select(above, (1.0f + g.lambda_v) / (1.0f + g.lambda_v + smith_lambda(g.alpha2, simd::max(cos_l, simd::broadcast(1e-6f)))), zero);
  V3 specular, diffuse;
  ggx_colours(g, schlick_weight(v_dot_h), specular, diffuse);
  weight = {specular.x * g2_over_g1, specular.y * g2_over_g1, specular.z * g2_over_g1};
  return l;
}

// The specular lobe at a given direction of reflection l (unit): `weight` as ggx_sample's (F
// G2 / G1, 0 below the surface), and the density ggx_sample picks l with per unit solid angle
// (the visible normals' D_v(h) / (4 v.h) = G1 D / (4 n.v)), 0 below the surface.
MESHTOUR_SIMD_INLINE F16 ggx_evaluate(const GgxLobe& g, const V3& n, const V3& view, const V3& l, V3& weight) {
  const F16 zero = simd::broadcast(0.0f);
  const V3 sum{l.x + view.x, l.y + view.y, l.z + view.z};
  const F16 inv = 1.0f / simd::sqrt(simd::max(dot(sum, sum), simd::broadcast(1e-12f)));
  const V3 h{sum.x * inv, sum.y * inv, sum.z * inv};
  const F16 cos_l = dot(n, l), n_dot_h = simd::max(dot(n, h), zero), v_dot_h = dot(view, h);
  const I16 above = simd::gt(cos_l, 0.0f);
  const F16 g2_over_g1 = simd::select(above, (1.0f + g.lambda_v) / (1.0f + g.lambda_v + smith_lambda(g.alpha2, simd::max(cos_l, simd::broadcast(1e-6f)))), zero);
  V3 specular, diffuse;
  ggx_colours(g, schlick_weight(v_dot_h), specular, diffuse);
  weight = {specular.x * g2_over_g1, specular.y * g2_over_g1, specular.z * g2_over_g1};
  const F16 q = n_dot_h * n_dot_h * (g.alpha2 - 1.0f) + 1.0f;
  const F16 distribution = g.alpha2 / (std::numbers::pi_v<float> * q * q);
  return simd::select(above, distribution / (4.0f * g.n_dot_v * (1.0f + g.lambda_v)), zero);
}

// atan2(y, x) in [0, pi] for y >= 0, float, plain arithmetic (the same bits on every CPU and
// ISA): two half-angle steps bring the argument under tan(pi / 16), where five terms of the
// series leave an error below 1e-7.
MESHTOUR_SIMD_INLINE F16 atan2_upper(F16 y, F16 x) {
  const F16 zero = simd::broadcast(0.0f), one = simd::broadcast(1.0f);
  const F16 ax = simd::max(x, -x);
  const I16 steep = simd::gt(y, ax);
  const F16 num = simd::select(steep, ax, y), den = simd::select(steep, y, ax);
  F16 t = simd::select(simd::gt(den, 0.0f), num / simd::select(simd::gt(den, 0.0f), den, one), zero);
  for (int k = 0; k < 2; ++k) t = t / (1.0f + simd::sqrt(1.0f + t * t));
  const F16 t2 = t * t;
  F16 angle = 4.0f * t * (1.0f + t2 * (-1.0f / 3 + t2 * (1.0f / 5 + t2 * (-1.0f / 7 + t2 * (1.0f / 9)))));
  constexpr float kPi = std::numbers::pi_v<float>;
  angle = simd::select(steep, 0.5f * kPi - angle, angle);
  return simd::select(simd::lt(x, 0.0f), kPi - angle, angle);
}

// The environment's diffuse light at unit normals n: E(n) / pi from its irradiance map
// (tracer/environment.h), the texel coordinates from the normal's angles (IEEE-exact float
// arithmetic, atan2_upper), the bilinear lookup IrradianceMap::at, per lane.
MESHTOUR_SIMD_INLINE V3 environment_light(const Frame& f, const V3& n) {
  const IrradianceMap& map = *f.sky_light;
  const Eigen::Matrix3f& m = map.environment_from_world;
  const V3 e{m(0, 0) * n.x + m(0, 1) * n.y + m(0, 2) * n.z, m(1, 0) * n.x + m(1, 1) * n.y + m(1, 2) * n.z,
             m(2, 0) * n.x + m(2, 1) * n.y + m(2, 2) * n.z};
  constexpr float kPi = std::numbers::pi_v<float>;
  const F16 theta = atan2_upper(simd::sqrt(e.x * e.x + e.z * e.z), e.y);
  const F16 phi_abs = atan2_upper(simd::max(e.x, -e.x), -e.z);
  const F16 phi = simd::select(simd::lt(e.x, 0.0f), -phi_abs, phi_abs);  // atan2(x, -z), u = 0.5 along -z
  const F16 row = theta * (static_cast<float>(map.height - 1) / kPi);
  const F16 column = (phi * (0.5f / kPi) + 0.5f) * static_cast<float>(map.width) - 0.5f;
  alignas(64) float lr[16], lg[16], lb[16];
  for (int l = 0; l < simd::kLanes; ++l) {
    const Eigen::Vector3f value = map.at(row[l], column[l]);
    lr[l] = value.x(), lg[l] = value.y(), lb[l] = value.z();
  }
  return {simd::load(lr), simd::load(lg), simd::load(lb)};
}

// EnvironmentDistribution::density at world directions `dir` (unit), vectorized for the lanes in
// `lanes` (0 elsewhere): the pixel a direction falls in, by its polar and azimuthal angles.
MESHTOUR_SIMD_INLINE F16 environment_density(const EnvironmentDistribution& d, I16 lanes, const V3& dir) {
  const Eigen::Matrix3f& m = d.environment_from_world;
  const V3 e{m(0, 0) * dir.x + m(0, 1) * dir.y + m(0, 2) * dir.z, m(1, 0) * dir.x + m(1, 1) * dir.y + m(1, 2) * dir.z,
             m(2, 0) * dir.x + m(2, 1) * dir.y + m(2, 2) * dir.z};
  const F16 sin_theta = simd::sqrt(e.x * e.x + e.z * e.z);
  constexpr float kPi = std::numbers::pi_v<float>;
  const F16 theta = atan2_upper(sin_theta, e.y);
  // phi = atan2(x, -z) in (-pi, pi]: the upper half-plane's angle, mirrored for x < 0.
  const F16 phi_abs = atan2_upper(simd::max(e.x, -e.x), -e.z);
  const F16 phi = simd::select(simd::lt(e.x, 0.0f), -phi_abs, phi_abs);
  const F16 row = theta * (static_cast<float>(d.height) / kPi);
  const F16 column = (phi * (0.5f / kPi) + 0.5f) * static_cast<float>(d.width);
  const I16 j = simd::to_int(simd::min(simd::max(row, simd::broadcast(0.0f)), simd::broadcast(static_cast<float>(d.height) - 0.5f)));
  const I16 i = simd::to_int(simd::min(simd::max(column, simd::broadcast(0.0f)), simd::broadcast(static_cast<float>(d.width) - 0.5f)));
  alignas(64) float density_sin[16];
  for (int l = 0; l < simd::kLanes; ++l) density_sin[l] = lanes[l] ? d.density_times_sin(i[l], j[l]) : 0.0f;
  return simd::load(density_sin) / simd::max(sin_theta, simd::broadcast(1e-6f));
}

// Directions towards the environment's light, picked by its luminance (EnvironmentDistribution)
// for the lanes in `lanes`, numbers (u, v) in [0, 1); `density` per unit solid angle. The polar
// and azimuthal angles come from sincos_turns, the same bits on every CPU.
MESHTOUR_SIMD_INLINE V3 environment_sample(const EnvironmentDistribution& d, I16 lanes, F16 u, F16 v, F16& density) {
  alignas(64) float theta_turns[16], phi_turns[16], density_sin[16];
  for (int l = 0; l < simd::kLanes; ++l) {
    theta_turns[l] = 0.25f, phi_turns[l] = 0.0f, density_sin[l] = 0.0f;
    if (!lanes[l]) continue;
    int i = 0, j = 0;
    float fu = 0.0f, fv = 0.0f;
    d.pick(u[l], v[l], i, j, fu, fv);
    theta_turns[l] = 0.5f * (static_cast<float>(j) + fv) / static_cast<float>(d.height);  // half a turn, zenith to nadir
    phi_turns[l] = (static_cast<float>(i) + fu) / static_cast<float>(d.width);            // from -pi, as the image's u
    density_sin[l] = d.density_times_sin(i, j);
  }
  F16 sin_t, cos_t, sin_p, cos_p;
  simd::sincos_turns(simd::load(theta_turns), sin_t, cos_t);
  simd::sincos_turns(simd::load(phi_turns), sin_p, cos_p);
  // phi = 2 pi t - pi: sin phi = -sin 2 pi t, cos phi = -cos 2 pi t; the environment's direction
  // (sin theta sin phi, cos theta, -sin theta cos phi), as pixel_direction() lays it out.
  const V3 e{-sin_t * sin_p, cos_t, sin_t * cos_p};
  const Eigen::Matrix3f& m = d.world_from_environment;
  density = simd::load(density_sin) / simd::max(sin_t, simd::broadcast(1e-6f));
  return {m(0, 0) * e.x + m(0, 1) * e.y + m(0, 2) * e.z, m(1, 0) * e.x + m(1, 1) * e.y + m(1, 2) * e.z,
          m(2, 0) * e.x + m(2, 1) * e.y + m(2, 2) * e.z};
}

// The environment's radiance along unit world directions, for the lanes in `lanes` (0 elsewhere):
// the image coordinates from the direction's angles in float (atan2_upper: plain arithmetic, the
// same bits on every CPU and kernel), EnvironmentRadiance::at's bilinear lookup per lane.
MESHTOUR_SIMD_INLINE V3 environment_radiance_at(const Frame& f, I16 lanes, const V3& dir) {
  const EnvironmentRadiance& radiance = *f.sky_radiance;
  const Eigen::Matrix3f& m = radiance.environment_from_world;
  const V3 e{m(0, 0) * dir.x + m(0, 1) * dir.y + m(0, 2) * dir.z, m(1, 0) * dir.x + m(1, 1) * dir.y + m(1, 2) * dir.z,
             m(2, 0) * dir.x + m(2, 1) * dir.y + m(2, 2) * dir.z};
  constexpr float kPi = std::numbers::pi_v<float>;
  const F16 theta = atan2_upper(simd::sqrt(e.x * e.x + e.z * e.z), e.y);
  const F16 phi_abs = atan2_upper(simd::max(e.x, -e.x), -e.z);
  const F16 phi = simd::select(simd::lt(e.x, 0.0f), -phi_abs, phi_abs);  // atan2(x, -z)
  const float width = static_cast<float>(radiance.image->width), height = static_cast<float>(radiance.image->height);
  const F16 x = (phi * (0.5f / kPi) + 0.5f) * width - 0.5f, y = theta * (height / kPi) - 0.5f;
  alignas(64) float lr[16], lg[16], lb[16];
  for (int l = 0; l < simd::kLanes; ++l) {
    Eigen::Vector3f value = Eigen::Vector3f::Zero();
    if (lanes[l]) value = radiance.at(x[l], y[l]);
    lr[l] = value.x(), lg[l] = value.y(), lb[l] = value.z();
  }
  return {simd::load(lr), simd::load(lg), simd::load(lb)};
}

// A diffuse surface's occlusion ray under an environment image (Frame::sample_sky): its direction
// and `scale`, the factor on the radiance it meets, (cos / pi) / density, so that albedo x
// radiance x scale is an unbiased sample of the reflected light. The direction is picked from the
// environment's distribution with probability c = Frame::sky_environment_share, else
// cosine-distributed about n (u stretched within the chosen share), and weighed by the density
// of the mixture, (1 - c) cos / pi + c p_env: one-sample multiple importance sampling with the
// balance heuristic, as the glossy lobe's (Veach 1997, 9.2.4). With c = 0 it is the plain
// cosine-distributed ray and scale is 1. Directions below the surface get scale 0.
struct SkySample {
  V3 dir;
  F16 scale;
};
MESHTOUR_SIMD_INLINE SkySample diffuse_sky_sample(const Frame& f, const V3& n, const V3& t1, const V3& t2, I16 lanes, F16 u, F16 v) {
  const F16 zero = simd::broadcast(0.0f), one = simd::broadcast(1.0f);
  if (!(f.sky_environment_share > 0.0f)) return {sky_direction(n, t1, t2, u, v), one};
  const float c = f.sky_environment_share;
  const I16 env_lane = simd::both(lanes, simd::lt(u, c));
  const F16 top = simd::broadcast(0x1.fffffep-1f);
  const F16 u2 = simd::min(top, simd::select(env_lane, u * (1.0f / c), (u - c) * (1.0f / (1.0f - c))));
  F16 env_density;
  const V3 env_dir = environment_sample(*f.sky_distribution, env_lane, u2, v, env_density);
  SkySample out;
  out.dir = select(env_lane, env_dir, sky_direction(n, t1, t2, u2, v));
  const F16 cos_l = dot(n, out.dir);
  const F16 other_density = environment_density(*f.sky_distribution, simd::both(lanes, ~env_lane), out.dir);
  const F16 cosine_density = simd::max(cos_l, zero) * std::numbers::inv_pi_v<float>;
  const F16 mixture = (1.0f - c) * cosine_density + c * simd::select(env_lane, env_density, other_density);
  const I16 weighed = simd::both(simd::gt(cos_l, 0.0f), simd::gt(mixture, 0.0f));
  out.scale = simd::select(weighed, cosine_density / simd::select(weighed, mixture, one), zero);
  return out;
}

// The samples on the model: what each light would bring unshadowed (diffuse and a Blinn-Phong
// highlight), one of them chosen for the shadow ray, and the sky for the occlusion ray.
MESHTOUR_SIMD_INLINE void shade_model(const Frame& f, const PacketSamples& s, const Hits& h, const V3& dir, const SurfacePoint& surface,
                                      bool guides, ShadedSamples& sh) {
  const F16 zero = simd::broadcast(0.0f), one = simd::broadcast(1.0f);
  const std::size_t nlights = f.lights.size();
  const I16 on_model = h.on_model;
  const V3& n = surface.n;
  const V3& albedo = surface.albedo;
  sh.guide_normal = select(on_model, n, sh.guide_normal);
  const V3 view{-dir.x, -dir.y, -dir.z};
  // Unshadowed Blinn-Phong light from a light (cos_l = cosine of its incidence, > 0).
  auto reflected = [&](const V3& light_dir, const V3& radiance, F16 cos_l) __attribute__((always_inline)) {
    const V3 half{light_dir.x + view.x, light_dir.y + view.y, light_dir.z + view.z};
    const F16 cos_h = dot(n, half) / simd::sqrt(dot(half, half));
    const F16 spec = simd::select(simd::gt(cos_h, f.spec_cutoff), f.spec_scale * simd::pow_unit(simd::max(cos_h, simd::broadcast(1e-30f)), f.shininess), zero);
    return V3{radiance.x * (albedo.x + spec) * cos_l, radiance.y * (albedo.y + spec) * cos_l, radiance.z * (albedo.z + spec) * cos_l};
  };
  // Lanes of the file's metallic-roughness materials: glTF's BRDF in place of the look's.
  const bool any_ggx = surface.any_metallic_roughness;
  const I16 ggx = simd::both(on_model, surface.metallic_roughness);
  const GgxLobe lobe = any_ggx ? ggx_lobe(surface, view) : GgxLobe{};
  // What each light would bring here unshadowed (diffuse and highlight; 0 from behind).
  V3 contributions[8];
  for (std::size_t i = 0; i < nlights; ++i) {
    const F16 cos_i = dot(n, broadcast(f.lights[i].direction));
    V3 c = reflected(broadcast(f.lights[i].direction), broadcast(f.lights[i].radiance), cos_i);
    if (any_ggx)
      c = select(ggx, ggx_reflected(lobe, n, view, broadcast(f.lights[i].direction), broadcast(f.lights[i].radiance), cos_i, f.lights[i].sin_half_angle), c);
    const I16 lit = simd::gt(cos_i, 0.0f);
    contributions[i] = {simd::select(lit, c.x, zero), simd::select(lit, c.y, zero), simd::select(lit, c.z, zero)};
  }
  V3 model_base{zero, zero, zero};
  V3 model_light{zero, zero, zero};
  I16 model_shadow = simd::broadcast_int(0);
  if (f.shadows) {
    // The light chosen by the luminance of its whole contribution here, highlight included.
    F16 weights[8];
    F16 total = zero;
    for (std::size_t i = 0; i < nlights; ++i) {
      weights[i] = luminance(contributions[i].x, contributions[i].y, contributions[i].z);
      total += weights[i];
    }
    const OneLightSample one_light = sample_one_light(f.lights, contributions, weights, total, on_model, s.u_light, s.v_light);
    model_shadow = one_light.valid;
    model_light = one_light.light;
    sh.shadow_dir = one_light.dir;
  } else {
    for (std::size_t i = 0; i < nlights; ++i)
      model_base = {model_base.x + contributions[i].x, model_base.y + contributions[i].y, model_base.z + contributions[i].z};
  }
  const V3 sky_light = f.environment ? environment_light(f, n) : broadcast(f.ambient);
  const F16 open = surface.sky_occlusion;
  const V3 sky{albedo.x * sky_light.x * open, albedo.y * sky_light.y * open, albedo.z * sky_light.z * open};
  // The sky's light on glTF materials: its expected value (for the guides, and as it is
  // without occlusion rays), and one sample of it along the occlusion ray's direction.
  V3 sky_expected = sky, ggx_sky = sky, ggx_sky_dir{zero, zero, one};
  // With Frame::sample_sky, what multiplies the radiance met along ggx_sky_dir, per glTF lane.
  V3 ggx_sky_factor{zero, zero, zero};
  // The factor on an interreflection's light: the diffuse look's albedo (its sky ray is cosine
  // distributed), or the chosen glTF lobe's weight.
  V3 bounce_weight{albedo.x * open, albedo.y * open, albedo.z * open};
  if (any_ggx) {
    // Expected: the diffuse share under the irradiance at n, and the specular share (Schlick
    // at the view with the roughness's fade, after Fdez-Aguera 2019) under the irradiance about
    // the mirror direction, which stands for the radiance the lobe gathers.
    const F16 w_v = schlick_weight(lobe.n_dot_v), m = lobe.metallic;
    const F16 keep = (1.0f - m) * (1.0f - (0.04f + 0.96f * w_v));
    const V3 diffuse_share{keep * albedo.x, keep * albedo.y, keep * albedo.z};
    const F16 rough_fade = 1.0f - surface.roughness;
    auto specular_share = [&](F16 base) __attribute__((always_inline)) {
      const F16 f0 = (1.0f - m) * 0.04f + m * base;
      return f0 + (simd::max(rough_fade, f0) - f0) * w_v;
    };
    const V3 spec_share{specular_share(albedo.x), specular_share(albedo.y), specular_share(albedo.z)};
    const V3 mirror{2.0f * lobe.n_dot_v * n.x - view.x, 2.0f * lobe.n_dot_v * n.y - view.y, 2.0f * lobe.n_dot_v * n.z - view.z};
    const V3 sky_mirror = f.environment ? environment_light(f, mirror) : broadcast(f.ambient);
    const V3 expected_diffuse{diffuse_share.x * sky_light.x, diffuse_share.y * sky_light.y, diffuse_share.z * sky_light.z};
    const V3 expected_specular{spec_share.x * sky_mirror.x, spec_share.y * sky_mirror.y, spec_share.z * sky_mirror.z};
    sky_expected = select(ggx, V3{(expected_diffuse.x + expected_specular.x) * open, (expected_diffuse.y + expected_specular.y) * open,
                                  (expected_diffuse.z + expected_specular.z) * open}, sky);
    if (f.ambient_occlusion) {
      // One lobe per sample, the specular with probability p in proportion to the expected
      // light of each; u is stretched to a fresh number within the chosen share (as choose()).
      const F16 ws = luminance(expected_specular.x, expected_specular.y, expected_specular.z);
      const F16 wd = luminance(expected_diffuse.x, expected_diffuse.y, expected_diffuse.z);
      const I16 weighed = simd::gt(ws + wd, 0.0f);
      const F16 p = simd::select(weighed, ws / simd::select(weighed, ws + wd, one), one);
      const I16 specular_lane = simd::lt(s.u_sky, p);
      const F16 top = simd::broadcast(0x1.fffffep-1f);
      const F16 u = simd::min(top, simd::select(specular_lane, s.u_sky / simd::select(simd::gt(p, 0.0f), p, one),
                                                (s.u_sky - p) / simd::select(simd::lt(p, 1.0f), 1.0f - p, one)));
      V3 t1, t2;
      basis(n, t1, t2);
      V3 weight;
      V3 spec_dir;
      if (!f.sky_distribution) {
        spec_dir = ggx_sample(lobe, n, t1, t2, view, u, s.v_sky, weight);
      } else {
        // The specular direction from the BRDF's visible normals or from the environment's
        // light, one of the two per sample (the environment with probability c, more for rougher
        // lobes: a mirror's own lobe is already where its light comes from), weighted by the
        // density of the mixture: one-sample multiple importance sampling with the balance
        // heuristic (Veach 1997, section 9.2.4), unbiased, and a small bright sun that the BRDF's
        // samples would find once in many is found by the environment's.
        const F16 c = 0.5f * simd::min(one, surface.roughness * 4.0f);
        const I16 env_lane = simd::both(simd::both(ggx, specular_lane), simd::lt(u, c));
        const F16 u2 = simd::min(top, simd::select(env_lane, u / simd::select(simd::gt(c, 0.0f), c, one), (u - c) / (1.0f - c)));
        const V3 brdf_dir = ggx_sample(lobe, n, t1, t2, view, u2, s.v_sky, weight);
        F16 env_density;
        const V3 env_dir = environment_sample(*f.sky_distribution, env_lane, u2, s.v_sky, env_density);
        spec_dir = select(env_lane, env_dir, brdf_dir);
        const F16 brdf_density = ggx_evaluate(lobe, n, view, spec_dir, weight);
        const I16 brdf_lane = simd::both(simd::both(ggx, specular_lane), ~env_lane);
        const F16 picked_density = environment_density(*f.sky_distribution, brdf_lane, brdf_dir);
        const F16 mixture = (1.0f - c) * brdf_density + c * simd::select(env_lane, env_density, picked_density);
        const I16 weighed = simd::gt(mixture, 0.0f);
        const F16 scale = simd::select(weighed, brdf_density / simd::select(weighed, mixture, one), zero);
        weight = {weight.x * scale, weight.y * scale, weight.z * scale};
      }
      V3 diffuse_dir;
      F16 diffuse_scale = one;
      if (f.sample_sky) {
        const SkySample diffuse = diffuse_sky_sample(f, n, t1, t2, simd::both(ggx, ~specular_lane), u, s.v_sky);
        diffuse_dir = diffuse.dir;
        diffuse_scale = diffuse.scale;
      } else {
        diffuse_dir = sky_direction(n, t1, t2, u, s.v_sky);
      }
      // The diffuse lobe's Fresnel at its own half vector.
      const V3 half{diffuse_dir.x + view.x, diffuse_dir.y + view.y, diffuse_dir.z + view.z};
      const F16 v_dot_h = dot(view, half) / simd::sqrt(simd::max(dot(half, half), simd::broadcast(1e-12f)));
      const F16 diffuse_keep = (1.0f - m) * (1.0f - (0.04f + 0.96f * schlick_weight(v_dot_h))) * open / simd::select(simd::lt(p, 1.0f), 1.0f - p, one);
      const F16 spec_scale = open / simd::select(simd::gt(p, 0.0f), p, one);
      ggx_sky_dir = select(specular_lane, spec_dir, diffuse_dir);
      if (f.sample_sky) {
        // Both lobes' rays meet the environment's image: its radiance is looked up once, with the
        // look's lanes (below).
        const V3 spec_factor{weight.x * spec_scale, weight.y * spec_scale, weight.z * spec_scale};
        const F16 keep = diffuse_keep * diffuse_scale;
        ggx_sky_factor = select(specular_lane, spec_factor, V3{keep * albedo.x, keep * albedo.y, keep * albedo.z});
        bounce_weight = select(ggx, ggx_sky_factor, bounce_weight);
      } else {
        // No image: the specular rays see the look's uniform sky where unblocked.
        const V3 ambient = broadcast(f.ambient);
        const V3 spec_value{weight.x * ambient.x * spec_scale, weight.y * ambient.y * spec_scale, weight.z * ambient.z * spec_scale};
        const V3 diffuse_value{diffuse_keep * albedo.x * sky_light.x, diffuse_keep * albedo.y * sky_light.y, diffuse_keep * albedo.z * sky_light.z};
        ggx_sky = select(ggx, select(specular_lane, spec_value, diffuse_value), sky);
        if (f.bounces > 0) {
          const V3 spec_bounce{weight.x * spec_scale, weight.y * spec_scale, weight.z * spec_scale};
          const V3 diffuse_bounce{diffuse_keep * albedo.x, diffuse_keep * albedo.y, diffuse_keep * albedo.z};
          bounce_weight = select(ggx, select(specular_lane, spec_bounce, diffuse_bounce), bounce_weight);
        }
      }
    }
  }
  if (guides) {
    V3 unshadowed = sky_expected;
    for (std::size_t i = 0; i < nlights; ++i)
      unshadowed = {unshadowed.x + contributions[i].x, unshadowed.y + contributions[i].y, unshadowed.z + contributions[i].z};
    sh.guide_unshadowed = select(on_model, unshadowed, sh.guide_unshadowed);
  }
  V3 model_sky{zero, zero, zero};
  I16 model_sky_valid = on_model;
  if (f.ambient_occlusion && f.sample_sky) {
    // The image's radiance along each lane's ray, times its lobe's factor; a ray that can
    // bring nothing (below the surface, a zero weight) is not traced. The look's diffuse lanes
    // get their whole irradiance (the map's, exact in the open) and the ray estimates what the
    // model takes away of it, (1 - V) x the sample: the same expectation as V x the sample, but
    // no noise where the ray is unblocked (a control variate; as the ground's shadow).
    V3 t1, t2;
    basis(n, t1, t2);
    const I16 look_lanes = any_ggx ? simd::both(on_model, ~ggx) : on_model;
    const SkySample look = diffuse_sky_sample(f, n, t1, t2, look_lanes, s.u_sky, s.v_sky);
    const F16 keep = open * look.scale;
    V3 factor{keep * albedo.x, keep * albedo.y, keep * albedo.z};
    V3 dir = look.dir;
    if (any_ggx) {
      factor = select(ggx, ggx_sky_factor, factor);
      dir = select(ggx, ggx_sky_dir, dir);
    }
    const V3 radiance = environment_radiance_at(f, on_model, dir);
    model_sky = {factor.x * radiance.x, factor.y * radiance.y, factor.z * radiance.z};
    const V3 open_sky = select(look_lanes, V3{sky.x - model_sky.x, sky.y - model_sky.y, sky.z - model_sky.z}, V3{zero, zero, zero});
    model_base = {model_base.x + open_sky.x, model_base.y + open_sky.y, model_base.z + open_sky.z};
    model_sky_valid = simd::both(on_model, simd::gt(simd::max(factor.x, simd::max(factor.y, factor.z)), 0.0f));
    bounce_weight = factor;
    sh.sky_dir = select(on_model, dir, sh.sky_dir);
  } else if (f.ambient_occlusion) {
    model_sky = any_ggx ? ggx_sky : sky;
    V3 t1, t2;
    basis(n, t1, t2);
    V3 dir = sky_direction(n, t1, t2, s.u_sky, s.v_sky);
    if (any_ggx) dir = select(ggx, ggx_sky_dir, dir);
    sh.sky_dir = select(on_model, dir, sh.sky_dir);
  } else {
    model_base = {model_base.x + sky_expected.x, model_base.y + sky_expected.y, model_base.z + sky_expected.z};
    model_sky_valid = simd::broadcast_int(0);
  }
  if (surface.any_emission) {
    const V3& e = surface.emission;
    model_base = {model_base.x + e.x, model_base.y + e.y, model_base.z + e.z};
    if (guides) sh.guide_unshadowed = select(on_model, V3{sh.guide_unshadowed.x + e.x, sh.guide_unshadowed.y + e.y, sh.guide_unshadowed.z + e.z}, sh.guide_unshadowed);
  }
  if (surface.any_unlit) {
    // KHR_materials_unlit: the base colour as it is; no light, no rays.
    const I16 unlit = simd::both(on_model, surface.unlit);
    model_base = select(unlit, albedo, model_base);
    model_shadow = simd::both(model_shadow, ~unlit);
    model_sky_valid = simd::both(model_sky_valid, ~unlit);
    if (guides) sh.guide_unshadowed = select(unlit, albedo, sh.guide_unshadowed);
  }
  sh.sky_valid = simd::either(sh.sky_valid, model_sky_valid);
  sh.shadow_valid = simd::either(sh.shadow_valid, model_shadow);
  if (f.bounces > 0) {
    sh.bounce_valid = simd::either(sh.bounce_valid, model_sky_valid);
    sh.bounce_weight = select(on_model, bounce_weight, sh.bounce_weight);
  }
  sh.base[0] = simd::select(on_model, model_base.x, sh.base[0]);
  sh.base[1] = simd::select(on_model, model_base.y, sh.base[1]);
  sh.base[2] = simd::select(on_model, model_base.z, sh.base[2]);
  sh.base[3] = simd::select(on_model, one, sh.base[3]);
  sh.with_light[0] = simd::select(model_shadow, model_light.x, sh.with_light[0]);
  sh.with_light[1] = simd::select(model_shadow, model_light.y, sh.with_light[1]);
  sh.with_light[2] = simd::select(model_shadow, model_light.z, sh.with_light[2]);
  sh.with_sky[0] = simd::select(on_model, model_sky.x, sh.with_sky[0]);
  sh.with_sky[1] = simd::select(on_model, model_sky.y, sh.with_sky[1]);
  sh.with_sky[2] = simd::select(on_model, model_sky.z, sh.with_sky[2]);
}

// The samples on the ground, a shadow catcher: it shows the background, darkened by the share of
// light and sky the model takes away from it; transparent frames get the shadow as alpha. The
// share whose ray is traced comes back if the ray is unblocked.
MESHTOUR_SIMD_INLINE void shade_ground(const Frame& f, const PacketSamples& s, const Hits& h, const V3& bg, ShadedSamples& sh) {
  const F16 zero = simd::broadcast(0.0f), one = simd::broadcast(1.0f);
  const std::size_t nlights = f.lights.size();
  const I16 on_ground = h.on_ground;
  const V3& org = h.org;
  sh.guide_normal = select(on_ground, broadcast(f.up), sh.guide_normal);
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
    const I16 candidates = simd::both(on_ground, shadow_possible);
    if (!simd::any(candidates)) {
      // No lane can trace a shadow ray (most of the visible ground): all get the light's share,
      // as the selects below would give them, without choosing and sampling a light.
      unshadowed += f.ground_light_share;
    } else {
      F16 u_disc;
      const I16 chosen = choose(f.ground_weights, nlights, simd::broadcast(f.ground_light_total), s.u_light, u_disc);
      const LaneLight light = lane_light(f.lights, chosen);
      const V3 d = light_direction(light, u_disc, s.v_light);
      const F16 b = dot(org, d), c = dist2 - radius2;
      const I16 may_hit = simd::either(simd::lt(c, 0.0f), simd::both(simd::lt(b, 0.0f), simd::ge(b * b, c)));
      const I16 traced = simd::both(candidates, simd::both(disc_may_hit_model(light.direction, light.cos_half_angle, light.sin_half_angle), may_hit));
      unshadowed += simd::select(traced, zero, simd::broadcast(f.ground_light_share));
      for (int ch = 0; ch < 3; ++ch)
        sh.with_light[ch] = simd::select(traced, (ch == 0 ? bg.x : ch == 1 ? bg.y : bg.z) * f.ground_light_share, sh.with_light[ch]);
      sh.with_light[3] = simd::select(traced, alpha_sign * f.ground_light_share, sh.with_light[3]);
      sh.shadow_dir = select(traced, d, sh.shadow_dir);
      sh.shadow_valid = simd::either(sh.shadow_valid, traced);
    }
  }
  if (f.ground_sky_share > 0.0f && f.sample_sky && f.sky_upward > 0.0f) {
    // Under an environment image: the share the model takes away is estimated, not the share
    // that stays, w (1 - V) with w = the radiance's luminance x the ray's scale / E(up) / pi
    // (mean 1 over the unblocked sky, so the estimate is unbiased), so that the ground is exact
    // and noise-free wherever the ray cannot meet the model's bounding sphere, and a sun's sharp
    // shadow falls where its light is blocked, at any distance.
    const V3 up = broadcast(f.up);
    const SkySample ray = diffuse_sky_sample(f, up, broadcast(f.up_t1), broadcast(f.up_t2), on_ground, s.u_sky, s.v_sky);
    const F16 b = dot(org, ray.dir), c = dist2 - radius2;
    const I16 may_hit = simd::either(simd::lt(c, 0.0f), simd::both(simd::lt(b, 0.0f), simd::ge(b * b, c)));
    const I16 traced = simd::both(simd::both(on_ground, may_hit), simd::gt(ray.scale, 0.0f));
    if (!simd::any(traced)) {
      unshadowed += f.ground_sky_share;
    } else {
      const V3 radiance = environment_radiance_at(f, traced, ray.dir);
      const F16 w = simd::select(traced, luminance(radiance.x, radiance.y, radiance.z) * ray.scale * (1.0f / f.sky_upward), zero);
      const F16 share = f.ground_sky_share * w;
      unshadowed += f.ground_sky_share - share;
      for (int ch = 0; ch < 3; ++ch)
        sh.with_sky[ch] = simd::select(traced, (ch == 0 ? bg.x : ch == 1 ? bg.y : bg.z) * share, sh.with_sky[ch]);
      sh.with_sky[3] = simd::select(traced, alpha_sign * share, sh.with_sky[3]);
      sh.sky_dir = select(traced, ray.dir, sh.sky_dir);
      sh.sky_valid = simd::either(sh.sky_valid, traced);
    }
  } else if (f.ground_sky_share > 0.0f) {
    // Beyond the AO length from the model's bounding sphere nothing can occlude the sky.
    const I16 traced = f.ambient_occlusion ? simd::both(on_ground, simd::lt(dist2, f.ground_ao_reach2)) : simd::broadcast_int(0);
    if (!simd::any(traced)) {
      unshadowed += f.ground_sky_share;  // as the selects below would give every lane
    } else {
      unshadowed += simd::select(traced, zero, simd::broadcast(f.ground_sky_share));
      for (int ch = 0; ch < 3; ++ch)
        sh.with_sky[ch] = simd::select(traced, (ch == 0 ? bg.x : ch == 1 ? bg.y : bg.z) * f.ground_sky_share, sh.with_sky[ch]);
      sh.with_sky[3] = simd::select(traced, alpha_sign * f.ground_sky_share, sh.with_sky[3]);
      const V3 up = broadcast(f.up);
      sh.sky_dir = select(traced, sky_direction(up, broadcast(f.up_t1), broadcast(f.up_t2), s.u_sky, s.v_sky), sh.sky_dir);
      sh.sky_valid = simd::either(sh.sky_valid, traced);
    }
  }
  sh.base[0] = simd::select(on_ground, bg.x * unshadowed, sh.base[0]);
  sh.base[1] = simd::select(on_ground, bg.y * unshadowed, sh.base[1]);
  sh.base[2] = simd::select(on_ground, bg.z * unshadowed, sh.base[2]);
  sh.base[3] = simd::select(on_ground, f.transparent ? 1.0f - unshadowed : zero, sh.base[3]);
}

// The extra layers (albedo, normal, depth) of the samples on the model: per pixel, over its own
// samples (no filter: they are data, not light).
MESHTOUR_SIMD_INLINE void add_to_extra_layers(const FilmTile& film, const Frame& f, const PacketSamples& s, const Hits& h, const V3& dir,
                                              const SurfacePoint& surface) {
  if (!film.albedo && !film.normal && !film.depth) return;
  for (int l = 0; l < simd::kLanes; ++l) {
    if (!h.on_model[l]) continue;
    const std::size_t pixel = static_cast<std::size_t>(s.layer_pixel[l]);
    if (film.albedo) {
      film.albedo[pixel * 3 + 0] += surface.albedo.x[l] / static_cast<float>(f.spp);
      film.albedo[pixel * 3 + 1] += surface.albedo.y[l] / static_cast<float>(f.spp);
      film.albedo[pixel * 3 + 2] += surface.albedo.z[l] / static_cast<float>(f.spp);
    }
    if (film.normal) {
      film.normal[pixel * 3 + 0] += surface.n.x[l];
      film.normal[pixel * 3 + 1] += surface.n.y[l];
      film.normal[pixel * 3 + 2] += surface.n.z[l];
    }
    if (film.depth) {
      const float depth = h.t[l] * (dir.x[l] * f.forward.x() + dir.y[l] * f.forward.y() + dir.z[l] * f.forward.z());
      film.depth[pixel] = std::min(film.depth[pixel], depth);
    }
  }
}

// 4. Shadow and occlusion rays, one rtcOccluded16 each (incoherent): Embree stops at the first
// hit. The samples' RGBA, now that the visibility is known. With interreflections, the occlusion
// rays that may bounce go through rtcIntersect16 instead (the same visibility, and where they
// stop: scratch.bounce), and the result is the lanes whose ray met the model there.
MESHTOUR_SIMD_INLINE I16 trace_shadow_and_occlusion_rays(const Impl& r, const Frame& f, RTCIntersectContext& incoherent, Scratch& scratch,
                                                         const Hits& h, const ShadedSamples& sh, RayRecording::Packet* rec,
                                                         TileCounts& counts, F16 (&rgba)[4]) {
  // The ground blocks what goes below it (the plane, intersected here); the rest is traced
  // against the model.
  I16 shadow_valid = sh.shadow_valid, sky_valid = sh.sky_valid;
  if (f.has_ground) {
    F16 t;
    shadow_valid = simd::both(shadow_valid, ~ground_hit(f, h.org, sh.shadow_dir, simd::broadcast(std::numeric_limits<float>::infinity()), t));
    sky_valid = simd::both(sky_valid, ~ground_hit(f, h.org, sh.sky_dir, simd::broadcast(f.sky_length), t));
  }
  ValidMask shadow_lanes, sky_lanes;
  simd::store_int(shadow_lanes.data(), shadow_valid);
  simd::store_int(sky_lanes.data(), sky_valid);
  const bool any_shadow = simd::any(shadow_valid), any_sky = simd::any(sky_valid);
  const bool bounce = f.bounces > 0 && simd::any(simd::both(sky_valid, sh.bounce_valid));
  if (any_shadow) set_rays(scratch.shadow, shadow_valid, h.org, sh.shadow_dir, std::numeric_limits<float>::infinity(), kModelMask);
  if (bounce) {
    set_rays(scratch.bounce.ray, sky_valid, h.org, sh.sky_dir, f.sky_length, kModelMask);
    simd::store_int(scratch.bounce.hit.geomID, simd::broadcast_int(static_cast<std::int32_t>(RTC_INVALID_GEOMETRY_ID)));
    simd::store_int(scratch.bounce.hit.instID[0], simd::broadcast_int(static_cast<std::int32_t>(RTC_INVALID_GEOMETRY_ID)));
  } else if (any_sky) {
    set_rays(scratch.sky, sky_valid, h.org, sh.sky_dir, f.sky_length, kModelMask);
  }
  if (rec) {
    if (any_shadow) rec->shadow = scratch.shadow;
    if (any_sky) rec->sky = bounce ? scratch.bounce.ray : scratch.sky;
    rec->shadow_valid = shadow_lanes;
    rec->sky_valid = sky_lanes;
  }
  if (any_shadow) rtcOccluded16(shadow_lanes.data(), r.rays->scene(), &incoherent, &scratch.shadow);
  if (bounce) rtcIntersect16(sky_lanes.data(), r.rays->scene(), &incoherent, &scratch.bounce);
  else if (any_sky) rtcOccluded16(sky_lanes.data(), r.rays->scene(), &incoherent, &scratch.sky);
  counts.secondary += static_cast<std::uint64_t>(popcount(shadow_valid) + popcount(sky_valid));
  // rtcOccluded16 sets tfar to -inf where the ray is blocked; rtcIntersect16 sets the geometry
  // it stopped at.
  const I16 light_seen = any_shadow ? simd::both(shadow_valid, simd::ge(simd::load(scratch.shadow.tfar), 0.0f)) : shadow_valid;
  const I16 sky_blocked = bounce ? simd::eq(simd::load_int(scratch.bounce.hit.geomID), static_cast<int>(kModelGeometry))
                                 : simd::lt(simd::load(scratch.sky.tfar), 0.0f);
  const I16 sky_seen = any_sky ? simd::both(sky_valid, ~sky_blocked) : sky_valid;
  const F16 zero = simd::broadcast(0.0f);
  for (int ch = 0; ch < 4; ++ch)
    rgba[ch] = sh.base[ch] + simd::select(light_seen, sh.with_light[ch], zero) + simd::select(sky_seen, sh.with_sky[ch], zero);
  return bounce ? simd::both(simd::both(sky_valid, sh.bounce_valid), sky_blocked) : simd::broadcast_int(0);
}

// 4b. Interreflections (Frame::bounces): from each point where an occlusion ray of `alive`
// met the model, the light it reflects back along that ray, added to the samples' RGB times
// `throughput`. The point is shaded as a diffuse surface of its base colour (glTF materials
// too: the glossy part of a second surface is left out), lit as a camera sample is lit: one
// shadow ray to one light chosen in proportion to its unshadowed light, the sky (or the
// environment's irradiance) through one cosine-distributed occlusion ray, the occlusion map
// on that sky, its emission, and, where that ray meets the model again, the next bounce.
// The floor is not a surface here (it only catches shadows): rays that meet it stop.
MESHTOUR_SIMD_INLINE void interreflect(const Impl& r, const Frame& f, RTCIntersectContext& incoherent, Scratch& scratch, const TileSampler& sampler,
                                       const PacketSamples& s, V3 org, V3 dir, V3 throughput, I16 alive, TileCounts& counts, F16 (&rgba)[4]) {
  const F16 zero = simd::broadcast(0.0f), one = simd::broadcast(1.0f);
  const std::size_t nlights = f.lights.size();
  // A wide footprint for the maps' lookups: a bounce's light is an average over a wide cone.
  constexpr float kBounceFootprint = 0.1f;
  for (int bounce = 0; bounce < f.bounces && simd::any(alive); ++bounce) {
    // The point met, as read_hits reads a camera ray's.
    Hits h;
    h.on_model = alive;
    h.on_ground = simd::broadcast_int(0);
    h.any = true;
    h.t = simd::select(alive, simd::load(scratch.bounce.ray.tfar), zero);
    h.ng = facing_normal(scratch.bounce.hit, dir);
    h.org = {org.x + h.t * dir.x + f.eps * h.ng.x, org.y + h.t * dir.y + f.eps * h.ng.y, org.z + h.t * dir.z + f.eps * h.ng.z};
    const SurfacePoint p = surface_at(r, f, scratch, scratch.bounce, h, dir, kBounceFootprint);
    const V3& n = p.n;
    const V3& albedo = p.albedo;
    F16 u_light, v_light, u_sky, v_sky;
    sampler.bounce(s, bounce, u_light, v_light, u_sky, v_sky);
    // Unlit lanes show their base colour and stop; the others may trace both rays.
    const I16 lit_lanes = p.any_unlit ? simd::both(alive, ~p.unlit) : alive;
    V3 emitted = p.emission;
    if (p.any_unlit) emitted = select(p.unlit, albedo, emitted);
    // The lights, diffusely (what each brings unshadowed; 0 from behind).
    V3 contributions[8];
    F16 weights[8];
    F16 total = zero;
    V3 unshadowed_lights{zero, zero, zero};
    for (std::size_t i = 0; i < nlights; ++i) {
      const F16 cos_i = simd::max(zero, dot(n, broadcast(f.lights[i].direction)));
      const Eigen::Vector3f& radiance = f.lights[i].radiance;
      contributions[i] = {albedo.x * radiance.x() * cos_i, albedo.y * radiance.y() * cos_i, albedo.z * radiance.z() * cos_i};
      weights[i] = luminance(contributions[i].x, contributions[i].y, contributions[i].z);
      total += weights[i];
      unshadowed_lights = {unshadowed_lights.x + contributions[i].x, unshadowed_lights.y + contributions[i].y, unshadowed_lights.z + contributions[i].z};
    }
    V3 light{zero, zero, zero};
    I16 shadow_valid = simd::broadcast_int(0);
    V3 shadow_dir{zero, zero, one};
    if (f.shadows && nlights > 0) {
      const OneLightSample one_light = sample_one_light(f.lights, contributions, weights, total, lit_lanes, u_light, v_light);
      shadow_valid = one_light.valid;
      light = one_light.light;
      shadow_dir = one_light.dir;
    } else {
      const V3 unshadowed = select(lit_lanes, unshadowed_lights, V3{zero, zero, zero});
      emitted = {emitted.x + unshadowed.x, emitted.y + unshadowed.y, emitted.z + unshadowed.z};
    }
    const V3 sky_light = f.environment ? environment_light(f, n) : broadcast(f.ambient);
    const F16 open = p.sky_occlusion;
    const V3 sky{albedo.x * sky_light.x * open, albedo.y * sky_light.y * open, albedo.z * sky_light.z * open};
    V3 t1, t2;
    basis(n, t1, t2);
    const V3 sky_dir = sky_direction(n, t1, t2, u_sky, v_sky);
    I16 sky_valid = lit_lanes;
    if (f.has_ground) {
      F16 t;
      shadow_valid = simd::both(shadow_valid, ~ground_hit(f, h.org, shadow_dir, simd::broadcast(std::numeric_limits<float>::infinity()), t));
      sky_valid = simd::both(sky_valid, ~ground_hit(f, h.org, sky_dir, simd::broadcast(f.ao_length), t));
    }
    const bool last = bounce + 1 == f.bounces;
    ValidMask shadow_lanes, sky_lanes;
    simd::store_int(shadow_lanes.data(), shadow_valid);
    simd::store_int(sky_lanes.data(), sky_valid);
    const bool any_shadow = simd::any(shadow_valid), any_sky = simd::any(sky_valid);
    if (any_shadow) {
      set_rays(scratch.shadow, shadow_valid, h.org, shadow_dir, std::numeric_limits<float>::infinity(), kModelMask);
      rtcOccluded16(shadow_lanes.data(), r.rays->scene(), &incoherent, &scratch.shadow);
    }
    I16 sky_blocked = simd::broadcast_int(0);
    if (any_sky && last) {
      set_rays(scratch.sky, sky_valid, h.org, sky_dir, f.ao_length, kModelMask);
      rtcOccluded16(sky_lanes.data(), r.rays->scene(), &incoherent, &scratch.sky);
      sky_blocked = simd::lt(simd::load(scratch.sky.tfar), 0.0f);
    } else if (any_sky) {
      set_rays(scratch.bounce.ray, sky_valid, h.org, sky_dir, f.ao_length, kModelMask);
      simd::store_int(scratch.bounce.hit.geomID, simd::broadcast_int(static_cast<std::int32_t>(RTC_INVALID_GEOMETRY_ID)));
      simd::store_int(scratch.bounce.hit.instID[0], simd::broadcast_int(static_cast<std::int32_t>(RTC_INVALID_GEOMETRY_ID)));
      rtcIntersect16(sky_lanes.data(), r.rays->scene(), &incoherent, &scratch.bounce);
      sky_blocked = simd::eq(simd::load_int(scratch.bounce.hit.geomID), static_cast<int>(kModelGeometry));
    }
    counts.secondary += static_cast<std::uint64_t>(popcount(shadow_valid) + popcount(sky_valid));
    const I16 light_seen = any_shadow ? simd::both(shadow_valid, simd::ge(simd::load(scratch.shadow.tfar), 0.0f)) : shadow_valid;
    const I16 sky_seen = simd::both(sky_valid, ~sky_blocked);
    const V3 reflected{emitted.x + simd::select(light_seen, light.x, zero) + simd::select(sky_seen, sky.x, zero),
                       emitted.y + simd::select(light_seen, light.y, zero) + simd::select(sky_seen, sky.y, zero),
                       emitted.z + simd::select(light_seen, light.z, zero) + simd::select(sky_seen, sky.z, zero)};
    rgba[0] += simd::select(alive, throughput.x * reflected.x, zero);
    rgba[1] += simd::select(alive, throughput.y * reflected.y, zero);
    rgba[2] += simd::select(alive, throughput.z * reflected.z, zero);
    throughput = {throughput.x * albedo.x * open, throughput.y * albedo.y * open, throughput.z * albedo.z * open};
    alive = simd::both(sky_valid, sky_blocked);
    org = h.org;
    dir = sky_dir;
  }
}

// 5. Splat: every sample onto the pixels within the filter's radius of it, on the tile's sums,
// with the denoiser's guides.
MESHTOUR_SIMD_INLINE void splat(const ReconstructionFilter& filter, const Frame& f, const FilmTile& film, const PacketSamples& s,
                                const Hits& h, const ShadedSamples& sh, const V3& bg, const F16 (&rgba)[4]) {
  const F16 zero = simd::broadcast(0.0f), one = simd::broadcast(1.0f);
  const int lanes = s.lanes;
  const int* buffer_pixel = s.sums_pixel;
  const int* image_pixel = s.layer_pixel;
  float* const sums = film.sums;
  F16 wx[5], wy[5];
  filter.weights(s.u_cam, wx);
  filter.weights(s.v_cam, wy);
  const bool one_pixel = lanes == simd::kLanes && buffer_pixel[0] == buffer_pixel[simd::kLanes - 1];
  // The unshadowed light splatted off the model: the background's colour at the pixel's centre
  // row rather than each sample's own (they differ by a thousandth at most), one colour for
  // all of a pixel's samples, so that a pixel of ground and background needs no sums of its own
  // for it (splat_uniform_light_packet). The moments keep each sample's own: there the far
  // ground's visibility is exactly 1, without noise, and is not filtered.
  V3 splat_light = sh.guide_unshadowed;
  if (film.guides && !f.transparent) {
    const F16 t_centre = simd::min(one, simd::max(zero, (simd::load(s.py) + 0.5f) * f.inv_height));
    // (An environment backdrop is per pixel already.)
    const V3 centre_bg = f.backdrop_rgb.empty() ? backdrop_colour(f.background_top, f.background_bottom, t_centre) : bg;
    splat_light = select(h.on_model, sh.guide_unshadowed, centre_bg);
  }
  if (film.guides && one_pixel && !h.any) {
    // One pixel's samples, all on the background: its guides stay as the tile cleared them (no
    // normal, no depth: the denoiser passes the pixel through).
    const float light[3] = {splat_light.x[0], splat_light.y[0], splat_light.z[0]};
    switch (filter.reach()) {
      case 0: splat_uniform_light_packet<0, 0>(rgba, light, wx, wy, buffer_pixel[0], sums, film.stride); break;
      case 1: splat_uniform_light_packet<1, 0>(rgba, light, wx, wy, buffer_pixel[0], sums, film.stride); break;
      default: splat_uniform_light_packet<2, 0>(rgba, light, wx, wy, buffer_pixel[0], sums, film.stride); break;
    }
  } else if (film.guides && one_pixel && !simd::any(h.on_model)) {
    // One pixel's samples on the ground and the background: the normal is the ground's for
    // every sample on it, and only the visibility's moments are summed.
    const float light[3] = {splat_light.x[0], splat_light.y[0], splat_light.z[0]};
    F16 values[kGuideSums];
    guide_values(f.transparent, rgba, sh.guide_unshadowed, sh.guide_normal, values);
    const F16 moments[2] = {values[3], values[4]};
    float moment_sums[2];
    switch (filter.reach()) {
      case 0: splat_uniform_light_packet<0, 2>(rgba, light, wx, wy, buffer_pixel[0], sums, film.stride, moments, moment_sums); break;
      case 1: splat_uniform_light_packet<1, 2>(rgba, light, wx, wy, buffer_pixel[0], sums, film.stride, moments, moment_sums); break;
      default: splat_uniform_light_packet<2, 2>(rgba, light, wx, wy, buffer_pixel[0], sums, film.stride, moments, moment_sums); break;
    }
    const float on_ground_samples = static_cast<float>(popcount(h.on_ground));
    const float pixel_sums[kGuideSums] = {f.up.x() * on_ground_samples, f.up.y() * on_ground_samples, f.up.z() * on_ground_samples,
                                          moment_sums[0], moment_sums[1]};
    add_pixel_guides(*film.guides, static_cast<std::size_t>(image_pixel[0]), pixel_sums, nearest_depth(sh.guide_depth));
  } else if (film.guides) {
    // The denoiser divides the frame by the unshadowed light: splatted with the very same
    // weights, so that the ratio is the visibility also at silhouettes and colour edges.
    const F16 values[7] = {rgba[0], rgba[1], rgba[2], rgba[3], splat_light.x, splat_light.y, splat_light.z};
    F16 extras[kGuideSums];
    guide_values(f.transparent, rgba, sh.guide_unshadowed, sh.guide_normal, extras);
    float extra_sums[kGuideSums];
    bool summed = false;
    switch (filter.reach()) {
      case 0: summed = splat_packet<0, 7, kGuideSums>(values, wx, wy, buffer_pixel, lanes, sums, film.stride, extras, extra_sums); break;
      case 1: summed = splat_packet<1, 7, kGuideSums>(values, wx, wy, buffer_pixel, lanes, sums, film.stride, extras, extra_sums); break;
      default: summed = splat_packet<2, 7, kGuideSums>(values, wx, wy, buffer_pixel, lanes, sums, film.stride, extras, extra_sums); break;
    }
    if (summed) {
      add_pixel_guides(*film.guides, static_cast<std::size_t>(image_pixel[0]), extra_sums, nearest_depth(sh.guide_depth));
    } else {
      add_lane_guides(*film.guides, image_pixel, lanes, extras, sh.guide_depth);
    }
  } else {
    switch (filter.reach()) {
      case 0: splat_packet<0>(rgba, wx, wy, buffer_pixel, lanes, sums, film.stride); break;
      case 1: splat_packet<1>(rgba, wx, wy, buffer_pixel, lanes, sums, film.stride); break;
      default: splat_packet<2>(rgba, wx, wy, buffer_pixel, lanes, sums, film.stride); break;
    }
  }
}

}  // namespace

// The integrator of a tile: its samples, 16 at a time (one packet), through the stages above:
// camera rays, intersection, shading, shadow and occlusion rays, splat.
template <InstructionSet Set>
void Renderer::Impl::render_tile(const Frame& f, Scratch& scratch, const FilmTile& film, RayRecording::Tile* recorded,
                                 TileCounts& counts) const {
  // A copy compiled anywhere but in its own set's file would be this file's code under that
  // set's name, and the linker could keep it (renderer_impl.h).
  static_assert(Set == kCompiledFor, "render_tile instantiated outside its instruction set's copy of tile_kernel.cpp");
  RayContext camera_context = ray_context(*this, scratch, true), secondary_context = ray_context(*this, scratch, false);
  RTCIntersectContext& coherent = camera_context.embree;
  RTCIntersectContext& incoherent = secondary_context.embree;
  const V3 eye = broadcast(f.eye);
  TileSampler sampler(f, film);
  for (int first = 0; first < sampler.sample_count(); first += simd::kLanes) {
    PacketSamples samples;
    sampler.next(std::min(simd::kLanes, sampler.sample_count() - first), samples);
    const CameraRays camera = camera_rays(f, samples);
    RayRecording::Packet* rec = intersect(*this, coherent, scratch.primary, samples, eye, camera.dir, recorded, counts);
    const Hits hits = read_hits(f, scratch.primary, samples, eye, camera.dir);
    const V3 bg = backdrop(f, samples, camera);
    ShadedSamples shaded;
    shade_background(f, bg, shaded);
    if (hits.any) {
      sampler.secondary(samples);
      shaded.guide_depth = simd::select(simd::either(hits.on_model, hits.on_ground), hits.t * dot(camera.dir, broadcast(f.forward)), shaded.guide_depth);
      if (simd::any(hits.on_model)) {
        // A camera sample's footprint: the pixel's width divided by sqrt(spp), because the
        // samples already average over the pixel.
        const SurfacePoint surface = surface_at(*this, f, scratch, scratch.primary, hits, camera.dir, f.pixel_angle / std::sqrt(static_cast<float>(f.spp)));
        shade_model(f, samples, hits, camera.dir, surface, film.guides != nullptr, shaded);
        add_to_extra_layers(film, f, samples, hits, camera.dir, surface);
      }
      if (simd::any(hits.on_ground)) shade_ground(f, samples, hits, bg, shaded);
    }
    F16 rgba[4];
    const I16 bounced = trace_shadow_and_occlusion_rays(*this, f, incoherent, scratch, hits, shaded, rec, counts, rgba);
    if (f.bounces > 0 && simd::any(bounced))
      interreflect(*this, f, incoherent, scratch, sampler, samples, hits.org, shaded.sky_dir, shaded.bounce_weight, bounced, counts, rgba);
    splat(filter, f, film, samples, hits, shaded, bg, rgba);
  }
}

// This file's copy of the kernel.
static_assert(kCompiledFor == InstructionSet::baseline || simd::kNativeLanes >= 8, "a wide copy compiled without wide vectors");
template void Renderer::Impl::render_tile<kCompiledFor>(const Frame&, Scratch&, const FilmTile&, RayRecording::Tile*, TileCounts&) const;

}  // namespace meshtour
