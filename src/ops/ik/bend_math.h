#pragma once
// Geometry the position-placing chain solves share (TwoBoneKeepPlaneJob,
// PseudoInverseJob, ChainReachJob; private to src/ops/ik): the smallest turn
// between two directions as a matrix, the perpendicular nearest a
// direction, and the axis a straight chain bends toward. They work on the
// bones' directions in world space, not on frames, so a turn applies to a
// joint's world linear part on the left: new = turn * old.

#include <algorithm>
#include <cmath>

#include "rigel/ops/ik/ik_chain.h"

namespace rigel::ops::ik::detail {

// The smallest rotation taking direction `from` to `to` (identity when
// either is degenerate).
inline Mat3 swing(const Vec3& from, const Vec3& to) {
  const double a = from.norm(), b = to.norm();
  if (a < 1e-300 || b < 1e-300) return Mat3::Identity();
  return Quat::FromTwoVectors(from / a, to / b).normalized().toRotationMatrix();
}

// The axis of `r` (a chain start's world linear part) most perpendicular
// to the unit direction `u`: where a straight chain bends (x before y
// before z on ties).
inline Vec3 straight_pole(const Mat3& r, const Vec3& u) {
  int best = 0;
  for (int c = 1; c < 3; ++c)
    if (std::abs(r.col(c).normalized().dot(u)) < std::abs(r.col(best).normalized().dot(u))) best = c;
  return r.col(best).normalized();
}

// The unit vector perpendicular to unit `u` nearest `toward` (any
// perpendicular when `toward` is along `u`).
inline Vec3 perpendicular(const Vec3& u, const Vec3& toward) {
  Vec3 w = toward - toward.dot(u) * u;
  if (w.norm() <= 1e-9 * std::max(1.0, toward.norm())) w = u.unitOrthogonal();
  return w.normalized();
}

}  // namespace rigel::ops::ik::detail
