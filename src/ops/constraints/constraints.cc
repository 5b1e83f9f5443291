#include "rigel/ops/constraints/constraints.h"

#include <cmath>
#include <cstddef>

namespace rigel::ops::constraints {
namespace {

using math::Mat3;
using math::Vec4;

bool is_affine_finite(const Mat4& m) {
  return m.allFinite() && m(3, 0) == 0.0 && m(3, 1) == 0.0 && m(3, 2) == 0.0 && m(3, 3) == 1.0;
}

// Everything the blending constraints check about their targets. Offsets
// may be left empty when `offsets_optional` (aim, pole vector).
bool targets_valid(const TargetSpans& t, bool offsets_optional) {
  const std::size_t n = t.world.size();
  if (n == 0 || t.weights.size() != n) return false;
  if (t.offsets.size() != n && !(offsets_optional && t.offsets.empty())) return false;
  for (std::size_t i = 0; i < n; ++i) {
    const double w = t.weights[i];
    if (!std::isfinite(w) || w < 0.0) return false;
    if (!is_affine_finite(t.world[i])) return false;
    if (!t.offsets.empty() && !is_affine_finite(t.offsets[i])) return false;
  }
  return true;
}

double total_weight(const TargetSpans& t) {
  double total = 0.0;
  for (const double w : t.weights) total += w;
  return total;
}

// Same shear convention as math::decompose: x += xy*y + xz*z, y += yz*z.
Mat3 shear_matrix(const Vec3& shear) {
  Mat3 m = Mat3::Identity();
  m(0, 1) = shear[0];
  m(0, 2) = shear[1];
  m(1, 2) = shear[2];
  return m;
}

Mat4 contribution(const TargetSpans& t, std::size_t i, bool rigid) {
  if (t.offsets.empty()) return t.world[i];
  return rigid ? rigid_concat(t.world[i], t.offsets[i]) : Mat4(t.world[i] * t.offsets[i]);
}

// Weighted mean of the contributions' positions. total > 0.
Vec3 blend_position(const TargetSpans& t, double total) {
  Vec3 sum = Vec3::Zero();
  for (std::size_t i = 0; i < t.world.size(); ++i) {
    const double w = t.weights[i];
    if (w == 0.0) continue;
    const Vec3 p = t.offsets.empty() ? Vec3(t.world[i].topRightCorner<3, 1>())
                                     : Vec3(t.world[i].topLeftCorner<3, 3>() * t.offsets[i].topRightCorner<3, 1>() +
                                            t.world[i].topRightCorner<3, 1>());
    sum += w * p;
  }
  return sum / total;
}

struct Blended {
  Vec3 translate = Vec3::Zero();
  Quat rotation = Quat::Identity();
  Vec3 scale = Vec3::Zero();
  Vec3 shear = Vec3::Zero();
};

// Blends the full transforms of the contributions. total > 0. Rotations:
// normalised weighted sum, each quaternion flipped into the hemisphere of
// the first weighted one's. That reference has weight > 0, so the sum has a
// positive dot product with it and is never zero.
Blended blend_all(const TargetSpans& t, double total, bool rigid) {
  Blended out;
  Vec4 q_sum = Vec4::Zero();
  Vec4 reference = Vec4::Zero();
  bool have_reference = false;
  for (std::size_t i = 0; i < t.world.size(); ++i) {
    const double w = t.weights[i] / total;
    if (w == 0.0) continue;
    const math::Decomposed d = math::decompose(contribution(t, i, rigid));
    Vec4 q = d.rotation.coeffs();
    if (!have_reference) {
      reference = q;
      have_reference = true;
    } else if (q.dot(reference) < 0.0) {
      q = -q;
    }
    q_sum += w * q;
    out.translate += w * d.translate;
    out.scale += w * d.scale;
    out.shear += w * d.shear;
  }
  out.rotation = Quat(q_sum[3], q_sum[0], q_sum[1], q_sum[2]).normalized();
  return out;
}

Quat positive_w(Quat q) {
  q.normalize();
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  return q;
}

Quat rotation_of(const Mat4& m) { return math::decompose(m).rotation; }

bool quat_usable(const Quat& q) { return q.coeffs().allFinite() && q.coeffs().squaredNorm() > 0.0; }


}  // namespace

// ---- offsets ----------------------------------------------------------------

bool is_offset_computable(const Mat4& target_world) {
  if (!is_affine_finite(target_world)) return false;
  const double det = target_world.topLeftCorner<3, 3>().determinant();
  return std::isfinite(det) && std::abs(det) > 1e-12;
}

Mat4 compute_offset(const Mat4& target_world, const Mat4& driven_world, bool rigid) {
  if (!is_offset_computable(target_world)) return Mat4::Identity();
  const Mat4 full = math::affine_inverse(target_world) * driven_world;
  if (!rigid) return full;
  Mat4 out = full;
  out.topLeftCorner<3, 3>() =
      rotation_of(target_world).toRotationMatrix().transpose() * driven_world.topLeftCorner<3, 3>();
  out.row(3) << 0.0, 0.0, 0.0, 1.0;
  return out;
}

Mat4 rigid_concat(const Mat4& target_world, const Mat4& offset) {
  Mat4 out = Mat4::Identity();
  out.topLeftCorner<3, 3>() = rotation_of(target_world).toRotationMatrix() * offset.topLeftCorner<3, 3>();
  out.topRightCorner<3, 1>() =
      target_world.topLeftCorner<3, 3>() * offset.topRightCorner<3, 1>() + target_world.topRightCorner<3, 1>();
  return out;
}

// ---- parent -----------------------------------------------------------------

bool ParentConstraintJob::validate() const {
  return output != nullptr && targets_valid(targets, false) && is_affine_finite(parent_inverse) &&
         is_affine_finite(rest_local);
}

bool ParentConstraintJob::run() const {
  if (!validate()) return false;
  const double total = total_weight(targets);
  if (!(total > 0.0)) {
    *output = rest_local;
    return true;
  }
  const Blended b = blend_all(targets, total, rigid);
  Mat4 world = Mat4::Identity();
  world.topLeftCorner<3, 3>() = b.rotation.toRotationMatrix() * shear_matrix(b.shear) * b.scale.asDiagonal();
  world.topRightCorner<3, 1>() = b.translate;
  Mat4 local = parent_inverse * world;
  local.row(3) << 0.0, 0.0, 0.0, 1.0;
  *output = local;
  return true;
}

// ---- point ------------------------------------------------------------------

bool PointConstraintJob::validate() const {
  return output != nullptr && targets_valid(targets, false) && is_affine_finite(parent_inverse) &&
         rest_translate.allFinite();
}

bool PointConstraintJob::run() const {
  if (!validate()) return false;
  const double total = total_weight(targets);
  if (!(total > 0.0)) {
    *output = rest_translate;
    return true;
  }
  const Vec3 world = blend_position(targets, total);
  *output = parent_inverse.topLeftCorner<3, 3>() * world + parent_inverse.topRightCorner<3, 1>();
  return true;
}

// ---- orient -----------------------------------------------------------------

bool OrientConstraintJob::validate() const {
  return output != nullptr && targets_valid(targets, false) && is_affine_finite(parent_inverse) &&
         quat_usable(rest_rotation);
}

bool OrientConstraintJob::run() const {
  if (!validate()) return false;
  const double total = total_weight(targets);
  if (!(total > 0.0)) {
    *output = positive_w(rest_rotation);
    return true;
  }
  const Blended b = blend_all(targets, total, false);
  *output = positive_w(rotation_of(parent_inverse) * b.rotation);
  return true;
}

// ---- scale ------------------------------------------------------------------

bool ScaleConstraintJob::validate() const {
  return output != nullptr && targets_valid(targets, false) && is_affine_finite(parent_inverse) &&
         rest_scale.allFinite();
}

bool ScaleConstraintJob::run() const {
  if (!validate()) return false;
  const double total = total_weight(targets);
  if (!(total > 0.0)) {
    *output = rest_scale;
    return true;
  }
  const Blended b = blend_all(targets, total, false);
  *output = b.scale.cwiseProduct(math::decompose(parent_inverse).scale);
  return true;
}

// ---- aim --------------------------------------------------------------------

namespace {
constexpr double kMinLength = 1e-9;
constexpr double kMinSine = 1e-6;
}  // namespace

bool AimConstraintJob::validate() const {
  if (output == nullptr || !targets_valid(targets, true)) return false;
  if (!aim_vector.allFinite() || !up_vector.allFinite()) return false;
  const double aim_length = aim_vector.norm();
  const double up_length = up_vector.norm();
  if (aim_length < kMinLength || up_length < kMinLength) return false;
  if (aim_vector.cross(up_vector).norm() < kMinSine * aim_length * up_length) return false;
  if (static_cast<int>(world_up_type) >= kWorldUpTypeCount) return false;
  if (!world_up_vector.allFinite() || !driven_position.allFinite()) return false;
  if (!quat_usable(rest_rotation) || !quat_usable(offset)) return false;
  return is_affine_finite(world_up_matrix) && is_affine_finite(parent_inverse);
}

bool AimConstraintJob::run() const {
  if (!validate()) return false;
  const double total = total_weight(targets);
  const Vec3 to_target = total > 0.0 ? Vec3(blend_position(targets, total) - driven_position) : Vec3::Zero();
  const double distance = to_target.norm();
  if (!(total > 0.0) || !(distance > kMinLength)) {
    *output = positive_w(rest_rotation);
    return true;
  }
  const Vec3 aim_world = to_target / distance;

  // The driven's own frame: aim, up made perpendicular to it, and their cross.
  const Vec3 aim_local = aim_vector.normalized();
  const Vec3 up_local = (up_vector - up_vector.dot(aim_local) * aim_local).normalized();
  Mat3 local_frame;
  local_frame << aim_local, up_local, aim_local.cross(up_local);

  Vec3 world_up = Vec3::Zero();
  switch (world_up_type) {
    case WorldUpType::kScene: world_up = Vec3::UnitY(); break;
    case WorldUpType::kObject: world_up = world_up_matrix.topRightCorner<3, 1>() - driven_position; break;
    case WorldUpType::kObjectRotation: world_up = world_up_matrix.topLeftCorner<3, 3>() * world_up_vector; break;
    case WorldUpType::kVector: world_up = world_up_vector; break;
    case WorldUpType::kNone: break;
  }
  // The world up with its component along the aim removed. When that is
  // (nearly) nothing, the world up says nothing about the twist: take the
  // up that the smallest rotation from aim_local to aim_world gives
  // (kNone always does; Eigen's FromTwoVectors handles opposite vectors).
  Vec3 up_world = world_up - world_up.dot(aim_world) * aim_world;
  const double up_length = up_world.norm();
  if (!(up_length > kMinSine * world_up.norm()) || !(up_length > kMinLength)) {
    up_world = Quat::FromTwoVectors(aim_local, aim_world) * up_local;
    up_world = (up_world - up_world.dot(aim_world) * aim_world).normalized();
  } else {
    up_world /= up_length;
  }
  Mat3 world_frame;
  world_frame << aim_world, up_world, aim_world.cross(up_world);
  const Quat world_rotation(Mat3(world_frame * local_frame.transpose()));
  *output = positive_w(rotation_of(parent_inverse) * world_rotation * offset.normalized());
  return true;
}

// ---- pole vector ------------------------------------------------------------

bool PoleVectorConstraintJob::validate() const {
  return output != nullptr && targets_valid(targets, true) && start_position.allFinite() &&
         handle_position.allFinite() && is_affine_finite(parent_inverse) && rest_pole_vector.allFinite();
}

bool PoleVectorConstraintJob::run() const {
  if (!validate()) return false;
  const double total = total_weight(targets);
  if (!(total > 0.0)) {
    *output = rest_pole_vector;
    return true;
  }
  Vec3 pole = blend_position(targets, total) - start_position;
  const Vec3 line = handle_position - start_position;
  const double length = line.norm();
  if (length > kMinLength) {
    const Vec3 axis = line / length;
    pole -= pole.dot(axis) * axis;
  }
  *output = parent_inverse.topLeftCorner<3, 3>() * pole;
  return true;
}

}  // namespace rigel::ops::constraints
