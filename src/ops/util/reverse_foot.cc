#include "rigel/ops/util/reverse_foot.h"

#include <algorithm>
#include <cmath>

namespace rigel::ops::util {
namespace {

using math::Mat4;
using math::Vec3;

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

bool usable_axis(const Vec3& axis) {
  const double length = axis.norm();
  return std::isfinite(length) && length > 0;
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

bool ReverseFootJob::validate() const {
  if (!ankle || !ball) return false;
  const ReverseFootValues& v = values;
  for (double x : {v.roll, v.roll_break, v.bank, v.heel_twist, v.toe_twist, v.ball_twist, v.toe_tap})
    if (!std::isfinite(x)) return false;
  const ReverseFootPivots& p = pivots;
  for (const Vec3* point : {&p.heel, &p.toe, &p.ball, &p.inner, &p.outer})
    if (!point->allFinite()) return false;
  return usable_axis(p.roll_axis) && usable_axis(p.bank_axis) && usable_axis(p.twist_axis);
}

bool ReverseFootJob::run() const {
  if (!validate()) return false;
  ReverseFootPivots unit = pivots;
  for (Vec3* axis : {&unit.roll_axis, &unit.bank_axis, &unit.twist_axis}) *axis /= axis->norm();
  const ReverseFootChain chain = reverse_foot_chain(unit, values);
  *ankle = control * chain.ankle * rest_ankle;
  *ball = control * chain.ball * rest_ball;
  return true;
}

}  // namespace rigel::ops::util
