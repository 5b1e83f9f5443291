#include "rigel/ops/anim/nodes.h"

#include <algorithm>
#include <string>
#include <vector>

#include "rigel/graph/graph.h"
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
  AttrSpec spec;
  spec.name = std::move(name);
  spec.type = type;
  spec.default_value = std::move(value);
  spec.flags = graph::kInput | graph::kStorable | extra;
  spec.affects = std::move(affects);
  return spec;
}

AttrSpec output(std::string name, AttrType type, std::uint32_t extra = 0) {
  AttrSpec spec;
  spec.name = std::move(name);
  spec.type = type;
  spec.flags = graph::kOutput | extra;
  return spec;
}

const std::vector<std::string> kOutputs = {"output", "error"};

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
      output("error", {ValueType::kString, false}, graph::kHidden),
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

// Evaluates the curve in the node's attributes at `x` (time or input).
void compute_curve_at(ComputeContext& c, double x) {
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
  const Status status = arrays.validate();
  c.output(a::kOutput) = status.is_ok() ? evaluate_arrays(arrays, x) : 0.0;
  write_error(c, a::kError, status);
}

void compute_anim_curve(ComputeContext& c) { compute_curve_at(c, c.time()); }

void compute_driven_key(ComputeContext& c) { compute_curve_at(c, c.get<double>(driven_key_attr::kInput)); }

template <typename T>
void compute_track(ComputeContext& c) {
  namespace a = track_attr;
  TrackArrays<T> arrays;
  arrays.times = c.get<std::vector<double>>(a::kKeyTimes);
  arrays.values = c.get<std::vector<T>>(a::kKeyValues);
  arrays.in_tangents = c.get<std::vector<T>>(a::kInTangents);
  arrays.out_tangents = c.get<std::vector<T>>(a::kOutTangents);
  arrays.interpolation = read_enum<Interpolation>(c, a::kInterpolation, kInterpolationCount);
  const Status status = arrays.validate();
  if (status.is_ok()) {
    c.output(a::kOutput) = evaluate_arrays(arrays, c.time());
  } else if constexpr (std::is_same_v<T, Quat>) {
    c.output(a::kOutput) = Quat(Quat::Identity());
  } else {
    c.output(a::kOutput) = Vec3(Vec3::Zero());
  }
  write_error(c, a::kError, status);
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
      output("error", {ValueType::kString, false}, graph::kHidden),
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
  curve.compute = compute_anim_curve;
  curve.time_dependent = true;

  graph::NodeTypeSpec driven;
  driven.name = kDrivenKeyType;
  driven.description = "A driven-key curve: keys over the value of its input attribute (set-driven keys)";
  driven.attrs = curve_attrs();
  driven.attrs.push_back(input("input", {ValueType::kDouble, false}, 0.0, kOutputs, graph::kKeyable));
  driven.compute = compute_driven_key;

  graph::NodeTypeSpec vec3 = track_spec<Vec3>(kAnimCurveVec3Type, ValueType::kDouble3,
                                              "A glTF translation or scale track: double3 keys in time (seconds)");
  graph::NodeTypeSpec quat = track_spec<Quat>(kAnimCurveQuatType, ValueType::kQuat,
                                              "A glTF rotation track: quaternion keys in time (seconds)");

  for (graph::NodeTypeSpec* spec : {&curve, &driven, &vec3, &quat}) {
    if (Status s = registry.add(std::move(*spec)); !s) return s;
  }
  return Status::ok();
}

}  // namespace rigel::ops::anim
