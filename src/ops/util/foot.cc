#include "rigel/ops/util/foot.h"

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

// Reads the values, pivots and axes into `job` and names the first
// attribute the job cannot take.
std::string read_foot(graph::ComputeContext& c, ReverseFootJob& job) {
  std::string problem;
  ReverseFootValues& v = job.values;
  const std::pair<graph::AttrIndex, double*> values[] = {{a::kRoll, &v.roll},          {a::kRollBreak, &v.roll_break},
                                                         {a::kBank, &v.bank},          {a::kHeelTwist, &v.heel_twist},
                                                         {a::kToeTwist, &v.toe_twist}, {a::kBallTwist, &v.ball_twist},
                                                         {a::kToeTap, &v.toe_tap}};
  for (const auto& [attr, into] : values) {
    *into = c.get<double>(attr);
    if (!std::isfinite(*into) && problem.empty()) problem = c.node().type().attr(attr).name + " is not finite";
  }
  ReverseFootPivots& p = job.pivots;
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
    if (!(std::isfinite(length) && length > 0) && problem.empty())
      problem = c.node().type().attr(attr).name + " is zero or not finite";
  }
  return problem;
}

void compute_reverse_foot(graph::ComputeContext& c) {
  ReverseFootJob job;
  job.control = c.get<Mat4>(a::kControlMatrix);
  job.rest_ankle = c.get<Mat4>(a::kRestAnkleMatrix);
  job.rest_ball = c.get<Mat4>(a::kRestBallMatrix);
  Mat4 ankle, ball;
  job.ankle = &ankle;
  job.ball = &ball;
  std::string problem = read_foot(c, job);
  if (!problem.empty() || !job.run()) {
    // The rest pose under the control.
    const Mat4 identity = Mat4::Identity();
    ankle = job.control * identity * job.rest_ankle;
    ball = job.control * identity * job.rest_ball;
  }
  c.set(a::kOutAnkleMatrix, ankle);
  c.set(a::kOutBallMatrix, ball);
  c.set(a::kError, std::move(problem));
}

}  // namespace

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
