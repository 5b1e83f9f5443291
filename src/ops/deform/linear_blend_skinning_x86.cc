// The x86 vector variants of LinearBlendSkinningJob (see skinning_kernels.h).
//
// Both keep one vertex's blended matrix in registers as its four columns of
// four floats (the SkinMatrix layout, row 3 = 0), so each influence is one
// load and one fused multiply-add per 8 or 16 floats, with no gathers. The
// cost per vertex is dominated by those loads and FMAs (bench/deform_bench.cc
// has the figures: loading the four joint indices in one 64-bit read, rather
// than four 16-bit ones, took the AVX-512 loop from 200 to 170 us).
// Positions are read and written exactly (masked or per-float), never a
// float past the vertex range, so ranges run in parallel may touch.

// GCC 12 warns that the AVX-512 intrinsics' own "undefined" pass-through
// operand "may be used uninitialized" (GCC bug 105593, fixed in 13). The
// warning is attributed to the intrinsic headers, so it is silenced before
// anything includes them.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

#include "skinning_kernels.h"

#if RIGEL_DEFORM_X86_KERNELS

#include <immintrin.h>

#include <cstring>

#define RIGEL_AVX2 __attribute__((target("avx2,fma")))
#define RIGEL_AVX512 __attribute__((target("avx512f,avx512vl,avx512dq,avx2,fma")))
#define RIGEL_INLINE inline __attribute__((always_inline))

namespace rigel::ops::detail {
namespace {

// The four joints of a fixed-layout vertex from one 64-bit load: fewer loads
// is what made this loop faster (the load ports, not the FMAs, were busy).
RIGEL_INLINE void fixed_joints(const std::uint16_t* joints, std::size_t out[4]) {
  std::uint64_t packed;
  std::memcpy(&packed, joints, sizeof packed);
  out[0] = packed & 0xffff;
  out[1] = (packed >> 16) & 0xffff;
  out[2] = (packed >> 32) & 0xffff;
  out[3] = packed >> 48;
}

// ---- Normals, eight vertices per instruction --------------------------------

// Columns 0, 1 and 2 (rows 0-2; row 3 is ignored) of eight vertices'
// blended matrices, as registers: [vertex] of each column.
struct Columns8 {
  __m128 a[8], b[8], c[8];
};

// x y - z w, and the three-term dot product, with explicit fused operations, so that
// nothing is left for the compiler to fuse (or not) differently at each
// place this is inlined: a vertex's bits stay the same in a block and in
// the tail.
RIGEL_AVX2 RIGEL_INLINE __m256 cross_term(__m256 x, __m256 y, __m256 z, __m256 w) {
  return _mm256_fmsub_ps(x, y, _mm256_mul_ps(z, w));
}
RIGEL_AVX2 RIGEL_INLINE __m256 dot3(__m256 x0, __m256 y0, __m256 x1, __m256 y1, __m256 x2, __m256 y2) {
  return _mm256_fmadd_ps(x2, y2, _mm256_fmadd_ps(x1, y1, _mm256_mul_ps(x0, y0)));
}

// Rows 0, 1, 2 of column `col` (vertex v's in lane v): two in-lane 4x4
// transposes of the 128-bit columns, vertices 0-3 in the low half.
RIGEL_AVX2 RIGEL_INLINE void rows8(const __m128* col, __m256& r0, __m256& r1, __m256& r2) {
  __m256 p[4];
  for (int i = 0; i < 4; ++i) p[i] = _mm256_insertf128_ps(_mm256_castps128_ps256(col[i]), col[i + 4], 1);
  const __m256 t0 = _mm256_unpacklo_ps(p[0], p[1]), t1 = _mm256_unpacklo_ps(p[2], p[3]);
  const __m256 t2 = _mm256_unpackhi_ps(p[0], p[1]), t3 = _mm256_unpackhi_ps(p[2], p[3]);
  r0 = _mm256_shuffle_ps(t0, t1, _MM_SHUFFLE(1, 0, 1, 0));
  r1 = _mm256_shuffle_ps(t0, t1, _MM_SHUFFLE(3, 2, 3, 2));
  r2 = _mm256_shuffle_ps(t2, t3, _MM_SHUFFLE(1, 0, 1, 0));
}

// skin_normal's arithmetic on eight vertices at once, one per lane, in
// float with fused operations (skin_normal works in double: the two differ
// in the last bits): `m` their blended matrices, `nx` `ny` `nz` their
// normals, the results in place. Lanes do not mix.
RIGEL_AVX2 RIGEL_INLINE void normals8(const Columns8& m, __m256& nx, __m256& ny, __m256& nz) {
  __m256 a0, a1, a2, b0, b1, b2, c0, c1, c2;
  rows8(m.a, a0, a1, a2);
  rows8(m.b, b0, b1, b2);
  rows8(m.c, c0, c1, c2);
  // Columns of the cofactor matrix: b x c, c x a, a x b.
  const __m256 bc0 = cross_term(b1, c2, b2, c1), bc1 = cross_term(b2, c0, b0, c2), bc2 = cross_term(b0, c1, b1, c0);
  const __m256 ca0 = cross_term(c1, a2, c2, a1), ca1 = cross_term(c2, a0, c0, a2), ca2 = cross_term(c0, a1, c1, a0);
  const __m256 ab0 = cross_term(a1, b2, a2, b1), ab1 = cross_term(a2, b0, a0, b2), ab2 = cross_term(a0, b1, a1, b0);
  const __m256 x = dot3(bc0, nx, ca0, ny, ab0, nz);
  const __m256 y = dot3(bc1, nx, ca1, ny, ab1, nz);
  const __m256 z = dot3(bc2, nx, ca2, ny, ab2, nz);
  const __m256 det = dot3(a0, bc0, a1, bc1, a2, bc2);
  const __m256 length = _mm256_sqrt_ps(dot3(x, x, y, y, z, z));
  const __m256 zero = _mm256_setzero_ps();
  const __m256 sign =
      _mm256_blendv_ps(_mm256_set1_ps(1.0f), _mm256_set1_ps(-1.0f), _mm256_cmp_ps(det, zero, _CMP_LT_OQ));
  // A zero (or NaN) length scales by 0, as skin_normal does.
  const __m256 scale = _mm256_blendv_ps(zero, _mm256_div_ps(sign, length), _mm256_cmp_ps(length, zero, _CMP_GT_OQ));
  nx = _mm256_mul_ps(x, scale);
  ny = _mm256_mul_ps(y, scale);
  nz = _mm256_mul_ps(z, scale);
}

// Normals of vertices v .. v + 7 (24 floats in, 24 out): x y z of eight
// vertices to one register each and back, in-lane shuffles (vertices 0-3
// in the low half).
RIGEL_AVX2 RIGEL_INLINE void block_normals(const Columns8& m, const LinearBlendSkinningJob& job, std::size_t v) {
  const float* in = job.in_normals[v].data();
  const __m256 m03 = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(in)), _mm_loadu_ps(in + 12), 1);
  const __m256 m14 = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(in + 4)), _mm_loadu_ps(in + 16), 1);
  const __m256 m25 = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(in + 8)), _mm_loadu_ps(in + 20), 1);
  const __m256 xy = _mm256_shuffle_ps(m14, m25, _MM_SHUFFLE(2, 1, 3, 2));  // x2 y2 x3 y3
  const __m256 yz = _mm256_shuffle_ps(m03, m14, _MM_SHUFFLE(1, 0, 2, 1));  // y0 z0 y1 z1
  __m256 x = _mm256_shuffle_ps(m03, xy, _MM_SHUFFLE(2, 0, 3, 0));
  __m256 y = _mm256_shuffle_ps(yz, xy, _MM_SHUFFLE(3, 1, 2, 0));
  __m256 z = _mm256_shuffle_ps(yz, m25, _MM_SHUFFLE(3, 0, 3, 1));
  normals8(m, x, y, z);
  const __m256 rxy = _mm256_shuffle_ps(x, y, _MM_SHUFFLE(2, 0, 2, 0));  // x0 x2 y0 y2
  const __m256 ryz = _mm256_shuffle_ps(y, z, _MM_SHUFFLE(3, 1, 3, 1));  // y1 y3 z1 z3
  const __m256 rzx = _mm256_shuffle_ps(z, x, _MM_SHUFFLE(3, 1, 2, 0));  // z0 z2 x1 x3
  const __m256 r03 = _mm256_shuffle_ps(rxy, rzx, _MM_SHUFFLE(2, 0, 2, 0));
  const __m256 r14 = _mm256_shuffle_ps(ryz, rxy, _MM_SHUFFLE(3, 1, 2, 0));
  const __m256 r25 = _mm256_shuffle_ps(rzx, ryz, _MM_SHUFFLE(3, 1, 3, 1));
  float* out = job.out_normals[v].data();
  _mm_storeu_ps(out, _mm256_castps256_ps128(r03));
  _mm_storeu_ps(out + 4, _mm256_castps256_ps128(r14));
  _mm_storeu_ps(out + 8, _mm256_castps256_ps128(r25));
  _mm_storeu_ps(out + 12, _mm256_extractf128_ps(r03, 1));
  _mm_storeu_ps(out + 16, _mm256_extractf128_ps(r14, 1));
  _mm_storeu_ps(out + 20, _mm256_extractf128_ps(r25, 1));
}

// One vertex's normal: lane 0 of normals8, the other lanes zero.
RIGEL_AVX2 RIGEL_INLINE void single_normal(__m128 c0, __m128 c1, __m128 c2, const LinearBlendSkinningJob& job,
                                           std::size_t v) {
  Columns8 m;
  for (int i = 1; i < 8; ++i) m.a[i] = m.b[i] = m.c[i] = _mm_setzero_ps();
  m.a[0] = c0;
  m.b[0] = c1;
  m.c[0] = c2;
  const float* in = job.in_normals[v].data();
  __m256 x = _mm256_castps128_ps256(_mm_set_ss(in[0])), y = _mm256_castps128_ps256(_mm_set_ss(in[1])),
         z = _mm256_castps128_ps256(_mm_set_ss(in[2]));
  x = _mm256_insertf128_ps(x, _mm_setzero_ps(), 1);
  y = _mm256_insertf128_ps(y, _mm_setzero_ps(), 1);
  z = _mm256_insertf128_ps(z, _mm_setzero_ps(), 1);
  normals8(m, x, y, z);
  float* out = job.out_normals[v].data();
  out[0] = _mm256_cvtss_f32(x);
  out[1] = _mm256_cvtss_f32(y);
  out[2] = _mm256_cvtss_f32(z);
}

// ---- AVX2 + FMA: a matrix is two registers, [c0 | c1] and [c2 | c3] --------

struct Blend8 {
  __m256 lo;
  __m256 hi;
};

RIGEL_AVX2 RIGEL_INLINE void accumulate8(const float* matrix, float weight, __m256& lo, __m256& hi) {
  const __m256 w = _mm256_set1_ps(weight);
  lo = _mm256_fmadd_ps(w, _mm256_load_ps(matrix), lo);
  hi = _mm256_fmadd_ps(w, _mm256_load_ps(matrix + 8), hi);
}

template <bool kFixed>
RIGEL_AVX2 RIGEL_INLINE Blend8 blend8(const float* matrices, const Skin& skin, std::size_t v) {
  __m256 a_lo = _mm256_setzero_ps(), a_hi = _mm256_setzero_ps();
  __m256 b_lo = _mm256_setzero_ps(), b_hi = _mm256_setzero_ps();
  if constexpr (kFixed) {
    std::size_t j[4];
    fixed_joints(skin.fixed_joints().data() + 4 * v, j);
    const float* w = skin.fixed_weights().data() + 4 * v;
    accumulate8(matrices + 16 * j[0], w[0], a_lo, a_hi);
    accumulate8(matrices + 16 * j[1], w[1], b_lo, b_hi);
    accumulate8(matrices + 16 * j[2], w[2], a_lo, a_hi);
    accumulate8(matrices + 16 * j[3], w[3], b_lo, b_hi);
  } else {
    const std::uint32_t begin = skin.offsets()[v];
    const std::uint32_t end = skin.offsets()[v + 1];
    const std::uint16_t* j = skin.joints().data();
    const float* w = skin.weights().data();
    std::uint32_t k = begin;
    for (; k + 1 < end; k += 2) {
      accumulate8(matrices + 16 * std::size_t{j[k]}, w[k], a_lo, a_hi);
      accumulate8(matrices + 16 * std::size_t{j[k + 1]}, w[k + 1], b_lo, b_hi);
    }
    if (k < end) accumulate8(matrices + 16 * std::size_t{j[k]}, w[k], a_lo, a_hi);
  }
  return {_mm256_add_ps(a_lo, b_lo), _mm256_add_ps(a_hi, b_hi)};
}

// (c0 x + c2 z) + (c1 y + c3) as x' y' z' 0. The first sum is fused (one
// rounding): written out, as GCC would fuse a multiply and an add here
// anyway (C++ allows it), so the result does not depend on its mood.
RIGEL_AVX2 RIGEL_INLINE __m128 transform8(const Blend8& m, const float* p) {
  const __m256 xy = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_broadcast_ss(p)), _mm_broadcast_ss(p + 1), 1);
  const __m256 z1 = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_broadcast_ss(p + 2)), _mm_set1_ps(1.0f), 1);
  const __m256 sum = _mm256_fmadd_ps(m.lo, xy, _mm256_mul_ps(m.hi, z1));
  return _mm_add_ps(_mm256_castps256_ps128(sum), _mm256_extractf128_ps(sum, 1));
}

// Columns 0, 1, 2 of a blended matrix.
RIGEL_AVX2 RIGEL_INLINE __m128 column8(const Blend8& m, int k) {
  switch (k) {
    case 0: return _mm256_castps256_ps128(m.lo);
    case 1: return _mm256_extractf128_ps(m.lo, 1);
    default: return _mm256_castps256_ps128(m.hi);
  }
}

template <bool kFixed, bool kNormals>
RIGEL_AVX2 void lbs_avx2_impl(const LinearBlendSkinningJob& job, std::size_t begin, std::size_t end) {
  const Skin& skin = *job.skin;
  const float* matrices = job.matrices.data()->m;
  const float* in = job.in_positions.data()->data();
  float* out = job.out_positions.data()->data();
  std::size_t v = begin;
  // Four vertices at a time: their x y z 0 results packed into three stores;
  // with normals, eight (normals8's width).
  constexpr std::size_t kBlock = kNormals ? 8 : 4;
  for (; v + kBlock <= end; v += kBlock) {
    [[maybe_unused]] Columns8 columns;
    for (std::size_t h = 0; h < kBlock; h += 4) {
      const std::size_t u = v + h;
      __m128 r[4];
      for (std::size_t i = 0; i < 4; ++i) {
        const Blend8 m = blend8<kFixed>(matrices, skin, u + i);
        r[i] = transform8(m, in + 3 * (u + i));
        if constexpr (kNormals) {
          columns.a[h + i] = column8(m, 0);
          columns.b[h + i] = column8(m, 1);
          columns.c[h + i] = column8(m, 2);
        }
      }
      const __m128 x1 = _mm_shuffle_ps(r[1], r[1], _MM_SHUFFLE(0, 0, 0, 0));
      const __m128 first = _mm_blend_ps(r[0], x1, 0x8);                           // x0 y0 z0 x1
      const __m128 second = _mm_shuffle_ps(r[1], r[2], _MM_SHUFFLE(1, 0, 2, 1));  // y1 z1 x2 y2
      const __m128 z2x3 = _mm_shuffle_ps(r[2], r[3], _MM_SHUFFLE(0, 0, 2, 2));    // z2 z2 x3 x3
      const __m128 third = _mm_shuffle_ps(z2x3, r[3], _MM_SHUFFLE(2, 1, 2, 0));   // z2 x3 y3 z3
      _mm_storeu_ps(out + 3 * u, first);
      _mm_storeu_ps(out + 3 * u + 4, second);
      _mm_storeu_ps(out + 3 * u + 8, third);
    }
    if constexpr (kNormals) block_normals(columns, job, v);
  }
  for (; v < end; ++v) {
    const Blend8 m = blend8<kFixed>(matrices, skin, v);
    const __m128 r = transform8(m, in + 3 * v);
    _mm_storel_pi(reinterpret_cast<__m64*>(out + 3 * v), r);
    _mm_store_ss(out + 3 * v + 2, _mm_movehl_ps(r, r));
    if constexpr (kNormals) single_normal(column8(m, 0), column8(m, 1), column8(m, 2), job, v);
  }
}

// ---- AVX-512: a matrix is one register [c0 | c1 | c2 | c3] ------------------

RIGEL_AVX512 RIGEL_INLINE __m512 accumulate16(const float* matrix, float weight, __m512 sum) {
  return _mm512_fmadd_ps(_mm512_set1_ps(weight), _mm512_load_ps(matrix), sum);
}

template <bool kFixed>
RIGEL_AVX512 RIGEL_INLINE __m512 blend16(const float* matrices, const Skin& skin, std::size_t v) {
  __m512 a = _mm512_setzero_ps();
  __m512 b = _mm512_setzero_ps();
  if constexpr (kFixed) {
    std::size_t j[4];
    fixed_joints(skin.fixed_joints().data() + 4 * v, j);
    const float* w = skin.fixed_weights().data() + 4 * v;
    a = accumulate16(matrices + 16 * j[0], w[0], a);
    b = accumulate16(matrices + 16 * j[1], w[1], b);
    a = accumulate16(matrices + 16 * j[2], w[2], a);
    b = accumulate16(matrices + 16 * j[3], w[3], b);
  } else {
    const std::uint32_t begin = skin.offsets()[v];
    const std::uint32_t end = skin.offsets()[v + 1];
    const std::uint16_t* j = skin.joints().data();
    const float* w = skin.weights().data();
    std::uint32_t k = begin;
    for (; k + 1 < end; k += 2) {
      a = accumulate16(matrices + 16 * std::size_t{j[k]}, w[k], a);
      b = accumulate16(matrices + 16 * std::size_t{j[k + 1]}, w[k + 1], b);
    }
    if (k < end) a = accumulate16(matrices + 16 * std::size_t{j[k]}, w[k], a);
  }
  return _mm512_add_ps(a, b);
}

template <bool kFixed, bool kNormals>
RIGEL_AVX512 void lbs_avx512_impl(const LinearBlendSkinningJob& job, std::size_t begin, std::size_t end) {
  const Skin& skin = *job.skin;
  const float* matrices = job.matrices.data()->m;
  const float* in = job.in_positions.data()->data();
  float* out = job.out_positions.data()->data();
  const __m512 one = _mm512_set1_ps(1.0f);
  // Lane i of the 16 takes coordinate i / 4 of a point: x x x x y y y y z z z z (1 1 1 1).
  const __m512i spread = _mm512_set_epi32(3, 3, 3, 3, 2, 2, 2, 2, 1, 1, 1, 1, 0, 0, 0, 0);
  // x y z of four x y z 0 results into 12 consecutive floats.
  const __m512i pack = _mm512_set_epi32(15, 11, 7, 3, 14, 13, 12, 10, 9, 8, 6, 5, 4, 2, 1, 0);
  std::size_t v = begin;
  // Four vertices at a time; with normals, eight (normals8's width).
  constexpr std::size_t kBlock = kNormals ? 8 : 4;
  for (; v + kBlock <= end; v += kBlock) {
    [[maybe_unused]] Columns8 columns;
    for (std::size_t h = 0; h < kBlock; h += 4) {
      const std::size_t u = v + h;
      // Four points, 12 floats, in one masked load.
      const __m512 points = _mm512_maskz_loadu_ps(0x0fff, in + 3 * u);
      __m512 r[4];
      for (std::size_t i = 0; i < 4; ++i) {
        const __m512 m = blend16<kFixed>(matrices, skin, u + i);
        const __m512i lanes = _mm512_add_epi32(spread, _mm512_set1_epi32(3 * static_cast<int>(i)));
        const __m512 p = _mm512_mask_permutexvar_ps(one, 0x0fff, lanes, points);  // x x x x y y y y z z z z 1 1 1 1
        r[i] = _mm512_mul_ps(m, p);
        if constexpr (kNormals) {
          columns.a[h + i] = _mm512_castps512_ps128(m);
          columns.b[h + i] = _mm512_extractf32x4_ps(m, 1);
          columns.c[h + i] = _mm512_extractf32x4_ps(m, 2);
        }
      }
      // Sum each result's four columns, four vertices at once:
      // (c0 x + c2 z) + (c1 y + c3), each product rounded (the shuffles
      // between the multiply and the adds leave nothing to fuse), as in the
      // tail below.
      const __m512 t01 = _mm512_add_ps(_mm512_shuffle_f32x4(r[0], r[1], 0x44), _mm512_shuffle_f32x4(r[0], r[1], 0xEE));
      const __m512 t23 = _mm512_add_ps(_mm512_shuffle_f32x4(r[2], r[3], 0x44), _mm512_shuffle_f32x4(r[2], r[3], 0xEE));
      const __m512 s = _mm512_add_ps(_mm512_shuffle_f32x4(t01, t23, 0x88), _mm512_shuffle_f32x4(t01, t23, 0xDD));
      _mm512_mask_storeu_ps(out + 3 * u, 0x0fff, _mm512_permutexvar_ps(pack, s));
    }
    if constexpr (kNormals) block_normals(columns, job, v);
  }
  for (; v < end; ++v) {
    const __m512 m = blend16<kFixed>(matrices, skin, v);
    const __m512 point = _mm512_castps128_ps512(_mm_maskz_loadu_ps(0x7, in + 3 * v));
    const __m512 p = _mm512_mask_permutexvar_ps(one, 0x0fff, spread, point);
    const __m512 r = _mm512_mul_ps(m, p);
    const __m256 t = _mm256_add_ps(_mm512_castps512_ps256(r), _mm512_extractf32x8_ps(r, 1));
    const __m128 s = _mm_add_ps(_mm256_castps256_ps128(t), _mm256_extractf128_ps(t, 1));
    _mm_mask_storeu_ps(out + 3 * v, 0x7, s);
    if constexpr (kNormals)
      single_normal(_mm512_castps512_ps128(m), _mm512_extractf32x4_ps(m, 1), _mm512_extractf32x4_ps(m, 2), job, v);
  }
}

}  // namespace

void lbs_avx2_fma(const LinearBlendSkinningJob& job, std::size_t begin, std::size_t end) {
  const bool fixed = job.skin->has_fixed_layout();
  const bool normals = !job.in_normals.empty();
  if (fixed && !normals)
    lbs_avx2_impl<true, false>(job, begin, end);
  else if (fixed)
    lbs_avx2_impl<true, true>(job, begin, end);
  else if (!normals)
    lbs_avx2_impl<false, false>(job, begin, end);
  else
    lbs_avx2_impl<false, true>(job, begin, end);
}

void lbs_avx512(const LinearBlendSkinningJob& job, std::size_t begin, std::size_t end) {
  const bool fixed = job.skin->has_fixed_layout();
  const bool normals = !job.in_normals.empty();
  if (fixed && !normals)
    lbs_avx512_impl<true, false>(job, begin, end);
  else if (fixed)
    lbs_avx512_impl<true, true>(job, begin, end);
  else if (!normals)
    lbs_avx512_impl<false, false>(job, begin, end);
  else
    lbs_avx512_impl<false, true>(job, begin, end);
}

bool avx2_fma_supported() {
  static const bool supported = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  }();
  return supported;
}

bool avx512_supported() {
  static const bool supported = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
           __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  }();
  return supported;
}

}  // namespace rigel::ops::detail

#endif  // RIGEL_DEFORM_X86_KERNELS
