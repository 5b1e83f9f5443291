#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "job_util.h"
#include "rigel/ops/deform/skinning.h"
#include "skinning_kernels.h"

namespace rigel::ops {

bool LinearBlendSkinningJob::validate() const {
  if (skin == nullptr) return false;
  if (matrices.size() < skin->joint_count()) return false;
  return detail::vertex_spans_valid(*this, skin->vertex_count());
}

bool LinearBlendSkinningJob::run() const { return run(0, skin ? skin->vertex_count() : 0); }

bool LinearBlendSkinningJob::run(std::size_t begin, std::size_t end) const {
  if (!validate() || begin > end || end > skin->vertex_count()) return false;
  if (begin < end) detail::lbs_best_kernel()(*this, begin, end);
  return true;
}

bool LinearBlendSkinningJob::run_parallel(std::size_t grain) const {
  if (!validate()) return false;
  const detail::LbsKernel kernel = detail::lbs_best_kernel();
  const std::size_t count = skin->vertex_count();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, grain == 0 ? detail::kDefaultGrain : grain),
                    [&](const tbb::blocked_range<std::size_t>& range) { kernel(*this, range.begin(), range.end()); });
  return true;
}

namespace detail {

void lbs_portable(const LinearBlendSkinningJob& job, std::size_t begin, std::size_t end) {
  const Skin& skin = *job.skin;
  const float* matrices = job.matrices.data()->m;
  const float* in = job.in_positions.data()->data();
  float* out = job.out_positions.data()->data();
  const bool normals = !job.in_normals.empty();
  for (std::size_t v = begin; v < end; ++v) {
    const VertexInfluences influences = vertex_influences(skin, v);
    // Two accumulators, even and odd influences (the vector variants' order).
    float a[16] = {};
    float b[16] = {};
    std::size_t k = 0;
    for (; k + 1 < influences.count; k += 2) {
      const float* ma = matrices + 16 * std::size_t{influences.joints[k]};
      const float* mb = matrices + 16 * std::size_t{influences.joints[k + 1]};
      const float wa = influences.weights[k];
      const float wb = influences.weights[k + 1];
      for (int n = 0; n < 16; ++n) {
        a[n] += wa * ma[n];
        b[n] += wb * mb[n];
      }
    }
    if (k < influences.count) {
      const float* ma = matrices + 16 * std::size_t{influences.joints[k]};
      const float wa = influences.weights[k];
      for (int n = 0; n < 16; ++n) a[n] += wa * ma[n];
    }
    float m[16];
    for (int n = 0; n < 16; ++n) m[n] = a[n] + b[n];
    const float x = in[3 * v], y = in[3 * v + 1], z = in[3 * v + 2];
    for (int r = 0; r < 3; ++r) out[3 * v + r] = (m[r] * x + m[8 + r] * z) + (m[4 + r] * y + m[12 + r]);
    if (normals) skin_normal(m, job.in_normals[v].data(), job.out_normals[v].data());
  }
}

LbsKernel lbs_best_kernel() {
#if RIGEL_DEFORM_X86_KERNELS
  static const LbsKernel best = avx512_supported() ? lbs_avx512 : avx2_fma_supported() ? lbs_avx2_fma : lbs_portable;
  return best;
#else
  return lbs_portable;
#endif
}

const char* lbs_best_kernel_name() {
#if RIGEL_DEFORM_X86_KERNELS
  if (avx512_supported()) return "avx512";
  if (avx2_fma_supported()) return "avx2_fma";
#endif
  return "portable";
}

}  // namespace detail
}  // namespace rigel::ops
