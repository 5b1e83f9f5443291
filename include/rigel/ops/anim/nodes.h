#pragma once
// Graph node types for animation: curves driven by time (animCurve), curves
// driven by any attribute (drivenKey: Maya's set-driven keys, seed 004), and
// glTF tracks (animCurveVec3, animCurveQuat). Each node stores its keys in
// its own input attributes and calls the kernels of curve.h / track.h.
//
// Each node keeps its keys compiled in a node cache (graph::NodeCache)
// with a playback cursor: an animCurve or drivenKey an AnimCurve (the
// active clip's keys, one precomputed segment per key pair), an
// animCurveVec3 or animCurveQuat a Track (a linear rotation track with its
// slerps prepared). The cache is rebuilt when a key array, a setting,
// clipOffsets or clip changes (their versions); the check of the keys runs
// then (O(keys)), with its result kept for the hidden `error` output, which
// is time-invariant (graph::kTimeInvariant). A time change therefore costs
// a cursor check and one interpolation (a binary search after a jump), not
// O(keys): playing or baking N frames of an N-key curve is O(N).
//
// Bad key data never crashes a compute: the node writes 0 (zero / the
// identity rotation for tracks) to `output` and the reason, naming the key
// ("keys[3].time: 1 is before keys[2].time 2 ..."), to its hidden `error`
// output, which is empty while the keys are valid.

#include "rigel/base/status.h"
#include "rigel/graph/node_type.h"

namespace rigel::ops::anim {

using graph::AttrIndex;

inline constexpr const char* kAnimCurveType = "animCurve";
inline constexpr const char* kDrivenKeyType = "drivenKey";
inline constexpr const char* kAnimCurveVec3Type = "animCurveVec3";
inline constexpr const char* kAnimCurveQuatType = "animCurveQuat";

// animCurve (time-dependent: reads the graph's time, in seconds) and
// drivenKey share these attributes, in this order. The arrays are
// CurveArrays: keyTimes and keyValues one entry per key; the others empty
// (defaults: auto tangents, slope 0, weight 1/3) or one entry per key.
namespace curve_attr {
enum : AttrIndex {
  kKeyTimes = 0,    // double[]: seconds (animCurve) or input units (drivenKey), increasing
  kKeyValues,       // double[]: the curve's unit (degrees for an angle channel)
  kInTangentType,   // enum[]: fixed linear flat step stepNext spline clamped plateau auto
  kOutTangentType,  // enum[]
  kInSlope,         // double[]: fixed tangents' slopes, value units per time unit
  kOutSlope,        // double[]
  kInWeight,        // double[]: weighted curves' handle lengths, fraction of the span
  kOutWeight,       // double[]
  kWeighted,        // bool
  kPreInfinity,     // enum: constant linear cycle cycleOffset oscillate
  kPostInfinity,    // enum
  kOutput,          // output double: the curve's value
  kError,           // output string, hidden: why the keys are invalid, or empty
  kCount
};
}  // namespace curve_attr

namespace driven_key_attr {
// drivenKey's driver: connect any double attribute (or set it).
enum : AttrIndex { kInput = curve_attr::kCount, kCount };
}  // namespace driven_key_attr

// Clips (glTF animations; DESIGN.md: "a glTF with several animations imports
// them all as clips"). A time-dependent curve (animCurve, animCurveVec3,
// animCurveQuat) may hold the keys of several clips one after the other:
// clipOffsets has clip_count + 1 entries, from 0 to the key count, and clip c
// owns keys [clipOffsets[c], clipOffsets[c+1]) of every per-key array. Each
// clip's keys are validated on their own (times increase within a clip, not
// across clips). `clip` picks the clip evaluated (connect it from an
// animClips node's activeClip, see clips.h); when that clip has no keys for
// this channel, or `clip` is out of range, the output is restValue, the
// value of the channel when no clip animates it. With clipOffsets empty all
// keys form one clip, and `clip` and restValue are ignored.
namespace anim_curve_attr {
enum : AttrIndex {
  kClipOffsets = curve_attr::kCount,  // int[]
  kClip,                              // int
  kRestValue,                         // double
  kCount
};
}  // namespace anim_curve_attr

// animCurveVec3 (translate/scale, double3) and animCurveQuat (rotation,
// quaternion): TrackArrays, time-dependent.
namespace track_attr {
enum : AttrIndex {
  kKeyTimes = 0,   // double[]: seconds, increasing
  kKeyValues,      // double3[] or quat[]
  kInTangents,     // double3[] or quat[]: cubic spline only (glTF a_k), else empty
  kOutTangents,    // double3[] or quat[]: cubic spline only (glTF b_k), else empty
  kInterpolation,  // enum: step linear cubicSpline (default linear)
  kOutput,         // output double3 or quat
  kError,          // output string, hidden
  kClipOffsets,    // int[]: see "Clips" above (anim_curve_attr)
  kClip,           // int
  kRestValue,      // double3 or quat
  kCount
};
}  // namespace track_attr

// Adds animCurve, drivenKey, animCurveVec3 and animCurveQuat to `registry`.
// Fails if one of the names is taken.
Status register_anim_types(graph::Registry& registry);

}  // namespace rigel::ops::anim
