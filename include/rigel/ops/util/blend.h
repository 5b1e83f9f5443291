#pragma once
// fkIkSwitch: blends two poses of one joint chain (FK and IK, given as world
// matrices) and writes the channels that put the chain's joints in the
// blended pose, with FkIkBlendJob (fk_ik_blend.h, where the maths is). It
// holds the keyable `fkIk` value a limb's switch control stands for (node
// types have fixed attributes, so the value lives here).
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
//   the identity local matrix for that joint and the joints after it, and
//   names it in `error`.

#include "rigel/base/status.h"
#include "rigel/graph/node_type.h"
#include "rigel/math/types.h"
#include "rigel/ops/util/fk_ik_blend.h"

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

// Adds fkIkSwitch (called by register_util_types).
Status register_blend_types(graph::Registry& registry);

}  // namespace rigel::ops::util
