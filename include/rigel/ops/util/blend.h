#pragma once
// fkIkSwitch: blends two poses of one joint chain (FK and IK, given as world
// matrices) and writes the channels that put the chain's joints in the
// blended pose. It holds the keyable `fkIk` value a limb's switch control
// stands for (node types have fixed attributes, so the value lives here).
//
// Per joint i (n = restOffsetParentMatrix's size, the chain's joint count):
//   P_side[i] = (i == 0 ? parentMatrix : W_side[i - 1]) * restOffsetParentMatrix[i]
//   L_side[i] = P_side[i]^-1 * W_side[i]            (side = fk, ik)
//   L[i]      = blend(L_fk[i], L_ik[i], fkIk): translate and scale and shear
//               linearly, rotation by shortest-path slerp (local blending
//               keeps bone lengths when both sides keep them)
//   W[i]      = P[i] * L[i] with the blended chain's P
// so fkIk = 0 gives the FK pose and 1 the IK pose (up to rounding).
// Channels: L[i] = T * JO * R * RA * SH * S (pivots zero), written as
// outTranslations, outRotations (R, for rotateQuaternion in quaternion
// mode), outScales, outShears; outWorldMatrices = W.
//
// Inputs:
//   fkIk                    double    keyable, clamped to [0, 1]
//   parentMatrix            matrix    world matrix of the root joint's parent
//   fkMatrix, ikMatrix      matrix[]  world matrices of each side; a missing
//                                     element is taken from the other side
//                                     (identity when both miss)
//   useIkEndMatrix          bool      the IK side's last joint takes rotation,
//   ikEndMatrix             matrix    scale and shear from ikEndMatrix (an IK
//                                     control's worldMatrix), translation
//                                     from ikMatrix
//   restOffsetParentMatrix  matrix[]  each joint's offsetParentMatrix
//   restJointOrient         double3[] angle, each joint's jointOrient (missing: 0)
//   restRotateAxis          double3[] angle, each joint's rotateAxis (missing: 0)
// Outputs: outTranslations, outRotations, outScales, outShears,
//   outWorldMatrices, error (hidden). A singular or non-finite matrix gives
//   the identity local matrix for that joint and names it in `error`.
//
// twistShare lives in twist.h.

#include <span>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/node_type.h"
#include "rigel/math/types.h"

namespace rigel::ops::util {

inline constexpr const char* kFkIkSwitchType = "fkIkSwitch";

namespace fk_ik_attr {
enum : graph::AttrIndex {
  kFkIk = 0,
  kParentMatrix,
  kFkMatrix,
  kIkMatrix,
  kUseIkEndMatrix,
  kIkEndMatrix,
  kRestOffsetParentMatrix,
  kRestJointOrient,
  kRestRotateAxis,
  kOutTranslations,
  kOutRotations,
  kOutScales,
  kOutShears,
  kOutWorldMatrices,
  kError,
  kCount
};
}  // namespace fk_ik_attr

// The IK side's world matrix of a chain's last joint: translation of
// `ik_world`, rotation, scale and shear of `end_control_world`.
math::Mat4 ik_end_world(const math::Mat4& ik_world, const math::Mat4& end_control_world);

// Adds fkIkSwitch (called by register_util_types).
Status register_blend_types(graph::Registry& registry);

}  // namespace rigel::ops::util
