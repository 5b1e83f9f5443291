#pragma once
// One time curve read and edited key by key: what a graph editor (curve
// editor) shows and does. channel_keys.h edits a channel's keys at a time
// (every curve of a double3 together); this edits the keys of one curve:
// a key's time and value, its tangent types and fixed slopes, new keys on
// the curve where it already passes.
//
// Keys are those of the curve's active clip (nodes.h, "Clips"); `key`
// indices count from the clip's first key.

#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/ops/anim/curve.h"

namespace rigel::ops::anim {

// A curve's keys as numbers: values per component (one for an animCurve,
// three for an animCurveVec3, four x y z w for an animCurveQuat).
struct CurveKeys {
  CurveKind kind = CurveKind::kOther;
  std::vector<double> times;               // seconds
  std::vector<std::vector<double>> values;  // [key][component]
  // animCurve only (empty for tracks): tangent types, and the slopes they
  // resolve to (value units per second; step counts as 0).
  std::vector<TangentType> in_types, out_types;
  std::vector<double> in_slopes, out_slopes;
};
// Empty (kind kOther) for a node that is not a time curve.
CurveKeys curve_keys(const graph::Graph& graph, graph::NodeId curve);

// The curve's value at each of `times` (seconds), as evaluation gives it
// (its active clip, tangents, infinities): [time][component]. A curve whose
// keys are invalid gives what its node outputs for them (zeros).
std::vector<std::vector<double>> sample_curve(const graph::Graph& graph, graph::NodeId curve,
                                              std::span<const double> times);

// A change to key `key` of a curve (an index into curve_keys' arrays), or,
// with `key` kNewKey, a key inserted at `time` with the value the curve has
// there (then `value` and the tangents may be set on it as well).
inline constexpr std::size_t kNewKey = static_cast<std::size_t>(-1);
struct KeyChange {
  std::size_t key = kNewKey;
  std::optional<double> time;   // seconds (required for a new key)
  std::optional<double> value;  // the curve's unit; component `component` of a vec3 track
  int component = -1;           // vec3 track: 0 1 2; -1 / 0 for a scalar curve
  // animCurve only: tangent types, and fixed slopes (a slope makes that
  // side's type kFixed).
  std::optional<TangentType> in_type, out_type;
  std::optional<double> in_slope, out_slope;
};

// Applies `changes` to `curve` in one undo step, all or nothing: keys move
// in time keeping their values and tangents, and the clip's keys are put
// back in time order. A key moved onto one that does not move (within
// kKeyTimeTolerance) replaces it; two keys changed to the same time, a
// key index out of range, a time or value that is not finite, a value on
// an animCurveQuat (a rotation is keyed as a rotation: channel_keys.h), a
// component out of range, or a tangent on a track: kInvalidArgument naming
// the key (changes[i]). Quaternion keys are kept sign-continuous.
Status edit_curve(graph::Graph& graph, graph::NodeId curve, std::span<const KeyChange> changes);

}  // namespace rigel::ops::anim
