#pragma once
// Transforms as a rigger knows them (Maya's transform and joint): translate,
// rotate (Euler in any rotate order, or a quaternion), scale, shear, joint
// orient, rotate axis, rotate/scale pivots and an offset parent matrix.
// Matrix composition, decomposition, and scale/shear-free concatenation.

#include "rigel/math/rotation.h"
#include "rigel/math/types.h"

namespace rigel::math {

enum class RotateMode : std::uint8_t { kEuler = 0, kQuaternion = 1 };

// The channels of one transform. Angles in radians. Defaults give identity.
struct TransformParts {
  Vec3 translate = Vec3::Zero();
  RotateMode rotate_mode = RotateMode::kEuler;
  Vec3 rotate = Vec3::Zero();                  // Euler angles, used when rotate_mode == kEuler
  RotateOrder rotate_order = RotateOrder::kXYZ;
  Quat rotate_quaternion = Quat::Identity();   // used when rotate_mode == kQuaternion (normalised on use)
  Vec3 scale = Vec3::Ones();
  Vec3 shear = Vec3::Zero();                   // xy, xz, yz (Maya's shear)
  Vec3 rotate_axis = Vec3::Zero();             // pre-rotation, Euler XYZ
  Vec3 joint_orient = Vec3::Zero();            // post-rotation, Euler XYZ (joints)
  Vec3 rotate_pivot = Vec3::Zero();
  Vec3 rotate_pivot_translate = Vec3::Zero();
  Vec3 scale_pivot = Vec3::Zero();
  Vec3 scale_pivot_translate = Vec3::Zero();
};

// Local matrix, Maya's order written for column vectors:
//   T * Rpt * Rp * JO * R * RA * Rp^-1 * Spt * Sp * SH * S * Sp^-1
// (the offset parent matrix is not part of it: see world_matrix()).
Mat4 compose(const TransformParts& parts);

// World matrix of a transform: parent_world * offset_parent * local.
inline Mat4 world_matrix(const Mat4& parent_world, const Mat4& offset_parent, const Mat4& local) {
  return parent_world * offset_parent * local;
}

// Translate, rotation, scale and shear of an affine matrix:
// m = T * R * SH * S (R a proper rotation; a negative determinant is carried
// by a negative scale.x). Pivots, rotate axis and joint orient are zero.
struct Decomposed {
  Vec3 translate = Vec3::Zero();
  Quat rotation = Quat::Identity();
  Vec3 scale = Vec3::Ones();
  Vec3 shear = Vec3::Zero();
};
Decomposed decompose(const Mat4& m);

// Decomposes `m` into parts with Euler rotation in `order` (no pivots):
// compose(decompose_to_parts(m, o)) == m within 1e-12 relative.
TransformParts decompose_to_parts(const Mat4& m, RotateOrder order);

Mat4 translation_matrix(const Vec3& t);
Mat4 rotation_matrix(const Quat& q);
Mat4 scale_matrix(const Vec3& s);
// m = T * R * S.
Mat4 trs_matrix(const Vec3& t, const Quat& r, const Vec3& s);

// Inverse of an affine matrix (last row 0 0 0 1).
Mat4 affine_inverse(const Mat4& m);

// Removes scale and shear: the rotation and translation of `m` as a rigid matrix.
Mat4 rigid_part(const Mat4& m);
// Whether `m`'s axes are orthonormal and right-handed, within `tolerance`
// (no scale, no shear, no mirror).
bool is_rigid(const Mat4& m, double tolerance = 1e-12);

// Seed 001's concatMatrices: parent * child with shear removed and the scale
// reset to the scale `child` had, so that scale and shear cannot creep into
// relations that are rebuilt many times.
Mat4 concat_without_scale_shear(const Mat4& parent, const Mat4& child);

// True when all entries differ by at most `tolerance`.
bool is_near(const Mat4& a, const Mat4& b, double tolerance);

}  // namespace rigel::math
