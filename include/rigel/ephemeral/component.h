#pragma once
// The `ephemeral` component type (its schema is in the rig layer's
// builtin_schemas.cc): a rig definition can ask for an ephemeral rig (seeds
// 000 and 001) on part or all of the character, built, stepped, updated and
// removed like any other component.
//
// One step:
//   setup  setup_ephemeral() on the guide joint and every joint below it
//          (no guide: every joint of the character). Controls are named
//          JOINT_RIG_COMPONENT_ctrl, linked to the component with role
//          "joint" and index = place in the hierarchy (parent first); the
//          ephemeralRig node has role "ephemeralRig". Params: keepAnimation
//          (curves on the joints move onto the controls, else dropped with
//          the pose kept), keyScope; the "joint" control size is the radius
//          of each control's circle.
//   hook   hook 0 is the root control.
// The controls mirror the skeleton: a root control hangs where its joint
// does (under the joint's parent), so when a parent component drives that
// parent the ephemeral part follows it; the attach point itself is not used.
// Joints another component already drives are refused (setup_ephemeral
// names them).
#include "rigel/base/status.h"
#include "rigel/rig/component.h"

namespace rigel::ephemeral {

// Adds the `ephemeral` class to `factory`.
Status add_ephemeral_component(rig::ComponentFactory& factory);

// The rig layer's classes plus `ephemeral`: the factory the CLI, the server
// and the Python module build with.
const rig::ComponentFactory& components();

}  // namespace rigel::ephemeral
