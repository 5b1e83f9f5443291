#include "rigel/ops/anim/nodes.h"

#include <algorithm>
#include <array>
#include <span>
#include <string>
#include <vector>

#include "rigel/graph/graph.h"
#include "rigel/ops/anim/clips.h"
#include "rigel/ops/anim/curve.h"
#include "rigel/ops/anim/track.h"

namespace rigel::ops::anim {
namespace {

using graph::AttrSpec;
using graph::AttrType;
using graph::ComputeContext;
using graph::Value;
using graph::ValueType;
using math::Quat;
using math::Vec3;

std::vector<std::string> names_of(std::span<const std::string_view> names) {
  return std::vector<std::string>(names.begin(), names.end());
}

AttrSpec input(std::string name, AttrType type, Value value, std::vector<std::string> affects,
               std::uint32_t extra = 0) {
  return graph::input_attr(std::move(name), type, std::move(value), std::move(affects), extra);
}

AttrSpec output(std::string name, AttrType type, std::uint32_t extra = 0) {
  return graph::output_attr(std::move(name), type, extra);
}

const std::vector<std::string> kOutputs = {"output", "error"};

// `error` holds the check of the keys, which does not depend on time (nor on
// a driven key's input): a time change leaves it clean (kTimeInvariant).
AttrSpec error_output() { return output("error", {ValueType::kString, false}, graph::kHidden | graph::kTimeInvariant); }

std::vector<AttrSpec> curve_attrs() {
  const AttrType doubles{ValueType::kDouble, true};
  const AttrType enums{ValueType::kEnum, true};
  AttrSpec in_type = input("inTangentType", enums, std::vector<std::int64_t>{}, kOutputs);
  in_type.enum_names = names_of(tangent_type_names());
  AttrSpec out_type = input("outTangentType", enums, std::vector<std::int64_t>{}, kOutputs);
  out_type.enum_names = names_of(tangent_type_names());
  AttrSpec pre = input("preInfinity", {ValueType::kEnum, false}, std::int64_t{0}, kOutputs);
  pre.enum_names = names_of(infinity_names());
  AttrSpec post = input("postInfinity", {ValueType::kEnum, false}, std::int64_t{0}, kOutputs);
  post.enum_names = names_of(infinity_names());
  return {
      input("keyTimes", doubles, std::vector<double>{}, kOutputs),
      input("keyValues", doubles, std::vector<double>{}, kOutputs),
      in_type,
      out_type,
      input("inSlope", doubles, std::vector<double>{}, kOutputs),
      input("outSlope", doubles, std::vector<double>{}, kOutputs),
      input("inWeight", doubles, std::vector<double>{}, kOutputs),
      input("outWeight", doubles, std::vector<double>{}, kOutputs),
      input("weighted", {ValueType::kBool, false}, false, kOutputs),
      pre,
      post,
      output("output", {ValueType::kDouble, false}),
      error_output(),
  };
}

template <typename E>
E read_enum(const ComputeContext& c, AttrIndex attr, int count) {
  // An enum fed by an int connection may be out of range: clamp it.
  return static_cast<E>(std::clamp<std::int64_t>(c.get<std::int64_t>(attr), 0, count - 1));
}

void write_error(ComputeContext& c, AttrIndex attr, const Status& status) {
  std::string& message = std::get<std::string>(c.output(attr));
  if (status.is_ok()) message.clear();
  else message = status.message();
}

// Whether the keys must be checked in this compute: `error` is dirty. While
// it is clean no input it depends on has changed since it was written (every
// key array affects it; time does not), so its message is the check's
// result. Playback then checks a curve's keys once, not at every frame
// (a check reads every key: per frame it made playing N frames of N keys
// cost N^2).
bool must_check(const ComputeContext& c, AttrIndex error_attr) { return c.node().is_dirty(error_attr); }

// ---- clips ------------------------------------------------------------------
// (nodes.h, "Clips"): which keys a curve evaluates.

// A per-key array must be empty or have one entry per key before it is cut
// into clips (each clip's own validation then checks the rest).
template <typename T>
Status check_per_key(std::span<const T> array, std::size_t key_count, const char* name) {
  if (array.empty() || array.size() == key_count) return Status::ok();
  return error(ErrorCode::kInvalidArgument, std::string(name) + ": " + std::to_string(array.size()) + " entries for " +
                         std::to_string(key_count) + " keys");
}

template <typename T>
std::span<const T> cut(std::span<const T> array, std::size_t first, std::size_t count) {
  return array.empty() ? array : array.subspan(first, count);
}

// clipOffsets checked: empty, or clip_count + 1 entries from 0 to key_count,
// never decreasing.
Status check_clip_offsets(std::span<const std::int64_t> offsets, std::size_t key_count) {
  if (offsets.empty()) return Status::ok();
  if (offsets.size() < 2) return error(ErrorCode::kInvalidArgument, "clipOffsets: needs at least 2 entries (0 and the key count)");
  if (offsets.front() != 0) return error(ErrorCode::kInvalidArgument, "clipOffsets[0]: must be 0, not " + std::to_string(offsets.front()));
  for (std::size_t i = 1; i < offsets.size(); ++i) {
    if (offsets[i] < offsets[i - 1]) {
      return error(ErrorCode::kInvalidArgument, "clipOffsets[" + std::to_string(i) + "]: " + std::to_string(offsets[i]) +
                             " is less than clipOffsets[" + std::to_string(i - 1) + "]");
    }
  }
  if (offsets.back() != static_cast<std::int64_t>(key_count)) {
    return error(ErrorCode::kInvalidArgument, "clipOffsets[" + std::to_string(offsets.size() - 1) + "]: must be the key count " +
                           std::to_string(key_count) + ", not " + std::to_string(offsets.back()));
  }
  return Status::ok();
}

// Validates every clip's keys with `validate_clip(first, count)`; then the
// keys of the active clip as [first, first + count), or nullopt when the
// active clip has none (the output is restValue).
struct ClipKeys {
  std::size_t first = 0;
  std::size_t count = 0;
};
template <typename Validate>
Result<std::optional<ClipKeys>> clip_keys(std::span<const std::int64_t> offsets, std::int64_t clip,
                                          std::size_t key_count, const Validate& validate_clip) {
  if (offsets.empty()) {
    if (Status s = validate_clip(0, key_count); !s) return s;
    return std::optional<ClipKeys>(ClipKeys{0, key_count});
  }
  const std::size_t clip_count = offsets.size() - 1;
  for (std::size_t k = 0; k < clip_count; ++k) {
    const auto first = static_cast<std::size_t>(offsets[k]);
    const auto count = static_cast<std::size_t>(offsets[k + 1] - offsets[k]);
    if (count == 0) continue;
    if (Status s = validate_clip(first, count); !s) {
      return error(ErrorCode::kInvalidArgument, "clip " + std::to_string(k) + " (keys from " + std::to_string(first) +
                             "): " + s.message());
    }
  }
  if (clip < 0 || static_cast<std::size_t>(clip) >= clip_count) return std::optional<ClipKeys>();
  const auto first = static_cast<std::size_t>(offsets[static_cast<std::size_t>(clip)]);
  const auto count = static_cast<std::size_t>(offsets[static_cast<std::size_t>(clip) + 1]) - first;
  if (count == 0) return std::optional<ClipKeys>();
  return std::optional<ClipKeys>(ClipKeys{first, count});
}

// The key and setting attributes of a curve: kKeyTimes .. kPostInfinity.
constexpr AttrIndex kCurveInputs = curve_attr::kPostInfinity + 1;

CurveArrays read_curve_arrays(const ComputeContext& c) {
  namespace a = curve_attr;
  CurveArrays arrays;
  arrays.times = c.get<std::vector<double>>(a::kKeyTimes);
  arrays.values = c.get<std::vector<double>>(a::kKeyValues);
  arrays.in_types = c.get<std::vector<std::int64_t>>(a::kInTangentType);
  arrays.out_types = c.get<std::vector<std::int64_t>>(a::kOutTangentType);
  arrays.in_slopes = c.get<std::vector<double>>(a::kInSlope);
  arrays.out_slopes = c.get<std::vector<double>>(a::kOutSlope);
  arrays.in_weights = c.get<std::vector<double>>(a::kInWeight);
  arrays.out_weights = c.get<std::vector<double>>(a::kOutWeight);
  arrays.settings.weighted = c.get<bool>(a::kWeighted);
  arrays.settings.pre_infinity = read_enum<Infinity>(c, a::kPreInfinity, kInfinityCount);
  arrays.settings.post_infinity = read_enum<Infinity>(c, a::kPostInfinity, kInfinityCount);
  return arrays;
}

// Keys [first, first + count) of every per-key array.
CurveArrays slice_curve(const CurveArrays& all, std::size_t first, std::size_t count) {
  CurveArrays part = all;
  part.times = cut(all.times, first, count);
  part.values = cut(all.values, first, count);
  part.in_types = cut(all.in_types, first, count);
  part.out_types = cut(all.out_types, first, count);
  part.in_slopes = cut(all.in_slopes, first, count);
  part.out_slopes = cut(all.out_slopes, first, count);
  part.in_weights = cut(all.in_weights, first, count);
  part.out_weights = cut(all.out_weights, first, count);
  return part;
}

// The check of every key, as `error` reports it (one clip of all keys when
// `offsets` is empty, else each clip's keys on their own), and the keys of
// clip `clip` (nullopt: none, the output is restValue).
Result<std::optional<ClipKeys>> check_curve(const CurveArrays& all, std::span<const std::int64_t> offsets,
                                            std::int64_t clip) {
  const std::size_t key_count = all.times.size();
  if (!offsets.empty()) {
    Status status = check_clip_offsets(offsets, key_count);
    for (const auto& [array, name] : {std::pair{all.values, "keyValues"}, std::pair{all.in_slopes, "inSlope"},
                                      std::pair{all.out_slopes, "outSlope"}, std::pair{all.in_weights, "inWeight"},
                                      std::pair{all.out_weights, "outWeight"}}) {
      if (status) status = check_per_key(array, key_count, name);
    }
    if (status) status = check_per_key(all.in_types, key_count, "inTangentType");
    if (status) status = check_per_key(all.out_types, key_count, "outTangentType");
    if (!status) return status;
  }
  // Without offsets the arrays' sizes are not checked yet: validate them whole.
  return clip_keys(offsets, clip, key_count, [&](std::size_t first, std::size_t count) {
    return offsets.empty() ? all.validate() : slice_curve(all, first, count).validate();
  });
}

// An animCurve's or drivenKey's keys compiled into an AnimCurve (the active
// clip's), kept between evaluations with a playback cursor: playing a frame
// costs a cursor check and a cubic instead of reading the key arrays and
// searching them. Rebuilt when a key, setting, clipOffsets or clip changes
// (their versions); the check's result is kept with it, so `error` is
// written from it and a time change checks nothing.
struct CurveCache final : graph::NodeCache {
  static constexpr std::size_t kVersions = kCurveInputs + 2;
  std::array<std::uint64_t, kVersions> versions{};
  bool built = false;
  Status status = Status::ok();
  bool rest = false;  // the active clip has no keys: the output is restValue
  AnimCurve curve;
  Cursor cursor;
};

// The node's compiled curve, rebuilt if its inputs changed. `clips`: an
// animCurve (clipOffsets, clip); a drivenKey has neither.
CurveCache& compiled_curve(ComputeContext& c, bool clips) {
  std::array<std::uint64_t, CurveCache::kVersions> now{};
  for (AttrIndex a = 0; a < kCurveInputs; ++a) now[a] = c.version(a);
  if (clips) {
    now[kCurveInputs] = c.version(anim_curve_attr::kClipOffsets);
    now[kCurveInputs + 1] = c.version(anim_curve_attr::kClip);
  }
  CurveCache& cache = c.cache<CurveCache>();
  if (cache.built && cache.versions == now) return cache;
  cache.versions = now;
  cache.built = true;
  cache.rest = false;
  cache.curve = AnimCurve();
  cache.cursor = Cursor{};
  const CurveArrays all = read_curve_arrays(c);
  const std::span<const std::int64_t> offsets =
      clips ? std::span<const std::int64_t>(c.get<std::vector<std::int64_t>>(anim_curve_attr::kClipOffsets))
            : std::span<const std::int64_t>();
  const auto keys = check_curve(all, offsets, clips ? c.get<std::int64_t>(anim_curve_attr::kClip) : 0);
  cache.status = keys ? Status::ok() : keys.status();
  if (!keys) return cache;
  if (!keys.value()) {
    cache.rest = true;
    return cache;
  }
  const CurveArrays active = slice_curve(all, keys.value()->first, keys.value()->count);
  auto built = AnimCurve::build(active.keys(), active.settings);
  if (built) cache.curve = std::move(built).value();
  else cache.status = built.status();
  return cache;
}

// Evaluates the node's curve at `x` (time or input) and writes `error` when
// it is dirty.
void compute_curve_at(ComputeContext& c, double x, bool clips) {
  namespace a = curve_attr;
  CurveCache& cache = compiled_curve(c, clips);
  double value = 0.0;
  if (cache.status.is_ok()) {
    value = cache.rest ? c.get<double>(anim_curve_attr::kRestValue) : cache.curve.evaluate(x, cache.cursor);
  }
  c.output(a::kOutput) = value;
  if (c.node().is_dirty(a::kError)) write_error(c, a::kError, cache.status);
}

void compute_anim_curve(ComputeContext& c) { compute_curve_at(c, c.time(), true); }

void compute_driven_key(ComputeContext& c) { compute_curve_at(c, c.get<double>(driven_key_attr::kInput), false); }

// An animCurveVec3's or animCurveQuat's keys (the active clip's) built into
// a Track, kept between evaluations with a playback cursor, as CurveCache
// keeps a curve: playing a frame costs a cursor check and one interpolation
// (a linear rotation's slerp prepared when built) instead of checking the
// key arrays and searching them. Rebuilt when a key array, the
// interpolation, clipOffsets or clip changes (their versions); the check's
// result is kept with it, so `error` is written from it.
template <typename T>
struct TrackCache final : graph::NodeCache {
  static constexpr std::array<AttrIndex, 7> kInputs = {track_attr::kKeyTimes,      track_attr::kKeyValues,
                                                      track_attr::kInTangents,    track_attr::kOutTangents,
                                                      track_attr::kInterpolation, track_attr::kClipOffsets,
                                                      track_attr::kClip};
  std::array<std::uint64_t, kInputs.size()> versions{};
  bool built = false;
  Status status = Status::ok();
  bool rest = false;  // the active clip has no keys: the output is restValue
  Track<T> track;
  Cursor cursor;
};

// The check of every key (as `error` reports it) and the active clip's keys
// built into cache.track.
template <typename T>
void build_track(ComputeContext& c, TrackCache<T>& cache) {
  namespace a = track_attr;
  TrackArrays<T> all;
  all.times = c.get<std::vector<double>>(a::kKeyTimes);
  all.values = c.get<std::vector<T>>(a::kKeyValues);
  all.in_tangents = c.get<std::vector<T>>(a::kInTangents);
  all.out_tangents = c.get<std::vector<T>>(a::kOutTangents);
  all.interpolation = read_enum<Interpolation>(c, a::kInterpolation, kInterpolationCount);
  const auto& offsets = c.get<std::vector<std::int64_t>>(a::kClipOffsets);
  const std::size_t key_count = all.times.size();
  cache.status = Status::ok();
  cache.rest = false;
  cache.track = Track<T>();
  cache.cursor = Cursor{};
  if (!offsets.empty()) {
    cache.status = check_clip_offsets(offsets, key_count);
    if (cache.status) cache.status = check_per_key(all.values, key_count, "keyValues");
    if (cache.status) cache.status = check_per_key(all.in_tangents, key_count, "inTangents");
    if (cache.status) cache.status = check_per_key(all.out_tangents, key_count, "outTangents");
    if (!cache.status) return;
  }
  const auto slice = [&all](std::size_t first, std::size_t count) {
    TrackArrays<T> part = all;
    part.times = cut(all.times, first, count);
    part.values = cut(all.values, first, count);
    part.in_tangents = cut(all.in_tangents, first, count);
    part.out_tangents = cut(all.out_tangents, first, count);
    return part;
  };
  auto keys = clip_keys(offsets, c.get<std::int64_t>(a::kClip), key_count,
                        [&](std::size_t first, std::size_t count) { return slice(first, count).validate(); });
  if (!keys) {
    cache.status = keys.status();
    return;
  }
  if (!keys.value()) {
    cache.rest = true;
    return;
  }
  const TrackArrays<T> active = slice(keys.value()->first, keys.value()->count);
  auto built = Track<T>::build(std::vector<double>(active.times.begin(), active.times.end()),
                               std::vector<T>(active.values.begin(), active.values.end()), active.interpolation,
                               std::vector<T>(active.in_tangents.begin(), active.in_tangents.end()),
                               std::vector<T>(active.out_tangents.begin(), active.out_tangents.end()));
  if (built) cache.track = std::move(built).value();
  else cache.status = built.status();
}

template <typename T>
void compute_track(ComputeContext& c) {
  namespace a = track_attr;
  TrackCache<T>& cache = c.cache<TrackCache<T>>();
  std::array<std::uint64_t, TrackCache<T>::kInputs.size()> now{};
  for (std::size_t i = 0; i < now.size(); ++i) now[i] = c.version(TrackCache<T>::kInputs[i]);
  if (!cache.built || cache.versions != now) {
    build_track(c, cache);
    cache.versions = now;
    cache.built = true;
  }
  if (cache.status.is_ok()) {
    c.output(a::kOutput) = cache.rest ? c.get<T>(a::kRestValue) : cache.track.evaluate(c.time(), cache.cursor);
  } else if constexpr (std::is_same_v<T, Quat>) {
    c.output(a::kOutput) = Quat(Quat::Identity());
  } else {
    c.output(a::kOutput) = Vec3(Vec3::Zero());
  }
  if (must_check(c, a::kError)) write_error(c, a::kError, cache.status);
}

template <typename T>
Value rest_default() {
  if constexpr (std::is_same_v<T, Quat>) return Quat(Quat::Identity());
  else return Vec3(Vec3::Zero());
}

template <typename T>
graph::NodeTypeSpec track_spec(std::string name, ValueType value_type, std::string description) {
  const AttrType values{value_type, true};
  AttrSpec interpolation = input("interpolation", {ValueType::kEnum, false},
                                 std::int64_t{static_cast<int>(Interpolation::kLinear)}, kOutputs);
  interpolation.enum_names = names_of(interpolation_names());
  graph::NodeTypeSpec spec;
  spec.name = std::move(name);
  spec.description = std::move(description);
  spec.attrs = {
      input("keyTimes", {ValueType::kDouble, true}, std::vector<double>{}, kOutputs),
      input("keyValues", values, std::vector<T>{}, kOutputs),
      input("inTangents", values, std::vector<T>{}, kOutputs),
      input("outTangents", values, std::vector<T>{}, kOutputs),
      interpolation,
      output("output", {value_type, false}),
      error_output(),
      input("clipOffsets", {ValueType::kInt, true}, std::vector<std::int64_t>{}, kOutputs),
      input("clip", {ValueType::kInt, false}, std::int64_t{0}, kOutputs),
      input("restValue", {value_type, false}, rest_default<T>(), kOutputs),
  };
  spec.compute = compute_track<T>;
  spec.time_dependent = true;
  return spec;
}

}  // namespace

Status register_anim_types(graph::Registry& registry) {
  graph::NodeTypeSpec curve;
  curve.name = kAnimCurveType;
  curve.description = "An animation curve: keys in time (seconds) with Maya's tangents and infinities";
  curve.attrs = curve_attrs();
  curve.attrs.push_back(input("clipOffsets", {ValueType::kInt, true}, std::vector<std::int64_t>{}, kOutputs));
  curve.attrs.push_back(input("clip", {ValueType::kInt, false}, std::int64_t{0}, kOutputs));
  curve.attrs.push_back(input("restValue", {ValueType::kDouble, false}, 0.0, kOutputs));
  curve.compute = compute_anim_curve;
  curve.time_dependent = true;

  graph::NodeTypeSpec driven;
  driven.name = kDrivenKeyType;
  driven.description = "A driven-key curve: keys over the value of its input attribute (set-driven keys)";
  driven.attrs = curve_attrs();
  driven.attrs.push_back(input("input", {ValueType::kDouble, false}, 0.0, {"output"}, graph::kKeyable));
  driven.compute = compute_driven_key;

  graph::NodeTypeSpec vec3 = track_spec<Vec3>(kAnimCurveVec3Type, ValueType::kDouble3,
                                              "A glTF translation or scale track: double3 keys in time (seconds)");
  graph::NodeTypeSpec quat = track_spec<Quat>(kAnimCurveQuatType, ValueType::kQuat,
                                              "A glTF rotation track: quaternion keys in time (seconds)");

  for (graph::NodeTypeSpec* spec : {&curve, &driven, &vec3, &quat}) {
    if (Status s = registry.add(std::move(*spec)); !s) return s;
  }
  return register_clip_types(registry);
}

}  // namespace rigel::ops::anim
