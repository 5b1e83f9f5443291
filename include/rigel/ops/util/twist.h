#pragma once
// twistShare: the share of a joint's twist that twist joints between it and
// its parent-side joint take (Luna's twist component, seed 004 §4.8).
//
//   D     = (R(startMatrix)^-1 * R(endMatrix)) * restRelative^-1
//           the end's turn relative to the start since rest, in the start's
//           frame (R: the rotation of a world matrix, scale removed)
//   twist = the swing-twist decomposition of D about `axis` (the start
//           joint's bone axis): D = swing * twist, twist about `axis`,
//           angle in (-180, 180]
//   outRotations[i] = rotation about `axis` by twist * (i + 1) / (count + 1),
//           i in [0, count): connect to twist joint i's rotateQuaternion
//
// Inputs: startMatrix, endMatrix (matrix), restRelative (quat: the end's
// rotation relative to the start at rest), axis (enum x y z), count (int,
// 0..1024). Outputs: outRotations (quat[]), twist (double, degrees),
// error (hidden string). Non-finite or singular matrices give identity
// rotations and say so in `error`.

#include "rigel/base/status.h"
#include "rigel/graph/node_type.h"
#include "rigel/math/types.h"

namespace rigel::ops::util {

inline constexpr const char* kTwistShareType = "twistShare";

namespace twist_attr {
enum : graph::AttrIndex { kStartMatrix = 0, kEndMatrix, kRestRelative, kAxis, kCount, kOutRotations, kTwist, kError };
}  // namespace twist_attr

// The twist angle (radians, in (-pi, pi]) of `q` about the unit `axis`.
double twist_angle(const math::Quat& q, const math::Vec3& axis);

// Adds twistShare (called by register_util_types).
Status register_twist_types(graph::Registry& registry);

}  // namespace rigel::ops::util
