#include "rigel/ops/util/blend.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "rigel/graph/graph.h"
#include "rigel/math/rotation.h"
#include "rigel/math/transform.h"

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

template <typename T>
const T& element_or(const std::vector<T>& v, std::size_t i, const T& fallback) {
  return i < v.size() ? v[i] : fallback;
}

bool usable(const Mat4& m) {
  if (!m.allFinite()) return false;
  if (m(3, 0) != 0 || m(3, 1) != 0 || m(3, 2) != 0 || m(3, 3) != 1) return false;
  const double scale = m.topLeftCorner<3, 3>().cwiseAbs().maxCoeff();
  const double det = m.topLeftCorner<3, 3>().determinant();
  return scale > 0 && std::abs(det) > 1e-12 * scale * scale * scale;
}

Quat orient_quat(const Vec3& degrees) { return math::euler_to_quat(math::to_radians(degrees), math::RotateOrder::kXYZ); }

void compute_switch(graph::ComputeContext& c) {
  const double w = std::clamp(std::isfinite(c.get<double>(a::kFkIk)) ? c.get<double>(a::kFkIk) : 0.0, 0.0, 1.0);
  const Mat4& parent = c.get<Mat4>(a::kParentMatrix);
  const auto& fk = c.get<std::vector<Mat4>>(a::kFkMatrix);
  const auto& ik = c.get<std::vector<Mat4>>(a::kIkMatrix);
  const auto& offsets = c.get<std::vector<Mat4>>(a::kRestOffsetParentMatrix);
  const auto& orients = c.get<std::vector<Vec3>>(a::kRestJointOrient);
  const auto& axes = c.get<std::vector<Vec3>>(a::kRestRotateAxis);
  const bool use_end = c.get<bool>(a::kUseIkEndMatrix);
  const Mat4& end_matrix = c.get<Mat4>(a::kIkEndMatrix);
  const std::size_t n = offsets.size();
  const Mat4 identity = Mat4::Identity();
  const Vec3 zero = Vec3::Zero();

  std::vector<Vec3> translations(n, zero), scales(n, Vec3::Ones()), shears(n, zero);
  std::vector<Quat> rotations(n, Quat::Identity());
  std::vector<Mat4> worlds(n, identity);
  std::string problem;
  auto side = [&](const std::vector<Mat4>& mine, const std::vector<Mat4>& other, std::size_t i) -> const Mat4& {
    return i < mine.size() ? mine[i] : element_or(other, i, identity);
  };
  Mat4 fk_prev = parent, ik_prev = parent, prev = parent;
  if (!usable(parent)) problem = "parentMatrix is singular or not finite";
  for (std::size_t i = 0; i < n; ++i) {
    const Mat4& fk_world = side(fk, ik, i);
    Mat4 ik_world = side(ik, fk, i);
    if (use_end && i + 1 == n) ik_world = ik_end_world(ik_world, end_matrix);
    const Mat4& offset = offsets[i];
    const Mat4 fk_parent = fk_prev * offset, ik_parent = ik_prev * offset, blended_parent = prev * offset;
    Mat4 local = identity;
    if (problem.empty() && usable(fk_world) && usable(ik_world) && usable(fk_parent) && usable(ik_parent) &&
        usable(blended_parent)) {
      const math::Decomposed f = math::decompose(math::affine_inverse(fk_parent) * fk_world);
      const math::Decomposed k = math::decompose(math::affine_inverse(ik_parent) * ik_world);
      math::TransformParts p;
      p.translate = (1 - w) * f.translate + w * k.translate;
      p.rotate_mode = math::RotateMode::kQuaternion;
      p.rotate_quaternion = f.rotation.slerp(w, k.rotation).normalized();  // Eigen's slerp takes the short way
      p.scale = (1 - w) * f.scale + w * k.scale;
      p.shear = (1 - w) * f.shear + w * k.shear;
      local = math::compose(p);
      translations[i] = p.translate;
      scales[i] = p.scale;
      shears[i] = p.shear;
      const Vec3 jo = element_or(orients, i, zero), ra = element_or(axes, i, zero);
      rotations[i] = (orient_quat(jo).conjugate() * p.rotate_quaternion * orient_quat(ra).conjugate()).normalized();
      // The matrix the joint computes from these channels.
      p.rotate_quaternion = rotations[i];
      p.joint_orient = math::to_radians(jo);
      p.rotate_axis = math::to_radians(ra);
      local = math::compose(p);
    } else if (problem.empty()) {
      problem = "joint " + std::to_string(i) + ": fkMatrix, ikMatrix, ikEndMatrix or restOffsetParentMatrix is " +
                "singular or not finite";
    }
    worlds[i] = blended_parent * local;
    fk_prev = fk_world;
    ik_prev = ik_world;
    prev = worlds[i];
  }
  c.set(a::kOutTranslations, std::move(translations));
  c.set(a::kOutRotations, std::move(rotations));
  c.set(a::kOutScales, std::move(scales));
  c.set(a::kOutShears, std::move(shears));
  c.set(a::kOutWorldMatrices, std::move(worlds));
  c.set(a::kError, std::move(problem));
}

}  // namespace

Mat4 ik_end_world(const Mat4& ik_world, const Mat4& end_control_world) {
  Mat4 out = end_control_world;
  out.topRightCorner<3, 1>() = ik_world.topRightCorner<3, 1>();
  return out;
}

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
