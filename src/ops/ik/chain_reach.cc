#include "rigel/ops/ik/chain_reach.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "bend_math.h"
#include "ik_math.h"
#include "rigel/ops/ik/fabrik.h"

namespace rigel::ops::ik {

using detail::perpendicular;
using detail::swing;
using detail::translation;

namespace {

// Lays joints 1..n of `p` (bone i from p[i] to p[i + 1], length len[i];
// p[0] stays) on a circular arc in the plane of unit `u` (toward the
// target) and unit `w` (perpendicular: the side the arc bulges to), every
// joint turning by the same angle, chosen by bisection so that the chord
// is `d` (straight when d is the chain's length or more).
void lay_arc(std::span<Vec3> p, std::span<const double> len, const Vec3& u, const Vec3& w, double d) {
  const std::size_t n = len.size();
  auto planar = [&](double turn, std::size_t upto) {
    Eigen::Vector2d q = Eigen::Vector2d::Zero();
    for (std::size_t i = 0; i < upto; ++i) q += len[i] * Eigen::Vector2d(std::cos(turn * i), std::sin(turn * i));
    return q;
  };
  double lo = 0, hi = 2 * std::numbers::pi / static_cast<double>(n);
  if (planar(hi, n).norm() >= d) {
    lo = hi;
  } else {
    for (int it = 0; it < 200 && hi - lo > 1e-17; ++it) {
      const double mid = 0.5 * (lo + hi);
      (planar(mid, n).norm() > d ? lo : hi) = mid;
    }
  }
  const Eigen::Vector2d chord = planar(lo, n);
  const Eigen::Vector2d c = chord.norm() > 0 ? Eigen::Vector2d(chord.normalized()) : Eigen::Vector2d(1, 0);
  const Eigen::Vector2d side(-c.y(), c.x());
  // The bulge toward +w.
  const double sign = planar(lo, n / 2 > 0 ? n / 2 : 1).dot(side) < 0 ? -1.0 : 1.0;
  for (std::size_t i = 1; i <= n; ++i) {
    const Eigen::Vector2d q = planar(lo, i);
    p[i] = p[0] + q.dot(c) * u + sign * q.dot(side) * w;
  }
}

// Places joints i + 1 .. j of `p` (bone k from p[k] to p[k + 1], length
// len[k]; p[i] stays) so that p[j] lands on `t` whenever the bones reach it
// (as near as they get otherwise), exactly to rounding. The range splits at
// its middle joint into two halves; the middle joint is placed by the
// two-bone rule in the current bend plane (toward `pole` when straight),
// each half turns rigidly about its start onto its new ends, and a half
// whose end-to-end span must change for the target to be reached (stretched
// toward its length, or folded toward its shortest span, each half in
// proportion to its room) is solved the same way. Recursion depth: log2 of
// the chain's length.
void reach(std::span<Vec3> p, std::span<const double> len, int i, int j, const Vec3& t, const Vec3& pole) {
  const int n = j - i;
  if (n <= 0) return;
  const Vec3 s = p[i];
  const Vec3 tv = t - s;
  const double d = tv.norm();
  if (n == 1) {
    if (d > 1e-300) p[j] = s + len[i] * tv / d;
    return;
  }
  const int k = i + n / 2;
  double la = 0, lb = 0, max_a = 0, max_b = 0;
  for (int x = i; x < k; ++x) la += len[x], max_a = std::max(max_a, len[x]);
  for (int x = k; x < j; ++x) lb += len[x], max_b = std::max(max_b, len[x]);
  const double min_a = std::max(0.0, 2 * max_a - la), min_b = std::max(0.0, 2 * max_b - lb);
  const double a = (p[k] - s).norm(), b = (p[j] - p[k]).norm();
  double a2 = a, b2 = b;
  if (d >= la + lb) {
    a2 = la;
    b2 = lb;
  } else if (d > a + b) {
    const double room = (la - a) + (lb - b);
    const double f = room > 0 ? std::clamp((d - a - b) / room, 0.0, 1.0) : 0.0;
    a2 = a + f * (la - a);
    b2 = b + f * (lb - b);
  } else if (d < std::abs(a - b)) {
    if (a >= b) {
      const double room = (a - min_a) + (lb - b);
      const double f = room > 0 ? std::clamp((a - b - d) / room, 0.0, 1.0) : 0.0;
      a2 = a - f * (a - min_a);
      b2 = b + f * (lb - b);
    } else {
      const double room = (b - min_b) + (la - a);
      const double f = room > 0 ? std::clamp((b - a - d) / room, 0.0, 1.0) : 0.0;
      b2 = b - f * (b - min_b);
      a2 = a + f * (la - a);
    }
  }
  const double scale = std::max(la + lb, 1e-300);
  Vec3 u = tv;
  if (d <= 1e-12 * scale) u = p[j] - s;
  if (u.norm() <= 1e-12 * scale) u = p[k] - s;
  u = u.norm() > 1e-300 ? Vec3(u.normalized()) : perpendicular(pole, Vec3::UnitX());
  Vec3 w = (p[k] - s) - (p[k] - s).dot(u) * u;
  w = w.norm() > 1e-9 * scale ? Vec3(w.normalized()) : perpendicular(u, pole);
  const double dc = std::clamp(d, std::abs(a2 - b2), a2 + b2);
  const double cos_a = a2 > 0 && dc > 0 ? std::clamp((a2 * a2 + dc * dc - b2 * b2) / (2 * a2 * dc), -1.0, 1.0) : 1.0;
  const double sin_a = std::sqrt(std::max(0.0, 1 - cos_a * cos_a));
  const Vec3 qk = s + a2 * (cos_a * u + sin_a * w);
  const Vec3 old_k = p[k];
  const Mat3 ra = swing(old_k - s, qk - s);
  for (int x = i + 1; x <= k; ++x) p[x] = s + ra * (p[x] - s);
  if (k - i >= 2 && a2 != a) reach(p, len, i, k, qk, pole);
  const Vec3 new_k = p[k];
  const Mat3 rb = swing(p[j] - old_k, t - new_k);
  for (int x = k + 1; x <= j; ++x) p[x] = new_k + rb * (p[x] - old_k);
  if (j - k >= 2 && b2 != b) reach(p, len, k, j, t, pole);
}

// The chain of three or more joints: arc or FABRIK, then exact.
bool solve_long(const ChainReachJob& job) {
  const std::size_t m = job.world.size();
  const std::span<Vec3> p = job.positions;
  const std::span<const double> len = job.lengths;
  for (std::size_t i = 0; i + 1 < m; ++i)
    job.lengths[i] = (translation(job.world[i + 1]) - translation(job.world[i])).norm();
  const Vec3 s = translation(job.world[0]);
  double total = 0;
  for (double l : len) total += l;
  const double scale = std::max(total, 1e-300);
  Vec3 u0 = translation(job.world[m - 1]) - s;
  if (u0.norm() <= 1e-12 * scale) u0 = translation(job.world[1]) - s;
  u0 = u0.norm() > 1e-300 ? Vec3(u0.normalized()) : Vec3::UnitX();
  bool straight = true;
  for (std::size_t i = 1; i < m && straight; ++i) {
    const Vec3 r = translation(job.world[i]) - s;
    straight = (r - r.dot(u0) * u0).norm() <= 1e-9 * scale;
  }
  const Vec3 pole = detail::straight_pole(job.world[0].topLeftCorner<3, 3>(), u0);
  const Vec3 tv = job.target - s;
  const double d = tv.norm();
  if (straight && total > 0) {
    // FABRIK cannot bend a straight chain out of its line (it folds it
    // along the line) and crawls near full reach: an arc instead.
    const Vec3 u = d > 1e-12 * scale ? Vec3(tv / d) : u0;
    p[0] = s;
    lay_arc(p, len, u, perpendicular(u, pole), d);
  } else {
    FabrikJob fabrik;
    fabrik.world = job.world;
    fabrik.target = job.target;
    fabrik.tolerance = job.tolerance;
    fabrik.max_iterations = job.max_iterations;
    fabrik.positions = p;
    fabrik.corrections = job.corrections;
    if (!fabrik.run()) return false;
  }
  // Exact to rounding: FABRIK stops at its tolerance or iteration limit;
  // the arc is as exact as its bisection.
  if ((p[m - 1] - job.target).norm() > 1e-13 * scale) reach(p, len, 0, static_cast<int>(m) - 1, job.target, pole);
  return true;
}

}  // namespace

bool ChainReachJob::validate() const {
  const std::size_t n = world.size();
  if (n < 2) return false;
  if (positions.size() != n || corrections.size() != n || lengths.size() != n - 1) return false;
  if (!turns.empty() && turns.size() != n) return false;
  using detail::overlap;
  if (overlap(positions.data(), n, world.data(), n) || overlap(lengths.data(), n - 1, world.data(), n) ||
      overlap(corrections.data(), n, world.data(), n) || overlap(turns.data(), turns.size(), world.data(), n))
    return false;
  if (overlap(positions.data(), n, lengths.data(), n - 1) || overlap(positions.data(), n, corrections.data(), n) ||
      overlap(positions.data(), n, turns.data(), turns.size()) ||
      overlap(lengths.data(), n - 1, corrections.data(), n) ||
      overlap(lengths.data(), n - 1, turns.data(), turns.size()) ||
      overlap(corrections.data(), n, turns.data(), turns.size()))
    return false;
  for (const Mat4& m : world)
    if (!detail::is_affine(m) || !m.allFinite()) return false;
  if (!detail::all_finite(target)) return false;
  if (!(tolerance >= 0.0 && std::isfinite(tolerance))) return false;
  return max_iterations >= 0;
}

bool ChainReachJob::run() const {
  if (!validate()) return false;
  const std::size_t m = world.size();
  if (m == 2) {
    const Vec3 s = translation(world[0]);
    const Vec3 tv = target - s;
    lengths[0] = (translation(world[1]) - s).norm();
    positions[0] = s;
    positions[1] = tv.norm() > 1e-300 ? Vec3(s + lengths[0] * tv.normalized()) : translation(world[1]);
  } else if (!solve_long(*this)) {
    return false;
  }
  if (!turns.empty()) {
    for (std::size_t i = 0; i + 1 < m; ++i)
      turns[i] = swing(translation(world[i + 1]) - translation(world[i]), positions[i + 1] - positions[i]);
    turns[m - 1] = Mat3::Identity();
  }
  return true;
}

}  // namespace rigel::ops::ik
