// Control spaces (seed 004: a control's `space` attribute and the custom
// space tool's add_space): the transforms a control can follow, one at a
// time, switched by a keyable index.
//
// A control with spaces has a spaceSwitch node (ops/util/space.h) writing
// its offsetParentMatrix and a compensation transform (no parent, under the
// rig's noTransform group when the control is a built rig's) whose channels
// a space switch keys (tools/spaces.h). The control keeps its parent, its
// channels and its keys: only what they are relative to changes. Space 0,
// "parent", follows the control's parent as it was when the first space was
// added; "world" (no target) follows nothing.
//
// Components declare default spaces for their controls (a limb's IK
// control: world, global, chest and head for an arm; world, global and hip
// for a leg), made by their "spaces" build step: add_space under the
// build's recorder, so they are destructed and rebuilt with the component.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/rig/build_context.h"
#include "rigel/scene/scene.h"

namespace rigel::rig {

using graph::NodeId;

struct Space {
  std::string name;
  NodeId target;  // invalid: the world
};

struct ControlSpaces {
  NodeId control;
  NodeId node;          // the spaceSwitch (invalid: the control has no spaces)
  NodeId compensation;  // its compensation transform
  std::vector<Space> spaces;
  int current = 0;      // the space followed at the graph's time
};

// The spaces of `control` (none when nothing but a spaceSwitch drives
// its offsetParentMatrix).
ControlSpaces spaces_of(scene::Scene& scene, NodeId control);

// Adds space `name` (an identifier, not yet one of the control's) that
// follows `target` (a transform that does not follow the control; invalid:
// the world) and returns its index. Its offset is taken at the graph's
// time so that following it there moves nothing. The first space also
// makes the spaceSwitch and the compensation transform, and space 0
// "parent". kInvalidArgument with field "control" (not a transform, its
// offsetParentMatrix driven by something else), "space" (the name) or
// "target" (not a transform, the control itself or something that follows
// it). One undo step; on failure nothing changes.
Result<int> add_space(scene::Scene& scene, NodeId control, std::string_view name, NodeId target);

// The index of space `name` among `spaces` (kInvalidArgument with field
// "space" listing them when there is none).
Result<int> find_space(const ControlSpaces& spaces, std::string_view name);

// A build step's default spaces for `control` (seed 004's add_space in a
// component's build): `spec` is a comma-separated list of `world` and
// NAME=COMPONENT/ROLE, COMPONENT a component of the rig being built (by
// name, else by type, first in build order) and ROLE one of its controls'
// roles. The spaceSwitch and compensation transform are linked to the
// component as `role`SpaceSwitch and `role`SpaceCompensation. A component the
// rig lacks (or has not built yet) is left out, unless `required` (the
// definition named it), which fails naming it; a malformed entry fails.
Status add_default_spaces(BuildContext& ctx, NodeId control, std::string_view role, std::string_view spec,
                          bool required);

}  // namespace rigel::rig
