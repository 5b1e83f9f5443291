#pragma once
// Pseudo-inverse posing of a chain (seed 000 §5.7), shaped as a job
// (STYLE.md §3): the end joint's motion to its target spread evenly down the
// chain, joint i of n moving by i / (n - 1) of it, so the top stays. It is
// not IK: bones stretch and shrink, unless keep_lengths restores each
// bone's length from the top out along its new direction (the end then
// misses the target by what the lengths take back).
//
// With `turns`, each joint but the last also gets the smallest world-space
// rotation taking its bone from its input direction to its solved one (its
// new world linear part is turn * old: it re-aims at its child).

#include <span>

#include "rigel/ops/ik/ik_chain.h"

namespace rigel::ops::ik {

struct PseudoInverseJob {
  // Validates job parameters. Returns false:
  // - if positions has fewer than 2 joints;
  // - if solved.size() differs from positions.size(), or turns is neither
  //   empty nor of positions.size();
  // - if solved or turns overlaps positions (or each other);
  // - if a position or the target is not finite.
  bool validate() const;
  // Writes solved (and turns). Returns false if the job is not valid.
  // A bone that the spread shrinks to nothing keeps its input direction
  // under keep_lengths; a turn of a zero-length bone is the identity.
  bool run() const;

  // The chain's joint positions, world space; joint 0 is the top (stays),
  // the last the end that moves to `target`.
  std::span<const Vec3> positions;
  Vec3 target = Vec3::Zero();
  // Restore each bone's input length after the spread.
  bool keep_lengths = false;

  // Output positions, one per joint.
  std::span<Vec3> solved;
  // Optional output: one world-space turn per joint (the last one's is the
  // identity), or empty.
  std::span<Mat3> turns;
};

}  // namespace rigel::ops::ik
