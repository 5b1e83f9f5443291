#include "rigel/ops/util/eyelid.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "rigel/graph/graph.h"
#include "rigel/math/rotation.h"
#include "rigel/math/transform.h"

namespace rigel::ops::util {
namespace {

using graph::ValueType;
using math::Mat4;
using math::Quat;
using math::Vec3;

constexpr double kDegrees = 180.0 / std::numbers::pi;

double clamped(const graph::ComputeContext& c, graph::AttrIndex attr) {
  const double v = c.get<double>(attr);
  return std::isfinite(v) ? std::clamp(v, 0.0, 1.0) : 0.0;
}

Vec3 turn_about(const Vec3& axis, double degrees) {
  const Quat q(Eigen::AngleAxisd(degrees / kDegrees, axis));
  return Vec3(math::quat_to_euler(q, math::RotateOrder::kXYZ) * kDegrees);
}

void compute_eyelid(graph::ComputeContext& c) {
  namespace a = eyelid_attr;
  Vec3 axis = c.get<Vec3>(a::kAxis);
  const bool usable = axis.allFinite() && axis.norm() > 1e-12;
  if (usable) axis.normalize();
  double pitch = 0.0;
  const Mat4& now = c.get<Mat4>(a::kEyeMatrix);
  const Mat4& rest = c.get<Mat4>(a::kEyeRestMatrix);
  if (usable && now.allFinite() && rest.allFinite())
    pitch = twist_degrees(math::decompose(rest).rotation, math::decompose(now).rotation, axis);
  if (!std::isfinite(pitch)) pitch = 0.0;
  const double blink = clamped(c, a::kBlink), height = clamped(c, a::kBlinkHeight);
  double gap = c.get<double>(a::kGap);
  if (!std::isfinite(gap)) gap = 0.0;
  const double upper = clamped(c, a::kUpperFollow) * pitch + gap * (1.0 - height) * blink;
  const double lower = clamped(c, a::kLowerFollow) * pitch - gap * height * blink;
  c.set(a::kUpperRotate, usable ? turn_about(axis, upper) : Vec3(Vec3::Zero()));
  c.set(a::kLowerRotate, usable ? turn_about(axis, lower) : Vec3(Vec3::Zero()));
  c.set(a::kPitch, pitch);
}

}  // namespace

double twist_degrees(const Quat& rest, const Quat& now, const Vec3& axis) {
  // The turn from rest to now in the parent's frame, its twist about axis.
  Quat delta = (now * rest.conjugate()).normalized();
  if (delta.w() < 0) delta.coeffs() = -delta.coeffs();
  const double along = delta.vec().dot(axis);
  return 2.0 * std::atan2(along, delta.w()) * kDegrees;
}

Status register_eyelid_types(graph::Registry& registry) {
  const std::vector<std::string> outs = {"upperRotate", "lowerRotate", "pitch"};
  const auto number = [&](const char* name, double value, std::uint32_t flags) {
    return graph::input_attr(name, {ValueType::kDouble, false}, value, outs, flags);
  };
  graph::NodeTypeSpec spec;
  spec.name = kEyelidBlinkType;
  spec.description = "Eyelids: turns that follow the eye's pitch by fractions and close them in a blink";
  spec.attrs = {graph::input_attr("eyeMatrix", {ValueType::kMatrix, false}, Mat4(Mat4::Identity()), outs),
                graph::input_attr("eyeRestMatrix", {ValueType::kMatrix, false}, Mat4(Mat4::Identity()), outs),
                graph::input_attr("axis", {ValueType::kDouble3, false}, Vec3(1, 0, 0), outs),
                number("upperFollow", 0.4, graph::kKeyable),
                number("lowerFollow", 0.2, graph::kKeyable),
                number("blink", 0.0, graph::kKeyable),
                number("blinkHeight", 0.3, graph::kKeyable),
                number("gap", 30.0, graph::kKeyable | graph::kAngle),
                graph::output_attr("upperRotate", {ValueType::kDouble3, false}, graph::kAngle),
                graph::output_attr("lowerRotate", {ValueType::kDouble3, false}, graph::kAngle),
                graph::output_attr("pitch", {ValueType::kDouble, false}, graph::kAngle)};
  spec.compute = compute_eyelid;
  return registry.add(std::move(spec));
}

}  // namespace rigel::ops::util
