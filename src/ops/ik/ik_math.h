#pragma once
// Small vector and quaternion helpers shared by the IK kernels (private to
// src/ops/ik). All inline: they sit in the solvers' inner loops.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>

#include "rigel/ops/ik/ik_chain.h"

// The kernels' run() is built twice on x86-64, for the baseline (SSE2) and
// for x86-64-v3 (AVX2, FMA, BMI2), and the loader picks one for the CPU
// (GCC/Clang function multiversioning). The v3 build is 8-15% faster on the
// two-bone solve (130 vs 142 ns on an idle AMD EPYC, 145 vs 168 ns under
// load: VEX encoding, FMA, wider SLP vectorisation); -DRIGEL_IK_NO_CLONES
// builds the baseline only. FMA contraction rounds differently, so results may differ
// in the last bits between CPUs, as math::LocalToWorldJob's variants do.
#if defined(__x86_64__) && defined(__has_attribute)
#if __has_attribute(target_clones) && !defined(RIGEL_IK_NO_CLONES)
#define RIGEL_IK_MULTIVERSION __attribute__((target_clones("arch=x86-64-v3", "default")))
#endif
#endif
#ifndef RIGEL_IK_MULTIVERSION
#define RIGEL_IK_MULTIVERSION
#endif

namespace rigel::ops::ik::detail {

// Lengths at or below this count as zero (world units: far below any joint
// spacing of a character, far above rounding of unit-sized coordinates).
inline constexpr double kTinyLength = 1e-12;

inline bool is_affine(const Mat4& m) { return m(3, 0) == 0.0 && m(3, 1) == 0.0 && m(3, 2) == 0.0 && m(3, 3) == 1.0; }

// |v| within kUnitTolerance of 1 (compared squared: no square root).
inline bool is_unit(const Vec3& v) {
  constexpr double kLow = (1.0 - kUnitTolerance) * (1.0 - kUnitTolerance);
  constexpr double kHigh = (1.0 + kUnitTolerance) * (1.0 + kUnitTolerance);
  const double n2 = v.squaredNorm();
  return n2 >= kLow && n2 <= kHigh;  // false for NaN
}

inline bool all_finite(const Vec3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

inline Vec3 translation(const Mat4& m) { return m.topRightCorner<3, 1>(); }

// Whether two spans share any memory (pointer ranges compared as addresses).
template <typename A, typename B>
bool overlap(const A* a, std::size_t a_count, const B* b, std::size_t b_count) {
  if (a_count == 0 || b_count == 0) return false;
  const auto a0 = reinterpret_cast<std::uintptr_t>(a);
  const auto a1 = a0 + a_count * sizeof(A);
  const auto b0 = reinterpret_cast<std::uintptr_t>(b);
  const auto b1 = b0 + b_count * sizeof(B);
  return a0 < b1 && b0 < a1;
}

// `v` scaled to unit length, or false (v untouched) when it is too short.
inline bool normalize_in_place(Vec3& v) {
  const double n2 = v.squaredNorm();
  if (!(n2 > kTinyLength * kTinyLength)) return false;
  v *= 1.0 / std::sqrt(n2);
  return true;
}

// For a linear part that is a uniform positive scale times a rotation (the
// usual joint: A = s R, no shear, no reflection), s^2; otherwise 0. Then the
// rotation frame is A / s, and R^T M R = A^T M A / s^2 needs no square root.
inline double uniform_scale_squared(const Mat3& a) {
  const double xx = a.col(0).squaredNorm();
  const double yy = a.col(1).squaredNorm();
  const double zz = a.col(2).squaredNorm();
  const double tolerance = 1e-12 * xx;
  if (!(xx > 0.0) || std::abs(yy - xx) > tolerance || std::abs(zz - xx) > tolerance) return 0.0;
  if (std::abs(a.col(0).dot(a.col(1))) > tolerance || std::abs(a.col(0).dot(a.col(2))) > tolerance ||
      std::abs(a.col(1).dot(a.col(2))) > tolerance) {
    return 0.0;
  }
  return a.col(2).dot(a.col(0).cross(a.col(1))) > 0.0 ? xx : 0.0;
}

// The rotation frame of a 3x3 linear part, as math::decompose() finds it:
// Gram-Schmidt on x, then y, then z; a reflection moves into the x axis (the
// frame stays a proper rotation); a collapsed axis is completed.
[[gnu::always_inline]] inline Mat3 rotation_frame(const Mat3& m) {
  const double scale2 = uniform_scale_squared(m);
  if (scale2 > 0.0) return m * (1.0 / std::sqrt(scale2));  // the usual case, one square root
  Vec3 x = m.col(0);
  if (!normalize_in_place(x)) x = Vec3::UnitX();
  Vec3 y = m.col(1) - x * x.dot(m.col(1));
  if (!normalize_in_place(y)) {
    y = m.col(2).cross(x);
    if (!normalize_in_place(y)) y = x.unitOrthogonal();
  }
  Vec3 z = x.cross(y);
  Mat3 r;
  if (m.col(2).dot(z) < 0.0) {
    // det < 0: decompose() gives the reflection to scale.x, so the frame is
    // (-x, y, -z), proper again.
    r.col(0) = -x;
    r.col(1) = y;
    r.col(2) = -z;
  } else {
    r.col(0) = x;
    r.col(1) = y;
    r.col(2) = z;
  }
  return r;
}
inline Mat3 rotation_frame(const Mat4& m) { return rotation_frame(Mat3(m.topLeftCorner<3, 3>())); }

// Rotation about the unit `axis` by the angle whose sine and cosine are `s`
// and `c` (need not be normalised; both zero gives the identity). Exact near
// 0 and near pi, continuous everywhere. Two square roots, one division.
inline Quat quat_from_axis_sin_cos(const Vec3& axis, double s, double c) {
  const double r2 = s * s + c * c;
  if (!(r2 > 0.0)) return Quat::Identity();
  const double r = std::sqrt(r2);  // not std::hypot: a libm call, slow, and s, c are small
  if (c >= 0.0) {
    // (axis sin a, 1 + cos a) has the direction of (axis sin a/2, cos a/2);
    // scaled by r that is (axis s, r + c), of length sqrt(2 r (r + c)).
    const double w = r + c;
    const double inv = 1.0 / std::sqrt(2.0 * r * w);
    const double h = s * inv;
    return Quat(w * inv, axis.x() * h, axis.y() * h, axis.z() * h);
  }
  // Near pi: cos a/2 = sqrt((1 + cos a) / 2) keeps its precision there.
  const double inv_r = 1.0 / r;
  const double cn = c * inv_r;
  const double w = std::sqrt(std::max(0.0, 0.5 * (1.0 + cn)));
  const double h = std::copysign(std::sqrt(std::max(0.0, 0.5 * (1.0 - cn))), s);
  return Quat(w, axis.x() * h, axis.y() * h, axis.z() * h);
}

// The smallest rotation taking unit `from` to unit `to`. Opposite vectors
// turn by pi about an axis perpendicular to `from`.
inline Quat shortest_arc(const Vec3& from, const Vec3& to) {
  const double c = from.dot(to);
  const Vec3 axis = from.cross(to);
  if (c >= 0.0) {
    const double w = 1.0 + c;
    const double n = std::sqrt(axis.squaredNorm() + w * w);
    return Quat(w / n, axis.x() / n, axis.y() / n, axis.z() / n);
  }
  const double s = axis.norm();
  if (s > 1e-15) return quat_from_axis_sin_cos(axis / s, s, c);
  const Vec3 any = from.unitOrthogonal();
  return Quat(0.0, any.x(), any.y(), any.z());
}

// q with w >= 0: the same rotation, and the form that interpolates with the
// identity along the short path.
inline Quat positive_w(const Quat& q) { return q.w() < 0.0 ? Quat(-q.w(), -q.x(), -q.y(), -q.z()) : q; }

}  // namespace rigel::ops::ik::detail

namespace rigel::ops::ik::detail {

// The checks FabrikJob and CcdJob share (their validate() lists them).
inline bool valid_chain_job(std::span<const Mat4> world, std::span<const Vec3> positions,
                            std::span<const Quat> corrections, std::span<const JointLimit> limits,
                            const Mat4& parent_world, const Vec3& target, double tolerance, int max_iterations) {
  const std::size_t count = world.size();
  if (count < 2) return false;
  if (positions.size() != count || corrections.size() != count) return false;
  if (!limits.empty() && limits.size() != count) return false;
  for (const JointLimit& limit : limits) {
    if (joint_limit_error(limit) != nullptr) return false;
  }
  if (!is_affine(parent_world)) return false;
  for (const Mat4& m : world) {
    if (!is_affine(m)) return false;
  }
  if (!all_finite(target)) return false;
  if (!(tolerance >= 0.0 && std::isfinite(tolerance))) return false;
  return max_iterations >= 0;
}

// Whether any bone (every joint but the last) has a limit.
inline bool has_limits(std::span<const JointLimit> limits) {
  for (std::size_t i = 0; i + 1 < limits.size(); ++i) {
    if (limits[i].kind != LimitKind::kNone) return true;
  }
  return false;
}

}  // namespace rigel::ops::ik::detail
