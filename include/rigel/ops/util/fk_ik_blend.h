#pragma once
// FK/IK blending of one joint chain, shaped as a job (STYLE.md §3): two
// poses of the chain (FK and IK, given as world matrices) blended into the
// channels that put each joint in the blended pose. The fkIkSwitch node
// (blend.h) calls it.
//
// Per joint i (n = rest_offset_parent.size(), the chain's joint count):
//   P_side[i] = (i == 0 ? parent : W_side[i - 1]) * rest_offset_parent[i]
//   L_side[i] = P_side[i]^-1 * W_side[i]            (side = fk, ik)
//   L[i]      = blend(L_fk[i], L_ik[i], fk_ik): translate and scale and shear
//               linearly, rotation by shortest-path slerp (local blending
//               keeps bone lengths when both sides keep them)
//   W[i]      = P[i] * L[i] with the blended chain's P
// so fk_ik = 0 gives the FK pose and 1 the IK pose (up to rounding).
// Channels: L[i] = T * JO * R * RA * SH * S (pivots zero), written as
// translations, rotations (R, a joint's rotateQuaternion in quaternion
// mode), scales, shears; worlds = W.

#include <span>

#include "rigel/math/types.h"

namespace rigel::ops::util {

// The IK side's world matrix of a chain's last joint: translation of
// `ik_world`, rotation, scale and shear of `end_control_world`.
math::Mat4 ik_end_world(const math::Mat4& ik_world, const math::Mat4& end_control_world);

// What FkIkBlendJob::run() found unusable (singular, not finite, or for
// `parent` not affine). Unusable input never gives NaN channels: the joints
// from the first unusable one on take the identity local matrix (channels
// 0, identity, 1, 0).
struct FkIkBlendResult {
  // `parent` is unusable: every joint takes the identity local matrix.
  bool unusable_parent = false;
  // The first joint whose FK or IK world matrix, IK end matrix or rest
  // offset (or a parent matrix built from them) is unusable; -1: none.
  int unusable_joint = -1;
};

struct FkIkBlendJob {
  // Validates job parameters. Returns false:
  // - if fk_ik is outside [0, 1] (NaN included);
  // - if translations, rotations, scales, shears or worlds is smaller than
  //   rest_offset_parent.
  bool validate() const;
  // Blends and writes the first n elements of each output, and *result
  // when given. Returns false if the job is not valid.
  bool run() const;

  // 0: the FK pose, 1: the IK pose.
  double fk_ik = 0.0;
  // World matrix of the root joint's parent.
  math::Mat4 parent = math::Mat4::Identity();
  // World matrices of each side, per joint; a missing element is taken from
  // the other side (the identity when both miss). Not owned.
  std::span<const math::Mat4> fk_world;
  std::span<const math::Mat4> ik_world;
  // When set, the IK side's last joint takes rotation, scale and shear from
  // ik_end (an IK control's world matrix), translation from ik_world
  // (ik_end_world()).
  bool use_ik_end = false;
  math::Mat4 ik_end = math::Mat4::Identity();
  // Each joint's offsetParentMatrix: its size is the chain's joint count.
  std::span<const math::Mat4> rest_offset_parent;
  // Each joint's jointOrient and rotateAxis, degrees (XYZ); missing: 0.
  std::span<const math::Vec3> rest_joint_orient;
  std::span<const math::Vec3> rest_rotate_axis;

  // Outputs, one element per joint (at least n each). Not owned.
  std::span<math::Vec3> translations;
  std::span<math::Quat> rotations;
  std::span<math::Vec3> scales;
  std::span<math::Vec3> shears;
  std::span<math::Mat4> worlds;
  // Optional output.
  FkIkBlendResult* result = nullptr;
};

}  // namespace rigel::ops::util
