#include "rigel/ops/ik/two_bone_keep_plane.h"

#include <algorithm>
#include <cmath>

#include "bend_math.h"
#include "ik_math.h"

namespace rigel::ops::ik {

using detail::all_finite;
using detail::is_affine;
using detail::translation;

namespace {

// Orthonormal frame with x along `x` and z along `z` (z perpendicular to x).
Mat3 frame(const Vec3& x, const Vec3& z) {
  Mat3 f;
  const Vec3 xn = x.normalized(), zn = z.normalized();
  f.col(0) = xn;
  f.col(1) = zn.cross(xn);
  f.col(2) = zn;
  return f;
}

bool valid_matrix(const Mat4* m) { return m != nullptr && is_affine(*m) && m->allFinite(); }

}  // namespace

bool TwoBoneKeepPlaneJob::validate() const {
  if (!valid_matrix(start_world) || !valid_matrix(mid_world) || !valid_matrix(end_world)) return false;
  return output != nullptr && all_finite(target);
}

bool TwoBoneKeepPlaneJob::run() const {
  if (!validate()) return false;
  TwoBoneKeepPlaneOutput& out = *output;
  const Vec3 s = translation(*start_world), mid = translation(*mid_world), end = translation(*end_world);
  out.mid = mid;
  out.end = end;
  out.start_turn = Mat3::Identity();
  out.mid_turn = Mat3::Identity();
  out.solved = false;
  out.reached = false;
  const double a = (mid - s).norm(), b = (end - mid).norm();
  const double scale = std::max(a + b, 1e-300);
  if (!(a > 1e-12 * scale && b > 1e-12 * scale)) return true;

  // The bend plane now: start-to-end u0 and the knee's direction kh
  // perpendicular to it (toward the start's most perpendicular axis when
  // the chain is straight).
  const Vec3 se = end - s;
  const Vec3 u0 = se.norm() > 1e-12 * scale ? Vec3(se.normalized()) : Vec3((mid - s).normalized());
  Vec3 k = (mid - s) - (mid - s).dot(u0) * u0;
  if (k.norm() <= 1e-9 * scale)
    k = detail::perpendicular(u0, detail::straight_pole(start_world->topLeftCorner<3, 3>(), u0));
  const Vec3 kh = k.normalized();
  const Vec3 n_old = u0.cross(kh).normalized();
  // The plane carried onto start-to-target u, the knee on the side it was.
  const Vec3 tv = target - s;
  const double d = tv.norm();
  const Vec3 u = d > 1e-12 * scale ? Vec3(tv / d) : u0;
  Vec3 w = kh - kh.dot(u) * u;
  if (w.norm() < 1e-9) w = n_old.cross(u);
  w.normalize();
  // Law of cosines at the start, the distance clamped to the chain's range.
  const double dc = std::clamp(d, std::abs(a - b), a + b);
  const double cos_a = dc > 0 ? std::clamp((a * a + dc * dc - b * b) / (2 * a * dc), -1.0, 1.0) : 1.0;
  const double sin_a = std::sqrt(std::max(0.0, 1 - cos_a * cos_a));
  out.mid = s + a * (cos_a * u + sin_a * w);
  out.end = s + dc * u;
  const Vec3 n_new = u.cross(w).normalized();
  out.start_turn = frame(out.mid - s, n_new) * frame(mid - s, n_old).transpose();
  out.mid_turn = frame(out.end - out.mid, n_new) * frame(end - mid, n_old).transpose();
  out.solved = true;
  out.reached = d >= std::abs(a - b) && d <= a + b;
  return true;
}

}  // namespace rigel::ops::ik
