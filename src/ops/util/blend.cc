#include "rigel/ops/util/blend.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "rigel/graph/graph.h"

namespace rigel::ops::util {
namespace {

using graph::AttrType;
using graph::ValueType;
using math::Mat4;
using math::Quat;
using math::Vec3;
namespace a = fk_ik_attr;

constexpr AttrType kMatrix{ValueType::kMatrix, false};
constexpr AttrType kMatrixArray{ValueType::kMatrix, true};
constexpr AttrType kVec3Array{ValueType::kDouble3, true};
constexpr AttrType kQuatArray{ValueType::kQuat, true};

void compute_switch(graph::ComputeContext& c) {
  const std::size_t n = c.get<std::vector<Mat4>>(a::kRestOffsetParentMatrix).size();
  std::vector<Vec3> translations(n, Vec3::Zero()), scales(n, Vec3::Ones()), shears(n, Vec3::Zero());
  std::vector<Quat> rotations(n, Quat::Identity());
  std::vector<Mat4> worlds(n, Mat4::Identity());
  FkIkBlendJob job;
  job.fk_ik = std::clamp(std::isfinite(c.get<double>(a::kFkIk)) ? c.get<double>(a::kFkIk) : 0.0, 0.0, 1.0);
  job.parent = c.get<Mat4>(a::kParentMatrix);
  job.fk_world = c.get<std::vector<Mat4>>(a::kFkMatrix);
  job.ik_world = c.get<std::vector<Mat4>>(a::kIkMatrix);
  job.use_ik_end = c.get<bool>(a::kUseIkEndMatrix);
  job.ik_end = c.get<Mat4>(a::kIkEndMatrix);
  job.rest_offset_parent = c.get<std::vector<Mat4>>(a::kRestOffsetParentMatrix);
  job.rest_joint_orient = c.get<std::vector<Vec3>>(a::kRestJointOrient);
  job.rest_rotate_axis = c.get<std::vector<Vec3>>(a::kRestRotateAxis);
  job.translations = translations;
  job.rotations = rotations;
  job.scales = scales;
  job.shears = shears;
  job.worlds = worlds;
  FkIkBlendResult result;
  job.result = &result;
  std::string problem;
  if (!job.run()) {
    problem = "fkIkSwitch: the blend's inputs are not valid";  // unreachable: the node sizes and clamps them
  } else if (result.unusable_parent) {
    problem = "parentMatrix is singular or not finite";
  } else if (result.unusable_joint >= 0) {
    problem = "joint " + std::to_string(result.unusable_joint) +
              ": fkMatrix, ikMatrix, ikEndMatrix or restOffsetParentMatrix is singular or not finite";
  }
  c.set(a::kOutTranslations, std::move(translations));
  c.set(a::kOutRotations, std::move(rotations));
  c.set(a::kOutScales, std::move(scales));
  c.set(a::kOutShears, std::move(shears));
  c.set(a::kOutWorldMatrices, std::move(worlds));
  c.set(a::kError, std::move(problem));
}

}  // namespace

Status register_blend_types(graph::Registry& registry) {
  const std::vector<std::string> outs = {"outTranslations", "outRotations", "outScales", "outShears",
                                         "outWorldMatrices", "error"};
  graph::NodeTypeSpec spec;
  spec.name = kFkIkSwitchType;
  spec.description = "Blends a chain's FK and IK world poses (fkIk) into joint channels";
  graph::AttrSpec fk_ik = graph::input_attr("fkIk", {ValueType::kDouble, false}, 0.0, outs, graph::kKeyable);
  spec.attrs = {fk_ik,
                graph::input_attr("parentMatrix", kMatrix, Mat4(Mat4::Identity()), outs),
                graph::input_attr("fkMatrix", kMatrixArray, std::vector<Mat4>{}, outs),
                graph::input_attr("ikMatrix", kMatrixArray, std::vector<Mat4>{}, outs),
                graph::input_attr("useIkEndMatrix", {ValueType::kBool, false}, false, outs),
                graph::input_attr("ikEndMatrix", kMatrix, Mat4(Mat4::Identity()), outs),
                graph::input_attr("restOffsetParentMatrix", kMatrixArray, std::vector<Mat4>{}, outs),
                graph::input_attr("restJointOrient", kVec3Array, std::vector<Vec3>{}, outs, graph::kAngle),
                graph::input_attr("restRotateAxis", kVec3Array, std::vector<Vec3>{}, outs, graph::kAngle),
                graph::output_attr("outTranslations", kVec3Array),
                graph::output_attr("outRotations", kQuatArray),
                graph::output_attr("outScales", kVec3Array),
                graph::output_attr("outShears", kVec3Array),
                graph::output_attr("outWorldMatrices", kMatrixArray, graph::kHidden),
                graph::output_attr("error", {ValueType::kString, false}, graph::kHidden)};
  spec.compute = compute_switch;
  return registry.add(std::move(spec));
}

}  // namespace rigel::ops::util
