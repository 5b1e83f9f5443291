#pragma once
// Space switching and space baking (seed 004's space menu, "switch is done
// with matching, so control will stay in place", and the animation baker's
// space mode) on a control with spaces (rig/spaces.h).
//
// A switch at frame F keys the control's spaceSwitch `space` and its
// compensation transform at F, both with step tangents (and steps out of
// their key before F): the compensation is what keeps the control's world
// matrix at F as it was, so there is no pop and no key on the control
// itself. Frames before F keep the space and compensation they had (when
// those were not keyed yet, a key at the scene's first keyed frame holds
// their old values: nothing is keyed outside the clip), so they are
// unchanged; from F on the control follows the new space with its own
// channels and keys as they are.
//
// A bake over [A, B] switches at A, removes the space and compensation keys
// in (A, B], then keys the control's channels at every frame of the range
// so that its world motion there is what it was (tools/match.h's rule:
// keys on the frames asked for only). One undo step; on failure nothing
// changes. The scene's time is put back.

#include <cstddef>
#include <functional>
#include <optional>
#include <string>

#include "rigel/base/status.h"
#include "rigel/rig/spaces.h"
#include "rigel/scene/scene.h"

namespace rigel::tools {

struct SpaceSwitchOptions {
  std::string space;                   // the space to follow (a name of rig::spaces_of)
  std::optional<double> frame;         // the switch's frame; none: the current frame
  std::optional<double> first, last;   // a bake over a range instead (scene frames)
  std::function<void(double)> progress;
};

struct SpaceSwitchReport {
  std::string from, to;        // the space followed before (at the switch's frame) and after
  std::size_t frames = 0, keys = 0;
  double max_error = 0;        // the largest change of the control's world matrix (relative), over the frames checked
  double worst_frame = 0;
};

// kInvalidArgument with field "control" (no spaces), "space" (not one of
// them) or "frames" (not finite, reversed, both a frame and a range);
// errors writing keys (a driven channel) name the channel.
Result<SpaceSwitchReport> switch_space(scene::Scene& scene, graph::NodeId control, const SpaceSwitchOptions& options);

}  // namespace rigel::tools
