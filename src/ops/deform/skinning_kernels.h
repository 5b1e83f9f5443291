#pragma once
// Private to rigel_ops (and the deform tests): the instruction-set variants
// behind LinearBlendSkinningJob, and helpers every variant shares. Each
// variant skins vertices [begin, end) of a job that passed validate(); the
// job picks the fastest one the CPU supports. Declared here so the tests can
// check every variant the test machine can run, not only the one picked.
//
// Every variant blends in the same order: two accumulators, even and odd
// influences, then their sum; then (c0 x + c2 z) + (c1 y + c3). The vector
// variants blend with fused multiply-adds (AVX2 also fuses c0 x + c2 z), the
// portable one rounds every product, so the three differ in the last bits.
// Within one variant a vertex gives the same bits whatever range runs it, and
// the fixed 4-influence layout gives the general layout's values (its
// padding adds 0 x a matrix).

#include <cmath>
#include <cstddef>

#include "rigel/ops/deform/skinning.h"

#if (defined(__x86_64__) || defined(_M_X64)) && (defined(__GNUC__) || defined(__clang__))
// Vector code is compiled per function (target attribute) and chosen at run
// time, so the build needs no -m flags.
#define RIGEL_DEFORM_X86_KERNELS 1
#else
#define RIGEL_DEFORM_X86_KERNELS 0
#endif

namespace rigel::ops::detail {

static_assert(sizeof(SkinMatrix) == 16 * sizeof(float), "SkinMatrix is one 64-byte line");

// Plain C++: any CPU.
void lbs_portable(const LinearBlendSkinningJob& job, std::size_t begin, std::size_t end);
#if RIGEL_DEFORM_X86_KERNELS
// Only where avx2_fma_supported().
void lbs_avx2_fma(const LinearBlendSkinningJob& job, std::size_t begin, std::size_t end);
// Only where avx512_supported() (AVX-512 F, VL, DQ).
void lbs_avx512(const LinearBlendSkinningJob& job, std::size_t begin, std::size_t end);
bool avx2_fma_supported();
bool avx512_supported();
#endif

// The variant LinearBlendSkinningJob::run() uses on this CPU.
using LbsKernel = void (*)(const LinearBlendSkinningJob&, std::size_t, std::size_t);
LbsKernel lbs_best_kernel();
const char* lbs_best_kernel_name();

// The variants behind DualQuaternionSkinningJob: the same C++ compiled
// plainly and for AVX2 + FMA (fused multiply-adds, vectorised four-wide
// loops), so they differ in the last bits.
void dqs_portable(const DualQuaternionSkinningJob& job, std::size_t begin, std::size_t end);
#if RIGEL_DEFORM_X86_KERNELS
void dqs_avx2_fma(const DualQuaternionSkinningJob& job, std::size_t begin, std::size_t end);
#endif
using DqsKernel = void (*)(const DualQuaternionSkinningJob&, std::size_t, std::size_t);
DqsKernel dqs_best_kernel();

// Normal through the blended matrix m (SkinMatrix layout): the cofactor
// matrix of its 3x3 (the inverse transpose times the determinant) with the
// determinant's sign, normalised; zero stays zero. In double, one vertex at
// a time: the portable variant's. The vector variants do the same
// arithmetic in float, eight vertices per instruction (normals8 in
// linear_blend_skinning_x86.cc), so they differ from it in the last bits.
inline void skin_normal(const float* m, const float* n, float* out) {
  const double a0 = m[0], a1 = m[1], a2 = m[2];
  const double b0 = m[4], b1 = m[5], b2 = m[6];
  const double c0 = m[8], c1 = m[9], c2 = m[10];
  // Columns of the cofactor matrix: b x c, c x a, a x b.
  const double bc0 = b1 * c2 - b2 * c1, bc1 = b2 * c0 - b0 * c2, bc2 = b0 * c1 - b1 * c0;
  const double ca0 = c1 * a2 - c2 * a1, ca1 = c2 * a0 - c0 * a2, ca2 = c0 * a1 - c1 * a0;
  const double ab0 = a1 * b2 - a2 * b1, ab1 = a2 * b0 - a0 * b2, ab2 = a0 * b1 - a1 * b0;
  const double nx = n[0], ny = n[1], nz = n[2];
  double x = bc0 * nx + ca0 * ny + ab0 * nz;
  double y = bc1 * nx + ca1 * ny + ab1 * nz;
  double z = bc2 * nx + ca2 * ny + ab2 * nz;
  const double det = a0 * bc0 + a1 * bc1 + a2 * bc2;
  const double length = std::sqrt(x * x + y * y + z * z);
  const double scale = length > 0.0 ? (det < 0.0 ? -1.0 : 1.0) / length : 0.0;
  out[0] = static_cast<float>(x * scale);
  out[1] = static_cast<float>(y * scale);
  out[2] = static_cast<float>(z * scale);
}

// Influences of vertex v: joints, weights, count (the fixed layout when the
// skin has one).
struct VertexInfluences {
  const std::uint16_t* joints;
  const float* weights;
  std::size_t count;
};
inline VertexInfluences vertex_influences(const Skin& skin, std::size_t v) {
  if (skin.has_fixed_layout()) {
    return {skin.fixed_joints().data() + v * kFixedInfluences, skin.fixed_weights().data() + v * kFixedInfluences,
            kFixedInfluences};
  }
  const std::uint32_t begin = skin.offsets()[v];
  return {skin.joints().data() + begin, skin.weights().data() + begin, skin.offsets()[v + 1] - begin};
}

}  // namespace rigel::ops::detail
