#pragma once
// Unit dual quaternions for rigid transforms (skinning, blending).

#include "rigel/math/types.h"

namespace rigel::math {

struct DualQuat {
  Quat real = Quat::Identity();        // rotation
  Quat dual = Quat(0.0, 0.0, 0.0, 0.0);  // 0.5 * translation * rotation

  static DualQuat from_rigid(const Quat& rotation, const Vec3& translation);
  // Takes the rigid part of `m` (see rigid_part()).
  static DualQuat from_matrix(const Mat4& m);

  Quat rotation() const;
  Vec3 translation() const;
  Mat4 to_matrix() const;

  // (a * b) applies b first, then a (as matrices).
  DualQuat operator*(const DualQuat& other) const;
  DualQuat normalized() const;
  DualQuat conjugate() const;  // the inverse, for unit dual quaternions
  Vec3 transform_point(const Vec3& p) const;
};

// Dual quaternion linear blending (Kavan et al.): weighted sum with
// antipodality handled against the first input, then normalised.
DualQuat blend(const DualQuat* dqs, const double* weights, int count);

}  // namespace rigel::math
