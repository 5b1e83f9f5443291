#pragma once
// spaceSwitch: the parent space a control follows, chosen by a keyable
// index among named spaces (seed 004's control spaces and custom space
// tool). It writes the control's offsetParentMatrix, so the control keeps
// its place in the hierarchy, its channels and its keys; only what its
// channels are relative to changes.
//
//   outMatrix = inverse(parentMatrix) * T_k * targetOffset[k]
//               * compensationMatrix * restOffset
//
// with k = round(space) clamped to the names given, T_k the world matrix
// of space k's target (targetWorldMatrix[k]; a missing element is the
// identity: the world). targetOffset[k] relates the target to the control's
// parent when the space was added, so that choosing it then moves nothing;
// restOffset is the control's offsetParentMatrix as built (where it rests);
// compensationMatrix is the local matrix of a transform whose channels a
// space switch keys with step tangents, so that a switch at a frame keeps
// the control's world matrix there without a key on the control itself
// (tools/spaces.h). The world matrix of the control is then
//   T_k * targetOffset[k] * compensationMatrix * restOffset * local.
//
// Inputs:
//   space               double    keyable: the index of the space followed
//   spaceNames          string[]  one name per space ("parent", "world", ...)
//   targetWorldMatrix   matrix[]  connect each target's worldMatrix
//   targetOffset        matrix[]  missing elements: identity
//   parentMatrix        matrix    the control's parent's worldMatrix
//   compensationMatrix  matrix    the compensation transform's matrix
//   restOffset          matrix
// Outputs: outMatrix, spaceIndex (int: k), error (hidden: a space index
// that is not finite, or a singular parent, which leaves the rest offset).

#include "rigel/base/status.h"
#include "rigel/graph/node_type.h"

namespace rigel::ops::util {

inline constexpr const char* kSpaceSwitchType = "spaceSwitch";

namespace space_attr {
enum : graph::AttrIndex {
  kSpace = 0,
  kSpaceNames,
  kTargetWorldMatrix,
  kTargetOffset,
  kParentMatrix,
  kCompensationMatrix,
  kRestOffset,
  kOutMatrix,
  kSpaceIndex,
  kError,
  kCount
};
}  // namespace space_attr

// The space index a `space` value selects among `count` spaces: the value
// rounded to the nearest integer, clamped to [0, count - 1] (0 when it is
// not finite or there is no space).
int space_index(double space, int count);

// Adds spaceSwitch (called by register_util_types).
Status register_space_types(graph::Registry& registry);

}  // namespace rigel::ops::util
