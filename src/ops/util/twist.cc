#include "rigel/ops/util/twist.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "rigel/graph/graph.h"

namespace rigel::ops::util {
namespace {

using graph::ValueType;
using math::Mat4;
using math::Quat;
using math::Vec3;
namespace a = twist_attr;

constexpr std::int64_t kMaxCount = 1024;

void compute_twist(graph::ComputeContext& c) {
  const std::int64_t count = std::clamp<std::int64_t>(c.get<std::int64_t>(a::kCount), 0, kMaxCount);
  std::vector<Quat> out(static_cast<std::size_t>(count), Quat::Identity());
  double angle = 0.0;
  TwistShareJob job;
  job.axis = Vec3::Zero();
  job.axis[std::clamp<std::int64_t>(c.get<std::int64_t>(a::kAxis), 0, 2)] = 1.0;
  job.start = c.get<Mat4>(a::kStartMatrix);
  job.end = c.get<Mat4>(a::kEndMatrix);
  job.rest_relative = c.get<Quat>(a::kRestRelative);
  job.rotations = out;
  job.twist = &angle;
  const bool solved = job.run();
  c.set(a::kOutRotations, std::move(out));
  c.set(a::kTwist, solved ? math::to_degrees(angle) : 0.0);
  c.set(a::kError, solved ? std::string() : std::string("startMatrix, endMatrix or restRelative is singular or not finite"));
}

}  // namespace

Status register_twist_types(graph::Registry& registry) {
  const std::vector<std::string> outs = {"outRotations", "twist", "error"};
  graph::NodeTypeSpec spec;
  spec.name = kTwistShareType;
  spec.description = "Shares of an end joint's twist about the bone axis, for twist joints";
  graph::AttrSpec axis = graph::input_attr("axis", {ValueType::kEnum, false}, std::int64_t{1}, outs);
  axis.enum_names = {"x", "y", "z"};
  spec.attrs = {graph::input_attr("startMatrix", {ValueType::kMatrix, false}, Mat4(Mat4::Identity()), outs),
                graph::input_attr("endMatrix", {ValueType::kMatrix, false}, Mat4(Mat4::Identity()), outs),
                graph::input_attr("restRelative", {ValueType::kQuat, false}, Quat::Identity(), outs),
                axis,
                graph::input_attr("count", {ValueType::kInt, false}, std::int64_t{1}, outs),
                graph::output_attr("outRotations", {ValueType::kQuat, true}),
                graph::output_attr("twist", {ValueType::kDouble, false}),
                graph::output_attr("error", {ValueType::kString, false}, graph::kHidden)};
  spec.compute = compute_twist;
  return registry.add(std::move(spec));
}

}  // namespace rigel::ops::util
