#pragma once
// Motion trails and ghosts (onion skin): where nodes are in the world over
// time, sampled from the evaluated graph (curves, constraints, IK, what a
// rig makes them do), for a viewport to draw as lines. The graph's time is
// restored afterwards and nothing is changed (no undo step).

#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/math/types.h"
#include "rigel/scene/scene.h"

namespace rigel::tools {

// At most this many node-samples (nodes x frames) in one call.
inline constexpr std::size_t kMaxTrailSamples = 2'000'000;

// The world position of each of `nodes` at each of `frames`: result[f][n].
// kInvalidArgument naming "frames" for a frame that is not finite or more
// than kMaxTrailSamples samples; naming "controls" for an invalid node.
Result<std::vector<std::vector<math::Vec3>>> world_positions(scene::Scene& scene, const std::vector<graph::NodeId>& nodes,
                                                             const std::vector<double>& frames);

struct MotionTrail {
  graph::NodeId node;
  std::vector<double> frames;
  std::vector<math::Vec3> points;   // one per frame
  std::vector<double> key_frames;   // frames where the node's own channels have keys, within the range
};

// A trail for each node over frames first..last every `step` frames (and at
// each key of the node inside the range, so a key is a point of its trail).
// kInvalidArgument naming "frames" for a reversed or non-finite range or a
// step that is not positive.
Result<std::vector<MotionTrail>> motion_trails(scene::Scene& scene, const std::vector<graph::NodeId>& nodes, double first,
                                               double last, double step = 1.0);

// The frames of the keys of `nodes`' own channels (sorted, each once).
std::vector<double> key_frames(const graph::Graph& graph, const std::vector<graph::NodeId>& nodes);

}  // namespace rigel::tools
