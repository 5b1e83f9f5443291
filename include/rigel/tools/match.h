#pragma once
// FK/IK match and bake (seed 004's animation baker, FK/IK mode): a limb's FK
// controls keyed to its IK pose, or its IK controls to its FK pose, at one
// frame or at every frame of a range, so the switch can change without the
// pose changing. The reverse foot of a child foot is included (its roll
// baked onto the FK toe; the toe tap keyed from the FK toe), as seed 004
// says Luna adds over HumanIK.
//
// What it guarantees, the complaints about FK/IK snaps elsewhere in mind:
// - exact: at every frame asked for, the controls set take the pose that
//   rig::components::plan_fk_ik_match computes from the other side (the
//   switch's own inputs), so every deform joint it drives has the same world
//   matrix on both sides (MatchReport::max_error says how close it came; an
//   IK side can only reach an FK pose bent about the elbow's or knee's rest
//   hinge);
// - no hidden keys: keys are made on the frames asked for only, on the set
//   side's controls (every keyable channel: translate, rotation, scale,
//   and shear where the pose has one) and on the switch;
// - no blend through a mismatch: the switch (fkIk: 0 FK, 1 IK) is keyed to
//   the side set at the range's first and last frame with step tangents, and
//   the key before the range, if any, gets a step out-tangent, so playback
//   holds each side's value until the next key instead of blending between
//   poses that do not match.
// One undo step; on failure nothing changes. The scene's time is put back.

#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/rig/components/limbs.h"
#include "rigel/scene/scene.h"

namespace rigel::tools {

struct MatchOptions {
  // The side that takes the other's pose and that the switch ends on ("--to
  // fk": the FK controls are keyed to the IK pose, fkIk keyed 0).
  rig::components::MatchSide to = rig::components::MatchSide::kFk;
  // Scene frames; none: the current frame only. first <= last.
  std::optional<double> first, last;
  // false: set the controls at the current frame without keying (one frame
  // only; a keyed channel must have a key there, which takes the value).
  bool key = true;
  std::function<void(double)> progress;  // fraction done, [0, 1]; may be empty
};

struct MatchReport {
  std::size_t frames = 0, keys = 0;
  std::vector<graph::NodeId> controls;  // the controls set
  // Afterwards, at the frames matched: the largest difference between a
  // driven joint's world matrix on the side set and on the other side,
  // relative to the matrix's size (max |a - b| / max(1, max |b|)), and its
  // frame.
  double max_error = 0, worst_frame = 0;
};

// kInvalidArgument naming the component when it has no FK/IK switch (only
// limbs have one) or no IK side, on frames that are not finite or reversed,
// and on `key` false with a range.
Result<MatchReport> match(scene::Scene& scene, graph::NodeId component, const MatchOptions& options);

}  // namespace rigel::tools
