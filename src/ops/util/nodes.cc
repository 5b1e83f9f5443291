#include "rigel/ops/util/nodes.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "rigel/graph/graph.h"
#include "rigel/math/rotation.h"
#include "rigel/math/transform.h"
#include "rigel/math/types.h"
#include "rigel/ops/util/blend.h"
#include "rigel/ops/util/eyelid.h"
#include "rigel/ops/util/finger.h"
#include "rigel/ops/util/foot.h"
#include "rigel/ops/util/space.h"
#include "rigel/ops/util/spring.h"
#include "rigel/ops/util/twist.h"

namespace rigel::ops::util {
namespace {

using graph::AttrType;
using graph::ValueType;
using math::Mat4;

constexpr AttrType kMatrix{ValueType::kMatrix, false};

enum : graph::AttrIndex { kInputMatrix = 0, kOffsetMatrix, kOutputMatrix, kError };

void compute_inverse(graph::ComputeContext& c) {
  const Mat4 m = c.get<Mat4>(kInputMatrix) * c.get<Mat4>(kOffsetMatrix);
  const double det = m.topLeftCorner<3, 3>().determinant();
  const double scale = m.topLeftCorner<3, 3>().cwiseAbs().maxCoeff();
  if (!std::isfinite(det) || !m.allFinite() || std::abs(det) <= 1e-12 * scale * scale * scale || scale == 0) {
    c.set(kOutputMatrix, Mat4(Mat4::Identity()));
    c.set(kError, std::string("inputMatrix * offsetMatrix is singular or not finite"));
    return;
  }
  c.set(kOutputMatrix, Mat4(m.inverse()));
  c.set(kError, std::string());
}

// The rotation of `matrix` relative to `restMatrix` (their rotation parts,
// scale and shear taken out): the swing of `axis` in degrees, and the
// relative rotation as Euler XYZ degrees.
void compute_pose_reader(graph::ComputeContext& c) {
  namespace pr = pose_reader_attr;
  const math::Quat now = math::decompose(c.get<Mat4>(pr::kMatrix)).rotation;
  const math::Quat rest = math::decompose(c.get<Mat4>(pr::kRestMatrix)).rotation;
  const math::Quat delta = (rest.conjugate() * now).normalized();
  math::Vec3 axis = c.get<math::Vec3>(pr::kAxis);
  double angle = 0.0;
  if (axis.norm() > 0 && axis.allFinite()) {
    axis.normalize();
    const math::Vec3 turned = delta * axis;
    angle = std::atan2(axis.cross(turned).norm(), axis.dot(turned)) * 180.0 / std::numbers::pi;
  }
  c.set(pr::kAngle, angle);
  c.set(pr::kRotate, math::Vec3(math::quat_to_euler(delta, math::RotateOrder::kXYZ) * (180.0 / std::numbers::pi)));
}

void compute_squash_stretch(graph::ComputeContext& c) {
  namespace sq = squash_attr;
  const math::Vec3 a = c.get<Mat4>(sq::kStartMatrix).topRightCorner<3, 1>();
  const math::Vec3 b = c.get<Mat4>(sq::kEndMatrix).topRightCorner<3, 1>();
  const double rest = c.get<double>(sq::kRestLength);
  double stretch = rest > 0 && std::isfinite(rest) ? (b - a).norm() / rest : 1.0;
  if (!std::isfinite(stretch) || stretch <= 0) stretch = 1.0;
  const double volume = std::clamp(c.get<double>(sq::kVolume), 0.0, 1.0);
  const double other = std::pow(stretch, -0.5 * volume);
  const auto axis = std::clamp<std::int64_t>(c.get<std::int64_t>(sq::kAxis), 0, 2);
  math::Vec3 scale = c.get<math::Vec3>(sq::kRestScale);
  for (int k = 0; k < 3; ++k) scale[k] *= k == axis ? stretch : other;
  c.set(sq::kStretch, stretch);
  c.set(sq::kScale, scale);
}

void compute_wheel_roll(graph::ComputeContext& c) {
  namespace wh = wheel_attr;
  const Mat4 now = c.get<Mat4>(wh::kMatrix), rest = c.get<Mat4>(wh::kRestMatrix);
  math::Vec3 forward = math::decompose(rest).rotation * c.get<math::Vec3>(wh::kForward);
  const double radius = c.get<double>(wh::kRadius);
  double travel = 0.0;
  if (forward.norm() > 0 && forward.allFinite()) {
    forward.normalize();
    travel = (now.topRightCorner<3, 1>() - rest.topRightCorner<3, 1>()).dot(forward);
  }
  if (!std::isfinite(travel)) travel = 0.0;
  math::Vec3 axle = c.get<math::Vec3>(wh::kAxle);
  if (!(axle.norm() > 0) || !axle.allFinite()) axle = math::Vec3::Zero();
  else axle.normalize();
  const double angle = radius > 0 && std::isfinite(radius) ? travel / radius * 180.0 / std::numbers::pi : 0.0;
  c.set(wh::kTravel, travel);
  c.set(wh::kRotate, math::Vec3(axle * angle));
}

}  // namespace

Status register_util_types(graph::Registry& registry) {
  graph::NodeTypeSpec spec;
  spec.name = kInverseMatrixType;
  spec.description = "outputMatrix = (inputMatrix * offsetMatrix)^-1";
  spec.attrs = {graph::input_attr("inputMatrix", kMatrix, Mat4(Mat4::Identity()), {"outputMatrix", "error"}),
                graph::input_attr("offsetMatrix", kMatrix, Mat4(Mat4::Identity()), {"outputMatrix", "error"}),
                graph::output_attr("outputMatrix", kMatrix),
                graph::output_attr("error", {ValueType::kString, false}, graph::kHidden)};
  spec.compute = compute_inverse;
  if (Status s = registry.add(std::move(spec)); !s) return s;
  graph::NodeTypeSpec reader;
  reader.name = kPoseReaderType;
  reader.description = "A joint's rotation from its rest: the swing angle of an axis and Euler XYZ angles (degrees)";
  reader.attrs = {graph::input_attr("matrix", kMatrix, Mat4(Mat4::Identity()), {"angle", "rotate"}),
                  graph::input_attr("restMatrix", kMatrix, Mat4(Mat4::Identity()), {"angle", "rotate"}),
                  graph::input_attr("axis", {ValueType::kDouble3, false}, math::Vec3(1, 0, 0), {"angle"}),
                  graph::output_attr("angle", {ValueType::kDouble, false}, graph::kAngle),
                  graph::output_attr("rotate", {ValueType::kDouble3, false}, graph::kAngle)};
  reader.compute = compute_pose_reader;
  if (Status s = registry.add(std::move(reader)); !s) return s;
  graph::NodeTypeSpec squash;
  squash.name = kSquashStretchType;
  squash.description = "Squash and stretch: a scale from the distance between two matrices over a rest length";
  const std::vector<std::string> outs = {"stretch", "scale"};
  graph::AttrSpec axis = graph::input_attr("axis", {ValueType::kEnum, false}, std::int64_t{1}, outs);
  axis.enum_names = {"x", "y", "z"};
  squash.attrs = {graph::input_attr("startMatrix", kMatrix, Mat4(Mat4::Identity()), outs),
                  graph::input_attr("endMatrix", kMatrix, Mat4(Mat4::Identity()), outs),
                  graph::input_attr("restLength", {ValueType::kDouble, false}, 1.0, outs),
                  axis,
                  graph::input_attr("volume", {ValueType::kDouble, false}, 1.0, outs),
                  graph::input_attr("restScale", {ValueType::kDouble3, false}, math::Vec3(1, 1, 1), outs),
                  graph::output_attr("stretch", {ValueType::kDouble, false}),
                  graph::output_attr("scale", {ValueType::kDouble3, false})};
  squash.compute = compute_squash_stretch;
  if (Status s = registry.add(std::move(squash)); !s) return s;
  graph::NodeTypeSpec wheel;
  wheel.name = kWheelRollType;
  wheel.description = "A wheel's roll: the turn about its axle that covers the distance it moved forward";
  const std::vector<std::string> wheel_outs = {"travel", "rotate"};
  wheel.attrs = {graph::input_attr("matrix", kMatrix, Mat4(Mat4::Identity()), wheel_outs),
                 graph::input_attr("restMatrix", kMatrix, Mat4(Mat4::Identity()), wheel_outs),
                 graph::input_attr("forward", {ValueType::kDouble3, false}, math::Vec3(0, 0, 1), wheel_outs),
                 graph::input_attr("axle", {ValueType::kDouble3, false}, math::Vec3(1, 0, 0), wheel_outs),
                 graph::input_attr("radius", {ValueType::kDouble, false}, 0.3, wheel_outs),
                 graph::output_attr("travel", {ValueType::kDouble, false}),
                 graph::output_attr("rotate", {ValueType::kDouble3, false}, graph::kAngle)};
  wheel.compute = compute_wheel_roll;
  if (Status s = registry.add(std::move(wheel)); !s) return s;
  if (Status s = register_blend_types(registry); !s) return s;
  if (Status s = register_finger_types(registry); !s) return s;
  if (Status s = register_foot_types(registry); !s) return s;
  if (Status s = register_space_types(registry); !s) return s;
  if (Status s = register_spring_types(registry); !s) return s;
  if (Status s = register_eyelid_types(registry); !s) return s;
  return register_twist_types(registry);
}

}  // namespace rigel::ops::util
