#pragma once
// 16-lane vectors for shading one camera-ray packet at a time. A 16-lane value is a few vectors
// of the target's own width (one AVX-512, two AVX, four SSE registers) and every operation is
// written piece by piece: GCC 12 lowers vector-extension types wider than the target's badly
// (comparisons and selects lane by lane, bitwise operations in 64-bit scalar pieces), which made
// the AVX2 and SSE2 kernels slower than plain scalar code.
//
// Only IEEE add, multiply, divide, square root, comparisons and integer operations are used (no
// approximate reciprocals, no fused multiply-add: -ffp-contract=off), and cross-lane sums add in
// one fixed order, so every instruction set gives the same bits: a frame does not depend on the
// CPU that rendered it.
//
// Everything is forced inline: tile_kernel.cpp is compiled once per instruction set, and an
// out-of-line copy of a helper could be shared between those copies by the linker.
#include <cstdint>
#include <cstring>
#include <numbers>
#if defined(__SSE2__)
#include <immintrin.h>
#endif

#define MESHTOUR_SIMD_INLINE [[gnu::always_inline]] inline

namespace meshtour::simd {

constexpr int kLanes = 16;
#if defined(__AVX512F__)
constexpr int kNativeLanes = 16;
#elif defined(__AVX__)
constexpr int kNativeLanes = 8;
#else
constexpr int kNativeLanes = 4;
#endif
using FNative = float __attribute__((vector_size(4 * kNativeLanes)));
using INative = std::int32_t __attribute__((vector_size(4 * kNativeLanes)));
using UNative = std::uint32_t __attribute__((vector_size(4 * kNativeLanes)));

/// 16 lanes of T as kLanes / kNativeLanes native vectors.
template <typename T, typename Native>
struct Vec {
  using Scalar = T;
  static constexpr int kPieces = kLanes / kNativeLanes;
  Native p[kPieces];
  MESHTOUR_SIMD_INLINE T operator[](int i) const { return p[i / kNativeLanes][i % kNativeLanes]; }
  MESHTOUR_SIMD_INLINE void set(int i, T v) { p[i / kNativeLanes][i % kNativeLanes] = v; }
};
using F16 = Vec<float, FNative>;
using I16 = Vec<std::int32_t, INative>;
using U16 = Vec<std::uint32_t, UNative>;

/// Applies `op` piece by piece (a lambda: inlined, like everything here).
template <typename Out, typename In, typename Op>
MESHTOUR_SIMD_INLINE Out map(const In& a, Op op) {
  Out r;
  for (int k = 0; k < In::kPieces; ++k) r.p[k] = op(a.p[k]);
  return r;
}
template <typename Out, typename In, typename Op>
MESHTOUR_SIMD_INLINE Out map(const In& a, const In& b, Op op) {
  Out r;
  for (int k = 0; k < In::kPieces; ++k) r.p[k] = op(a.p[k], b.p[k]);
  return r;
}

#define MESHTOUR_SIMD_BINARY(V, op)                                                                          \
  MESHTOUR_SIMD_INLINE V operator op(const V& a, const V& b) {                                             \
    return map<V>(a, b, [](auto x, auto y) __attribute__((always_inline)) { return x op y; });             \
  }                                                                                                         \
  MESHTOUR_SIMD_INLINE V operator op(const V& a, V::Scalar b) {                                            \
    return map<V>(a, [b](auto x) __attribute__((always_inline)) { return x op b; });                       \
  }                                                                                                         \
  MESHTOUR_SIMD_INLINE V operator op(V::Scalar a, const V& b) {                                            \
    return map<V>(b, [a](auto y) __attribute__((always_inline)) { return a op y; });                       \
  }                                                                                                         \
  MESHTOUR_SIMD_INLINE V& operator op##=(V& a, const V& b) { return a = a op b; }                          \
  MESHTOUR_SIMD_INLINE V& operator op##=(V& a, V::Scalar b) { return a = a op b; }
MESHTOUR_SIMD_BINARY(F16, +)
MESHTOUR_SIMD_BINARY(F16, -)
MESHTOUR_SIMD_BINARY(F16, *)
MESHTOUR_SIMD_BINARY(F16, /)
MESHTOUR_SIMD_BINARY(I16, +)
MESHTOUR_SIMD_BINARY(I16, -)
MESHTOUR_SIMD_BINARY(I16, &)
MESHTOUR_SIMD_BINARY(I16, |)
MESHTOUR_SIMD_BINARY(U16, +)
MESHTOUR_SIMD_BINARY(U16, *)
MESHTOUR_SIMD_BINARY(U16, &)
MESHTOUR_SIMD_BINARY(U16, ^)
MESHTOUR_SIMD_BINARY(U16, |)
#undef MESHTOUR_SIMD_BINARY
MESHTOUR_SIMD_INLINE F16 operator-(const F16& a) {
  return map<F16>(a, [](auto x) __attribute__((always_inline)) { return -x; });
}
MESHTOUR_SIMD_INLINE I16 operator~(const I16& a) {
  return map<I16>(a, [](auto x) __attribute__((always_inline)) { return ~x; });
}
MESHTOUR_SIMD_INLINE I16 operator<<(const I16& a, int n) {
  return map<I16>(a, [n](auto x) __attribute__((always_inline)) { return x << n; });
}
MESHTOUR_SIMD_INLINE I16 operator>>(const I16& a, int n) {
  return map<I16>(a, [n](auto x) __attribute__((always_inline)) { return x >> n; });
}
MESHTOUR_SIMD_INLINE U16 operator>>(const U16& a, int n) {
  return map<U16>(a, [n](auto x) __attribute__((always_inline)) { return x >> n; });
}
MESHTOUR_SIMD_INLINE U16 operator<<(const U16& a, int n) {
  return map<U16>(a, [n](auto x) __attribute__((always_inline)) { return x << n; });
}

MESHTOUR_SIMD_INLINE F16 broadcast(float v) {
  F16 r;
  for (auto& piece : r.p) piece = FNative{} + v;
  return r;
}
MESHTOUR_SIMD_INLINE I16 broadcast_int(std::int32_t v) {
  I16 r;
  for (auto& piece : r.p) piece = INative{} + v;
  return r;
}
MESHTOUR_SIMD_INLINE F16 load(const float* p) {
  F16 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
MESHTOUR_SIMD_INLINE I16 load_int(const void* p) {
  I16 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
MESHTOUR_SIMD_INLINE U16 load_uint(const void* p) {
  U16 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
MESHTOUR_SIMD_INLINE void store(float* p, const F16& v) { std::memcpy(p, &v, sizeof v); }
MESHTOUR_SIMD_INLINE void store_int(void* p, const I16& v) { std::memcpy(p, &v, sizeof v); }

/// The same bits seen as another lane type.
MESHTOUR_SIMD_INLINE I16 as_int(const F16& v) {
  return map<I16>(v, [](FNative x) __attribute__((always_inline)) { return reinterpret_cast<INative>(x); });
}
MESHTOUR_SIMD_INLINE I16 as_int(const U16& v) {
  return map<I16>(v, [](UNative x) __attribute__((always_inline)) { return reinterpret_cast<INative>(x); });
}
MESHTOUR_SIMD_INLINE F16 as_float(const I16& v) {
  return map<F16>(v, [](INative x) __attribute__((always_inline)) { return reinterpret_cast<FNative>(x); });
}

/// Lane-wise comparisons: lanes are -1 (true) or 0 (false).
#define MESHTOUR_SIMD_COMPARE(name, op)                                                                      \
  MESHTOUR_SIMD_INLINE I16 name(const F16& a, const F16& b) {                                              \
    return map<I16>(a, b, [](FNative x, FNative y) __attribute__((always_inline)) { return x op y; });     \
  }                                                                                                         \
  MESHTOUR_SIMD_INLINE I16 name(const F16& a, float b) { return name(a, broadcast(b)); }                   \
  MESHTOUR_SIMD_INLINE I16 name(const I16& a, const I16& b) {                                              \
    return map<I16>(a, b, [](INative x, INative y) __attribute__((always_inline)) { return x op y; });     \
  }                                                                                                         \
  MESHTOUR_SIMD_INLINE I16 name(const I16& a, std::int32_t b) { return name(a, broadcast_int(b)); }
MESHTOUR_SIMD_COMPARE(lt, <)
MESHTOUR_SIMD_COMPARE(le, <=)
MESHTOUR_SIMD_COMPARE(gt, >)
MESHTOUR_SIMD_COMPARE(ge, >=)
MESHTOUR_SIMD_COMPARE(eq, ==)
MESHTOUR_SIMD_COMPARE(ne, !=)
#undef MESHTOUR_SIMD_COMPARE

/// Masks combined.
MESHTOUR_SIMD_INLINE I16 both(const I16& a, const I16& b) { return a & b; }
MESHTOUR_SIMD_INLINE I16 either(const I16& a, const I16& b) { return a | b; }
/// Lane-wise choice by a mask (lanes -1 or 0): bitwise, never a branch.
MESHTOUR_SIMD_INLINE I16 select_int(const I16& mask, const I16& a, const I16& b) { return (mask & a) | (~mask & b); }
MESHTOUR_SIMD_INLINE F16 select(const I16& mask, const F16& a, const F16& b) {
  return as_float(select_int(mask, as_int(a), as_int(b)));
}
MESHTOUR_SIMD_INLINE F16 min(const F16& a, const F16& b) { return select(lt(a, b), a, b); }
MESHTOUR_SIMD_INLINE F16 max(const F16& a, const F16& b) { return select(gt(a, b), a, b); }
MESHTOUR_SIMD_INLINE bool any(const I16& mask) {
  INative acc = mask.p[0];
  for (int k = 1; k < I16::kPieces; ++k) acc |= mask.p[k];
  std::int32_t bits = 0;
  for (int i = 0; i < kNativeLanes; ++i) bits |= acc[i];
  return bits != 0;
}
MESHTOUR_SIMD_INLINE F16 to_float(const I16& v) {
  return map<F16>(v, [](INative x) __attribute__((always_inline)) { return __builtin_convertvector(x, FNative); });
}
/// Truncates towards zero.
MESHTOUR_SIMD_INLINE I16 to_int(const F16& v) {
  return map<I16>(v, [](FNative x) __attribute__((always_inline)) { return __builtin_convertvector(x, INative); });
}

MESHTOUR_SIMD_INLINE F16 sqrt(const F16& x) {
  return map<F16>(x, [](FNative v) __attribute__((always_inline)) {
#if defined(__AVX512F__)
    // (The intrinsic trips a false -Wmaybe-uninitialized in GCC 12's headers; with
    // -fno-math-errno this loop is the same single vsqrtps.)
    FNative r;
    for (int i = 0; i < kNativeLanes; ++i) r[i] = __builtin_sqrtf(v[i]);
    return r;
#elif defined(__AVX__)
    return FNative(_mm256_sqrt_ps(v));
#elif defined(__SSE2__)
    return FNative(_mm_sqrt_ps(v));
#else
    FNative r;
    for (int i = 0; i < kNativeLanes; ++i) r[i] = __builtin_sqrtf(v[i]);
    return r;
#endif
  });
}

/// The lane sums of 16 vectors: lane k of the result is the sum of x[k]'s lanes, always added as
/// ((q0 + q2) + (q1 + q3)) with q_l = p_l + p_(l+4), p_l = x_l + x_(l+8).
MESHTOUR_SIMD_INLINE F16 sum_lanes(const F16* x) {
#if defined(__AVX512F__)
  // 16 sums at once: a tree of 15 adds and 30 two-vector shuffles.
#if defined(__clang__)
#define MESHTOUR_SHUFFLE(a, b, ...) __builtin_shufflevector(a, b, __VA_ARGS__)
#else
#define MESHTOUR_SHUFFLE(a, b, ...) __builtin_shuffle(a, b, INative{__VA_ARGS__})
#endif
  FNative a[8], b[4], c[2];
  for (int i = 0; i < 8; ++i)  // p: x[2i] in lanes 0-7, x[2i+1] in lanes 8-15
    a[i] = MESHTOUR_SHUFFLE(x[2 * i].p[0], x[2 * i + 1].p[0], 0, 1, 2, 3, 4, 5, 6, 7, 16, 17, 18, 19, 20, 21, 22, 23) +
           MESHTOUR_SHUFFLE(x[2 * i].p[0], x[2 * i + 1].p[0], 8, 9, 10, 11, 12, 13, 14, 15, 24, 25, 26, 27, 28, 29, 30, 31);
  for (int i = 0; i < 4; ++i)  // q: four per vector
    b[i] = MESHTOUR_SHUFFLE(a[2 * i], a[2 * i + 1], 0, 1, 2, 3, 8, 9, 10, 11, 16, 17, 18, 19, 24, 25, 26, 27) +
           MESHTOUR_SHUFFLE(a[2 * i], a[2 * i + 1], 4, 5, 6, 7, 12, 13, 14, 15, 20, 21, 22, 23, 28, 29, 30, 31);
  for (int i = 0; i < 2; ++i)  // q0 + q2, q1 + q3
    c[i] = MESHTOUR_SHUFFLE(b[2 * i], b[2 * i + 1], 0, 1, 4, 5, 8, 9, 12, 13, 16, 17, 20, 21, 24, 25, 28, 29) +
           MESHTOUR_SHUFFLE(b[2 * i], b[2 * i + 1], 2, 3, 6, 7, 10, 11, 14, 15, 18, 19, 22, 23, 26, 27, 30, 31);
  F16 r;
  r.p[0] = MESHTOUR_SHUFFLE(c[0], c[1], 0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30) +
           MESHTOUR_SHUFFLE(c[0], c[1], 1, 3, 5, 7, 9, 11, 13, 15, 17, 19, 21, 23, 25, 27, 29, 31);
#undef MESHTOUR_SHUFFLE
  return r;
#else
  // One vector at a time, the same additions on halves and quarters.
  using F4 = float __attribute__((vector_size(16)));
  F16 r;
  for (int k = 0; k < kLanes; ++k) {
#if defined(__AVX__)  // two 8-lane pieces
    const FNative p = x[k].p[0] + x[k].p[1];
    F4 lo, hi;
    std::memcpy(&lo, &p, sizeof lo);
    std::memcpy(&hi, reinterpret_cast<const char*>(&p) + sizeof lo, sizeof hi);
    const F4 q = lo + hi;
#else  // four 4-lane pieces
    const F4 q = (x[k].p[0] + x[k].p[2]) + (x[k].p[1] + x[k].p[3]);
#endif
    r.set(k, (q[0] + q[2]) + (q[1] + q[3]));
  }
  return r;
#endif
}

/// A 32-bit integer hash with good avalanche ("lowbias32", C. Wellons 2018): the sampler's
/// per-pixel seeds (sampler.h) are hashes of the pixel's key, computed 16 lanes at a time.
/// For one std::uint32_t (per-pixel values) or for 16 lanes (U16).
template <typename Uint>
MESHTOUR_SIMD_INLINE constexpr Uint hash(Uint x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

/// sin and cos of 2 pi u for u in [0, 1]: quadrant reduction and short Taylor polynomials on
/// [-pi/4, pi/4] (error < 4e-7), plain arithmetic, so every CPU and libm give the same bits.
MESHTOUR_SIMD_INLINE void sincos_turns(F16 u, F16& s, F16& c) {
  const I16 quadrant = to_int(u * 4.0f + 0.5f);  // 0..4, u >= 0
  const F16 x = (u - 0.25f * to_float(quadrant)) * (2.0f * std::numbers::pi_v<float>);
  const F16 x2 = x * x;
  const F16 sin_x = x * (1.0f + x2 * (-1.0f / 6 + x2 * (1.0f / 120 + x2 * (-1.0f / 5040))));
  const F16 cos_x = 1.0f + x2 * (-0.5f + x2 * (1.0f / 24 + x2 * (-1.0f / 720 + x2 * (1.0f / 40320))));
  // Quadrant q: (sin, cos) = (s, c), (c, -s), (-s, -c), (-c, s).
  const I16 swap = ne(quadrant & 1, 0);
  const F16 s0 = select(swap, cos_x, sin_x), c0 = select(swap, sin_x, cos_x);
  s = select(ne(quadrant & 2, 0), -s0, s0);
  c = select(ne((quadrant + 1) & 2, 0), -c0, c0);
}

/// x^e for x in (0, 1] and e * log2(x) >= -126 (a Blinn-Phong highlight above its cut-off):
/// exp2(e log2 x) with polynomial log2 and exp2, relative error below 1e-5.
MESHTOUR_SIMD_INLINE F16 pow_unit(F16 x, float e) {
  // log2: x = 2^k m with m in [1, 2); log2 m = 2/ln 2 atanh(t), t = (m - 1)/(m + 1) in [0, 1/3].
  const I16 bits = as_int(x);
  const F16 k = to_float(((bits >> 23) & 0xff) - 127);
  const F16 m = as_float((bits & 0x7fffff) | 0x3f800000);
  const F16 t = (m - 1.0f) / (m + 1.0f), t2 = t * t;
  const F16 atanh_t = t * (1.0f + t2 * (1.0f / 3 + t2 * (1.0f / 5 + t2 * (1.0f / 7 + t2 * (1.0f / 9 + t2 * (1.0f / 11))))));
  // <= 0; clamped where 2^y would no longer be a normal float (a highlight that small is 0 anyway).
  const F16 y = max(e * (k + (2.0f / std::numbers::ln2_v<float>)*atanh_t), broadcast(-126.0f));
  // exp2: y = n + f with n = floor(y), f in [0, 1); 2^f = sqrt 2 * e^((f - 1/2) ln 2).
  I16 n = to_int(y);
  n += gt(to_float(n), y);  // -1 where truncation rounded a negative value up
  const F16 g = (y - to_float(n) - 0.5f) * std::numbers::ln2_v<float>;
  const F16 e_g = 1.0f + g * (1.0f + g * (0.5f + g * (1.0f / 6 + g * (1.0f / 24 + g * (1.0f / 120 + g * (1.0f / 720))))));
  const F16 scale = as_float((n + 127) << 23);
  return e_g * std::numbers::sqrt2_v<float> * scale;
}

}  // namespace meshtour::simd
