#pragma once
// reverseFoot: the pivot chain of a reverse foot (the heel / toe / bank /
// ball roll of Maya auto-rigs and Luna's FootComponent, seed 004 §4.8) as
// matrices, without a transform per pivot, with ReverseFootJob
// (reverse_foot.h, where the maths is). It holds the keyable values a foot
// control's roll attributes stand for (node types have fixed attributes, so
// the values live here, not on the control) and writes the world matrices
// the ankle and the ball (toe) joint take in IK.
//
// Inputs:
//   roll, bank, heelTwist, toeTwist, ballTwist, toeTap
//                     double   keyable, angle (degrees)
//   rollBreak         double   keyable, angle: where the ball hands over to
//                              the toe (default 30; below 0 counts as 0)
//   controlMatrix     matrix   the foot control's worldMatrix
//   heelPivot, toePivot, ballPivot, innerPivot, outerPivot
//                     double3  the pivots (control space)
//   rollAxis, bankAxis, twistAxis
//                     double3  the axes (control space; normalized here;
//                              default x, -z, y)
//   restAnkleMatrix, restBallMatrix
//                     matrix   the ankle's and ball joint's world matrices
//                              at rest, in control space
//                              (controlMatrix_rest^-1 * world_rest)
// Outputs: outAnkleMatrix, outBallMatrix (matrix), error (hidden string).
// A value, pivot or axis that is not finite, or an axis of zero length,
// gives controlMatrix * rest for both outputs and names the attribute in
// `error`.

#include "rigel/base/status.h"
#include "rigel/graph/node_type.h"
#include "rigel/math/types.h"
#include "rigel/ops/util/reverse_foot.h"

namespace rigel::ops::util {

inline constexpr const char* kReverseFootType = "reverseFoot";

namespace reverse_foot_attr {
enum : graph::AttrIndex {
  kRoll = 0,
  kRollBreak,
  kBank,
  kHeelTwist,
  kToeTwist,
  kBallTwist,
  kToeTap,
  kControlMatrix,
  kHeelPivot,
  kToePivot,
  kBallPivot,
  kInnerPivot,
  kOuterPivot,
  kRollAxis,
  kBankAxis,
  kTwistAxis,
  kRestAnkleMatrix,
  kRestBallMatrix,
  kOutAnkleMatrix,
  kOutBallMatrix,
  kError,
  kCount
};
}  // namespace reverse_foot_attr

// Adds reverseFoot (called by register_util_types).
Status register_foot_types(graph::Registry& registry);

}  // namespace rigel::ops::util
