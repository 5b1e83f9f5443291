#pragma once
// Tween and breakdown (the tween machine and breakdowner animators use in
// Maya, Blender, Unreal and Cascadeur): channels at the graph's time set to
// a blend between their previous and their next key.
//
// For each channel (tools/keys.h: a transform's translate, rotation and
// scale, a switch's fkIk, ...) the previous and the next key are the
// nearest key times of its curves before and after the time (beyond the
// key tolerance); the channel is evaluated there and blended by `fraction`:
// 0 gives the previous key's value, 1 the next's, 0.5 halfway, below 0 or
// above 1 an overshoot. Translate, scale and scalars blend linearly,
// rotations by quaternion slerp (an Euler channel through its rotate
// order, the result the Euler angles closest to the previous key's). A
// channel without a key on both sides is left as it is. The result is
// keyed at the time (`key`), or written into the key already there (a
// keyed channel with none: kInvalidArgument naming it). One undo step; the
// time is put back.

#include <cstddef>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/tools/keys.h"

namespace rigel::tools {

// The number of channels blended. kInvalidArgument naming "fraction" when
// it is not finite (or beyond +-10: no tween overshoots ten times).
Result<std::size_t> tween(graph::Graph& graph, const std::vector<Channel>& channels, double fraction, bool key);

}  // namespace rigel::tools
