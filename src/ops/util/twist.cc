#include "rigel/ops/util/twist.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "rigel/graph/graph.h"
#include "rigel/math/transform.h"

namespace rigel::ops::util {
namespace {

using graph::ValueType;
using math::Mat4;
using math::Quat;
using math::Vec3;
namespace a = twist_attr;

constexpr std::int64_t kMaxCount = 1024;

bool usable(const Mat4& m) {
  if (!m.allFinite()) return false;
  const double scale = m.topLeftCorner<3, 3>().cwiseAbs().maxCoeff();
  return scale > 0 && std::abs(m.topLeftCorner<3, 3>().determinant()) > 1e-12 * scale * scale * scale;
}

void compute_twist(graph::ComputeContext& c) {
  const std::int64_t count = std::clamp<std::int64_t>(c.get<std::int64_t>(a::kCount), 0, kMaxCount);
  Vec3 axis = Vec3::Zero();
  axis[std::clamp<std::int64_t>(c.get<std::int64_t>(a::kAxis), 0, 2)] = 1.0;
  const Mat4& start = c.get<Mat4>(a::kStartMatrix);
  const Mat4& end = c.get<Mat4>(a::kEndMatrix);
  const Quat& rest = c.get<Quat>(a::kRestRelative);
  std::vector<Quat> out(static_cast<std::size_t>(count), Quat::Identity());
  if (!usable(start) || !usable(end) || !rest.coeffs().allFinite() || rest.norm() < 1e-12) {
    c.set(a::kOutRotations, std::move(out));
    c.set(a::kTwist, 0.0);
    c.set(a::kError, std::string("startMatrix, endMatrix or restRelative is singular or not finite"));
    return;
  }
  const Quat relative = math::decompose(start).rotation.conjugate() * math::decompose(end).rotation;
  const double angle = twist_angle(relative * rest.normalized().conjugate(), axis);
  for (std::int64_t i = 0; i < count; ++i)
    out[i] = Quat(Eigen::AngleAxisd(angle * double(i + 1) / double(count + 1), axis));
  c.set(a::kOutRotations, std::move(out));
  c.set(a::kTwist, math::to_degrees(angle));
  c.set(a::kError, std::string());
}

}  // namespace

double twist_angle(const Quat& q, const Vec3& axis) {
  Quat u = q.normalized();
  if (u.w() < 0) u.coeffs() = -u.coeffs();  // the short way: angle within (-pi, pi]
  const double along = u.vec().dot(axis);
  if (std::abs(along) < 1e-300 && std::abs(u.w()) < 1e-300) return 0.0;  // a half turn of swing: no twist
  return 2.0 * std::atan2(along, u.w());
}

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
