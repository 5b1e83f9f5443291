#pragma once
// Mirror and flip (seed 004's mirror tool): a built rig's pose copied to the
// other side, or both sides swapped, at one frame or keyed at every frame
// of a range.
//
// Pairs come from the rig's metadata (rig::mirror_pair: the same role and
// index in the component of the same type and name on the other side),
// never from node names, so renamed controls mirror all the same. The two
// sides are related by their rest (the world matrices recorded at build,
// rig::rest_world): with M the reflection in the mirror plane and K =
// rest_a^-1 * M * rest_b, a control b takes K^-1 * C_a * K of a's channel
// matrix C_a (its translate, rotation and scale under its offset parent),
// so whatever axes either side's controls have, the result is a proper
// transform, the rest pose maps onto itself, and mirroring twice gives the
// pose back (to rounding). Scalar channels of a component's other keyable
// nodes (a limb's fkIk, a foot's roll, a hand's curl: side-relative by
// construction) are copied as they are with `all`.
//
//   mirror: each given control's pose goes onto its pair (a centre
//           component's controls are left as they are);
//   flip:   each given control and its pair swap mirrored poses, centre
//           controls mirror in place (a symmetric pose is unchanged).
//
// With a range every frame is sampled first and each channel then keyed
// once (tools/match.h's rule: keys on the frames asked for only); without
// one the current frame is set (keyed where `key`). One undo step; on
// failure nothing changes. The scene's time is put back.

#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/scene/scene.h"

namespace rigel::tools {

enum class MirrorPlane { kYZ, kXY, kXZ };  // x -> -x (glTF's left-right, the default), z -> -z, y -> -y

struct MirrorOptions {
  // Built rigs' controls (and with `all` their rigs); empty with `all`:
  // every built rig.
  std::vector<graph::NodeId> controls;
  // Every control of those rigs, and their components' other keyable
  // nodes; the side copied from is `from` (mirror) or both (flip).
  bool all = false;
  char from = 'L';  // 'L' or 'R', for `all` without `flip`
  bool flip = false;
  MirrorPlane plane = MirrorPlane::kYZ;
  std::optional<double> first, last;  // scene frames; none: the current frame
  bool key = true;  // false: set the current frame only, without keys
  std::function<void(double)> progress;
};

struct MirrorReport {
  std::size_t frames = 0, keys = 0;
  std::vector<graph::NodeId> set;       // the nodes whose channels it set
  std::vector<graph::NodeId> unpaired;  // with `all`: controls left, their component having no pair
};

// kInvalidArgument with field "controls" naming a control that is not a
// built rig's or has no pair (with `all`, unpaired controls are left and
// listed instead), or when nothing is given; "frames" for
// frames that are not finite or reversed; a control without a recorded
// rest (built before rigel recorded it) asks for a rebuild.
Result<MirrorReport> mirror(scene::Scene& scene, const MirrorOptions& options);

}  // namespace rigel::tools
