#include <cmath>

#include "rigel/math/dual_quat.h"
#include "rigel/math/transform.h"
#include "rigel/ops/deform/skinning.h"

namespace rigel::ops {
namespace {

bool is_affine_finite(const math::Mat4& m) {
  return m(3, 0) == 0.0 && m(3, 1) == 0.0 && m(3, 2) == 0.0 && m(3, 3) == 1.0 && m.allFinite();
}

}  // namespace

SkinMatrix SkinMatrix::from(const math::Mat4& matrix) {
  SkinMatrix out;
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 3; ++r) out.m[4 * c + r] = static_cast<float>(matrix(r, c));
    out.m[4 * c + 3] = 0.0f;
  }
  return out;
}

math::Mat4 SkinMatrix::to_mat4() const {
  math::Mat4 out = math::Mat4::Identity();
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 3; ++r) out(r, c) = m[4 * c + r];
  }
  return out;
}

DualQuatSkinMatrix DualQuatSkinMatrix::from(const math::Mat4& matrix) {
  // M = [R t] * [S 0] with R from math::rigid_part (Gram-Schmidt on the
  // columns; a reflection stays in S as a negative scale), S = R^T A.
  const math::Mat4 rigid = math::rigid_part(matrix);
  const math::Mat3 rotation = rigid.topLeftCorner<3, 3>();
  const math::DualQuat dq = math::DualQuat::from_rigid(math::Quat(rotation), matrix.topRightCorner<3, 1>());
  const math::Mat3 stretch = rotation.transpose() * matrix.topLeftCorner<3, 3>();
  DualQuatSkinMatrix out;
  for (int n = 0; n < 4; ++n) {
    out.real[n] = dq.real.coeffs()[n];
    out.dual[n] = dq.dual.coeffs()[n];
  }
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) out.stretch[3 * c + r] = stretch(r, c);
  }
  out.has_stretch = !((stretch - math::Mat3::Identity()).cwiseAbs().maxCoeff() <= kStretchTolerance);
  return out;
}

bool SkinningMatricesJob::validate() const {
  const std::size_t count = joint_world.size();
  if (inverse_bind.size() != count) return false;
  if (!matrices.empty() && matrices.size() != count) return false;
  if (!linear.empty() && linear.size() != count) return false;
  if (!dual_quat.empty() && dual_quat.size() != count) return false;
  if (!is_affine_finite(world_to_mesh)) return false;
  for (std::size_t j = 0; j < count; ++j) {
    if (!is_affine_finite(joint_world[j]) || !is_affine_finite(inverse_bind[j])) return false;
  }
  return true;
}

bool SkinningMatricesJob::run() const {
  if (!validate()) return false;
  if (matrices.empty() && linear.empty() && dual_quat.empty()) return true;
  const bool premultiply = world_to_mesh != math::Mat4::Identity();
  for (std::size_t j = 0; j < joint_world.size(); ++j) {
    math::Mat4 m;
    m.noalias() = joint_world[j] * inverse_bind[j];
    if (premultiply) m = world_to_mesh * m;
    // The product of affine matrices is affine; make its last row exact.
    m.row(3) << 0.0, 0.0, 0.0, 1.0;
    if (!matrices.empty()) matrices[j] = m;
    if (!linear.empty()) linear[j] = SkinMatrix::from(m);
    if (!dual_quat.empty()) dual_quat[j] = DualQuatSkinMatrix::from(m);
  }
  return true;
}

}  // namespace rigel::ops
