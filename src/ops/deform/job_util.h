#pragma once
// Private to the deform jobs: checks their validate() functions share.

#include <cstdint>
#include <span>

namespace rigel::ops::detail {

// True when the two spans share a byte. Empty spans overlap nothing.
template <typename A, typename B>
bool overlaps(std::span<A> a, std::span<B> b) {
  if (a.empty() || b.empty()) return false;
  const auto a0 = reinterpret_cast<std::uintptr_t>(a.data());
  const auto b0 = reinterpret_cast<std::uintptr_t>(b.data());
  return a0 < b0 + b.size_bytes() && b0 < a0 + a.size_bytes();
}

// The vertex spans of a skinning job: positions of `count`, normals of
// `count` or none, outputs the size of their inputs, no output overlapping
// an input or the other output.
template <typename Job>
bool vertex_spans_valid(const Job& job, std::size_t count) {
  if (job.in_positions.size() != count || job.out_positions.size() != count) return false;
  if (!job.in_normals.empty() && job.in_normals.size() != count) return false;
  if (job.out_normals.size() != job.in_normals.size()) return false;
  return !overlaps(job.out_positions, job.in_positions) && !overlaps(job.out_positions, job.in_normals) &&
         !overlaps(job.out_normals, job.in_positions) && !overlaps(job.out_normals, job.in_normals) &&
         !overlaps(job.out_positions, job.out_normals);
}

// Default vertices per TBB task: large enough that a task's overhead
// (about a microsecond) is noise, small enough to balance two cores.
inline constexpr std::size_t kDefaultGrain = 8192;

}  // namespace rigel::ops::detail
