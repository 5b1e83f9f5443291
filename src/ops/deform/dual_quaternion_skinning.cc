#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <bit>
#include <cmath>
#include <cstdint>

#include "job_util.h"
#include "rigel/ops/deform/skinning.h"
#include "skinning_kernels.h"

namespace rigel::ops {
namespace {

namespace portable {
#include "dual_quaternion_skinning_kernel.inc"
}  // namespace portable

#if RIGEL_DEFORM_X86_KERNELS
// Everything defined in this region (the kernel templates, their lambdas) is
// compiled for AVX2 + FMA; it is only called where the CPU has both.
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2,fma"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2,fma")
#endif
namespace avx2_fma {
#include "dual_quaternion_skinning_kernel.inc"
}  // namespace avx2_fma
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
#endif

template <template <bool, bool> class Kernel>
void dqs_dispatch(const DualQuaternionSkinningJob& job, std::size_t begin, std::size_t end) {
  // The stretch phase is needed only if a joint the skin uses stretches;
  // checking every matrix is cheap (one per joint) and decides for the whole
  // job, so a vertex gives the same bits whatever range runs it.
  bool stretch = false;
  for (std::size_t j = 0; j < job.skin->joint_count(); ++j) stretch |= job.matrices[j].has_stretch;
  const bool normals = !job.in_normals.empty();
  if (stretch && normals)
    Kernel<true, true>::run(job, begin, end);
  else if (stretch)
    Kernel<true, false>::run(job, begin, end);
  else if (normals)
    Kernel<false, true>::run(job, begin, end);
  else
    Kernel<false, false>::run(job, begin, end);
}

void dqs_range(const DualQuaternionSkinningJob& job, std::size_t begin, std::size_t end) {
  detail::dqs_best_kernel()(job, begin, end);
}

}  // namespace

namespace detail {

void dqs_portable(const DualQuaternionSkinningJob& job, std::size_t begin, std::size_t end) {
  dqs_dispatch<portable::DqsKernel>(job, begin, end);
}

#if RIGEL_DEFORM_X86_KERNELS
void dqs_avx2_fma(const DualQuaternionSkinningJob& job, std::size_t begin, std::size_t end) {
  dqs_dispatch<avx2_fma::DqsKernel>(job, begin, end);
}
#endif

DqsKernel dqs_best_kernel() {
#if RIGEL_DEFORM_X86_KERNELS
  static const DqsKernel best = avx2_fma_supported() ? dqs_avx2_fma : dqs_portable;
  return best;
#else
  return dqs_portable;
#endif
}

}  // namespace detail

bool DualQuaternionSkinningJob::validate() const {
  if (skin == nullptr) return false;
  if (matrices.size() < skin->joint_count()) return false;
  return detail::vertex_spans_valid(*this, skin->vertex_count());
}

bool DualQuaternionSkinningJob::run() const { return run(0, skin ? skin->vertex_count() : 0); }

bool DualQuaternionSkinningJob::run(std::size_t begin, std::size_t end) const {
  if (!validate() || begin > end || end > skin->vertex_count()) return false;
  if (begin < end) dqs_range(*this, begin, end);
  return true;
}

bool DualQuaternionSkinningJob::run_parallel(std::size_t grain) const {
  if (!validate()) return false;
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, skin->vertex_count(), grain == 0 ? detail::kDefaultGrain : grain),
      [&](const tbb::blocked_range<std::size_t>& range) { dqs_range(*this, range.begin(), range.end()); });
  return true;
}

}  // namespace rigel::ops
