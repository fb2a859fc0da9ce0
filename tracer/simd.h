#pragma once
// 16-lane vectors for shading one camera-ray packet at a time (GCC/Clang vector extensions).
// The compiler maps a 16-lane operation onto whatever the target has (4 SSE, 2 AVX or 1 AVX-512
// instruction). Only IEEE add, multiply, divide, square root, comparisons and integer operations
// are used (no approximate reciprocals, no fused multiply-add: -ffp-contract=off), so every
// instruction set gives the same bits, and a frame does not depend on the CPU that rendered it.
#include <cstdint>
#include <cstring>
#include <numbers>

// Everything here is forced inline: the renderer's kernel is compiled for several instruction
// sets (target_clones), and a 16-lane vector passed to a separate function would be passed
// differently by each of them.
#define MESHTOUR_SIMD_INLINE [[gnu::always_inline]] inline

namespace meshtour::simd {

constexpr int kLanes = 16;
using F16 = float __attribute__((vector_size(64)));
using I16 = std::int32_t __attribute__((vector_size(64)));
using U16 = std::uint32_t __attribute__((vector_size(64)));

MESHTOUR_SIMD_INLINE F16 broadcast(float v) { return F16{} + v; }
MESHTOUR_SIMD_INLINE I16 broadcast_int(std::int32_t v) { return I16{} + v; }
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
MESHTOUR_SIMD_INLINE void store(float* p, F16 v) { std::memcpy(p, &v, sizeof v); }
MESHTOUR_SIMD_INLINE void store_int(void* p, I16 v) { std::memcpy(p, &v, sizeof v); }

// The widest vectors the target has. Comparisons and conversions are written piece by piece at
// this width: GCC 12 lowers them lane by lane (scalar compares and inserts) for vectors wider
// than the target's, which made the AVX2 and SSE2 kernels slower than plain scalar code.
#if defined(__AVX512F__)
constexpr int kNativeLanes = 16;
#elif defined(__AVX__)
constexpr int kNativeLanes = 8;
#else
constexpr int kNativeLanes = 4;
#endif
using FNative = float __attribute__((vector_size(4 * kNativeLanes)));
using INative = std::int32_t __attribute__((vector_size(4 * kNativeLanes)));

/// Applies `op` to native-width pieces of 16-lane vectors (a function object, inlined).
template <typename Out, typename In, typename PieceIn, typename PieceOut, typename Op>
MESHTOUR_SIMD_INLINE Out piecewise(In a, In b, Op op) {
  Out r;
  for (int k = 0; k < kLanes; k += kNativeLanes) {
    PieceIn x, y;
    std::memcpy(&x, reinterpret_cast<const char*>(&a) + 4 * k, sizeof x);
    std::memcpy(&y, reinterpret_cast<const char*>(&b) + 4 * k, sizeof y);
    const PieceOut m = op(x, y);
    std::memcpy(reinterpret_cast<char*>(&r) + 4 * k, &m, sizeof m);
  }
  return r;
}

/// Lane-wise comparisons: lanes are -1 (true) or 0 (false).
#define MESHTOUR_SIMD_COMPARE(name, op)                                                                 \
  struct name##_op {                                                                                    \
    MESHTOUR_SIMD_INLINE INative operator()(FNative x, FNative y) const { return x op y; }             \
    MESHTOUR_SIMD_INLINE INative operator()(INative x, INative y) const { return x op y; }             \
  };                                                                                                    \
  MESHTOUR_SIMD_INLINE I16 name(F16 a, F16 b) { return piecewise<I16, F16, FNative, INative>(a, b, name##_op{}); } \
  MESHTOUR_SIMD_INLINE I16 name(F16 a, float b) { return name(a, broadcast(b)); }                     \
  MESHTOUR_SIMD_INLINE I16 name(I16 a, I16 b) { return piecewise<I16, I16, INative, INative>(a, b, name##_op{}); } \
  MESHTOUR_SIMD_INLINE I16 name(I16 a, std::int32_t b) { return name(a, broadcast_int(b)); }
MESHTOUR_SIMD_COMPARE(lt, <)
MESHTOUR_SIMD_COMPARE(le, <=)
MESHTOUR_SIMD_COMPARE(gt, >)
MESHTOUR_SIMD_COMPARE(ge, >=)
MESHTOUR_SIMD_COMPARE(eq, ==)
MESHTOUR_SIMD_COMPARE(ne, !=)
#undef MESHTOUR_SIMD_COMPARE

/// Lane-wise: mask lanes are -1 (true) or 0 (false), as comparisons return them.
/// Bitwise, piece by piece: GCC lowers `mask ? a : b` lane by lane, and bitwise operations on
/// vectors wider than the target's in 64-bit scalar pieces.
MESHTOUR_SIMD_INLINE I16 select_int(I16 mask, I16 a, I16 b) {
  I16 r;
  for (int k = 0; k < kLanes; k += kNativeLanes) {
    INative m, x, y;
    std::memcpy(&m, reinterpret_cast<const char*>(&mask) + 4 * k, sizeof m);
    std::memcpy(&x, reinterpret_cast<const char*>(&a) + 4 * k, sizeof x);
    std::memcpy(&y, reinterpret_cast<const char*>(&b) + 4 * k, sizeof y);
    const INative v = (m & x) | (~m & y);
    std::memcpy(reinterpret_cast<char*>(&r) + 4 * k, &v, sizeof v);
  }
  return r;
}
struct and_op {
  MESHTOUR_SIMD_INLINE INative operator()(INative x, INative y) const { return x & y; }
};
struct or_op {
  MESHTOUR_SIMD_INLINE INative operator()(INative x, INative y) const { return x | y; }
};
/// Masks combined (the same piecewise reason as select_int).
MESHTOUR_SIMD_INLINE I16 both(I16 a, I16 b) { return piecewise<I16, I16, INative, INative>(a, b, and_op{}); }
MESHTOUR_SIMD_INLINE I16 either(I16 a, I16 b) { return piecewise<I16, I16, INative, INative>(a, b, or_op{}); }
MESHTOUR_SIMD_INLINE F16 select(I16 mask, F16 a, F16 b) {
  return reinterpret_cast<F16>(select_int(mask, reinterpret_cast<I16>(a), reinterpret_cast<I16>(b)));
}
MESHTOUR_SIMD_INLINE F16 min(F16 a, F16 b) { return select(lt(a, b), a, b); }
MESHTOUR_SIMD_INLINE F16 max(F16 a, F16 b) { return select(gt(a, b), a, b); }
MESHTOUR_SIMD_INLINE bool any(I16 mask) {
  std::int32_t acc = 0;
  for (int i = 0; i < kLanes; ++i) acc |= mask[i];
  return acc != 0;
}
struct to_float_op {
  MESHTOUR_SIMD_INLINE FNative operator()(INative x, INative) const { return __builtin_convertvector(x, FNative); }
};
struct to_int_op {
  MESHTOUR_SIMD_INLINE INative operator()(FNative x, FNative) const { return __builtin_convertvector(x, INative); }
};
MESHTOUR_SIMD_INLINE F16 to_float(I16 v) { return piecewise<F16, I16, INative, FNative>(v, v, to_float_op{}); }
/// Truncates towards zero.
MESHTOUR_SIMD_INLINE I16 to_int(F16 v) { return piecewise<I16, F16, FNative, INative>(v, v, to_int_op{}); }

MESHTOUR_SIMD_INLINE F16 sqrt(F16 x) {
  // Compiled with -fno-math-errno, so the loop becomes packed square roots.
  F16 r;
  for (int i = 0; i < kLanes; ++i) r[i] = __builtin_sqrtf(x[i]);
  return r;
}

#if defined(__clang__)
#define MESHTOUR_SHUFFLE(a, b, ...) __builtin_shufflevector(a, b, __VA_ARGS__)
#else
#define MESHTOUR_SHUFFLE(a, b, ...) __builtin_shuffle(a, b, I16{__VA_ARGS__})
#endif

/// The lane sums of 16 vectors at once: result lane k = the sum of x[k]'s lanes. A tree of 15
/// adds and 30 shuffles instead of 16 separate reductions; the order of the additions is fixed
/// by this code, so every instruction set gives the same sums.
MESHTOUR_SIMD_INLINE F16 sum_lanes(const F16* x) {
#if !defined(__AVX512F__)
  // Without 16-lane registers GCC turns the shuffles below into lane-by-lane inserts: the same
  // additions, in the same order, one vector at a time on halves and quarters instead.
  using F8 = float __attribute__((vector_size(32)));
  using F4 = float __attribute__((vector_size(16)));
  alignas(64) float out[kLanes];
  for (int k = 0; k < kLanes; ++k) {
    F8 lo, hi;
    std::memcpy(&lo, reinterpret_cast<const char*>(&x[k]), sizeof lo);
    std::memcpy(&hi, reinterpret_cast<const char*>(&x[k]) + sizeof lo, sizeof hi);
    const F8 p = lo + hi;  // lanes l and l + 8
    F4 p_lo, p_hi;
    std::memcpy(&p_lo, &p, sizeof p_lo);
    std::memcpy(&p_hi, reinterpret_cast<const char*>(&p) + sizeof p_lo, sizeof p_hi);
    const F4 q = p_lo + p_hi;  // and l + 4
    out[k] = (q[0] + q[2]) + (q[1] + q[3]);
  }
  return load(out);
#else
  F16 a[8], b[4], c[2];
  for (int i = 0; i < 8; ++i)  // lanes l and l + 8; x[2i] in lanes 0-7, x[2i+1] in lanes 8-15
    a[i] = MESHTOUR_SHUFFLE(x[2 * i], x[2 * i + 1], 0, 1, 2, 3, 4, 5, 6, 7, 16, 17, 18, 19, 20, 21, 22, 23) +
           MESHTOUR_SHUFFLE(x[2 * i], x[2 * i + 1], 8, 9, 10, 11, 12, 13, 14, 15, 24, 25, 26, 27, 28, 29, 30, 31);
  for (int i = 0; i < 4; ++i)  // four partial sums per vector
    b[i] = MESHTOUR_SHUFFLE(a[2 * i], a[2 * i + 1], 0, 1, 2, 3, 8, 9, 10, 11, 16, 17, 18, 19, 24, 25, 26, 27) +
           MESHTOUR_SHUFFLE(a[2 * i], a[2 * i + 1], 4, 5, 6, 7, 12, 13, 14, 15, 20, 21, 22, 23, 28, 29, 30, 31);
  for (int i = 0; i < 2; ++i)  // two partial sums per vector
    c[i] = MESHTOUR_SHUFFLE(b[2 * i], b[2 * i + 1], 0, 1, 4, 5, 8, 9, 12, 13, 16, 17, 20, 21, 24, 25, 28, 29) +
           MESHTOUR_SHUFFLE(b[2 * i], b[2 * i + 1], 2, 3, 6, 7, 10, 11, 14, 15, 18, 19, 22, 23, 26, 27, 30, 31);
  return MESHTOUR_SHUFFLE(c[0], c[1], 0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30) +
         MESHTOUR_SHUFFLE(c[0], c[1], 1, 3, 5, 7, 9, 11, 13, 15, 17, 19, 21, 23, 25, 27, 29, 31);
#endif
}

/// A 32-bit integer hash with good avalanche ("lowbias32", C. Wellons 2018): the random numbers
/// of a sample are hashes of (frame, pixel, sample, dimension), computed 16 lanes at a time.
MESHTOUR_SIMD_INLINE U16 hash(U16 x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}
MESHTOUR_SIMD_INLINE constexpr std::uint32_t hash(std::uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

/// Two uniform numbers in (0, 1) from one hash: 16 bits each, the centres of 65536 bins. Samples
/// are stratified, so a number only places a sample inside its stratum, where 16 bits is far
/// finer than anything a pixel resolves.
MESHTOUR_SIMD_INLINE void uniform_pair(U16 h, F16& u, F16& v) {
  const I16 hi = reinterpret_cast<I16>(h >> 16), lo = reinterpret_cast<I16>(h & 0xffffU);
  u = (to_float(hi) + 0.5f) * 0x1.0p-16f;
  v = (to_float(lo) + 0.5f) * 0x1.0p-16f;
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
  const I16 bits = reinterpret_cast<I16>(x);
  const F16 k = to_float(((bits >> 23) & 0xff) - 127);
  const F16 m = reinterpret_cast<F16>((bits & 0x7fffff) | 0x3f800000);
  const F16 t = (m - 1.0f) / (m + 1.0f), t2 = t * t;
  const F16 atanh_t = t * (1.0f + t2 * (1.0f / 3 + t2 * (1.0f / 5 + t2 * (1.0f / 7 + t2 * (1.0f / 9 + t2 * (1.0f / 11))))));
  // <= 0; clamped where 2^y would no longer be a normal float (a highlight that small is 0 anyway).
  const F16 y = max(e * (k + (2.0f / std::numbers::ln2_v<float>)*atanh_t), broadcast(-126.0f));
  // exp2: y = n + f with n = floor(y), f in [0, 1); 2^f = sqrt 2 * e^((f - 1/2) ln 2).
  I16 n = to_int(y);
  n += gt(to_float(n), y);  // -1 where truncation rounded a negative value up
  const F16 g = (y - to_float(n) - 0.5f) * std::numbers::ln2_v<float>;
  const F16 e_g = 1.0f + g * (1.0f + g * (0.5f + g * (1.0f / 6 + g * (1.0f / 24 + g * (1.0f / 120 + g * (1.0f / 720))))));
  const F16 scale = reinterpret_cast<F16>((n + 127) << 23);
  return e_g * std::numbers::sqrt2_v<float> * scale;
}

}  // namespace meshtour::simd
