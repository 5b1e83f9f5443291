#pragma once
// IK for a chain of any length that lands its end on the target exactly (to
// rounding) whenever the bones reach it, bone lengths kept, shaped as a job
// (STYLE.md §3): what a posing tool wants while the animator drags the end
// of a tail or a spine, where FABRIK alone stops at its tolerance and
// cannot bend a straight chain out of its line.
//
// The solve, positions only:
// - two joints: the one bone points at the target;
// - a straight chain (every joint within 1e-9 of the chain's length of the
//   line from the first to the last) is laid on a circular arc toward the
//   target, every joint turning by the same angle, bulging toward the axis
//   of the first joint's world matrix most perpendicular to the chain (x
//   before y before z on ties): deterministic, and no crawl near full reach;
// - any other chain is solved by FabrikJob (tolerance, max_iterations);
// - then, when the end is not on the target (to 1e-13 of the chain's
//   length), the chain is split at its middle joint, the middle joint placed
//   by the two-bone rule in the current bend plane, each half turned rigidly
//   onto its new ends, and a half whose span must change solved the same
//   way (stretched toward its length or folded toward its shortest span, in
//   proportion to its room): exact to rounding.
// Out of reach, the chain points at the target as straight as it gets.
//
// With `turns`, each joint but the last also gets the smallest world-space
// rotation taking its bone from its input direction to its solved one (its
// new world linear part is turn * old: it re-aims at its child).

#include <span>

#include "rigel/ops/ik/ik_chain.h"

namespace rigel::ops::ik {

struct ChainReachJob {
  // Validates job parameters. Returns false:
  // - if world has fewer than 2 joints;
  // - if positions.size() or corrections.size() differs from world.size(),
  //   lengths.size() from world.size() - 1, or turns is neither empty nor
  //   of world.size();
  // - if positions, lengths, corrections and turns overlap each other or
  //   world;
  // - if a world matrix is not affine (last row 0 0 0 1) or not finite;
  // - if target is not finite;
  // - if tolerance is negative or not finite, or max_iterations is negative.
  bool validate() const;
  // Solves and writes positions (and turns). Returns false if the job is
  // not valid. A chain with no length stays where it is; nothing produces
  // NaN.
  bool run() const;

  // The chain's world matrices (affine), joint i + 1 the child of joint i;
  // joint 0 stays where it is. Their positions are the joints; the first
  // one's axes choose where a straight chain bends.
  std::span<const Mat4> world;
  // Target of the last joint, world space.
  Vec3 target = Vec3::Zero();
  // FabrikJob's stopping rule (before the exact finish).
  double tolerance = 1e-10;
  int max_iterations = 64;

  // Output: the solved world positions, one per joint.
  std::span<Vec3> positions;
  // Caller-owned scratch: the bone lengths (world.size() - 1), and
  // FabrikJob's corrections (world.size()).
  std::span<double> lengths;
  std::span<Quat> corrections;
  // Optional output: one world-space turn per joint (the last one's is the
  // identity), or empty.
  std::span<Mat3> turns;
};

}  // namespace rigel::ops::ik
