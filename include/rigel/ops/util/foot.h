#pragma once
// reverseFoot: the pivot chain of a reverse foot (the heel / toe / bank /
// ball roll of Maya auto-rigs and Luna's FootComponent, seed 004 §4.8) as
// matrices, without a transform per pivot. It holds the keyable values a
// foot control's roll attributes stand for (node types have fixed
// attributes, so the values live here, not on the control) and writes the
// world matrices the ankle and the ball (toe) joint take in IK.
//
// Every point and axis is in the space of controlMatrix at rest (the foot
// control's space: rig::components foot makes it x = roll axis, y = up,
// z = forward, so the defaults fit a foot whose outer edge is toward +x).
// piv(p, axis, t) is the rotation by t degrees about the line through p
// along the unit `axis` (right-hand rule): T(p) * R(axis, t) * T(-p), the
// identity when t is 0. With the values in degrees:
//
//   heelRoll = min(roll, 0)
//   ballRoll = clamp(roll, 0, b)       b = max(rollBreak, 0)
//   toeRoll  = max(roll - b, 0)
//   H    = piv(heelPivot, twistAxis, heelTwist) * piv(heelPivot, rollAxis, heelRoll)
//   T    = piv(toePivot,  twistAxis, toeTwist)  * piv(toePivot,  rollAxis, toeRoll)
//   B    = piv(bank > 0 ? outerPivot : innerPivot, bankAxis, bank)
//   L    = piv(ballPivot, twistAxis, ballTwist) * piv(ballPivot, rollAxis, ballRoll)
//   P    = piv(ballPivot, rollAxis, -toeTap)
//   outAnkleMatrix = controlMatrix * H * T * B * L * restAnkleMatrix
//   outBallMatrix  = controlMatrix * H * T * B * P * restBallMatrix
//
// So a positive roll tips the forward direction down (rollAxis = up x
// forward): below zero the foot rolls back on the heel (the toes lift),
// from 0 to rollBreak it rolls on the ball (the heel lifts; the toes stay
// down because the ball joint's branch skips L), beyond rollBreak on the
// toe tip (the ball lifts too). The foot turns by `roll` in all, without a
// jump at rollBreak. bank > 0 rolls onto the outer edge, bank < 0 onto the
// inner one, when bankAxis = up x outward (a positive turn about it lifts
// the inner edge). The twists turn about twistAxis through their pivot
// (twistAxis = forward x outward: positive swings the toes outward, on
// either side). toeTap > 0 lifts the toes about the ball, leaving the ankle.
// At zero values both outputs are controlMatrix * rest (the rest pose when
// the control is at rest).
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

// The rest layout of a reverse foot (control space, see above).
struct ReverseFootPivots {
  math::Vec3 heel = math::Vec3::Zero(), toe = math::Vec3::Zero(), ball = math::Vec3::Zero();
  math::Vec3 inner = math::Vec3::Zero(), outer = math::Vec3::Zero();
  math::Vec3 roll_axis = math::Vec3::UnitX(), bank_axis = -math::Vec3::UnitZ(), twist_axis = math::Vec3::UnitY();
};

// The values, in degrees.
struct ReverseFootValues {
  double roll = 0, roll_break = 30, bank = 0, heel_twist = 0, toe_twist = 0, ball_twist = 0, toe_tap = 0;
};

// The chain's rigid motions in control space: `ankle` = H T B L and
// `ball` = H T B P (above); they take a rest point of that branch to where
// it is now. Axes must be unit length.
struct ReverseFootChain {
  math::Mat4 ankle = math::Mat4::Identity();
  math::Mat4 ball = math::Mat4::Identity();
};
ReverseFootChain reverse_foot_chain(const ReverseFootPivots& pivots, const ReverseFootValues& values);

// Adds reverseFoot (called by register_util_types).
Status register_foot_types(graph::Registry& registry);

}  // namespace rigel::ops::util
