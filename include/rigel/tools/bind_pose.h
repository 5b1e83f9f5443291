#pragma once
// Bind pose (seed 004's pose actions): a control, a component or a whole
// built character back to its pose as built. Controls are built zeroed (the
// rest is in their offsetParentMatrix, rig::rest_world records it), so
// their bind pose is translate 0, rotation 0 (identity), scale 1, shear 0;
// a component's other keyable nodes (a limb's fkIkSwitch, a foot's
// reverseFoot) take the scalar values recorded when their build step ran
// (rig::bind_values), so a rebuild or an update that keeps a component keeps
// its bind pose too; a spaceSwitch's compensation transform goes back to
// the identity with its `space` (rig/spaces.h).
//
// `nodes`: controls, components (their metaComponent, `hero:arm_L`) or rigs
// (their metaRoot, `hero:`): everything a component or rig built. At the
// graph's time: keyed channels get a key there (or `key` false: their key
// there takes the value, kInvalidArgument when there is none), free ones
// are set, or keyed when `key`. One undo step; on failure nothing changes.

#include <cstddef>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"

namespace rigel::tools {

struct BindPoseReport {
  std::size_t channels = 0;
  std::vector<graph::NodeId> set;  // the nodes reset
};

// kInvalidArgument with field "controls" for a node that is neither a built
// rig's control, component nor rig, or when none is given.
Result<BindPoseReport> reset_bind_pose(graph::Graph& graph, const std::vector<graph::NodeId>& nodes, bool key);

}  // namespace rigel::tools
