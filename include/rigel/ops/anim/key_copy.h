#pragma once
// Keys copied from one time curve onto a channel with every field they
// have: what transferring keys between characters and moving keys in time
// share (tools/transfer.h, tools::move_keys).
//
// A key keeps its value and its tangents: on a scalar curve (animCurve) its
// in and out tangent types, fixed slopes and weights; on a track
// (animCurveVec3, animCurveQuat) its cubic tangents. Keys are read from the
// source's active clip and written into the target curve's active clip.

#include <cstddef>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/ops/anim/channel_keys.h"

namespace rigel::ops::anim {

struct KeyCopy {
  // The source keys copied: times (seconds) in [first, last], each end
  // widened by `tolerance`.
  double first = 0.0, last = 0.0;
  // Seconds added to each copied key's time.
  double offset = 0.0;
  double tolerance = kKeyTimeTolerance;
};

// Copies the keys of time curve `source` that `copy` selects onto `target`
// (a channel plug: a scalar input, one component of a double3, or a
// rotateQuaternion), each at its time + offset. The keys the target's curve
// has between the first and last destination time (the range [first,
// last] + offset and every copied key, each widened by the tolerance) are
// replaced; its others are kept. A free target gets a new curve of the
// source's type and settings (weighted, infinities, interpolation); a
// target already keyed keeps its curve's settings. No key in the range:
// nothing changes (`copied` 0). Fails, changing nothing:
// kInvalidArgument when `source` is not a time curve or its active clip is
// not the target's kind of curve, when the target (or the channel it is
// part of) is driven by something other than such a curve, or when the
// target curve's active clip does not animate it. One undo step; `copied`
// (when given) is the number of keys written.
Status copy_curve_keys(graph::Graph& graph, graph::NodeId source, const KeyCopy& copy, const graph::Plug& target,
                       std::size_t* copied = nullptr);

}  // namespace rigel::ops::anim
