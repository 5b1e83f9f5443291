#include "rigel/ops/util/foot.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "rigel/graph/graph.h"

namespace rigel::ops::util {
namespace {

using graph::AttrType;
using graph::ValueType;
using math::Mat4;
using math::Vec3;
namespace a = reverse_foot_attr;

constexpr AttrType kMatrix{ValueType::kMatrix, false};
constexpr AttrType kDouble{ValueType::kDouble, false};
constexpr AttrType kDouble3{ValueType::kDouble3, false};

// The rotation by `degrees` about the line through `pivot` along the unit
// `axis`; exactly the identity at 0, so a foot at rest gives its rest pose
// bit for bit.
Mat4 pivot_turn(const Vec3& pivot, const Vec3& axis, double degrees) {
  Mat4 m = Mat4::Identity();
  if (degrees == 0.0) return m;
  const math::Mat3 r = Eigen::AngleAxisd(math::to_radians(degrees), axis).toRotationMatrix();
  m.topLeftCorner<3, 3>() = r;
  m.topRightCorner<3, 1>() = pivot - r * pivot;
  return m;
}

void compute_reverse_foot(graph::ComputeContext& c) {
  const Mat4& control = c.get<Mat4>(a::kControlMatrix);
  const Mat4& rest_ankle = c.get<Mat4>(a::kRestAnkleMatrix);
  const Mat4& rest_ball = c.get<Mat4>(a::kRestBallMatrix);
  std::string problem;
  ReverseFootValues v;
  const std::pair<graph::AttrIndex, double*> values[] = {{a::kRoll, &v.roll},          {a::kRollBreak, &v.roll_break},
                                                         {a::kBank, &v.bank},          {a::kHeelTwist, &v.heel_twist},
                                                         {a::kToeTwist, &v.toe_twist}, {a::kBallTwist, &v.ball_twist},
                                                         {a::kToeTap, &v.toe_tap}};
  for (const auto& [attr, into] : values) {
    *into = c.get<double>(attr);
    if (!std::isfinite(*into) && problem.empty()) problem = c.node().type().attr(attr).name + " is not finite";
  }
  ReverseFootPivots p;
  const std::pair<graph::AttrIndex, Vec3*> points[] = {{a::kHeelPivot, &p.heel},
                                                       {a::kToePivot, &p.toe},
                                                       {a::kBallPivot, &p.ball},
                                                       {a::kInnerPivot, &p.inner},
                                                       {a::kOuterPivot, &p.outer}};
  for (const auto& [attr, into] : points) {
    *into = c.get<Vec3>(attr);
    if (!into->allFinite() && problem.empty()) problem = c.node().type().attr(attr).name + " is not finite";
  }
  const std::pair<graph::AttrIndex, Vec3*> axes[] = {
      {a::kRollAxis, &p.roll_axis}, {a::kBankAxis, &p.bank_axis}, {a::kTwistAxis, &p.twist_axis}};
  for (const auto& [attr, into] : axes) {
    *into = c.get<Vec3>(attr);
    const double length = into->norm();
    if (!(std::isfinite(length) && length > 0)) {
      if (problem.empty()) problem = c.node().type().attr(attr).name + " is zero or not finite";
    } else {
      *into /= length;
    }
  }
  ReverseFootChain chain;
  if (problem.empty()) chain = reverse_foot_chain(p, v);
  c.set(a::kOutAnkleMatrix, Mat4(control * chain.ankle * rest_ankle));
  c.set(a::kOutBallMatrix, Mat4(control * chain.ball * rest_ball));
  c.set(a::kError, std::move(problem));
}

}  // namespace

ReverseFootChain reverse_foot_chain(const ReverseFootPivots& p, const ReverseFootValues& v) {
  const double roll_break = std::max(v.roll_break, 0.0);
  const double heel_roll = std::min(v.roll, 0.0);
  const double ball_roll = std::clamp(v.roll, 0.0, roll_break);
  const double toe_roll = std::max(v.roll - roll_break, 0.0);
  // The pivots nest as the transforms of a Maya reverse foot would: heel,
  // toe tip, bank, then the ball (ankle branch) or the toe tap (toe branch).
  const Mat4 shared = pivot_turn(p.heel, p.twist_axis, v.heel_twist) * pivot_turn(p.heel, p.roll_axis, heel_roll) *
                      pivot_turn(p.toe, p.twist_axis, v.toe_twist) * pivot_turn(p.toe, p.roll_axis, toe_roll) *
                      pivot_turn(v.bank > 0 ? p.outer : p.inner, p.bank_axis, v.bank);
  ReverseFootChain out;
  out.ankle = shared * pivot_turn(p.ball, p.twist_axis, v.ball_twist) * pivot_turn(p.ball, p.roll_axis, ball_roll);
  out.ball = shared * pivot_turn(p.ball, p.roll_axis, -v.toe_tap);
  return out;
}

Status register_foot_types(graph::Registry& registry) {
  const std::vector<std::string> outs = {"outAnkleMatrix", "outBallMatrix", "error"};
  const auto value = [&](const char* name, double fallback) {
    return graph::input_attr(name, kDouble, fallback, outs, graph::kKeyable | graph::kAngle);
  };
  const auto point = [&](const char* name) { return graph::input_attr(name, kDouble3, Vec3(Vec3::Zero()), outs); };
  graph::NodeTypeSpec spec;
  spec.name = kReverseFootType;
  spec.description = "A reverse foot's heel, toe, bank and ball pivots: the ankle's and ball joint's world matrices";
  spec.attrs = {value("roll", 0.0),
                value("rollBreak", 30.0),
                value("bank", 0.0),
                value("heelTwist", 0.0),
                value("toeTwist", 0.0),
                value("ballTwist", 0.0),
                value("toeTap", 0.0),
                graph::input_attr("controlMatrix", kMatrix, Mat4(Mat4::Identity()), outs),
                point("heelPivot"),
                point("toePivot"),
                point("ballPivot"),
                point("innerPivot"),
                point("outerPivot"),
                graph::input_attr("rollAxis", kDouble3, Vec3(Vec3::UnitX()), outs),
                graph::input_attr("bankAxis", kDouble3, Vec3(-Vec3::UnitZ()), outs),
                graph::input_attr("twistAxis", kDouble3, Vec3(Vec3::UnitY()), outs),
                graph::input_attr("restAnkleMatrix", kMatrix, Mat4(Mat4::Identity()), outs),
                graph::input_attr("restBallMatrix", kMatrix, Mat4(Mat4::Identity()), outs),
                graph::output_attr("outAnkleMatrix", kMatrix),
                graph::output_attr("outBallMatrix", kMatrix),
                graph::output_attr("error", {ValueType::kString, false}, graph::kHidden)};
  spec.compute = compute_reverse_foot;
  return registry.add(std::move(spec));
}

}  // namespace rigel::ops::util
