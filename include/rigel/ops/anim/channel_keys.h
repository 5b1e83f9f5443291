#pragma once
// Keys on the channels of transforms: the curve editing that keying
// (ephemeral::set_key), tools and rig updates (keep world positions of keys)
// share.
//
// A channel is a transform's translate, rotate, scale, shear or
// rotateQuaternion, or a scalar (double) input of any node, such as a
// switch's fkIk. A double3 channel is keyed by one `animCurve` per
// component (node.translateX <- curve.output) or by one `animCurveVec3`; a
// quaternion rotation by an `animCurveQuat`; a scalar by one `animCurve`. Curves that hold several clips
// (clipOffsets, nodes.h) are read and edited in their active clip.
//
// Keys closer than kKeyTimeTolerance are the same key: float32 glTF times of
// frame f differ from f / fps by ~1e-9.

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/math/types.h"
#include "rigel/ops/anim/curve.h"

namespace rigel::ops::anim {

inline constexpr double kKeyTimeTolerance = 1e-6;

enum class CurveKind { kScalar, kVec3, kQuat, kOther };
// What a node is as a time curve: animCurve, animCurveVec3, animCurveQuat,
// or other (drivenKey and any non-curve node included).
CurveKind curve_kind(const graph::Graph& graph, graph::NodeId node);

// Key times (seconds, sorted) of a curve's active clip; empty for a node
// that is not a time curve.
std::vector<double> curve_key_times(const graph::Graph& graph, graph::NodeId curve);
// The values of those keys, in the same order: double (animCurve),
// math::Vec3 (animCurveVec3) or math::Quat (animCurveQuat).
std::vector<graph::Value> curve_key_values(const graph::Graph& graph, graph::NodeId curve);
// The in and out tangent types of those keys (scalar curves; empty for
// tracks, whose interpolation is the track's).
std::pair<std::vector<TangentType>, std::vector<TangentType>> curve_key_tangents(const graph::Graph& graph,
                                                                                  graph::NodeId curve);
// "auto", "step", ... (tangent_type_names()); nullopt for anything else.
std::optional<TangentType> tangent_type_from_name(std::string_view name);
// True when the curve has a key at `t` in its active clip.
bool curve_has_key_at(const graph::Graph& graph, graph::NodeId curve, double t);

// Writes `value` (double3 as math::Vec3, math::Quat for rotateQuaternion,
// double for a scalar)
// into channel `attr` of `node` at time `t`. A free channel is set when not
// `insert`, or gets new curves keyed once at `t` when `insert`. A keyed
// channel: the key at `t` takes the value; with no key there, one is
// inserted when `insert` (auto tangents; quaternion keys are kept
// sign-continuous with their neighbour), else kInvalidArgument naming the
// channel and the frame. A channel (or a component) driven by anything but
// a fitting curve: kInvalidArgument naming the driver. One undo step.
Status write_channel_key(graph::Graph& graph, graph::NodeId node, graph::AttrIndex attr, const graph::Value& value,
                         double t, bool insert);

// Many keys on one channel: what write_channel_key(values[k], times[k])
// gives for k = 0, 1, ... in turn (same keys, tangents, quaternion signs,
// clip offsets and curve names), but each curve's arrays are merged in one
// pass and set once, so time and memory grow with the keys, not with their
// square: the undo step holds each array before and after, not a copy per
// key (a bake of N frames set every array N times, O(N^2)). `times` are
// finite and increase, each more than kKeyTimeTolerance after the one
// before; one value per time (math::Vec3 for a double3 channel, math::Quat
// for rotateQuaternion, double for a scalar channel). A free channel is set
// to the last value when not
// `insert`. Fails as write_channel_key, and on times out of order; all or
// nothing, one undo step.
Status write_channel_keys(graph::Graph& graph, graph::NodeId node, graph::AttrIndex attr, std::span<const double> times,
                          std::span<const math::Vec3> values, bool insert);
Status write_channel_keys(graph::Graph& graph, graph::NodeId node, graph::AttrIndex attr, std::span<const double> times,
                          std::span<const math::Quat> values, bool insert);
Status write_channel_keys(graph::Graph& graph, graph::NodeId node, graph::AttrIndex attr, std::span<const double> times,
                          std::span<const double> values, bool insert);

// Sets the in and/or out tangent type of the key at `t` (within
// kKeyTimeTolerance) on every curve keying channel `attr` of `node`: a
// scalar channel's curve, or each keyed component of a double3 channel.
// kInvalidArgument for a channel keyed by a track (animCurveVec3 or
// animCurveQuat: one interpolation for all its keys), kNotFound naming the
// channel and the frame when no curve of it has a key there. One undo step.
Status set_key_tangents(graph::Graph& graph, graph::NodeId node, graph::AttrIndex attr, double t,
                        std::optional<TangentType> in, std::optional<TangentType> out);

// Removes the key at `t` from `curve`, which drives `channel`; a curve left
// without keys is deleted and the channel is set to `keep`. Ok with
// `removed` false when the curve has no key there.
Status delete_curve_key(graph::Graph& graph, graph::NodeId curve, double t, const graph::Plug& channel,
                        const graph::Value& keep, bool& removed);

}  // namespace rigel::ops::anim
