#include "rigel/ops/deform/blend_shape.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <string>

#include "job_util.h"

namespace rigel::ops {

BlendShapeTargets::Target BlendShapeTargets::target(std::size_t t) const {
  const Range& r = targets_[t];
  Target out;
  out.dense = r.dense;
  out.deltas = std::span<const Vec3f>(deltas_).subspan(r.delta_begin, r.count);
  if (!r.dense) out.indices = std::span<const std::uint32_t>(indices_).subspan(r.index_begin, r.count);
  return out;
}

BlendShapeBuilder& BlendShapeBuilder::add_dense_target(std::span<const Vec3f> deltas) {
  pending_.push_back({true, {}, std::vector<Vec3f>(deltas.begin(), deltas.end())});
  return *this;
}

BlendShapeBuilder& BlendShapeBuilder::add_sparse_target(std::span<const std::int64_t> indices,
                                                        std::span<const Vec3f> deltas) {
  pending_.push_back({false, std::vector<std::int64_t>(indices.begin(), indices.end()),
                      std::vector<Vec3f>(deltas.begin(), deltas.end())});
  return *this;
}

Result<BlendShapeTargets> BlendShapeBuilder::build() const {
  auto fail = [](std::size_t t, const std::string& what) {
    return Status(ErrorCode::kInvalidArgument, "blend shape target " + std::to_string(t) + ": " + what);
  };
  if (vertex_count_ > std::numeric_limits<std::uint32_t>::max()) {
    return Status(ErrorCode::kInvalidArgument, "blend shapes support at most 2^32 - 1 vertices");
  }
  BlendShapeTargets out;
  out.vertex_count_ = vertex_count_;
  std::vector<std::uint32_t> order;
  std::vector<std::uint8_t> seen;
  for (std::size_t t = 0; t < pending_.size(); ++t) {
    const Pending& p = pending_[t];
    if (p.dense && p.deltas.size() != vertex_count_) {
      return fail(t, "a dense target needs one delta per vertex (" + std::to_string(vertex_count_) + "), not " +
                         std::to_string(p.deltas.size()));
    }
    if (!p.dense && p.indices.size() != p.deltas.size()) {
      return fail(t, std::to_string(p.indices.size()) + " indices but " + std::to_string(p.deltas.size()) + " deltas");
    }
    // (vertex, delta) pairs, validated, zero deltas dropped.
    order.clear();
    if (!p.dense) seen.assign(vertex_count_, 0);
    for (std::size_t i = 0; i < p.deltas.size(); ++i) {
      const std::int64_t vertex = p.dense ? static_cast<std::int64_t>(i) : p.indices[i];
      if (!p.dense) {
        if (vertex < 0 || static_cast<std::uint64_t>(vertex) >= vertex_count_) {
          return fail(t, "vertex index " + std::to_string(vertex) + " is out of range (the mesh has " +
                             std::to_string(vertex_count_) + " vertices)");
        }
        if (seen[static_cast<std::size_t>(vertex)])
          return fail(t, "vertex " + std::to_string(vertex) + " is listed twice");
        seen[static_cast<std::size_t>(vertex)] = 1;
      }
      if (!p.deltas[i].allFinite()) {
        return fail(t, "the delta of vertex " + std::to_string(vertex) + " is not finite");
      }
      if (p.deltas[i] != Vec3f::Zero()) order.push_back(static_cast<std::uint32_t>(i));
    }
    BlendShapeTargets::Range range;
    range.delta_begin = out.deltas_.size();
    range.index_begin = out.indices_.size();
    range.dense =
        static_cast<double>(order.size()) >= sparse_below * static_cast<double>(vertex_count_) && !order.empty();
    if (range.dense) {
      const std::size_t count = vertex_count_;
      range.count = count;
      out.deltas_.resize(out.deltas_.size() + count, Vec3f::Zero());
      for (std::uint32_t i : order) {
        const auto vertex = static_cast<std::size_t>(p.dense ? i : p.indices[i]);
        out.deltas_[range.delta_begin + vertex] = p.deltas[i];
      }
    } else {
      auto vertex_of = [&](std::uint32_t i) { return p.dense ? std::int64_t{i} : p.indices[i]; };
      std::sort(order.begin(), order.end(),
                [&](std::uint32_t a, std::uint32_t b) { return vertex_of(a) < vertex_of(b); });
      range.count = order.size();
      for (std::uint32_t i : order) {
        out.indices_.push_back(static_cast<std::uint32_t>(vertex_of(i)));
        out.deltas_.push_back(p.deltas[i]);
      }
    }
    out.targets_.push_back(range);
  }
  return out;
}

namespace {

void blend_range(const BlendShapeJob& job, std::size_t begin, std::size_t end) {
  float* out = job.out.data()->data();
  if (job.out.data() != job.base.data()) {
    std::memcpy(out + 3 * begin, job.base.data()->data() + 3 * begin, 3 * (end - begin) * sizeof(float));
  }
  for (std::size_t t = 0; t < job.targets->target_count(); ++t) {
    const float w = job.weights[t];
    if (w == 0.0f) continue;
    const BlendShapeTargets::Target target = job.targets->target(t);
    if (target.deltas.empty()) continue;
    const float* delta = target.deltas.data()->data();
    if (target.dense) {
      // A flat float loop the compiler vectorises.
      for (std::size_t i = 3 * begin; i < 3 * end; ++i) out[i] += w * delta[i];
    } else {
      const std::uint32_t* first = target.indices.data();
      const std::uint32_t* last = first + target.indices.size();
      const std::uint32_t* lo = begin == 0 ? first : std::lower_bound(first, last, static_cast<std::uint32_t>(begin));
      const std::uint32_t* hi = std::lower_bound(lo, last, static_cast<std::uint32_t>(end));
      for (const std::uint32_t* i = lo; i < hi; ++i) {
        const std::size_t at = std::size_t{*i} * 3;
        const std::size_t from = static_cast<std::size_t>(i - first) * 3;
        out[at] += w * delta[from];
        out[at + 1] += w * delta[from + 1];
        out[at + 2] += w * delta[from + 2];
      }
    }
  }
}

}  // namespace

bool BlendShapeJob::validate() const {
  if (targets == nullptr) return false;
  if (base.size() != targets->vertex_count() || out.size() != targets->vertex_count()) return false;
  if (weights.size() != targets->target_count()) return false;
  for (float w : weights) {
    if (!std::isfinite(w)) return false;
  }
  return !detail::overlaps(out, base) || out.data() == base.data();
}

bool BlendShapeJob::run() const { return run(0, targets ? targets->vertex_count() : 0); }

bool BlendShapeJob::run(std::size_t begin, std::size_t end) const {
  if (!validate() || begin > end || end > targets->vertex_count()) return false;
  if (begin < end) blend_range(*this, begin, end);
  return true;
}

bool BlendShapeJob::run_parallel(std::size_t grain) const {
  if (!validate()) return false;
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, targets->vertex_count(), grain == 0 ? detail::kDefaultGrain : grain),
      [&](const tbb::blocked_range<std::size_t>& range) { blend_range(*this, range.begin(), range.end()); });
  return true;
}

}  // namespace rigel::ops
