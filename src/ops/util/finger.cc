#include "rigel/ops/util/finger.h"

#include <string>
#include <vector>

#include "rigel/graph/graph.h"

namespace rigel::ops::util {
namespace {

using graph::ValueType;
using math::Mat4;
using math::Vec3;
namespace a = finger_attr;

// "WHAT[i] REASON", naming the attribute a FingerCurlJob problem is about.
std::string describe(const FingerCurlResult& r) {
  using Problem = FingerCurlResult::Problem;
  struct Text {
    const char* what;
    const char* reason;
  };
  Text t{"", ""};
  switch (r.problem) {
    case Problem::kNone: return {};
    case Problem::kMissingFinger: t = {"finger", "is missing"}; break;
    case Problem::kCurlNotFinite: t = {"outOffsetParentMatrix", "has a curl that is not finite"}; break;
    case Problem::kSpreadNotFinite: t = {"outOffsetParentMatrix", "has a spread that is not finite"}; break;
    case Problem::kBadBendAxis: t = {"bendAxis", "is missing, zero or not finite"}; break;
    case Problem::kBadSpreadAxis: t = {"spreadAxis", "is missing, zero or not finite"}; break;
  }
  std::string out = t.what;
  out += '[';
  out += std::to_string(r.control);
  out += "] ";
  out += t.reason;
  return out;
}

void compute_finger_curl(graph::ComputeContext& c) {
  FingerCurlJob job;
  job.curl = c.get<double>(a::kCurl);
  job.spread = c.get<double>(a::kSpread);
  job.finger_curl = c.get<std::vector<double>>(a::kFingerCurl);
  job.finger = c.get<std::vector<std::int64_t>>(a::kFinger);
  job.rest_offset_parent = c.get<std::vector<Mat4>>(a::kRestOffsetParentMatrix);
  job.bend_axis = c.get<std::vector<Vec3>>(a::kBendAxis);
  job.spread_axis = c.get<std::vector<Vec3>>(a::kSpreadAxis);
  job.spread_weight = c.get<std::vector<double>>(a::kSpreadWeight);
  std::vector<Mat4> out(job.rest_offset_parent.begin(), job.rest_offset_parent.end());
  job.output = out;
  FingerCurlResult result;
  job.result = &result;
  std::string problem = job.run() ? describe(result) : "fingerCurl: the job is not valid";  // unreachable: sized here
  c.set(a::kOutOffsetParentMatrix, std::move(out));
  c.set(a::kError, std::move(problem));
}

}  // namespace

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
