#pragma once
// Cyclic coordinate descent on a chain of N joints, shaped as a job
// (STYLE.md §3). Each sweep turns joints N - 2 down to 0 in turn, each by the
// smallest rotation that points (its joint -> end) at (its joint -> target),
// carrying its descendants rigidly. Orientations are tracked as rotations
// (not rebuilt from positions), so a limit checked in the parent's frame
// stays true when an ancestor turns later. Output convention: ik_chain.h.

#include <span>

#include "rigel/ops/ik/ik_chain.h"

namespace rigel::ops::ik {

struct CcdJob {
  // Validates job parameters. Returns false:
  // - if world has fewer than 2 joints;
  // - if positions.size() or corrections.size() differs from world.size();
  // - if limits is neither empty nor of world.size();
  // - if a limit is invalid (see joint_limit_error());
  // - if a world matrix or parent_world is not affine (last row 0 0 0 1);
  // - if target is not finite;
  // - if tolerance is negative or not finite, or max_iterations is negative.
  bool validate() const;
  // Solves and writes positions, corrections and *result (when given).
  // Returns false if the job is not valid.
  // - Out of reach with no limits, each bone is turned onto the line to the
  //   target in closed form (0 iterations): the chain lies straight.
  // - Otherwise it sweeps until the end is within tolerance of the target
  //   or max_iterations sweeps have run.
  // - Under a cone, a joint's turn that would take its bone outside is
  //   followed by the smallest turn back to the cone (constrain_direction()),
  //   so the solve varies continuously as the limit starts to bite. Under a
  //   hinge, a joint turns only about the hinge axis: from its bone to the
  //   wanted direction projected onto the hinge plane and clamped to the
  //   range.
  // - Limits are solved locally: an unreachable target under limits runs
  //   every sweep, and different targets may settle in different poses.
  // - Positions on return are rebuilt from the rotations (each bone its
  //   input vector turned), so lengths do not drift over many sweeps.
  bool run() const;

  // The chain's world matrices (affine), joint i + 1 the child of joint i;
  // joint 0 stays where it is. The last joint is the end effector.
  std::span<const Mat4> world;
  // Target of the end joint, world space.
  Vec3 target = Vec3::Zero();
  // Stop when |end - target| <= tolerance (world units).
  double tolerance = 1e-6;
  int max_iterations = 64;
  // Empty (no limits), or one per joint: limits[i] constrains the bone from
  // joint i to joint i + 1 in the frame of joint i - 1 (parent_world for
  // i = 0). The last joint's entry is ignored.
  std::span<const JointLimit> limits;
  // World matrix of joint 0's parent: the frame of limits[0].
  Mat4 parent_world = Mat4::Identity();

  // Caller-owned scratch, and on return the solved world positions.
  std::span<Vec3> positions;
  // Scratch during the solve (world-space turn of each joint), and on return
  // one correction per joint in its own frame (the last is the identity).
  std::span<Quat> corrections;
  // Optional output.
  IkChainResult* result = nullptr;
};

}  // namespace rigel::ops::ik
