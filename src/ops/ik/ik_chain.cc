#include "rigel/ops/ik/ik_chain.h"

#include <cmath>

#include "ik_math.h"

namespace rigel::ops::ik {

using detail::is_affine;
using detail::is_unit;
using detail::overlap;

const char* joint_limit_error(const JointLimit& limit) {
  switch (limit.kind) {
    case LimitKind::kNone:
      return nullptr;
    case LimitKind::kHinge:
      if (!is_unit(limit.axis)) return "hinge axis is not a unit vector";
      if (!is_unit(limit.reference)) return "hinge reference is not a unit vector";
      if (!(std::abs(limit.axis.dot(limit.reference)) <= kUnitTolerance)) {
        return "hinge reference is not perpendicular to the axis";
      }
      if (!(limit.min_angle >= -math::kPi && limit.max_angle <= math::kPi && limit.min_angle <= limit.max_angle)) {
        return "hinge range is not -pi <= min_angle <= max_angle <= pi";
      }
      return nullptr;
    case LimitKind::kCone:
      if (!is_unit(limit.axis)) return "cone axis is not a unit vector";
      if (!(limit.half_angle >= 0.0 && limit.half_angle <= math::kPi)) return "cone half angle is not in [0, pi]";
      return nullptr;
  }
  return "unknown limit kind";
}

namespace {

// Signed distance from angle a to the interval's end b, going the short way
// round the circle: in [0, pi].
double circle_distance(double a, double b) {
  double d = std::fmod(std::abs(a - b), 2.0 * math::kPi);
  return d > math::kPi ? 2.0 * math::kPi - d : d;
}

}  // namespace

Vec3 constrain_direction(const JointLimit& limit, const Vec3& direction) {
  switch (limit.kind) {
    case LimitKind::kNone:
      return direction;
    case LimitKind::kCone: {
      const double c = direction.dot(limit.axis);
      const double cos_half = std::cos(limit.half_angle);
      if (c >= cos_half) return direction;
      Vec3 side = direction - limit.axis * c;
      if (!detail::normalize_in_place(side)) side = limit.axis.unitOrthogonal();
      return limit.axis * cos_half + side * std::sin(limit.half_angle);
    }
    case LimitKind::kHinge: {
      const Vec3 across = limit.axis.cross(limit.reference);
      const double x = direction.dot(limit.reference);
      const double y = direction.dot(across);
      // Along the axis (x = y = 0) the direction has no angle: take 0.
      const double angle = (x == 0.0 && y == 0.0) ? 0.0 : std::atan2(y, x);
      double clamped = angle;
      if (angle < limit.min_angle || angle > limit.max_angle) {
        clamped = circle_distance(angle, limit.min_angle) <= circle_distance(angle, limit.max_angle) ? limit.min_angle
                                                                                                     : limit.max_angle;
      }
      if (clamped == angle) {
        Vec3 in_plane = limit.reference * x + across * y;
        if (detail::normalize_in_place(in_plane)) return in_plane;
      }
      return limit.reference * std::cos(clamped) + across * std::sin(clamped);
    }
  }
  return direction;
}

bool ChainCorrectionJob::validate() const {
  const std::size_t count = local.size();
  if (count == 0) return false;
  if (corrections.size() != count || local_out.size() != count) return false;
  if (!translate_scale.empty() && translate_scale.size() != count) return false;
  if (!world_out.empty() && world_out.size() != count) return false;
  if (overlap(world_out.data(), world_out.size(), local.data(), count) ||
      overlap(world_out.data(), world_out.size(), local_out.data(), count) ||
      overlap(world_out.data(), world_out.size(), corrections.data(), count)) {
    return false;
  }
  if (local_out.data() != local.data() && overlap(local_out.data(), count, local.data(), count)) return false;
  if (overlap(local_out.data(), count, corrections.data(), count)) return false;
  return is_affine(parent_world);
}

bool ChainCorrectionJob::run() const {
  if (!validate()) return false;
  const std::size_t count = local.size();
  for (std::size_t i = 0; i < count; ++i) {
    const Mat4 in = local[i];  // a copy: local_out may be local
    const Mat3 linear = in.topLeftCorner<3, 3>();
    const Mat3 frame = detail::rotation_frame(linear);
    const double norm = corrections[i].norm();
    const Quat c = norm > 0.0 ? Quat(corrections[i].coeffs() / norm) : Quat::Identity();
    // T * (Q * C) * U with U = Q^T * linear.
    Mat4 out = Mat4::Identity();
    out.topLeftCorner<3, 3>() = frame * c.toRotationMatrix() * (frame.transpose() * linear);
    const double s = translate_scale.empty() ? 1.0 : translate_scale[i];
    out.topRightCorner<3, 1>() = in.topRightCorner<3, 1>() * s;
    local_out[i] = out;
    if (!world_out.empty()) world_out[i] = (i == 0 ? parent_world : world_out[i - 1]) * out;
  }
  return true;
}

bool ChainWorldToLocalJob::validate() const {
  const std::size_t count = world.size();
  if (count == 0 || local.size() != count) return false;
  if (overlap(local.data(), count, world.data(), count)) return false;
  auto invertible = [](const Mat4& m) {
    return is_affine(m) && std::abs(m.topLeftCorner<3, 3>().determinant()) > 1e-300;
  };
  if (!invertible(parent_world)) return false;
  for (const Mat4& m : world) {
    if (!invertible(m)) return false;
  }
  return true;
}

bool ChainWorldToLocalJob::run() const {
  if (!validate()) return false;
  for (std::size_t i = 0; i < world.size(); ++i) {
    const Mat4& parent = i == 0 ? parent_world : world[i - 1];
    const Mat3 inverse = parent.topLeftCorner<3, 3>().inverse();
    Mat4 out = Mat4::Identity();
    out.topLeftCorner<3, 3>() = inverse * world[i].topLeftCorner<3, 3>();
    out.topRightCorner<3, 1>() = inverse * (world[i].topRightCorner<3, 1>() - parent.topRightCorner<3, 1>());
    local[i] = out;
  }
  return true;
}

}  // namespace rigel::ops::ik
