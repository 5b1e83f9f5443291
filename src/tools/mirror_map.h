#pragma once
// How mirroring relates the two sides of a built rig (mirror.h): with M
// the reflection in the mirror plane and K = rest_a^-1 * M * rest_b (the
// rests: rig::rest_world, the world matrices recorded at build), control b
// takes K^-1 * C_a * K of control a's channel matrix C_a. Shared by mirror
// (mirror.cc) and the pose library's mirrored apply (poses.cc). Internal
// to the tools layer.
#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/math/types.h"
#include "rigel/tools/mirror.h"

namespace rigel::tools::internal {

// The reflection in `plane` (it negates one world axis).
math::Mat4 reflection(MirrorPlane plane);

struct MirrorMap {
  math::Mat4 k, k_inverse;
  // b's channel matrix for a's.
  math::Mat4 operator()(const math::Mat4& channels_a) const { return k_inverse * channels_a * k; }
};

// The map from `source`'s channels to `target`'s. kFailedPrecondition
// naming "controls" (`what` in front) for a control without a recorded
// rest (built before rigel recorded it: a rebuild records it).
Result<MirrorMap> mirror_map(const graph::Graph& g, graph::NodeId source, graph::NodeId target,
                             const math::Mat4& reflection, const char* what);

}  // namespace rigel::tools::internal
