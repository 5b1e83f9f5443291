#pragma once
// The pivot chain of a reverse foot (the heel / toe / bank / ball roll of
// Maya auto-rigs and Luna's FootComponent, seed 004 §4.8) as matrices,
// shaped as a job (STYLE.md §3). The reverseFoot node (foot.h) calls it.
//
// Every point and axis is in the space of the control at rest (the foot
// control's space: rig::components foot makes it x = roll axis, y = up,
// z = forward, so the defaults fit a foot whose outer edge is toward +x).
// piv(p, axis, t) is the rotation by t degrees about the line through p
// along the unit `axis` (right-hand rule): T(p) * R(axis, t) * T(-p), the
// identity when t is 0. With the values in degrees (ReverseFootValues) and
// the pivots and axes of ReverseFootPivots:
//
//   heel_roll = min(roll, 0)
//   ball_roll = clamp(roll, 0, b)       b = max(roll_break, 0)
//   toe_roll  = max(roll - b, 0)
//   H = piv(heel, twist_axis, heel_twist) * piv(heel, roll_axis, heel_roll)
//   T = piv(toe,  twist_axis, toe_twist)  * piv(toe,  roll_axis, toe_roll)
//   B = piv(bank > 0 ? outer : inner, bank_axis, bank)
//   L = piv(ball, twist_axis, ball_twist) * piv(ball, roll_axis, ball_roll)
//   P = piv(ball, roll_axis, -toe_tap)
//   ankle world = control * H * T * B * L * rest_ankle
//   ball world  = control * H * T * B * P * rest_ball
//
// So a positive roll tips the forward direction down (roll_axis = up x
// forward): below zero the foot rolls back on the heel (the toes lift),
// from 0 to roll_break it rolls on the ball (the heel lifts; the toes stay
// down because the ball joint's branch skips L), beyond roll_break on the
// toe tip (the ball lifts too). The foot turns by `roll` in all, without a
// jump at roll_break. bank > 0 rolls onto the outer edge, bank < 0 onto the
// inner one, when bank_axis = up x outward (a positive turn about it lifts
// the inner edge). The twists turn about twist_axis through their pivot
// (twist_axis = forward x outward: positive swings the toes outward, on
// either side). toe_tap > 0 lifts the toes about the ball, leaving the
// ankle. At zero values both outputs are control * rest (the rest pose when
// the control is at rest).

#include "rigel/math/types.h"

namespace rigel::ops::util {

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

struct ReverseFootJob {
  // Validates job parameters. Returns false:
  // - if ankle or ball is null;
  // - if a value or a pivot is not finite;
  // - if an axis is zero or not finite.
  bool validate() const;
  // Writes *ankle = control * H T B L * rest_ankle and *ball = control *
  // H T B P * rest_ball. Returns false if the job is not valid (writing
  // nothing).
  bool run() const;

  // The pivots and axes (axes of any length: normalized here).
  ReverseFootPivots pivots;
  ReverseFootValues values;
  // The foot control's world matrix.
  math::Mat4 control = math::Mat4::Identity();
  // The ankle's and ball joint's world matrices at rest, in control space
  // (control_rest^-1 * world_rest).
  math::Mat4 rest_ankle = math::Mat4::Identity();
  math::Mat4 rest_ball = math::Mat4::Identity();

  // Outputs: world matrices of the ankle and the ball joint. Not owned.
  math::Mat4* ankle = nullptr;
  math::Mat4* ball = nullptr;
};

}  // namespace rigel::ops::util
