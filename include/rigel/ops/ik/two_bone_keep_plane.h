#pragma once
// Analytic two-bone IK that keeps the chain's current bend plane, shaped as
// a job (STYLE.md §3): what a posing tool wants while the animator drags the
// end of a limb. There is no pole: the knee keeps pointing where it points
// now (its direction perpendicular to start-to-end, carried onto the new
// start-to-target direction, stays on the side it was), so a target at the
// end's current position changes nothing. TwoBoneIkJob is the rig's solver
// (pole, twist, soft IK, stretch); this one has none of those.
//
// Positions are solved, then each of the start and mid joints gets the
// world-space rotation that takes its bone and the bend plane's normal from
// where they were to where they are (the joint's new world linear part is
// turn * old: the bone turns, and so does the plane, so the joint keeps its
// orientation relative to the plane). Bone lengths are kept exactly.
//
// A straight chain has no bend plane: it bends toward the axis of the start
// joint's world matrix most perpendicular to the chain (x before y before z
// on ties), so the result is deterministic.

#include "rigel/ops/ik/ik_chain.h"

namespace rigel::ops::ik {

// What TwoBoneKeepPlaneJob::run() writes.
struct TwoBoneKeepPlaneOutput {
  // Solved world positions of the mid and end joints (the start stays).
  Vec3 mid = Vec3::Zero();
  Vec3 end = Vec3::Zero();
  // World-space turns of the start and mid joints: a joint's new world
  // linear part is turn * its old one.
  Mat3 start_turn = Mat3::Identity();
  Mat3 mid_turn = Mat3::Identity();
  // false when a bone has no length (at most 1e-12 of the chain's length):
  // the chain cannot be turned by this solve; mid and end are then the
  // input positions and the turns the identity.
  bool solved = false;
  // The target's distance from the start is within the chain's range
  // [|a - b|, a + b] (a, b the bone lengths): the end lands on it. Otherwise
  // the chain points at it, fully stretched or folded.
  bool reached = false;
};

struct TwoBoneKeepPlaneJob {
  // Validates job parameters. Returns false:
  // - if start_world, mid_world, end_world or output is null;
  // - if one of the three world matrices is not affine (last row 0 0 0 1)
  //   or not finite;
  // - if target is not finite.
  bool validate() const;
  // Solves and writes *output. Returns false if the job is not valid.
  // Degenerate input never produces NaN: a target at the start keeps the
  // current start-to-end direction; an end at the start keeps the start
  // bone's direction; a zero-length bone solves nothing (output.solved).
  bool run() const;

  // World matrices of the three joints (affine): only their positions and
  // the start's axes (for a straight chain) are read. Not owned.
  const Mat4* start_world = nullptr;
  const Mat4* mid_world = nullptr;
  const Mat4* end_world = nullptr;
  // Target of the end joint, world space.
  Vec3 target = Vec3::Zero();
  // Output. Not owned.
  TwoBoneKeepPlaneOutput* output = nullptr;
};

}  // namespace rigel::ops::ik
