#pragma once
// eyelidBlink: an eyelid pair's turns about the lid axis (the eyelid
// component): each lid follows the eye's turn about that axis by a
// fraction, and a blink closes them until they meet.
//
//   pitch  = the eye's turn about `axis` since rest (the twist about it of
//            eyeMatrix's rotation times the inverse of eyeRestMatrix's, both
//            in the eye's parent's frame), degrees, in (-180, 180]
//   upper  = upperFollow * pitch + gap * (1 - blinkHeight) * blink
//   lower  = lowerFollow * pitch - gap * blinkHeight * blink
// so at blink 1 the upper lid has come down and the lower up by the `gap`
// between them, meeting at blinkHeight (0: at the lower lid, 1: at the
// upper). Turning about +axis closes the upper lid (about x for a face
// looking along +z, as glTF's).
//
// Inputs: eyeMatrix, eyeRestMatrix (matrix: the eye joint's local matrix,
// now and at rest), axis (double3, the eye's parent's frame), upperFollow,
// lowerFollow (keyable, 0..1), blink (keyable, 0..1), blinkHeight (keyable,
// 0..1), gap (keyable, degrees). Outputs: upperRotate, lowerRotate (double3:
// Euler XYZ degrees of the turns about axis), pitch (double, degrees).
// Values outside their range are clamped; a zero axis gives no turns.

#include "rigel/base/status.h"
#include "rigel/graph/node_type.h"
#include "rigel/math/types.h"

namespace rigel::ops::util {

inline constexpr const char* kEyelidBlinkType = "eyelidBlink";

namespace eyelid_attr {
enum : graph::AttrIndex {
  kEyeMatrix = 0,
  kEyeRestMatrix,
  kAxis,
  kUpperFollow,
  kLowerFollow,
  kBlink,
  kBlinkHeight,
  kGap,
  kUpperRotate,
  kLowerRotate,
  kPitch,
  kCount
};
}  // namespace eyelid_attr

// The eye's turn about `axis` (unit) from `rest` to `now`, degrees.
double twist_degrees(const math::Quat& rest, const math::Quat& now, const math::Vec3& axis);

// Adds eyelidBlink (called by register_util_types).
Status register_eyelid_types(graph::Registry& registry);

}  // namespace rigel::ops::util
