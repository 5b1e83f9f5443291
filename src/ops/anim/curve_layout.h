#pragma once
// Where a time curve node keeps its keys: the per-key arrays of each curve
// kind and the key range of its active clip. Shared by the key edits of
// channel_keys.cc and key_copy.cc; private to ops/anim.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "rigel/graph/graph.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/ops/anim/nodes.h"

namespace rigel::ops::anim::internal {

using graph::AttrIndex;

// The arrays of a curve node that hold one entry per key, and its clips.
struct CurveLayout {
  AttrIndex times, values;
  std::vector<AttrIndex> per_key;  // besides times and values (empty or one per key)
  AttrIndex offsets, clip;
};
inline CurveLayout layout(CurveKind kind) {
  if (kind == CurveKind::kScalar)
    return {curve_attr::kKeyTimes,
            curve_attr::kKeyValues,
            {curve_attr::kInTangentType, curve_attr::kOutTangentType, curve_attr::kInSlope, curve_attr::kOutSlope,
             curve_attr::kInWeight, curve_attr::kOutWeight},
            anim_curve_attr::kClipOffsets,
            anim_curve_attr::kClip};
  return {track_attr::kKeyTimes,
          track_attr::kKeyValues,
          {track_attr::kInTangents, track_attr::kOutTangents},
          track_attr::kClipOffsets,
          track_attr::kClip};
}

// Keys [begin, end) of the active clip (all keys when the curve has no clips).
struct KeyRange {
  std::size_t begin = 0, end = 0;
  int clip = -1;  // -1: no clips
};
inline KeyRange active_range(const graph::Node& curve, const CurveLayout& l) {
  const auto& times = std::get<std::vector<double>>(curve.value(l.times));
  const auto& offsets = std::get<std::vector<std::int64_t>>(curve.value(l.offsets));
  KeyRange r{0, times.size(), -1};
  if (offsets.size() < 2) return r;
  const std::int64_t c = std::get<std::int64_t>(curve.value(l.clip));
  if (c < 0 || c + 1 >= static_cast<std::int64_t>(offsets.size())) return KeyRange{0, 0, -2};  // rest value
  r.begin = static_cast<std::size_t>(std::clamp<std::int64_t>(offsets[c], 0, static_cast<std::int64_t>(times.size())));
  r.end = static_cast<std::size_t>(std::clamp<std::int64_t>(offsets[c + 1], 0, static_cast<std::int64_t>(times.size())));
  r.clip = static_cast<int>(c);
  return r;
}


}  // namespace rigel::ops::anim::internal
