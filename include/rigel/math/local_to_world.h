#pragma once
// Compiled local-to-world: the inner loop of skeleton evaluation, shaped as a
// job (STYLE.md §3): spans in, spans out, no allocation.

#include <cstdint>
#include <span>

#include "rigel/math/types.h"

namespace rigel::math {

inline constexpr std::int32_t kNoParent = -1;

struct LocalToWorldJob {
  // Validates job parameters. Returns false:
  // - if `parents`, `local` or `world` sizes differ, or any is empty while
  //   another is not;
  // - if a parent index is not kNoParent and not in [0, own index)
  //   (parents must come before children; other negative indices are
  //   rejected too, as they would index outside `world`);
  // - if `root` is not the identity and is not affine (last row 0 0 0 1).
  bool validate() const;
  // world[i] = (parents[i] == kNoParent ? root : world[parents[i]]) * local[i].
  // Returns false if the job is not valid.
  bool run() const;

  // Parent index of each joint, parents before children.
  std::span<const std::int32_t> parents;
  // Local matrices (affine), in parent space.
  std::span<const Mat4> local;
  // Output world matrices (affine), in the space of `root`.
  std::span<Mat4> world;
  // Matrix applied above every root joint.
  Mat4 root = Mat4::Identity();
};

}  // namespace rigel::math
