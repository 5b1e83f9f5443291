#pragma once
// FABRIK (Aristidou and Lasenby 2011) on a chain of N joints, shaped as a job
// (STYLE.md §3). Positions are solved; each joint's correction is then the
// smallest turn that takes its bone from where its parent carried it to its
// solved direction (no twist about the bone). Output convention: ik_chain.h.
//
// One iteration is a forward pass (end placed on the target, toward the
// root) and a backward pass (root put back, toward the end). Limits apply
// exactly in the backward pass, which is the last of every iteration, so the
// solution always keeps the bone lengths and the limits. The forward pass
// applies them approximately, from the other side: where a child's bone
// would leave its limit (seen in its parent's frame as the last backward
// pass left it, turned with the parent's new bone), the parent's bone turns
// until it is inside. Without that, limited joints near the end stall the
// solve (the forward pass leaves the joints above them in place and the
// backward pass clamps the same bones again).
//
// Limits make the solve local: tight limits (or a target the limited chain
// cannot reach) may leave FABRIK short of a target CCD would reach, and
// nearby targets may settle in different poses. CcdJob is the more robust
// choice under tight limits; FABRIK the faster one without them.

#include <span>

#include "rigel/ops/ik/ik_chain.h"

namespace rigel::ops::ik {

struct FabrikJob {
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
  // - Out of reach with no limits, the chain is laid straight at the target
  //   in closed form (0 iterations).
  // - Otherwise it iterates until the end is within tolerance of the target
  //   or max_iterations have run (an unreachable target under limits runs
  //   them all).
  // - A zero-length direction (two joints that meet) keeps the bone's input
  //   direction; nothing produces NaN.
  // - A chain that starts perfectly straight with the target on its line
  //   cannot bend out of the line (FABRIK's known limitation): it folds
  //   along the line. Give it a bend (a rest pose) to choose the plane.
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
  // i = 0). The last joint's entry has no bone and is ignored.
  std::span<const JointLimit> limits;
  // World matrix of joint 0's parent: the frame of limits[0].
  Mat4 parent_world = Mat4::Identity();

  // Caller-owned scratch, and on return the solved world positions.
  std::span<Vec3> positions;
  // Scratch during the solve (bone lengths, or each joint's turn under
  // limits), and on return one correction per joint, in its own frame (the
  // last joint's is the identity: it follows its parent).
  std::span<Quat> corrections;
  // Optional output.
  IkChainResult* result = nullptr;
};

}  // namespace rigel::ops::ik
