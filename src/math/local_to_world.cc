#include "rigel/math/local_to_world.h"

#include <cstddef>

#include "local_to_world_kernels.h"

#if RIGEL_MATH_X86_KERNELS
#include <immintrin.h>
#endif

// All variants exploit that the matrices are affine: only the 3x4 part of
// each product is computed (the local's last row is not read; it is taken to
// be 0 0 0 1) and the last row of every world matrix is written as exactly
// 0 0 0 1. The x86 variants also keep the most recent world matrix in
// registers: when a joint's parent is the joint just before it (every link of
// a chain), it is used from there instead of being reloaded right after its
// store.

namespace rigel::math {
namespace {

bool is_affine(const Mat4& m) { return m(3, 0) == 0.0 && m(3, 1) == 0.0 && m(3, 2) == 0.0 && m(3, 3) == 1.0; }

}  // namespace

bool LocalToWorldJob::validate() const {
  const std::size_t count = parents.size();
  if (local.size() != count || world.size() != count) return false;
  const std::int32_t* parent = parents.data();
  for (std::size_t i = 0; i < count; ++i) {
    // Unsigned compare: kNoParent is fine; any other negative index wraps to
    // a huge value and fails, as does a parent at or after its child.
    if (parent[i] != kNoParent && static_cast<std::uint64_t>(static_cast<std::int64_t>(parent[i])) >= i) {
      return false;
    }
  }
  return is_affine(root);
}

bool LocalToWorldJob::run() const {
  if (!validate()) return false;
#if RIGEL_MATH_X86_KERNELS
  if (detail::avx2_fma_supported()) {
    detail::local_to_world_avx2_fma(*this);
  } else {
    detail::local_to_world_sse2(*this);
  }
#else
  detail::local_to_world_portable(*this);
#endif
  return true;
}

namespace detail {

void local_to_world_portable(const LocalToWorldJob& job) {
  const std::size_t count = job.parents.size();
  const std::int32_t* parent = job.parents.data();
  const Mat4* local = job.local.data();
  Mat4* world = job.world.data();
  for (std::size_t i = 0; i < count; ++i) {
    const double* pw = (parent[i] == kNoParent ? job.root : world[static_cast<std::size_t>(parent[i])]).data();
    const double* lm = local[i].data();
    // Rows 0..2 of each column, packed: [0..2] x axis, [3..5] y axis,
    // [6..8] z axis, [9..11] translation (index n + n / 3 skips each row 3).
    // Everything is read before anything is stored, so the compiler need not
    // assume a store into world[i] changes the parent.
    double p[12];
    double l[12];
    for (int n = 0; n < 12; ++n) p[n] = pw[n + n / 3];
    for (int n = 0; n < 12; ++n) l[n] = lm[n + n / 3];
    double r[12];
    for (int c = 0; c < 4; ++c) {
      for (int row = 0; row < 3; ++row) {
        r[3 * c + row] = p[row] * l[3 * c] + p[3 + row] * l[3 * c + 1] + p[6 + row] * l[3 * c + 2];
      }
    }
    for (int row = 0; row < 3; ++row) r[9 + row] += p[9 + row];
    double* out = world[i].data();
    for (int c = 0; c < 4; ++c) {
      out[4 * c + 0] = r[3 * c + 0];
      out[4 * c + 1] = r[3 * c + 1];
      out[4 * c + 2] = r[3 * c + 2];
      out[4 * c + 3] = c == 3 ? 1.0 : 0.0;
    }
  }
}

#if RIGEL_MATH_X86_KERNELS

void local_to_world_sse2(const LocalToWorldJob& job) {
  const std::size_t count = job.parents.size();
  const std::int32_t* parent = job.parents.data();
  const Mat4* local = job.local.data();
  Mat4* world = job.world.data();
  const double* root = job.root.data();
  const __m128d zero = _mm_setzero_pd();
  const __m128d one = _mm_set_sd(1.0);

  // The parent in registers: column c has rows 0-1 in half[2c], rows 2-3 in
  // half[2c + 1]. Seeded with the root, so joint 0 (parent kNoParent, which
  // is 0 - 1) takes the "parent just before" path.
  __m128d half[8];
  for (int n = 0; n < 8; ++n) half[n] = _mm_loadu_pd(root + 2 * n);

  for (std::size_t i = 0; i < count; ++i) {
    const std::int32_t p = parent[i];
    if (p != static_cast<std::int64_t>(i) - 1) {
      const double* source = p == kNoParent ? root : world[static_cast<std::size_t>(p)].data();
      for (int n = 0; n < 8; ++n) half[n] = _mm_loadu_pd(source + 2 * n);
    }
    const double* l = local[i].data();
    double* out = world[i].data();
    __m128d result[8];
    for (int c = 0; c < 4; ++c) {
      const __m128d x = _mm_set1_pd(l[4 * c + 0]);
      const __m128d y = _mm_set1_pd(l[4 * c + 1]);
      const __m128d z = _mm_set1_pd(l[4 * c + 2]);
      __m128d top_z = _mm_mul_pd(half[4], z);
      __m128d bottom_z = _mm_mul_pd(half[5], z);
      if (c == 3) {
        top_z = _mm_add_pd(top_z, half[6]);
        bottom_z = _mm_add_pd(bottom_z, half[7]);
      }
      const __m128d top = _mm_add_pd(_mm_add_pd(_mm_mul_pd(half[0], x), _mm_mul_pd(half[2], y)), top_z);
      const __m128d bottom = _mm_add_pd(_mm_add_pd(_mm_mul_pd(half[1], x), _mm_mul_pd(half[3], y)), bottom_z);
      result[2 * c] = top;
      // Row 3: row 2 stays in the low lane, the high lane becomes exactly 0
      // (1 for the translation) rather than trusting 0 * x to be +0.
      result[2 * c + 1] = _mm_unpacklo_pd(bottom, c == 3 ? one : zero);
    }
    for (int n = 0; n < 8; ++n) {
      _mm_storeu_pd(out + 2 * n, result[n]);
      half[n] = result[n];
    }
  }
}

// The same with one 4-double register per column: a third of the
// instructions of the SSE2 variant.
__attribute__((target("avx2,fma"))) void local_to_world_avx2_fma(const LocalToWorldJob& job) {
  const std::size_t count = job.parents.size();
  const std::int32_t* parent = job.parents.data();
  const Mat4* local = job.local.data();
  Mat4* world = job.world.data();
  const double* root = job.root.data();
  const __m256d zero = _mm256_setzero_pd();
  const __m256d one = _mm256_set1_pd(1.0);

  __m256d column[4];  // the parent, seeded with the root as in the SSE2 variant
  for (int c = 0; c < 4; ++c) column[c] = _mm256_loadu_pd(root + 4 * c);

  for (std::size_t i = 0; i < count; ++i) {
    const std::int32_t p = parent[i];
    if (p != static_cast<std::int64_t>(i) - 1) {
      const double* source = p == kNoParent ? root : world[static_cast<std::size_t>(p)].data();
      for (int c = 0; c < 4; ++c) column[c] = _mm256_loadu_pd(source + 4 * c);
    }
    const double* l = local[i].data();
    double* out = world[i].data();
    __m256d result[4];
    for (int c = 0; c < 4; ++c) {
      const __m256d x = _mm256_broadcast_sd(l + 4 * c + 0);
      const __m256d y = _mm256_broadcast_sd(l + 4 * c + 1);
      const __m256d z = _mm256_broadcast_sd(l + 4 * c + 2);
      // Two independent halves, summed last: a shorter dependency chain.
      const __m256d xz = _mm256_fmadd_pd(column[2], z, _mm256_mul_pd(column[0], x));
      const __m256d y_t = c == 3 ? _mm256_fmadd_pd(column[1], y, column[3]) : _mm256_mul_pd(column[1], y);
      // Lane 3 is row 3: exactly 0, or 1 for the translation.
      result[c] = _mm256_blend_pd(_mm256_add_pd(xz, y_t), c == 3 ? one : zero, 0x8);
    }
    for (int c = 0; c < 4; ++c) {
      _mm256_storeu_pd(out + 4 * c, result[c]);
      column[c] = result[c];
    }
  }
}

bool avx2_fma_supported() {
  static const bool supported = [] {
    __builtin_cpu_init();  // in case this runs before libgcc's own initialiser
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  }();
  return supported;
}

#endif  // RIGEL_MATH_X86_KERNELS

}  // namespace detail
}  // namespace rigel::math
