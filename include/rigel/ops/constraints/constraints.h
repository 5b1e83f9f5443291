#pragma once
// Constraints as kernels (STYLE.md §3): parent, point, orient, scale, aim and
// pole vector. Each is a job with spans in and pointers out, no allocation.
//
// Shared model (parent, point, orient, scale). Target i contributes the
// world matrix
//   contribution_i = target_world[i] * target_offsets[i]
// where the offset is the maintain-offset matrix (compute_offset(), identity
// when maintain offset is off). The contributions are blended with the
// weights normalised to sum to 1:
// - translations: weighted mean;
// - rotations: the normalised weighted sum of quaternions, each first
//   flipped into the hemisphere of the first target's (shortest path; for
//   two targets at 0.5/0.5 this is exactly the slerp half-way rotation);
// - scale and shear: weighted mean.
// The blended world transform is then brought into the driven's parent
// space with `parent_inverse` (the inverse of the driven's parent world
// matrix, times the inverse of its offset parent matrix if it has one).
//
// Weights must be >= 0. When they sum to 0 (every target switched off), the
// driven keeps its rest value (`rest_*` fields): there is nothing to follow.

#include <cstdint>
#include <span>

#include "rigel/math/rotation.h"
#include "rigel/math/transform.h"
#include "rigel/math/types.h"

namespace rigel::ops::constraints {

using math::Mat4;
using math::Quat;
using math::Vec3;

// The maintain-offset matrix of one target: the offset that keeps the
// driven exactly where it is (driven_world) when the constraint is created
// with this target alone at weight 1.
// - rigid false: inverse(target_world) * driven_world, so that
//   target_world * offset == driven_world.
// - rigid true (see ParentConstraintJob::rigid): the linear part is
//   R_target^T * driven_linear and the translation is the driven's position
//   in the target's full space, so that rigid_concat(target_world, offset)
//   == driven_world.
// Fails (returns identity) only when target_world is singular; check with
// is_offset_computable() first if that can happen.
Mat4 compute_offset(const Mat4& target_world, const Mat4& driven_world, bool rigid = false);
// False when target_world is not affine, not finite or singular.
bool is_offset_computable(const Mat4& target_world);

// The scale- and shear-free concatenation of seed 001 used by the rigid
// parent constraint: the translation is that of target_world * offset (a
// scaled target repositions the driven, as a parent would), the linear part
// is rotation(target_world) * linear(offset): the target's scale and shear
// never reach the driven, which keeps the scale and shear of its offset (its
// own, with compute_offset(..., true)). For a target with uniform scale and
// no shear and an offset without shear this equals
// math::concat_without_scale_shear(target_world, offset); for a non-uniform
// scale it differs on purpose: the polar rotation of the product would turn
// the driven with the target's scale, not with its rotation.
Mat4 rigid_concat(const Mat4& target_world, const Mat4& offset);

// Inputs common to the blending constraints. Not owned.
struct TargetSpans {
  // World matrices of the targets (affine, finite).
  std::span<const Mat4> world;
  // Weight of each target: finite, >= 0. Normalised by their sum.
  std::span<const double> weights;
  // Maintain-offset matrix of each target (affine, finite; identity = off).
  std::span<const Mat4> offsets;
};

struct ParentConstraintJob {
  // Validates job parameters. Returns false:
  // - if `output` is null;
  // - if targets.world, targets.weights and targets.offsets sizes differ, or
  //   there is no target;
  // - if a weight is negative or not finite;
  // - if a target world matrix or offset is not affine (last row 0 0 0 1)
  //   or has a non-finite entry;
  // - if parent_inverse or rest_local is not affine or not finite.
  bool validate() const;
  // Writes the driven's local matrix (parent_inverse * blended world), or
  // rest_local when the weights sum to 0. Returns false if not valid.
  bool run() const;

  TargetSpans targets;
  // Inverse world matrix of the driven's parent (identity for a root).
  Mat4 parent_inverse = Mat4::Identity();
  // The driven's local matrix while every weight is 0.
  Mat4 rest_local = Mat4::Identity();
  // Seed 001: each contribution is rigid_concat(target, offset) instead of
  // target * offset, so the targets' scale and shear do not creep into the
  // driven (a scaled target moves the driven but does not scale it).
  bool rigid = false;
  // Output: the driven's local matrix. Not owned.
  Mat4* output = nullptr;
};

struct PointConstraintJob {
  // Validates job parameters. Returns false:
  // - if `output` is null;
  // - if the target spans' sizes differ, or there is no target;
  // - if a weight is negative or not finite;
  // - if a target world matrix or offset is not affine or not finite;
  // - if parent_inverse is not affine or not finite, or rest_translate is
  //   not finite.
  bool validate() const;
  // Writes the driven's local translation: parent_inverse applied to the
  // weighted mean of the contributions' positions; rest_translate when the
  // weights sum to 0. Returns false if not valid.
  bool run() const;

  TargetSpans targets;
  Mat4 parent_inverse = Mat4::Identity();
  Vec3 rest_translate = Vec3::Zero();
  // Output: local translation, parent space. Not owned.
  Vec3* output = nullptr;
};

struct OrientConstraintJob {
  // Validates job parameters. Returns false:
  // - if `output` is null;
  // - if the target spans' sizes differ, or there is no target;
  // - if a weight is negative or not finite;
  // - if a target world matrix or offset is not affine or not finite;
  // - if parent_inverse is not affine or not finite, or rest_rotation is
  //   not a finite non-zero quaternion.
  bool validate() const;
  // Writes the driven's local rotation: rotation(parent_inverse) times the
  // blended world rotation (shortest path); the normalised rest_rotation
  // when the weights sum to 0. w >= 0. Returns false if not valid.
  bool run() const;

  TargetSpans targets;
  Mat4 parent_inverse = Mat4::Identity();
  Quat rest_rotation = Quat::Identity();
  // Output: local rotation (the rotation of the local matrix; a joint's
  // joint orient is the caller's to remove). Not owned.
  Quat* output = nullptr;
};

struct ScaleConstraintJob {
  // Validates job parameters. Returns false:
  // - if `output` is null;
  // - if the target spans' sizes differ, or there is no target;
  // - if a weight is negative or not finite;
  // - if a target world matrix or offset is not affine or not finite;
  // - if parent_inverse is not affine or not finite, or rest_scale is not
  //   finite.
  bool validate() const;
  // Writes the driven's local scale: the weighted mean of the contributions'
  // scales, multiplied per axis by the scale of parent_inverse (exact when
  // the parent's axes line up with the driven's, as in Maya's
  // scaleConstraint); rest_scale when the weights sum to 0. Returns false if
  // not valid.
  bool run() const;

  TargetSpans targets;
  Mat4 parent_inverse = Mat4::Identity();
  Vec3 rest_scale = Vec3::Ones();
  Vec3* output = nullptr;
};

// How AimConstraintJob finds the world direction the up vector leans to
// (Maya's worldUpType; the same values).
enum class WorldUpType : std::uint8_t {
  kScene = 0,           // the scene's up: +Y
  kObject = 1,          // toward the position of world_up_matrix
  kObjectRotation = 2,  // world_up_vector turned by world_up_matrix
  kVector = 3,          // world_up_vector, world space
  kNone = 4,            // no up: the smallest rotation taking aim_vector to the target
};
inline constexpr int kWorldUpTypeCount = 5;

struct AimConstraintJob {
  // Validates job parameters. Returns false:
  // - if `output` is null;
  // - if targets.world and targets.weights sizes differ, or there is no
  //   target (targets.offsets is not used and must be empty or the same
  //   size);
  // - if a weight is negative or not finite;
  // - if a target world matrix (or offset) is not affine or not finite;
  // - if aim_vector or up_vector is shorter than 1e-9 or not finite, or
  //   they are parallel (|sin| < 1e-6);
  // - if world_up_type is not one of WorldUpType's values;
  // - if world_up_vector, driven_position, rest_rotation or offset has a non-finite
  //   entry, or rest_rotation or offset is zero;
  // - if world_up_matrix or parent_inverse is not affine or not finite.
  bool validate() const;
  // Writes the driven's local rotation (rotation(parent_inverse) * world
  // rotation * offset): its aim_vector points from driven_position at the
  // weighted mean of the targets' positions (offsets applied), and its
  // up_vector is as close to the world up as that allows. Never NaN: when
  // the world up is parallel to the aim direction (or zero), the up vector
  // keeps the direction the smallest aiming rotation gives it; when the
  // target is at the driven (or the weights sum to 0), the rest rotation is
  // written. Returns false if not valid.
  bool run() const;

  TargetSpans targets;
  // World position of the driven (the pivot it aims from).
  Vec3 driven_position = Vec3::Zero();
  // Axes of the driven, in its own space (need not be unit or orthogonal,
  // but not parallel).
  Vec3 aim_vector = Vec3::UnitX();
  Vec3 up_vector = Vec3::UnitY();
  WorldUpType world_up_type = WorldUpType::kScene;
  // kVector: world direction; kObjectRotation: direction in world_up_matrix's space.
  Vec3 world_up_vector = Vec3::UnitY();
  // kObject and kObjectRotation: world matrix of the up object.
  Mat4 world_up_matrix = Mat4::Identity();
  // Rotation applied after aiming, in the driven's space (Maya's offset).
  Quat offset = Quat::Identity();
  Mat4 parent_inverse = Mat4::Identity();
  Quat rest_rotation = Quat::Identity();
  Quat* output = nullptr;
};

struct PoleVectorConstraintJob {
  // Validates job parameters. Returns false:
  // - if `output` is null;
  // - if targets.world and targets.weights sizes differ, or there is no
  //   target (offsets as for AimConstraintJob);
  // - if a weight is negative or not finite;
  // - if a target world matrix (or offset) is not affine or not finite;
  // - if start_position, handle_position or rest_pole_vector is not finite;
  // - if parent_inverse is not affine or not finite.
  bool validate() const;
  // The pole position p is the weighted mean of the targets' positions. With
  // s the chain start and h the handle (the end's target), writes the part
  // of p - s perpendicular to the line s-h: the pole's offset from that
  // line, a vector from the start (TwoBoneIkJob's pole_vector), turned into
  // the handle's parent space by the linear part of parent_inverse. When
  // h == s the whole p - s is used; when the pole lies on the line the
  // result is zero (a solver keeps its plane then). When the weights sum to
  // 0, rest_pole_vector is written. Returns false if not valid.
  bool run() const;

  TargetSpans targets;
  Vec3 start_position = Vec3::Zero();
  Vec3 handle_position = Vec3::Zero();
  Mat4 parent_inverse = Mat4::Identity();
  Vec3 rest_pole_vector = Vec3::Zero();
  Vec3* output = nullptr;
};

}  // namespace rigel::ops::constraints
