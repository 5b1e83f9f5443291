#include "rigel/math/dual_quat.h"

#include "rigel/math/transform.h"

namespace rigel::math {
namespace {

Quat add(const Quat& a, const Quat& b) { return Quat(a.coeffs() + b.coeffs()); }
Quat scaled(const Quat& q, double s) { return Quat(q.coeffs() * s); }
Quat pure(const Vec3& v) { return Quat(0.0, v.x(), v.y(), v.z()); }

}  // namespace

DualQuat DualQuat::from_rigid(const Quat& rotation, const Vec3& translation) {
  DualQuat out;
  const double norm = rotation.norm();
  out.real = norm > 0.0 ? scaled(rotation, 1.0 / norm) : Quat::Identity();
  out.dual = scaled(pure(translation) * out.real, 0.5);
  return out;
}

DualQuat DualQuat::from_matrix(const Mat4& m) {
  const Mat4 rigid = rigid_part(m);
  return from_rigid(Quat(Mat3(rigid.topLeftCorner<3, 3>())), rigid.topRightCorner<3, 1>());
}

Quat DualQuat::rotation() const {
  const double norm = real.norm();
  return norm > 0.0 ? scaled(real, 1.0 / norm) : Quat::Identity();
}

Vec3 DualQuat::translation() const {
  // t = 2 * dual * conj(real) / |real|^2 (the division makes it hold for a
  // dual quaternion that is only a scalar multiple of a unit one).
  const double norm2 = real.squaredNorm();
  if (!(norm2 > 0.0)) return Vec3::Zero();
  return (dual * real.conjugate()).vec() * (2.0 / norm2);
}

Mat4 DualQuat::to_matrix() const {
  Mat4 m = Mat4::Identity();
  m.topLeftCorner<3, 3>() = rotation().toRotationMatrix();
  m.topRightCorner<3, 1>() = translation();
  return m;
}

DualQuat DualQuat::operator*(const DualQuat& other) const {
  DualQuat out;
  out.real = real * other.real;
  out.dual = add(real * other.dual, dual * other.real);
  return out;
}

DualQuat DualQuat::normalized() const {
  const double norm = real.norm();
  if (!(norm > 0.0)) return DualQuat{};  // no rotation to normalise: identity
  DualQuat out;
  out.real = scaled(real, 1.0 / norm);
  // Divide by |real|, then remove the part of dual along real so that
  // real . dual = 0 (the unit condition). The translation is unchanged.
  const Quat d = scaled(dual, 1.0 / norm);
  out.dual = add(d, scaled(out.real, -out.real.coeffs().dot(d.coeffs())));
  return out;
}

DualQuat DualQuat::conjugate() const {
  DualQuat out;
  out.real = real.conjugate();
  out.dual = dual.conjugate();
  return out;
}

Vec3 DualQuat::transform_point(const Vec3& p) const { return rotation() * p + translation(); }

DualQuat blend(const DualQuat* dqs, const double* weights, int count) {
  if (dqs == nullptr || weights == nullptr || count <= 0) return DualQuat{};
  Eigen::Vector4d real = Eigen::Vector4d::Zero();
  Eigen::Vector4d dual = Eigen::Vector4d::Zero();
  const Eigen::Vector4d& pivot = dqs[0].real.coeffs();
  for (int n = 0; n < count; ++n) {
    // q and -q are the same rigid transform; take the one in the hemisphere
    // of the first input so opposite signs do not cancel out.
    const double w = pivot.dot(dqs[n].real.coeffs()) < 0.0 ? -weights[n] : weights[n];
    real += w * dqs[n].real.coeffs();
    dual += w * dqs[n].dual.coeffs();
  }
  DualQuat sum;
  sum.real = Quat(real);
  sum.dual = Quat(dual);
  return sum.normalized();
}

}  // namespace rigel::math
