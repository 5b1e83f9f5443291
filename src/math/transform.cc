#include "rigel/math/transform.h"

#include <cmath>
#include <limits>

namespace rigel::math {
namespace {

// m3 = rotation * shear_matrix(shear) * diag(scale), rotation proper.
struct LinearSplit {
  Mat3 rotation = Mat3::Identity();
  Vec3 scale = Vec3::Ones();
  Vec3 shear = Vec3::Zero();
};

// Maya's shear (xy, xz, yz) for column vectors: x += xy * y + xz * z and
// y += yz * z, an upper unitriangular matrix.
Mat3 shear_matrix(const Vec3& shear) {
  Mat3 m = Mat3::Identity();
  m(0, 1) = shear[0];
  m(0, 2) = shear[1];
  m(1, 2) = shear[2];
  return m;
}

// Lengths at or below this are treated as zero (a collapsed axis): the
// smallest normal double, so that legitimately tiny scales still decompose.
constexpr double kTinyLength = std::numeric_limits<double>::min();

// QR by Gram-Schmidt on the columns: m3 = Q * U with Q orthonormal and U upper
// triangular with a positive diagonal, U = SH * S. A reflection (det < 0) is
// moved out of Q into a negative scale.x. A collapsed column (zero scale)
// gets an axis completing Q, and the shears that would divide by the zero
// scale are zero.
LinearSplit split_linear(const Mat3& m3) {
  LinearSplit out;
  const Vec3 c0 = m3.col(0);
  const Vec3 c1 = m3.col(1);
  const Vec3 c2 = m3.col(2);

  const double sx = c0.norm();
  const Vec3 r0 = sx > kTinyLength ? Vec3(c0 / sx) : Vec3::UnitX();

  const double d01 = r0.dot(c1);
  const Vec3 c1_orth = c1 - d01 * r0;
  const double sy = c1_orth.norm();
  Vec3 r1;
  if (sy > kTinyLength) {
    r1 = c1_orth / sy;
  } else {
    // y collapsed: choose r1 across c2, so c2 stays in span(r0, r2) and
    // keeps its own (non-zero) scale; in this order r0 x r1 points along c2,
    // so no reflection is introduced.
    const Vec3 across = c2.cross(r0);
    const double length = across.norm();
    r1 = length > kTinyLength ? Vec3(across / length) : Vec3(r0.unitOrthogonal());
  }

  // Modified Gram-Schmidt (project out r0, then r1 from what is left): keeps
  // Q orthonormal to rounding even when the shear is strong.
  const double d02 = r0.dot(c2);
  const Vec3 c2_minus_x = c2 - d02 * r0;
  const double d12 = r1.dot(c2_minus_x);
  const Vec3 c2_orth = c2_minus_x - d12 * r1;
  const double sz = c2_orth.norm();
  const Vec3 r2 = sz > kTinyLength ? Vec3(c2_orth / sz) : Vec3(r0.cross(r1));

  out.rotation.col(0) = r0;
  out.rotation.col(1) = r1;
  out.rotation.col(2) = r2;
  out.scale = Vec3(sx, sy, sz);
  out.shear = Vec3(sy > kTinyLength ? d01 / sy : 0.0,   // xy
                   sz > kTinyLength ? d02 / sz : 0.0,   // xz
                   sz > kTinyLength ? d12 / sz : 0.0);  // yz

  if (r0.cross(r1).dot(r2) < 0.0) {
    // Q * U = (Q * D) * (D * U) with D = diag(-1, 1, 1): Q * D is proper, and
    // D * U = SH' * S' with S' = diag(-sx, sy, sz), xy' = -xy, xz' = -xz.
    out.rotation.col(0) = -r0;
    out.scale.x() = -sx;
    out.shear.x() = -out.shear.x();
    out.shear.y() = -out.shear.y();
  }
  return out;
}

Mat3 rotation_part(const TransformParts& parts) {
  if (parts.rotate_mode == RotateMode::kQuaternion) {
    const double norm = parts.rotate_quaternion.norm();
    if (!(norm > 0.0)) return Mat3::Identity();  // a zero quaternion has no rotation
    return Quat(parts.rotate_quaternion.coeffs() / norm).toRotationMatrix();
  }
  return euler_to_matrix(parts.rotate, parts.rotate_order);
}

}  // namespace

Mat4 compose(const TransformParts& parts) {
  // T * Rpt * Rp * JO * R * RA * Rp^-1 * Spt * Sp * SH * S * Sp^-1, multiplied
  // out: the linear part is rot * ss, and a point x maps to
  //   rot * (ss * (x - Sp) + Sp + Spt - Rp) + Rp + Rpt + T.
  // Most joints have no joint orient, rotate axis or shear: their factors
  // (the identity) are skipped, which gives the same finite values at a
  // fraction of the cost (two Euler conversions are most of a compose).
  Mat3 rot = rotation_part(parts);
  if (!parts.joint_orient.isZero(0.0)) rot = euler_to_matrix(parts.joint_orient, RotateOrder::kXYZ) * rot;
  if (!parts.rotate_axis.isZero(0.0)) rot = rot * euler_to_matrix(parts.rotate_axis, RotateOrder::kXYZ);
  const Mat3 ss = parts.shear.isZero(0.0) ? Mat3(parts.scale.asDiagonal())
                                          : Mat3(shear_matrix(parts.shear) * parts.scale.asDiagonal());
  // Translation of Spt * Sp * SH * S * Sp^-1.
  const Vec3 scale_offset = parts.scale_pivot - ss * parts.scale_pivot + parts.scale_pivot_translate;

  Mat4 m = Mat4::Identity();
  m.topLeftCorner<3, 3>() = rot * ss;
  m.topRightCorner<3, 1>() = rot * (scale_offset - parts.rotate_pivot) + parts.rotate_pivot +
                             parts.rotate_pivot_translate + parts.translate;
  return m;
}

Decomposed decompose(const Mat4& m) {
  const LinearSplit split = split_linear(m.topLeftCorner<3, 3>());
  Decomposed out;
  out.translate = m.topRightCorner<3, 1>();
  out.rotation = Quat(split.rotation).normalized();
  out.scale = split.scale;
  out.shear = split.shear;
  return out;
}

TransformParts decompose_to_parts(const Mat4& m, RotateOrder order) {
  const LinearSplit split = split_linear(m.topLeftCorner<3, 3>());
  TransformParts parts;
  parts.translate = m.topRightCorner<3, 1>();
  parts.rotate_mode = RotateMode::kEuler;
  parts.rotate_order = order;
  // From the matrix rather than through a quaternion: one rounding fewer.
  parts.rotate = matrix_to_euler(split.rotation, order);
  parts.scale = split.scale;
  parts.shear = split.shear;
  return parts;
}

Mat4 translation_matrix(const Vec3& t) {
  Mat4 m = Mat4::Identity();
  m.topRightCorner<3, 1>() = t;
  return m;
}

Mat4 rotation_matrix(const Quat& q) {
  Mat4 m = Mat4::Identity();
  const double norm = q.norm();
  if (norm > 0.0) m.topLeftCorner<3, 3>() = Quat(q.coeffs() / norm).toRotationMatrix();
  return m;
}

Mat4 scale_matrix(const Vec3& s) {
  Mat4 m = Mat4::Identity();
  m(0, 0) = s.x();
  m(1, 1) = s.y();
  m(2, 2) = s.z();
  return m;
}

Mat4 trs_matrix(const Vec3& t, const Quat& r, const Vec3& s) {
  Mat4 m = rotation_matrix(r);
  m.topLeftCorner<3, 3>() *= s.asDiagonal();
  m.topRightCorner<3, 1>() = t;
  return m;
}

Mat4 affine_inverse(const Mat4& m) {
  const Mat3 inverse = m.topLeftCorner<3, 3>().inverse();
  Mat4 out = Mat4::Identity();
  out.topLeftCorner<3, 3>() = inverse;
  out.topRightCorner<3, 1>() = -(inverse * m.topRightCorner<3, 1>());
  return out;
}

Mat4 rigid_part(const Mat4& m) {
  Mat4 out = Mat4::Identity();
  out.topLeftCorner<3, 3>() = split_linear(m.topLeftCorner<3, 3>()).rotation;
  out.topRightCorner<3, 1>() = m.topRightCorner<3, 1>();
  return out;
}

bool is_rigid(const Mat4& m, double tolerance) {
  const Mat3 r = m.topLeftCorner<3, 3>();
  return (r.transpose() * r - Mat3::Identity()).cwiseAbs().maxCoeff() <= tolerance && r.determinant() > 0;
}

Mat4 concat_without_scale_shear(const Mat4& parent, const Mat4& child) {
  const Mat4 product = parent * child;
  const Vec3 child_scale = split_linear(child.topLeftCorner<3, 3>()).scale;
  Mat4 out = Mat4::Identity();
  out.topLeftCorner<3, 3>() = split_linear(product.topLeftCorner<3, 3>()).rotation * child_scale.asDiagonal();
  out.topRightCorner<3, 1>() = product.topRightCorner<3, 1>();
  return out;
}

bool is_near(const Mat4& a, const Mat4& b, double tolerance) {
  return ((a - b).cwiseAbs().array() <= tolerance).all();
}

}  // namespace rigel::math
