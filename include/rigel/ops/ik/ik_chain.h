#pragma once
// What the IK solvers share: the convention of their output, joint limits,
// the result of an iterative solve, and the two jobs that turn a solver's
// output into new local matrices for a chain (the one path that tests and
// graph nodes use).
//
// Convention (every solver in rigel/ops/ik):
// - Inputs are in world (model) space: the chain's current world matrices,
//   the target, the pole. A "chain" is a span of joints where joint i + 1 is
//   the child of joint i; joint 0's parent is outside the chain.
// - A joint's "rotation frame" is the rotation of its world matrix as
//   math::decompose() finds it (Gram-Schmidt on the columns x, y, z; a
//   reflection is carried by the scale, not the frame).
// - Rotational solvers (TwoBoneIkJob, FabrikJob, CcdJob) output one
//   corrective quaternion per joint, in that joint's own rotation frame.
//   It applies on the right of the joint's local rotation, before its scale:
//       local_rotation = local_rotation * correction
//       local_matrix   = T * (Q * correction) * U    where local = T * Q * U
//   (U: the scale and shear), which ChainCorrectionJob does. This is what
//   ozz-animation's IKTwoBoneJob outputs and how its samples apply it
//   (`aos_quat_ref = aos_quat_ref * quat`). A correction in the joint's own
//   frame does not depend on what happens to its parents: the new world
//   matrices are world'[i] = world'[i - 1] * local[i] * R(correction[i]),
//   so corrections along a chain compose without the solver knowing the
//   chain's parent.
// - Exactness: bone lengths and reach are exact when the chain's world
//   matrices have uniform (positive) scale and no shear, the usual case.
//   With non-uniform scale above a joint a rotation cannot be rigid in world
//   space, and the result is approximate.
// - Spline IK places joints directly and outputs world matrices;
//   ChainWorldToLocalJob turns them into local matrices.

#include <cstdint>
#include <span>

#include "rigel/math/types.h"

namespace rigel::ops::ik {

using math::Mat3;
using math::Mat4;
using math::Quat;
using math::Vec3;

// Tolerance on |v| - 1 for inputs documented as unit vectors.
inline constexpr double kUnitTolerance = 1e-6;

enum class LimitKind : std::uint8_t {
  kNone = 0,   // free
  kHinge = 1,  // the bone turns in the plane perpendicular to `axis`, within [min_angle, max_angle]
  kCone = 2,   // the bone stays within `half_angle` of `axis`
};

// A limit on the direction of one bone (from its joint to the next joint of
// the chain), expressed in the rotation frame of the joint's parent: joint
// i - 1 as the solver leaves it, or for joint 0 the chain's parent_world.
// Angles in radians.
struct JointLimit {
  LimitKind kind = LimitKind::kNone;
  // Hinge axis or cone axis, unit, in the parent's frame.
  Vec3 axis = Vec3::UnitZ();
  // Hinge only: the bone direction at angle 0, unit and perpendicular to
  // `axis`, in the parent's frame. Angles are measured from it about `axis`
  // (right-handed).
  Vec3 reference = Vec3::UnitX();
  // Hinge only: allowed range, -pi <= min_angle <= max_angle <= pi.
  double min_angle = -math::kPi;
  double max_angle = math::kPi;
  // Cone only: largest angle between the bone and `axis`, in [0, pi].
  double half_angle = math::kPi;
};

// Why a limit is invalid, or nullptr when it is valid. Failures:
// - kind is not one of LimitKind's values;
// - hinge or cone: axis is not unit length (kUnitTolerance) or not finite;
// - hinge: reference is not unit length, or not perpendicular to axis
//   (|dot| > kUnitTolerance);
// - hinge: min_angle > max_angle, or either outside [-pi, pi] (or NaN);
// - cone: half_angle outside [0, pi] (or NaN).
const char* joint_limit_error(const JointLimit& limit);

// The allowed direction nearest to `direction` (unit, parent frame): itself
// when allowed; for a cone, the direction on the cone's boundary in the same
// plane as the axis; for a hinge, the projection onto the hinge plane with
// its angle clamped to the nearer end of the range (a direction along the
// hinge axis counts as angle 0). The limit must be valid.
Vec3 constrain_direction(const JointLimit& limit, const Vec3& direction);

// What an iterative chain solve (FabrikJob, CcdJob) did.
struct IkChainResult {
  // Iterations run (one FABRIK forward+backward pass, or one CCD sweep from
  // the end to the root). 0 when the input was already within tolerance, or
  // when the solver placed the chain in closed form (target out of reach,
  // no limits).
  int iterations = 0;
  // Distance from the end joint to the target at the solution.
  double error = 0.0;
  // error <= tolerance.
  bool reached = false;
};

// Applies per-joint corrections (and optional stretch) to a chain's local
// matrices, and optionally computes its new world matrices.
struct ChainCorrectionJob {
  // Validates job parameters. Returns false:
  // - if local is empty;
  // - if corrections.size() or local_out.size() differs from local.size();
  // - if translate_scale is neither empty nor of local.size();
  // - if world_out is neither empty nor of local.size();
  // - if world_out overlaps local, local_out or corrections, or local_out
  //   overlaps local without being the same span (in place is allowed);
  // - if parent_world is not affine (last row 0 0 0 1).
  bool validate() const;
  // With local[i] = T * Q * U (T its translation, Q its rotation frame, U
  // its scale and shear): local_out[i] = T' * Q * R(correction[i]) * U,
  // where T' is T's offset times translate_scale[i] (or 1); and
  // world_out[i] = (i == 0 ? parent_world : world_out[i - 1]) * local_out[i].
  // Returns false if the job is not valid.
  bool run() const;

  // The chain's local matrices (affine), joint i + 1 the child of joint i.
  std::span<const Mat4> local;
  // One correction per joint, in the joint's own frame (need not be
  // normalised; a zero quaternion counts as the identity).
  std::span<const Quat> corrections;
  // Empty, or a factor per joint for its local translation (stretch: the
  // bone from the parent to this joint gets longer by this factor).
  std::span<const double> translate_scale;
  // World matrix of joint 0's parent.
  Mat4 parent_world = Mat4::Identity();
  // Output local matrices. May be `local` itself.
  std::span<Mat4> local_out;
  // Optional output world matrices (empty: not computed).
  std::span<Mat4> world_out;
};

// Local matrices of a chain from its world matrices:
// local[i] = inverse(i == 0 ? parent_world : world[i - 1]) * world[i].
struct ChainWorldToLocalJob {
  // Validates job parameters. Returns false:
  // - if world is empty, or local.size() differs from world.size();
  // - if local overlaps world;
  // - if parent_world or a world matrix is not affine, or not invertible
  //   (|det| of its 3x3 part <= 1e-300).
  bool validate() const;
  bool run() const;  // Returns false if the job is not valid.

  std::span<const Mat4> world;
  Mat4 parent_world = Mat4::Identity();
  std::span<Mat4> local;
};

}  // namespace rigel::ops::ik
