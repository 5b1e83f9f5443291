#pragma once
// Keys on any keyable channel of any node: an animator's keys on a built
// rig's controls and switches as on an ephemeral rig's controls.
//
// A channel is an input an animator keys: a transform's translate, its
// rotation (rotate, or rotateQuaternion in quaternion mode) and scale, and
// every other input flagged kKeyable that holds a double or a double3 (a
// switch's fkIk, a foot's roll, a finger's curl, an IK's pole vector).
// Keys go through the ops::anim channel keys (curves in the active clip,
// auto tangents) at the graph's time, and a key within the ephemeral
// layer's kKeyFrameTolerance of that time is the key at that time (a key a
// hair off a frame is that frame's key). Each edit is one undo step.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/ops/anim/curve.h"

namespace rigel::tools {

struct Channel {
  graph::NodeId node;
  graph::AttrIndex attr = graph::kNoAttr;
  // One component (0 x, 1 y, 2 z) of a double3 channel, for set_values (a
  // channel box's translateX); -1 the whole channel. Keys are per channel.
  int component = -1;
};

// Whether something other than a time curve drives `attr` of `node` (or a
// component of it): a connection such a channel cannot be keyed through.
bool driven_otherwise(const graph::Graph& graph, graph::NodeId node, graph::AttrIndex attr);

// The keyable channels of `node`, attribute order (empty for none).
std::vector<graph::AttrIndex> keyable_attrs(const graph::Node& node);

// What a key on `nodes` keys when no channel is named: for an ephemeral
// rig's control, its keying set (ephemeral::keying_set: the character, or
// the control alone with its rig's `controls` scope); for a built rig's
// control, every control of that rig (a built character is one keying
// group, so a key is a pose, as seed 001 asks); any other node itself.
// First appearance order.
std::vector<graph::NodeId> keying_group(const graph::Graph& graph, const std::vector<graph::NodeId>& nodes);

// The channels of `nodes`, node by node: every keyable channel that is free
// or keyed (those driven by something else, such as a constraint, are left
// out), or only those named in `attrs` (each must be a keyable channel of
// each node: kInvalidArgument naming the node and the attribute, with
// Status::field() "attrs"). kInvalidArgument naming "controls" when no
// node has a keyable channel.
Result<std::vector<Channel>> channels_of(const graph::Graph& graph, const std::vector<graph::NodeId>& nodes,
                                         const std::vector<std::string>& attrs = {});

// Keys `channels` at the graph's time with their current values, or with
// `value` (scalar channels only; kInvalidArgument naming "value" otherwise).
// Fails, changing nothing, on a channel driven by something that is not a
// curve. One undo step.
// With `in` / `out`, the keys made get those tangent types (Maya's: auto,
// spline, linear, flat, step, stepNext, clamped, plateau, fixed): curves
// only, kInvalidArgument naming "tangent" for a channel keyed by a track.
struct Tangents {
  std::optional<ops::anim::TangentType> in, out;
  bool any() const { return in || out; }
};
Status set_keys(graph::Graph& graph, const std::vector<Channel>& channels,
                const std::optional<double>& value = std::nullopt, const Tangents& tangents = {});

// Removes the keys of `channels` at the graph's time; a curve left without
// keys is deleted and its channel keeps its current value. kNotFound when
// none of them has a key there. One undo step.
Status delete_keys(graph::Graph& graph, const std::vector<Channel>& channels);

// Moves the keys of `channels` at time `from` (seconds; a key within the
// ephemeral layer's kKeyFrameTolerance of it is its key) to `to`, each
// keeping its value and tangents (ops::anim::copy_curve_keys); a key
// already at `to` (within that tolerance) is replaced. Every curve of a
// channel moves its key (each component of a double3). kInvalidArgument
// naming "moveTo" for a time that is not finite; kNotFound when none of
// the channels has a key at `from`. One undo step; returns the number of
// keys moved (0 when `to` is `from`'s key time). With `copy` the keys at
// `from` stay and copies land at `to` (the timeline's Alt-drag).
Result<std::size_t> move_keys(graph::Graph& graph, const std::vector<Channel>& channels, double from, double to,
                              bool copy = false);

// Sets scalar channels to values at the graph's time: a keyed channel gets
// a key there with its value (a curve drives it, so a set alone would not
// hold), a free one is set, and keyed too when `auto_key`. `values`: one
// for every channel, or one per channel. kInvalidArgument naming "value"
// for a value that is not finite, a count that fits neither, or a channel
// that is not scalar; fails as set_keys on a channel driven otherwise. One
// undo step.
// A double3 channel takes a value through one component (Channel::component;
// the others keep theirs).
Status set_values(graph::Graph& graph, const std::vector<Channel>& channels, const std::vector<double>& values,
                  bool auto_key);

// The keys of one keyed plug: a scalar channel or one component of a
// double3 channel keyed by its own curve (values double), a double3 keyed
// by one curve (math::Vec3) or a quaternion rotation (math::Quat).
struct PlugKeys {
  graph::Plug plug;
  std::string name;  // "hero_arm_L_ik.translateX"
  std::vector<double> times;  // seconds, the active clip's
  std::vector<graph::Value> values;
  // Per key (scalar curves; empty for tracks): tangent type names.
  std::vector<std::string> in_tangents, out_tangents;
};
// The keyed plugs of `channels`, channel order (free channels have none).
std::vector<PlugKeys> keys_of(const graph::Graph& graph, const std::vector<Channel>& channels);

}  // namespace rigel::tools
