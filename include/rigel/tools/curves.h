#pragma once
// The graph editor's curves: the animation curves of some channels as keys,
// tangents and samples to draw, and edits of single keys on single curves
// (move in time and value, tangent types and slopes, insert, delete).
//
// A curve is named by the channel plug it drives ("hero_arm_L_ik.translateX",
// "hero_arm_L.fkIk", "ctrl.rotateQuaternion"). A scalar animCurve shows as
// itself; a vector track (animCurveVec3, glTF translation/scale) as its
// three components; a rotation track (animCurveQuat, glTF rotation) as its
// x y z w components, or as Euler angles in degrees (the node's rotate
// order, unwrapped so the curve does not jump by 360). Keys are found by
// time within the ephemeral layer's key tolerance (a key a hair off a frame
// is that frame's key). Each edit is one undo step.

#include <optional>
#include <string>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/ops/anim/curve.h"
#include "rigel/tools/keys.h"

namespace rigel::tools {

struct CurveViewOptions {
  // Samples from `first` to `last` (seconds) every `step` seconds (and at
  // every key): without a range, the curve's keys (a single key: one
  // second around it); without a step, one frame.
  std::optional<double> first, last, step;
  bool quat_as_euler = true;
};

struct CurveView {
  graph::Plug plug;       // the channel plug the curve drives
  std::string name;       // its name (what edits take)
  std::string curve;      // the curve node's name
  std::string kind;       // "curve", "vectorTrack", "rotationTrack"
  int component = -1;     // a track's component shown (x y z [w], or an Euler axis); -1 for a curve
  std::string label;      // "translateX", "fkIk", "rotate.x" (Euler), "rotateQuaternion.w"
  bool editable = true;   // whether key values can be edited (not a rotation track's)
  std::vector<double> key_times, key_values;  // seconds, the curve's unit (degrees for Euler)
  // Curves only: tangent type names and the slopes they resolve to (value
  // units per second).
  std::vector<std::string> in_tangents, out_tangents;
  std::vector<double> in_slopes, out_slopes;
  std::vector<double> sample_times, sample_values;
};

// The curves keying `channels`, channel order (free channels have none).
// kInvalidArgument naming "first", "last" or "step" for a range that is not
// finite, reversed, or a step that is not positive or would take more than
// 100,000 samples.
Result<std::vector<CurveView>> curve_views(const graph::Graph& graph, const std::vector<Channel>& channels,
                                           const CurveViewOptions& options = {});

// One key of one curve: the curve by the plug it drives, the key by time.
struct CurveKeyRef {
  std::string curve;  // CurveView::name
  double time = 0;    // seconds
};
struct CurveKeyEdit {
  CurveKeyRef key;
  std::optional<double> to_time;  // seconds
  std::optional<double> value;    // a vector track: component `component`
  int component = -1;
  std::optional<ops::anim::TangentType> in_type, out_type;
  std::optional<double> in_slope, out_slope;  // value units per second (the side becomes fixed)
};

// Edits keys (several curves, several keys; all or nothing, one undo step).
// Errors name "keys" (kNotFound: no such curve or no key there;
// kInvalidArgument: what ops::anim::edit_curve refuses). Returns the number
// of keys changed.
Result<std::size_t> edit_curve_keys(graph::Graph& graph, const std::vector<CurveKeyEdit>& edits);
// Inserts a key on each curve at its time with the value the curve has
// there (an existing key there is kept). Errors name "keys".
Result<std::size_t> insert_curve_keys(graph::Graph& graph, const std::vector<CurveKeyRef>& keys);
// Deletes keys; a curve left without keys is removed and its channel keeps
// the value it had. Errors name "keys".
Result<std::size_t> delete_curve_keys(graph::Graph& graph, const std::vector<CurveKeyRef>& keys);

}  // namespace rigel::tools
