#include "rigel/ops/util/fk_ik_blend.h"

#include <cmath>

#include "rigel/math/rotation.h"
#include "rigel/math/transform.h"

namespace rigel::ops::util {
namespace {

using math::Mat4;
using math::Quat;
using math::Vec3;

template <typename T>
const T& element_or(std::span<const T> v, std::size_t i, const T& fallback) {
  return i < v.size() ? v[i] : fallback;
}

// Affine, finite and not singular.
bool usable(const Mat4& m) {
  if (!m.allFinite()) return false;
  if (m(3, 0) != 0 || m(3, 1) != 0 || m(3, 2) != 0 || m(3, 3) != 1) return false;
  const double scale = m.topLeftCorner<3, 3>().cwiseAbs().maxCoeff();
  const double det = m.topLeftCorner<3, 3>().determinant();
  return scale > 0 && std::abs(det) > 1e-12 * scale * scale * scale;
}

Quat orient_quat(const Vec3& degrees) { return math::euler_to_quat(math::to_radians(degrees), math::RotateOrder::kXYZ); }

}  // namespace

Mat4 ik_end_world(const Mat4& ik_world, const Mat4& end_control_world) {
  Mat4 out = end_control_world;
  out.topRightCorner<3, 1>() = ik_world.topRightCorner<3, 1>();
  return out;
}

bool FkIkBlendJob::validate() const {
  if (!(fk_ik >= 0.0 && fk_ik <= 1.0)) return false;
  const std::size_t n = rest_offset_parent.size();
  return translations.size() >= n && rotations.size() >= n && scales.size() >= n && shears.size() >= n &&
         worlds.size() >= n;
}

bool FkIkBlendJob::run() const {
  if (!validate()) return false;
  const double w = fk_ik;
  const std::size_t n = rest_offset_parent.size();
  const Mat4 identity = Mat4::Identity();
  const Vec3 zero = Vec3::Zero();
  FkIkBlendResult found;
  auto side = [&](std::span<const Mat4> mine, std::span<const Mat4> other, std::size_t i) -> const Mat4& {
    return i < mine.size() ? mine[i] : element_or(other, i, identity);
  };
  Mat4 fk_prev = parent, ik_prev = parent, prev = parent;
  found.unusable_parent = !usable(parent);
  bool bad = found.unusable_parent;
  for (std::size_t i = 0; i < n; ++i) {
    const Mat4& fk_joint = side(fk_world, ik_world, i);
    Mat4 ik_joint = side(ik_world, fk_world, i);
    if (use_ik_end && i + 1 == n) ik_joint = ik_end_world(ik_joint, ik_end);
    const Mat4& offset = rest_offset_parent[i];
    const Mat4 fk_parent = fk_prev * offset, ik_parent = ik_prev * offset, blended_parent = prev * offset;
    Mat4 local = identity;
    translations[i] = zero;
    rotations[i] = Quat::Identity();
    scales[i] = Vec3::Ones();
    shears[i] = zero;
    if (!bad && usable(fk_joint) && usable(ik_joint) && usable(fk_parent) && usable(ik_parent) &&
        usable(blended_parent)) {
      const math::Decomposed f = math::decompose(math::affine_inverse(fk_parent) * fk_joint);
      const math::Decomposed k = math::decompose(math::affine_inverse(ik_parent) * ik_joint);
      math::TransformParts p;
      p.translate = (1 - w) * f.translate + w * k.translate;
      p.rotate_mode = math::RotateMode::kQuaternion;
      p.rotate_quaternion = f.rotation.slerp(w, k.rotation).normalized();  // Eigen's slerp takes the short way
      p.scale = (1 - w) * f.scale + w * k.scale;
      p.shear = (1 - w) * f.shear + w * k.shear;
      translations[i] = p.translate;
      scales[i] = p.scale;
      shears[i] = p.shear;
      const Vec3 jo = element_or(rest_joint_orient, i, zero), ra = element_or(rest_rotate_axis, i, zero);
      rotations[i] = (orient_quat(jo).conjugate() * p.rotate_quaternion * orient_quat(ra).conjugate()).normalized();
      // The matrix the joint computes from these channels.
      p.rotate_quaternion = rotations[i];
      p.joint_orient = math::to_radians(jo);
      p.rotate_axis = math::to_radians(ra);
      local = math::compose(p);
    } else if (!bad) {
      bad = true;
      found.unusable_joint = static_cast<int>(i);
    }
    worlds[i] = blended_parent * local;
    fk_prev = fk_joint;
    ik_prev = ik_joint;
    prev = worlds[i];
  }
  if (result) *result = found;
  return true;
}

}  // namespace rigel::ops::util
