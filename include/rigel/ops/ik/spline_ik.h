#pragma once
// Spline IK: a chain laid along a curve, shaped as a job (STYLE.md §3).
//
// The curve is the clamped uniform B-spline of the control points (degree
// min(3, count - 1): it starts at the first control point and ends at the
// last, like Maya's curves), parameter u in [0, 1].
//
// Joint 0 goes to the curve's start. Without stretch, each next joint is the
// first point further along the curve whose straight distance from the
// previous joint is that bone's length (so bone lengths are kept exactly);
// past the curve's end the chain continues straight along the end tangent.
// With stretch, joints go to the arc lengths that divide the whole curve in
// the proportions of the bone lengths, and each joint's aim axis is scaled by
// its bone's new length / old length (squash: the other two axes by
// 1 / sqrt of that, keeping volume).
//
// Orientation: each joint's aim axis points at the next joint (the chord of
// the curve, which keeps every child on its parent's aim axis, so local
// translations stay pure offsets along the aim); the end joint's aims along
// the curve's tangent. The up axis points toward up_vector (made
// perpendicular to the aim), then turns about the aim by the twist, which
// goes linearly, by length along the chain, from start_twist to end_twist.
// Where the aim is parallel to up_vector the previous joint's up is used.
// This assumes the joints' rest poses have each child on its parent's aim
// axis (joints oriented down the chain), as Maya's spline IK does.

#include <span>

#include "rigel/ops/ik/ik_chain.h"

namespace rigel::ops::ik {

// Point (and, when `tangent` is given, derivative dC/du) of the clamped
// uniform B-spline of `control_points` (at least 1) at u, clamped to [0, 1].
Vec3 bspline_point(std::span<const Vec3> control_points, double u, Vec3* tangent = nullptr);

// What SplineIkJob::run() reports.
struct SplineIkResult {
  // Length of the curve (from the arc-length table).
  double curve_length = 0.0;
  // Sum of the input bone lengths.
  double chain_length = 0.0;
  // Whether the chain ran past the curve's end (no stretch, chain longer
  // than the curve).
  bool overran = false;
};

struct SplineIkJob {
  // Validates job parameters. Returns false:
  // - if control_points has fewer than 2 points, or one is not finite;
  // - if world has fewer than 2 joints, or world_out.size() differs;
  // - if world_out overlaps world;
  // - if arc_lengths has fewer than 2 entries;
  // - if a world matrix is not affine (last row 0 0 0 1);
  // - if aim_axis or up_axis is not a unit vector, or they are not
  //   perpendicular (|dot| > kUnitTolerance);
  // - if up_vector is zero or not finite;
  // - if start_twist or end_twist is not finite.
  bool validate() const;
  // Fills arc_lengths and world_out (and *result when given). Returns false
  // if the job is not valid.
  bool run() const;

  // Curve control points, world space.
  std::span<const Vec3> control_points;
  // The chain's world matrices (affine), joint i + 1 the child of joint i:
  // the bone lengths and each joint's scale (column lengths) come from here.
  std::span<const Mat4> world;
  // The joint axis that points down the chain, and the one that points
  // toward up_vector: unit, perpendicular, in joint space.
  Vec3 aim_axis = Vec3::UnitX();
  Vec3 up_axis = Vec3::UnitY();
  // World-space up direction (need not be unit).
  Vec3 up_vector = Vec3::UnitY();
  // Twist about the aim axis at the first and last joint, radians.
  double start_twist = 0.0;
  double end_twist = 0.0;
  bool stretch = false;
  bool squash = false;
  // Caller-owned scratch: the curve's arc-length table at size() evenly
  // spaced parameters (entry k: length from u = 0 to u = k / (size() - 1)).
  // More entries, more accurate arc lengths (stretch); a few per control
  // point times 16 is plenty.
  std::span<double> arc_lengths;

  // Output world matrices: rotation (and stretch/squash) times the input
  // joint's column lengths, position on the curve.
  std::span<Mat4> world_out;
  // Optional output.
  SplineIkResult* result = nullptr;
};

}  // namespace rigel::ops::ik
