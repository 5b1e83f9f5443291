#pragma once
// Helpers for the IK tests: chains built from joint positions, the one path
// from a solver's corrections to new world matrices (ChainWorldToLocalJob +
// ChainCorrectionJob, as graph nodes use it), angles between frames, and the
// invariant checks every solver is held to along swept targets.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "rigel/math/types.h"
#include "rigel/ops/ik/ik_chain.h"

namespace rigel::ops::ik::testing {

using math::kPi;

inline Vec3 position_of(const Mat4& m) { return m.topRightCorner<3, 1>(); }

// The rotation of a matrix with uniform positive scale (what the tests
// build): its columns normalised.
inline Mat3 frame_of(const Mat4& m) {
  Mat3 r = m.topLeftCorner<3, 3>();
  for (int c = 0; c < 3; ++c) r.col(c).normalize();
  return r;
}

// Angle of the rotation between two frames, in [0, pi].
inline double angle_between(const Mat3& a, const Mat3& b) {
  const double c = std::clamp(((a.transpose() * b).trace() - 1.0) / 2.0, -1.0, 1.0);
  return std::acos(c);
}

inline double rotation_angle(const Quat& q) { return 2.0 * std::atan2(q.vec().norm(), std::abs(q.w())); }

inline ::testing::AssertionResult vec_near(const Vec3& a, const Vec3& b, double tolerance) {
  const double diff = (a - b).norm();
  if (diff <= tolerance) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "(" << a.transpose() << ") and (" << b.transpose() << ") are " << diff
                                       << " apart, more than " << tolerance;
}

// q and -q are the same rotation.
inline ::testing::AssertionResult same_rotation(const Quat& a, const Quat& b, double tolerance) {
  const double diff =
      std::min((a.coeffs() - b.coeffs()).cwiseAbs().maxCoeff(), (a.coeffs() + b.coeffs()).cwiseAbs().maxCoeff());
  if (diff <= tolerance) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "quaternions (x y z w) " << a.coeffs().transpose() << " and "
                                       << b.coeffs().transpose() << " differ by " << diff << " (up to sign)";
}

inline bool finite(const Mat4& m) { return m.allFinite(); }

// World matrices for joints at `points`: each joint's x axis along its bone
// (the last joint keeps its parent's), z as near `normal` as the bone
// allows, y = z cross x. `scale` (uniform) multiplies every axis.
inline std::vector<Mat4> chain_from_points(const std::vector<Vec3>& points, const Vec3& normal = Vec3::UnitZ(),
                                           double scale = 1.0) {
  std::vector<Mat4> world(points.size(), Mat4::Identity());
  Vec3 x = Vec3::UnitX();
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (i + 1 < points.size() && (points[i + 1] - points[i]).norm() > 1e-12)
      x = (points[i + 1] - points[i]).normalized();
    Vec3 z = normal - x * x.dot(normal);
    z = z.norm() > 1e-9 ? Vec3(z.normalized()) : x.unitOrthogonal();
    const Vec3 y = z.cross(x);
    world[i].block<3, 1>(0, 0) = x * scale;
    world[i].block<3, 1>(0, 1) = y * scale;
    world[i].block<3, 1>(0, 2) = z * scale;
    world[i].topRightCorner<3, 1>() = points[i];
  }
  return world;
}

// The chain's new world matrices: its locals (from `world` under
// `parent_world`) with the corrections applied. The path graph nodes take.
inline std::vector<Mat4> apply_corrections(const std::vector<Mat4>& world, const std::vector<Quat>& corrections,
                                           const std::vector<double>& translate_scale = {},
                                           const Mat4& parent_world = Mat4::Identity()) {
  std::vector<Mat4> local(world.size());
  ChainWorldToLocalJob to_local;
  to_local.world = world;
  to_local.parent_world = parent_world;
  to_local.local = local;
  EXPECT_TRUE(to_local.run()) << "the test chain should convert to local matrices";
  std::vector<Mat4> out_world(world.size());
  ChainCorrectionJob apply;
  apply.local = local;
  apply.corrections = corrections;
  apply.translate_scale = translate_scale;
  apply.parent_world = parent_world;
  apply.local_out = local;  // in place
  apply.world_out = out_world;
  EXPECT_TRUE(apply.run()) << "the corrections should apply";
  return out_world;
}

// Largest |new bone length - old bone length| along a chain.
inline double bone_length_error(const std::vector<Mat4>& before, const std::vector<Mat4>& after) {
  double worst = 0.0;
  for (std::size_t i = 0; i + 1 < before.size(); ++i) {
    const double a = (position_of(before[i + 1]) - position_of(before[i])).norm();
    const double b = (position_of(after[i + 1]) - position_of(after[i])).norm();
    worst = std::max(worst, std::abs(a - b));
  }
  return worst;
}

inline double chain_length(const std::vector<Mat4>& world) {
  double total = 0.0;
  for (std::size_t i = 0; i + 1 < world.size(); ++i)
    total += (position_of(world[i + 1]) - position_of(world[i])).norm();
  return total;
}

// Largest distance of a joint from the ray from the root toward `target`,
// with joints required in order along it.
inline ::testing::AssertionResult straight_at(const std::vector<Mat4>& world, const Vec3& target, double tolerance) {
  const Vec3 root = position_of(world[0]);
  const Vec3 dir = (target - root).normalized();
  double along = 0.0;
  for (std::size_t i = 1; i < world.size(); ++i) {
    const Vec3 v = position_of(world[i]) - root;
    const double off = (v - dir * v.dot(dir)).norm();
    if (off > tolerance) {
      return ::testing::AssertionFailure() << "joint " << i << " is " << off << " off the line to the target";
    }
    if (v.dot(dir) < along - tolerance) {
      return ::testing::AssertionFailure() << "joint " << i << " turns back along the line";
    }
    along = v.dot(dir);
  }
  return ::testing::AssertionSuccess();
}

// Largest angle between the frames of the same joint in two poses.
inline double largest_turn(const std::vector<Mat4>& a, const std::vector<Mat4>& b) {
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, angle_between(frame_of(a[i]), frame_of(b[i])));
  return worst;
}

class Random {
 public:
  explicit Random(unsigned seed) : engine_(seed) {}
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(engine_); }
  Vec3 vec3(double lo, double hi) { return Vec3(uniform(lo, hi), uniform(lo, hi), uniform(lo, hi)); }
  Vec3 unit() {
    Vec3 v;
    do v = vec3(-1, 1);
    while (v.norm() < 0.1 || v.norm() > 1.0);
    return v.normalized();
  }
  Quat quat() {
    return Quat(Eigen::Vector4d(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1), uniform(-1, 1))).normalized();
  }

 private:
  std::mt19937 engine_;
};

// A random bent chain of `count` joints from the origin: each bone of length
// in [0.5, 1.5] turned from its parent's by up to `max_bend` radians.
inline std::vector<Vec3> random_chain_points(Random& random, std::size_t count, double max_bend = 0.6) {
  std::vector<Vec3> points(count, Vec3::Zero());
  Vec3 dir = random.unit();
  for (std::size_t i = 1; i < count; ++i) {
    const Vec3 axis = random.unit();
    dir = (Eigen::AngleAxisd(random.uniform(-max_bend, max_bend), axis) * dir).normalized();
    points[i] = points[i - 1] + dir * random.uniform(0.5, 1.5);
  }
  return points;
}

// How far (radians) the bone from `from` to `to` is outside `limit`, seen in
// `parent_frame` (0 when inside). Written out independently of
// constrain_direction().
inline double limit_excess(const JointLimit& limit, const Mat3& parent_frame, const Vec3& from, const Vec3& to) {
  const Vec3 d = (parent_frame.transpose() * (to - from)).normalized();
  switch (limit.kind) {
    case LimitKind::kNone:
      return 0.0;
    case LimitKind::kCone:
      return std::max(0.0, std::acos(std::clamp(d.dot(limit.axis), -1.0, 1.0)) - limit.half_angle);
    case LimitKind::kHinge: {
      const double off_plane = std::asin(std::clamp(std::abs(d.dot(limit.axis)), 0.0, 1.0));
      const double angle = std::atan2(d.dot(limit.axis.cross(limit.reference)), d.dot(limit.reference));
      const double outside = std::max({0.0, limit.min_angle - angle, angle - limit.max_angle});
      return std::max(off_plane, outside);
    }
  }
  return 0.0;
}

// Largest limit_excess over a solved chain (parent frames from the solved
// world matrices, joint 0's from parent_world).
inline double worst_limit_excess(const std::vector<JointLimit>& limits, const std::vector<Mat4>& world,
                                 const Mat4& parent_world = Mat4::Identity()) {
  double worst = 0.0;
  for (std::size_t i = 0; i + 1 < world.size() && i < limits.size(); ++i) {
    const Mat3 parent = frame_of(i == 0 ? parent_world : world[i - 1]);
    worst = std::max(worst, limit_excess(limits[i], parent, position_of(world[i]), position_of(world[i + 1])));
  }
  return worst;
}

// A FabrikJob or CcdJob run on a chain, with its output applied.
struct ChainSolve {
  bool ok = false;
  std::vector<Vec3> positions;  // the solver's positions
  std::vector<Quat> corrections;
  IkChainResult result;
  std::vector<Mat4> world;  // the chain after the corrections
};

// Fills the job's spans (world, limits, scratch, output) and runs it.
template <typename Job>
ChainSolve solve_chain(const std::vector<Mat4>& chain, Job job, const std::vector<JointLimit>& limits = {}) {
  ChainSolve s;
  s.positions.assign(chain.size(), Vec3::Constant(-7.0));
  s.corrections.assign(chain.size(), Quat(0.5, 0.5, 0.5, 0.5));
  job.world = chain;
  job.limits = limits;
  job.positions = s.positions;
  job.corrections = s.corrections;
  job.result = &s.result;
  s.ok = job.run();
  EXPECT_TRUE(s.ok) << "the job should be valid";
  if (s.ok) s.world = apply_corrections(chain, s.corrections, {}, job.parent_world);
  return s;
}

}  // namespace rigel::ops::ik::testing
