#pragma once
// Transfer keys (seed 004 §4.12.1, the transfer keyframes tool): the keys of
// one built component copied onto another component of the same type (in
// the same rig or another), or a whole character's onto another character
// built from matching components.
//
// Nothing is matched by node names. Components pair by rigId, else by name
// and side; nodes within them by their role and index tags (rig.role or
// rig.step, rig.index), so a character with renamed controls takes the
// keys all the same. Every keyed channel of a component's nodes is copied:
// its controls' translate, rotation (Euler curves, or a quaternion track)
// and scale, and its other nodes' keyable inputs (a limb's fkIkSwitch, a
// foot's roll, a hand's curl). Keys keep their values and tangents
// (ops::anim::copy_curve_keys); a key at source frame t lands at t +
// offset. On the target, each channel that takes keys loses its keys
// inside the destination range ([first, last] + offset) and keeps the
// others; a channel without source keys in the range is left alone. One
// undo step; on failure nothing changes.

#include <cstddef>
#include <optional>
#include <utility>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"

namespace rigel::tools {

struct TransferOptions {
  // Both metaComponents (a component onto one of the same type) or both
  // metaRoots (a whole character onto another).
  graph::NodeId from, to;
  // Source frames; none: from the first key to the last of what is
  // transferred.
  std::optional<double> first, last;
  double offset = 0.0;  // frames
};

struct TransferReport {
  std::vector<std::pair<graph::NodeId, graph::NodeId>> components;  // source -> target meta nodes, with keys
  std::vector<graph::NodeId> set;  // the target nodes that took keys
  std::size_t channels = 0, keys = 0;
  std::optional<double> first, last;  // the source range copied (none when nothing was keyed)
};

// kInvalidArgument with field "from" or "to" when a node is not a built
// component or rig, or they are not the same kind; "to" for components of
// different types, a source component with keys that the target character
// lacks, a keyed node with no match on the target (naming it, its role and
// index) or a target channel that cannot take keys (driven by something
// else); "frames" for frames not finite or reversed (or only one end
// given); "offset" for an offset not finite.
Result<TransferReport> transfer_keys(graph::Graph& graph, const TransferOptions& options);

}  // namespace rigel::tools
