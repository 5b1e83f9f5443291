#pragma once
// twistShare: the share of a joint's twist that twist joints between it and
// its parent-side joint take, with TwistShareJob (twist_share.h, where the
// maths is): outRotations[i] is twist joint i's rotateQuaternion, `twist`
// the end's whole twist about `axis`.
//
// Inputs: startMatrix, endMatrix (matrix), restRelative (quat: the end's
// rotation relative to the start at rest), axis (enum x y z), count (int,
// 0..1024). Outputs: outRotations (quat[]), twist (double, degrees),
// error (hidden string). Non-finite or singular matrices give identity
// rotations and say so in `error`.

#include "rigel/base/status.h"
#include "rigel/graph/node_type.h"
#include "rigel/math/types.h"
#include "rigel/ops/util/twist_share.h"

namespace rigel::ops::util {

inline constexpr const char* kTwistShareType = "twistShare";

namespace twist_attr {
enum : graph::AttrIndex { kStartMatrix = 0, kEndMatrix, kRestRelative, kAxis, kCount, kOutRotations, kTwist, kError };
}  // namespace twist_attr

// Adds twistShare (called by register_util_types).
Status register_twist_types(graph::Registry& registry);

}  // namespace rigel::ops::util
