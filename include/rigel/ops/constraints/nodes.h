#pragma once
// Graph node types for the constraints of constraints.h: parentConstraint,
// pointConstraint, orientConstraint, scaleConstraint, aimConstraint and
// poleVectorConstraint. Each node keeps what it needs as its own inputs and
// writes channels to connect to the driven's inputs (translate, rotate,
// scale, or an IK node's pole vector): it never reads the driven, so no
// node-level cycle forms.
//
// Shared inputs (all types):
//   targetWorldMatrix  matrix[]  connect each target's worldMatrix to an element
//   targetWeight       double[]  keyable; missing elements weigh 1
//   targetOffset       matrix[]  maintain-offset matrices (compute_offset());
//                                missing elements are the identity
//   parentInverseMatrix matrix   inverse world matrix of the driven's parent:
//                                set it, or connect it from a node that is not
//                                downstream of the driven (never the driven)
// Blending constraints (parent, point, orient, scale, aim) also have:
//   rotateOrder enum   the driven's rotate order (rotate output is in it)
//   jointOrient double3 angle  the driven joint's orient, removed from rotate
//   restTranslate/restRotate/restScale double3  what the outputs hold while
//                                every weight is 0
// and write translate, rotate (degrees) and scale (double3), plus a hidden
// string `error`, empty while the inputs are valid. Invalid inputs never
// crash a compute: the outputs keep the rest values and `error` says why.
// parentConstraint adds `rigid` (bool): seed 001's scale/shear-free variant.
// aimConstraint adds aimVector, upVector, worldUpType (scene object
// objectRotation vector none), worldUpVector, worldUpMatrix, and
// constraintTranslate (double3, the driven's translate, in parent space: its
// pivot) — set, or connected from the same source as the driven's translate.
// poleVectorConstraint has startPosition and handlePosition (double3, world)
// instead and writes poleVector (double3).

#include "rigel/base/status.h"
#include "rigel/graph/node_type.h"

namespace rigel::ops::constraints {

inline constexpr const char* kParentConstraintType = "parentConstraint";
inline constexpr const char* kPointConstraintType = "pointConstraint";
inline constexpr const char* kOrientConstraintType = "orientConstraint";
inline constexpr const char* kScaleConstraintType = "scaleConstraint";
inline constexpr const char* kAimConstraintType = "aimConstraint";
inline constexpr const char* kPoleVectorConstraintType = "poleVectorConstraint";

// Adds the six constraint types to `registry`. Fails if a name is taken.
Status register_constraint_types(graph::Registry& registry);

}  // namespace rigel::ops::constraints
