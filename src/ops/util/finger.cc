#include "rigel/ops/util/finger.h"

#include <cmath>
#include <string>
#include <vector>

#include "rigel/graph/graph.h"

namespace rigel::ops::util {
namespace {

using graph::AttrType;
using graph::ValueType;
using math::Mat3;
using math::Mat4;
using math::Vec3;
namespace a = finger_attr;

bool usable_axis(const Vec3& axis) { return axis.allFinite() && axis.norm() > 1e-12; }

void compute_finger_curl(graph::ComputeContext& c) {
  const double curl = c.get<double>(a::kCurl);
  const double spread = c.get<double>(a::kSpread);
  const auto& finger_curl = c.get<std::vector<double>>(a::kFingerCurl);
  const auto& finger = c.get<std::vector<std::int64_t>>(a::kFinger);
  const auto& rest = c.get<std::vector<Mat4>>(a::kRestOffsetParentMatrix);
  const auto& bend_axis = c.get<std::vector<Vec3>>(a::kBendAxis);
  const auto& spread_axis = c.get<std::vector<Vec3>>(a::kSpreadAxis);
  const auto& spread_weight = c.get<std::vector<double>>(a::kSpreadWeight);
  std::vector<Mat4> out(rest.size());
  std::string problem;
  // The first problem only: "WHAT[i] REASON".
  auto complain = [&](const char* what, std::size_t i, const char* reason) {
    if (!problem.empty()) return;
    problem = what;
    problem += '[';
    problem += std::to_string(i);
    problem += "] ";
    problem += reason;
  };
  for (std::size_t i = 0; i < rest.size(); ++i) {
    double curl_i = curl;
    if (i < finger.size()) {
      const std::int64_t k = finger[i];
      const auto index = static_cast<std::size_t>(k);
      if (k >= 0 && index < finger_curl.size()) curl_i += finger_curl[index];
    } else {
      complain("finger", i, "is missing");
    }
    double spread_i = i < spread_weight.size() ? spread * spread_weight[i] : 0.0;
    if (!std::isfinite(curl_i)) {
      complain("outOffsetParentMatrix", i, "has a curl that is not finite");
      curl_i = 0.0;
    }
    if (!std::isfinite(spread_i)) {
      complain("outOffsetParentMatrix", i, "has a spread that is not finite");
      spread_i = 0.0;
    }
    Vec3 bend = i < bend_axis.size() ? bend_axis[i] : Vec3(Vec3::Zero());
    Vec3 side = i < spread_axis.size() ? spread_axis[i] : Vec3(Vec3::Zero());
    if (curl_i != 0.0 && !usable_axis(bend)) {
      complain("bendAxis", i, "is missing, zero or not finite");
      curl_i = 0.0;
    }
    if (spread_i != 0.0 && !usable_axis(side)) {
      complain("spreadAxis", i, "is missing, zero or not finite");
      spread_i = 0.0;
    }
    if (curl_i != 0.0) bend.normalize();
    if (spread_i != 0.0) side.normalize();
    out[i] = finger_offset(rest[i], side, math::to_radians(spread_i), bend, math::to_radians(curl_i));
  }
  c.set(a::kOutOffsetParentMatrix, std::move(out));
  c.set(a::kError, std::move(problem));
}

}  // namespace

Mat4 finger_offset(const Mat4& rest_offset, const Vec3& spread_axis, double spread, const Vec3& bend_axis,
                   double curl) {
  if (spread == 0.0 && curl == 0.0) return rest_offset;
  Mat3 turn = Mat3::Identity();
  if (spread != 0.0) turn = Eigen::AngleAxisd(spread, spread_axis).toRotationMatrix();
  if (curl != 0.0) turn = turn * Eigen::AngleAxisd(curl, bend_axis).toRotationMatrix();
  Mat4 out = rest_offset;
  out.topLeftCorner<3, 3>() = rest_offset.topLeftCorner<3, 3>() * turn;
  return out;
}

Status register_finger_types(graph::Registry& registry) {
  const std::vector<std::string> outs = {"outOffsetParentMatrix", "error"};
  graph::NodeTypeSpec spec;
  spec.name = kFingerCurlType;
  spec.description = "Curl and spread of a hand's fingers, layered under the finger controls' channels";
  spec.attrs = {
      graph::input_attr("curl", {ValueType::kDouble, false}, 0.0, outs, graph::kKeyable | graph::kAngle),
      graph::input_attr("spread", {ValueType::kDouble, false}, 0.0, outs, graph::kKeyable | graph::kAngle),
      graph::input_attr("fingerCurl", {ValueType::kDouble, true}, std::vector<double>{}, outs,
                        graph::kKeyable | graph::kAngle),
      graph::input_attr("fingerNames", {ValueType::kString, true}, std::vector<std::string>{}, {}),
      graph::input_attr("finger", {ValueType::kInt, true}, std::vector<std::int64_t>{}, outs),
      graph::input_attr("restOffsetParentMatrix", {ValueType::kMatrix, true}, std::vector<Mat4>{}, outs),
      graph::input_attr("bendAxis", {ValueType::kDouble3, true}, std::vector<Vec3>{}, outs),
      graph::input_attr("spreadAxis", {ValueType::kDouble3, true}, std::vector<Vec3>{}, outs),
      graph::input_attr("spreadWeight", {ValueType::kDouble, true}, std::vector<double>{}, outs),
      graph::output_attr("outOffsetParentMatrix", {ValueType::kMatrix, true}),
      graph::output_attr("error", {ValueType::kString, false}, graph::kHidden)};
  spec.compute = compute_finger_curl;
  return registry.add(std::move(spec));
}

}  // namespace rigel::ops::util
