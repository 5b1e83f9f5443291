#include "rigel/ops/ik/two_bone_ik.h"

#include <algorithm>
#include <limits>
#include <cmath>

#include "ik_math.h"

namespace rigel::ops::ik {

using detail::all_finite;
using detail::is_affine;
using detail::normalize_in_place;
using detail::translation;

bool TwoBoneIkJob::validate() const {
  if (start_world == nullptr || mid_world == nullptr || end_world == nullptr || output == nullptr) return false;
  if (!is_affine(*start_world) || !is_affine(*mid_world) || !is_affine(*end_world)) return false;
  if (!detail::is_unit(mid_axis)) return false;
  if (!all_finite(target) || !all_finite(pole_vector) || !std::isfinite(twist_angle)) return false;
  if (pole_mode != TwoBonePoleMode::kPoleVector && pole_mode != TwoBonePoleMode::kPlaneNormal) return false;
  if (!(soft >= 0.0 && soft <= 1.0)) return false;
  if (!(weight >= 0.0 && weight <= 1.0)) return false;
  if (stretch && !(max_stretch >= 1.0)) return false;
  return true;
}

// Over 150 lines: one analytic solve in the order of its steps (reach and
// soft IK, stretch, the bend plane from the pole, the two rotations, twist,
// weight), over the same locals; the kernel the benchmarks time as one.
RIGEL_IK_MULTIVERSION bool TwoBoneIkJob::run() const {
  if (!validate()) return false;
  // Square roots and divisions set the pace here (their latencies chain), so
  // lengths are kept squared where possible and each normalisation is one
  // square root and one division.
  constexpr double kTiny2 = detail::kTinyLength * detail::kTinyLength;

  const Vec3 start = translation(*start_world);
  const Vec3 mid = translation(*mid_world);
  const Vec3 end = translation(*end_world);
  const Vec3 upper = mid - start;  // the start bone
  const Vec3 lower = end - mid;    // the mid bone
  const double chain = std::sqrt(upper.squaredNorm()) + std::sqrt(lower.squaredNorm());
  const Vec3 to_target = target - start;
  const double distance = std::sqrt(to_target.squaredNorm());

  // 1. The distance the unstretched chain aims for, and the stretch factor.
  double reach = distance;
  if (soft > 0.0 && chain > 0.0) {
    const double ds = soft * chain;
    const double da = chain - ds;
    if (distance > da) reach = da + ds * (1.0 - std::exp(-(distance - da) / ds));
  }
  reach = std::min(reach, chain);
  double scale = 1.0;
  if (stretch && reach > 0.0 && distance > reach) scale = std::min(distance / reach, max_stretch);

  // 2. The mid joint turns about its hinge axis (world: hinge) until
  // start-to-end has length `reach`. With the bones split into parts along
  // the hinge (fixed) and across it (turning), the law of cosines gives the
  // angle gamma from the upper bone's across part to the lower bone's:
  //   reach^2 = along^2 + |upper_across|^2 + |lower_across|^2
  //             + 2 |upper_across| |lower_across| cos(gamma).
  // The knee bends positively about the hinge: gamma in [0, pi].
  const Mat3 mid_linear = mid_world->topLeftCorner<3, 3>();
  Vec3 hinge = mid_linear * mid_axis;
  const bool has_hinge = normalize_in_place(hinge);
  Quat mid_turn = Quat::Identity();  // world space, about `hinge`
  Vec3 end_offset = upper + lower;   // start to end after the mid turn
  double end_distance2 = end_offset.squaredNorm();
  if (has_hinge) {
    const double upper_along = hinge.dot(upper);
    const double lower_along = hinge.dot(lower);
    const Vec3 upper_across = upper - hinge * upper_along;
    const Vec3 lower_across = lower - hinge * lower_along;
    const double ua2 = upper_across.squaredNorm();
    const double la2 = lower_across.squaredNorm();
    if (ua2 > kTiny2 && la2 > kTiny2) {
      const double along = upper_along + lower_along;
      const double product = std::sqrt(ua2 * la2);  // |upper_across| |lower_across|
      const double inv_product = 1.0 / product;
      const double base = along * along + ua2 + la2;
      double cos_gamma = std::clamp((reach * reach - base) * (0.5 * inv_product), -1.0, 1.0);
      // At full extension (reach = the chain's length) rounding leaves
      // cos_gamma a few ulps below 1, and sin_gamma = sqrt(1 - cos^2) turns
      // that into a 1e-8 knee offset. Within 4 ulps of 1 the chain is
      // straight as far as doubles can tell.
      if (cos_gamma > 1.0 - 4.0 * std::numeric_limits<double>::epsilon()) cos_gamma = 1.0;
      const double sin_gamma = std::sqrt(1.0 - cos_gamma * cos_gamma);
      // The current angle beta (from upper_across to lower_across about the
      // hinge) and the turn alpha = gamma - beta, as sines and cosines
      // (unit up to rounding).
      const double cos_beta = upper_across.dot(lower_across) * inv_product;
      const double sin_beta = hinge.dot(upper_across.cross(lower_across)) * inv_product;
      const double cos_alpha = cos_gamma * cos_beta + sin_gamma * sin_beta;
      const double sin_alpha = sin_gamma * cos_beta - cos_gamma * sin_beta;
      mid_turn = detail::quat_from_axis_sin_cos(hinge, sin_alpha, cos_alpha);
      const Vec3 new_lower = hinge * lower_along + lower_across * cos_alpha + hinge.cross(lower_across) * sin_alpha;
      end_offset = upper + new_lower;
      end_distance2 = std::max(0.0, base + 2.0 * product * cos_gamma);
    }
  }
  const double end_distance = std::sqrt(end_distance2);

  // 3. The start joint maps the frame (start-to-end, hinge across it) onto
  // (start-to-target, reference across it).
  Mat3 start_turn = Mat3::Identity();  // world space
  Vec3 end_dir;
  bool has_end_dir = false;
  if (end_distance > detail::kTinyLength) {
    end_dir = end_offset * (1.0 / end_distance);
    has_end_dir = true;
  } else {
    end_dir = upper;  // the chain folds onto the start: aim the upper bone
    has_end_dir = normalize_in_place(end_dir);
  }
  if (has_end_dir) {
    // Target at the start joint: keep the current direction.
    const Vec3 aim = distance > detail::kTinyLength ? Vec3(to_target * (1.0 / distance)) : end_dir;
    Vec3 hinge_across = hinge - end_dir * end_dir.dot(hinge);
    const bool has_frame = has_hinge && normalize_in_place(hinge_across);
    Vec3 reference = pole_mode == TwoBonePoleMode::kPoleVector ? Vec3(pole_vector.cross(aim))
                                                               : Vec3(pole_vector - aim * aim.dot(pole_vector));
    bool has_reference = normalize_in_place(reference);
    if (!has_reference && has_hinge) {
      // Pole along start-to-target: no plane. Keep the hinge where it is.
      reference = hinge - aim * aim.dot(hinge);
      has_reference = normalize_in_place(reference);
    }
    if (has_frame && has_reference) {
      if (twist_angle != 0.0) {
        reference = reference * std::cos(twist_angle) + aim.cross(reference) * std::sin(twist_angle);
      }
      Mat3 from;
      from.col(0) = end_dir;
      from.col(1) = hinge_across;
      from.col(2) = end_dir.cross(hinge_across);
      Mat3 to;
      to.col(0) = aim;
      to.col(1) = reference;
      to.col(2) = aim.cross(reference);
      start_turn.noalias() = to * from.transpose();
    } else {
      // No hinge to align: the smallest turn onto the target, then the twist.
      Quat q = detail::shortest_arc(end_dir, aim);
      if (twist_angle != 0.0) q = Quat(Eigen::AngleAxisd(twist_angle, aim)) * q;
      start_turn = q.toRotationMatrix();
    }
  }

  // World-space turns to corrections in each joint's own frame:
  // C = R^T * turn * R, with R = A / s for the usual uniformly scaled joint.
  const Mat3 start_linear = start_world->topLeftCorner<3, 3>();
  Mat3 start_correction;
  const double start_scale2 = detail::uniform_scale_squared(start_linear);
  if (start_scale2 > 0.0) {
    start_correction.noalias() = start_linear.transpose() * (start_turn * start_linear);
    start_correction *= 1.0 / start_scale2;
  } else {
    const Mat3 frame = detail::rotation_frame(start_linear);
    start_correction.noalias() = frame.transpose() * (start_turn * frame);
  }
  Quat start_q = detail::positive_w(Quat(start_correction));
  // The mid turn is about the hinge: in the mid frame, about R^T hinge
  // (mid_axis itself, normalised, for a uniformly scaled joint).
  Quat mid_q = mid_turn;
  if (has_hinge) {
    const double sin_half = mid_turn.vec().dot(hinge);
    if (detail::uniform_scale_squared(mid_linear) > 0.0) {
      mid_q.vec() = mid_axis * (sin_half / std::sqrt(mid_axis.squaredNorm()));
    } else {
      mid_q.vec() = detail::rotation_frame(mid_linear).transpose() * mid_turn.vec();
    }
  }
  mid_q = detail::positive_w(mid_q);

  TwoBoneIkOutput& out = *output;
  out.reached = std::abs(scale * end_distance - distance) <= 1e-9 * std::max(1.0, scale * chain);
  const Quat start_world_q = detail::positive_w(Quat(start_turn));
  const Quat mid_world_q = detail::positive_w(mid_turn);
  if (weight < 1.0) {
    out.start_correction = Quat::Identity().slerp(weight, start_q);
    out.mid_correction = Quat::Identity().slerp(weight, mid_q);
    out.start_turn = Quat::Identity().slerp(weight, start_world_q);
    out.mid_turn = Quat::Identity().slerp(weight, mid_world_q);
    out.stretch = 1.0 + weight * (scale - 1.0);
  } else {
    out.start_correction = start_q;
    out.mid_correction = mid_q;
    out.start_turn = start_world_q;
    out.mid_turn = mid_world_q;
    out.stretch = scale;
  }
  return true;
}

}  // namespace rigel::ops::ik
