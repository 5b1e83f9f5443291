#pragma once
// Twist sharing (Luna's twist component, seed 004 §4.8), shaped as a job
// (STYLE.md §3): the shares of a joint's twist that twist joints between it
// and its parent-side joint take. The twistShare node (twist.h) calls it.
//
//   D     = (R(start)^-1 * R(end)) * rest_relative^-1
//           the end's turn relative to the start since rest, in the start's
//           frame (R: the rotation of a world matrix, scale removed)
//   twist = the swing-twist decomposition of D about `axis` (the start
//           joint's bone axis): D = swing * twist, twist about `axis`,
//           angle in (-pi, pi]
//   rotations[i] = rotation about `axis` by twist * (i + 1) / (count + 1),
//           i in [0, count), count = rotations.size()

#include <span>

#include "rigel/math/types.h"

namespace rigel::ops::util {

// The twist angle (radians, in (-pi, pi]) of `q` about the unit `axis`.
double twist_angle(const math::Quat& q, const math::Vec3& axis);

struct TwistShareJob {
  // Validates job parameters. Returns false:
  // - if `twist` is null;
  // - if start or end is not finite, or its 3x3 part is zero or singular
  //   (|det| <= 1e-12 * largest entry^3);
  // - if rest_relative is not finite or shorter than 1e-12;
  // - if axis is not a unit vector (within 1e-9) or not finite.
  bool validate() const;
  // Writes every element of `rotations` and *twist. Returns false if the job
  // is not valid (writing nothing).
  bool run() const;

  // World matrices of the start joint and of the end joint.
  math::Mat4 start = math::Mat4::Identity();
  math::Mat4 end = math::Mat4::Identity();
  // The end's rotation relative to the start at rest (normalized here).
  math::Quat rest_relative = math::Quat::Identity();
  // The start joint's bone axis, in its frame; unit.
  math::Vec3 axis = math::Vec3::UnitY();

  // Outputs. One rotation per twist joint (its rotateQuaternion). Not owned.
  std::span<math::Quat> rotations;
  // The twist, radians.
  double* twist = nullptr;
};

}  // namespace rigel::ops::util
