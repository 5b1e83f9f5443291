#pragma once
// Baking (seed 004's animation baker): what a rig makes joints do, turned
// into keys on the joints themselves, so the animation survives the rig's
// removal or travels to another tool (`rigel bake`).
//
// For every frame from `first` to `last` (scene frames at the scene's fps)
// each node's evaluated local channels are sampled (translate, rotation,
// scale), everything that drove those channels (constraints, IK, controls,
// curves) is disconnected, and the samples become keys, one per frame. The
// rotation is keyed both as Euler degrees on `rotate` (kept continuous from
// frame to frame) and as a quaternion on `rotateQuaternion` (kept
// sign-continuous), so the motion holds whichever rotate mode the node has
// later: removing a rig restores the modes its build changed (a driven
// joint is switched to Euler while the rig drives it). Nodes are done parents
// first, so a baked child's keys are relative to its baked parent. The
// scene's time is put back. One undo step; on failure nothing changes.

#include <functional>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/scene/scene.h"

namespace rigel::tools {

struct BakeOptions {
  double first = 0, last = 0;  // scene frames, first <= last
  // Transform nodes to bake; empty: every joint of the scene.
  std::vector<graph::NodeId> nodes;
  // Called with the fraction done, in [0, 1]; may be empty.
  std::function<void(double)> progress;
};

struct BakeReport {
  std::size_t nodes = 0, frames = 0, keys = 0;
  std::size_t disconnected = 0;  // drivers removed
};

// Fails, naming the node, on frames that are not finite or reversed, a node
// that is not a transform, or a node whose pivots or rotate axis are set
// (its channels cannot be solved from a matrix).
Result<BakeReport> bake(scene::Scene& scene, const BakeOptions& options);

}  // namespace rigel::tools
