#pragma once
// Tests every N-bone solver (FabrikJob, CcdJob) must pass: a test per
// documented validate() failure, hand-computed answers, and the invariants
// along swept targets. fabrik_tests.cc and ccd_tests.cc instantiate them
// (gtest's type-parameterised tests), each beside its solver's own tests.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "ik_test_util.h"
#include "rigel/math/transform.h"

namespace rigel::ops::ik::testing {

template <typename Job>
class ChainSolverTest : public ::testing::Test {};

TYPED_TEST_SUITE_P(ChainSolverTest);

// Three joints: (0,0,0), (1,0,0), (2,0,0), identity frames.
inline std::vector<Mat4> straight_three() { return chain_from_points({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)}); }

TYPED_TEST_P(ChainSolverTest, validate__rejects_each_documented_failure) {
  using Job = TypeParam;
  const std::vector<Mat4> chain = straight_three();
  std::vector<Vec3> positions(3);
  std::vector<Quat> corrections(3);
  std::vector<JointLimit> limits(3);
  auto valid = [&] {
    Job job;
    job.world = chain;
    job.positions = positions;
    job.corrections = corrections;
    job.limits = limits;
    job.target = Vec3(1, 1, 0);
    return job;
  };
  {
    Job job = valid();
    EXPECT_TRUE(job.validate()) << "a well-formed job should validate";
    EXPECT_TRUE(job.run()) << "and run";
    job.limits = {};
    job.result = nullptr;
    EXPECT_TRUE(job.validate()) << "limits and result are optional";
  }
  {
    Job job;
    EXPECT_FALSE(job.validate()) << "an empty job should be rejected";
    EXPECT_FALSE(job.run()) << "run() should refuse a job that does not validate";
  }
  {
    Job job = valid();
    job.world = std::span<const Mat4>(chain).first(1);
    job.positions = std::span<Vec3>(positions).first(1);
    job.corrections = std::span<Quat>(corrections).first(1);
    job.limits = {};
    EXPECT_FALSE(job.validate()) << "a chain of one joint (no bone) should be rejected";
  }
  {
    Job job = valid();
    job.positions = std::span<Vec3>(positions).first(2);
    EXPECT_FALSE(job.validate()) << "positions shorter than world should be rejected";
  }
  {
    Job job = valid();
    job.corrections = std::span<Quat>(corrections).first(2);
    EXPECT_FALSE(job.validate()) << "corrections shorter than world should be rejected";
  }
  {
    Job job = valid();
    job.limits = std::span<const JointLimit>(limits).first(2);
    EXPECT_FALSE(job.validate()) << "limits neither empty nor one per joint should be rejected";
  }
  {
    std::vector<JointLimit> bad = limits;
    bad[1].kind = LimitKind::kCone;
    bad[1].half_angle = -1.0;
    Job job = valid();
    job.limits = bad;
    EXPECT_FALSE(job.validate()) << "an invalid limit should be rejected";
    bad[1].kind = LimitKind::kNone;
    bad[2].kind = LimitKind::kHinge;
    bad[2].axis = Vec3::Zero();
    EXPECT_FALSE(job.validate()) << "an invalid limit on the last joint (whose entry is otherwise unused) too";
  }
  {
    std::vector<Mat4> bad = chain;
    bad[2](3, 0) = 1.0;
    Job job = valid();
    job.world = bad;
    EXPECT_FALSE(job.validate()) << "a world matrix that is not affine should be rejected";
  }
  {
    Job job = valid();
    job.parent_world(3, 3) = 0.0;
    EXPECT_FALSE(job.validate()) << "a parent_world that is not affine should be rejected";
  }
  {
    Job job = valid();
    job.target = Vec3(0, std::numeric_limits<double>::quiet_NaN(), 0);
    EXPECT_FALSE(job.validate()) << "a NaN target should be rejected";
  }
  {
    Job job = valid();
    job.tolerance = -1e-6;
    EXPECT_FALSE(job.validate()) << "a negative tolerance should be rejected";
    job.tolerance = std::numeric_limits<double>::infinity();
    EXPECT_FALSE(job.validate()) << "an infinite tolerance should be rejected";
    job.tolerance = std::numeric_limits<double>::quiet_NaN();
    EXPECT_FALSE(job.validate()) << "a NaN tolerance should be rejected";
  }
  {
    Job job = valid();
    job.max_iterations = -1;
    EXPECT_FALSE(job.validate()) << "negative max_iterations should be rejected";
  }
}

TYPED_TEST_P(ChainSolverTest, run__invalid_job_writes_nothing) {
  const std::vector<Mat4> chain = straight_three();
  std::vector<Vec3> positions(3, Vec3::Constant(9.0));
  std::vector<Quat> corrections(3, Quat(0, 1, 0, 0));
  IkChainResult result;
  result.iterations = 77;
  TypeParam job;
  job.world = chain;
  job.positions = positions;
  job.corrections = corrections;
  job.result = &result;
  job.max_iterations = -3;
  EXPECT_FALSE(job.run());
  EXPECT_EQ(positions[1], Vec3::Constant(9.0)) << "positions untouched";
  EXPECT_EQ(corrections[1].coeffs(), Quat(0, 1, 0, 0).coeffs()) << "corrections untouched";
  EXPECT_EQ(result.iterations, 77) << "result untouched";
}

TYPED_TEST_P(ChainSolverTest, run__two_bones_reach_the_triangle_by_hand) {
  // Bones 1 and 1 bent up (+y), target at (1.2, 0, 0): the only solutions
  // put the middle joint at (0.6, +-0.8, 0); starting bent up, it is +0.8.
  const std::vector<Mat4> chain = chain_from_points({Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)});
  TypeParam job;
  job.target = Vec3(1.2, 0, 0);
  job.tolerance = 1e-13;
  job.max_iterations = 1000;
  const ChainSolve s = solve_chain(chain, job);
  EXPECT_TRUE(vec_near(s.positions[1], Vec3(0.6, 0.8, 0), 1e-9)) << "the middle joint by hand";
  EXPECT_TRUE(vec_near(s.positions[2], Vec3(1.2, 0, 0), 1e-12)) << "the end on the target";
  EXPECT_TRUE(s.result.reached);
  EXPECT_LE(s.result.error, 1e-13);
  EXPECT_GT(s.result.iterations, 0);
}

TYPED_TEST_P(ChainSolverTest, run__out_of_reach_lies_straight_in_closed_form) {
  TypeParam job;
  job.target = Vec3(0, 10, 0);
  const ChainSolve s = solve_chain(straight_three(), job);
  EXPECT_TRUE(vec_near(s.positions[1], Vec3(0, 1, 0), 1e-15)) << "straight up the y axis";
  EXPECT_TRUE(vec_near(s.positions[2], Vec3(0, 2, 0), 1e-15));
  EXPECT_TRUE(same_rotation(s.corrections[0], Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ())), 1e-15))
      << "the root turns 90 degrees about z";
  EXPECT_TRUE(same_rotation(s.corrections[1], Quat::Identity(), 1e-15)) << "the rest follow";
  EXPECT_TRUE(same_rotation(s.corrections[2], Quat::Identity(), 0.0)) << "the end joint's correction is the identity";
  EXPECT_EQ(s.result.iterations, 0) << "closed form";
  EXPECT_NEAR(s.result.error, 8.0, 1e-15);
  EXPECT_FALSE(s.result.reached);
}

TYPED_TEST_P(ChainSolverTest, run__zero_iterations_returns_the_input) {
  const std::vector<Mat4> chain = chain_from_points({Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)});
  TypeParam job;
  job.target = Vec3(1.2, 0, 0);
  job.max_iterations = 0;
  const ChainSolve s = solve_chain(chain, job);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_TRUE(vec_near(s.positions[i], position_of(chain[i]), 1e-15)) << "joint " << i << " stays";
    EXPECT_TRUE(same_rotation(s.corrections[i], Quat::Identity(), 1e-15)) << "joint " << i << " is not turned";
  }
  EXPECT_EQ(s.result.iterations, 0);
  EXPECT_NEAR(s.result.error, std::hypot(0.2, 1.0), 1e-15) << "the distance from (1, 1, 0) to the target";
  job.target = Vec3(1, 1, 0);
  job.max_iterations = 10;
  const ChainSolve there = solve_chain(chain, job);
  EXPECT_EQ(there.result.iterations, 0) << "a target already within tolerance takes no iteration";
  EXPECT_TRUE(there.result.reached);
}

TYPED_TEST_P(ChainSolverTest, run__corrections_reproduce_the_solved_positions) {
  Random random(21);
  for (int trial = 0; trial < 30; ++trial) {
    std::vector<Mat4> chain = chain_from_points(random_chain_points(random, 8), random.unit(), 1.3);
    for (Mat4& m : chain) {
      // Roll each frame about its bone so frames are arbitrary.
      m.topLeftCorner<3, 3>() =
          Mat3(m.topLeftCorner<3, 3>()) * Eigen::AngleAxisd(random.uniform(-3, 3), Vec3::UnitX()).toRotationMatrix();
    }
    TypeParam job;
    job.target = position_of(chain[0]) + random.unit() * random.uniform(0.5, 6.0);
    job.max_iterations = 20;
    const ChainSolve s = solve_chain(chain, job);
    for (std::size_t i = 0; i < chain.size(); ++i) {
      EXPECT_TRUE(vec_near(position_of(s.world[i]), s.positions[i], 1e-11))
          << "trial " << trial << " joint " << i << ": corrections applied through the local matrices give the "
          << "solver's positions";
    }
  }
}

TYPED_TEST_P(ChainSolverTest, run__reachable_targets_are_reached_with_lengths_kept) {
  Random random(22);
  for (int trial = 0; trial < 30; ++trial) {
    const std::vector<Mat4> chain = chain_from_points(random_chain_points(random, 10));
    const double length = chain_length(chain);
    TypeParam job;
    job.target = random.unit() * random.uniform(0.3, 0.9) * length;
    job.tolerance = 1e-7 * length;
    job.max_iterations = 10000;
    const ChainSolve s = solve_chain(chain, job);
    EXPECT_LE(bone_length_error(chain, s.world), 1e-9) << "trial " << trial << ": bone lengths kept";
    EXPECT_LE((position_of(s.world.back()) - job.target).norm(), 1e-6 * length)
        << "trial " << trial << ": reached within 1e-6 of the chain length";
    EXPECT_TRUE(s.result.reached) << "trial " << trial;
    EXPECT_LE(s.result.error, job.tolerance);
    EXPECT_LE(s.result.iterations, job.max_iterations);
  }
}

TYPED_TEST_P(ChainSolverTest, run__unreachable_targets_point_straight) {
  Random random(23);
  for (int trial = 0; trial < 50; ++trial) {
    const std::vector<Mat4> chain = chain_from_points(random_chain_points(random, 10));
    const double length = chain_length(chain);
    TypeParam job;
    job.target = random.unit() * random.uniform(1.0001, 3.0) * length;
    const ChainSolve s = solve_chain(chain, job);
    EXPECT_LE(bone_length_error(chain, s.world), 1e-9) << "trial " << trial;
    EXPECT_TRUE(straight_at(s.world, job.target, 1e-9)) << "trial " << trial << ": straight at the target";
    EXPECT_NEAR(s.result.error, job.target.norm() - length, 1e-9) << "trial " << trial;
  }
}

TYPED_TEST_P(ChainSolverTest, run__cone_limit_by_hand) {
  // One bone along x, target straight up: a 30-degree cone about x stops it
  // at 30 degrees toward the target.
  const std::vector<Mat4> chain = chain_from_points({Vec3(0, 0, 0), Vec3(1, 0, 0)});
  std::vector<JointLimit> limits(2);
  limits[0].kind = LimitKind::kCone;
  limits[0].axis = Vec3::UnitX();
  limits[0].half_angle = kPi / 6;
  TypeParam job;
  job.target = Vec3(0, 0.5, 0);
  const ChainSolve s = solve_chain(chain, job, limits);
  EXPECT_TRUE(vec_near(s.positions[1], Vec3(std::sqrt(3.0) / 2, 0.5, 0), 1e-12)) << "(cos 30, sin 30, 0)";
  EXPECT_FALSE(s.result.reached);
  EXPECT_TRUE(same_rotation(s.corrections[0], Quat(Eigen::AngleAxisd(kPi / 6, Vec3::UnitZ())), 1e-12));
}

TYPED_TEST_P(ChainSolverTest, run__hinge_limit_by_hand) {
  // One bone along x; a hinge about z allowing 0..45 degrees. A target at
  // (-1, 1, 0.5) is at 135 degrees in the hinge plane: clamped to 45.
  const std::vector<Mat4> chain = chain_from_points({Vec3(0, 0, 0), Vec3(1, 0, 0)});
  std::vector<JointLimit> limits(2);
  limits[0].kind = LimitKind::kHinge;
  limits[0].axis = Vec3::UnitZ();
  limits[0].reference = Vec3::UnitX();
  limits[0].min_angle = 0.0;
  limits[0].max_angle = kPi / 4;
  TypeParam job;
  job.target = Vec3(-1, 1, 0.5);
  const ChainSolve s = solve_chain(chain, job, limits);
  EXPECT_TRUE(vec_near(s.positions[1], Vec3(std::sqrt(0.5), std::sqrt(0.5), 0), 1e-12));
  EXPECT_TRUE(same_rotation(s.corrections[0], Quat(Eigen::AngleAxisd(kPi / 4, Vec3::UnitZ())), 1e-12))
      << "a pure turn about the hinge axis";
}

TYPED_TEST_P(ChainSolverTest, run__limit_frames_follow_parent_world) {
  // The same hinge, with the chain's parent turned 90 degrees about x: the
  // hinge axis (z in the parent's frame) is now world -y... so the bone
  // turns in the world xz plane.
  const std::vector<Mat4> chain = chain_from_points({Vec3(0, 0, 0), Vec3(1, 0, 0)});
  std::vector<JointLimit> limits(2);
  limits[0].kind = LimitKind::kHinge;
  limits[0].min_angle = -kPi;
  limits[0].max_angle = kPi;
  TypeParam job;
  job.parent_world = math::rotation_matrix(Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitX())));
  job.target = Vec3(0, 0.3, 2);
  const ChainSolve s = solve_chain(chain, job, limits);
  EXPECT_TRUE(vec_near(s.positions[1], Vec3(0, 0, 1), 1e-12)) << "the hinge plane is world xz: the bone aims at +z";
  EXPECT_LE(worst_limit_excess(limits, s.world, job.parent_world), 1e-12);
}

TYPED_TEST_P(ChainSolverTest, run__limits_hold_at_the_solution) {
  Random random(24);
  for (int trial = 0; trial < 20; ++trial) {
    const std::size_t count = 8;
    // A chain in the xy plane bent about z; every joint limited: hinges about
    // the frames' z (the bend axis) within +-0.8 rad, or cones of 0.5 rad
    // about the bone's rest direction in the parent's frame.
    std::vector<Vec3> points(count, Vec3::Zero());
    double heading = 0.0;
    for (std::size_t i = 1; i < count; ++i) {
      heading += random.uniform(-0.4, 0.4);
      points[i] = points[i - 1] + Vec3(std::cos(heading), std::sin(heading), 0) * random.uniform(0.6, 1.2);
    }
    const std::vector<Mat4> chain = chain_from_points(points, Vec3::UnitZ());
    const bool hinges = trial % 2 == 0;
    std::vector<JointLimit> limits(count);
    for (std::size_t i = 0; i + 1 < count; ++i) {
      const Mat3 parent = i == 0 ? Mat3::Identity() : frame_of(chain[i - 1]);
      const Vec3 rest = (parent.transpose() * (points[i + 1] - points[i])).normalized();
      if (hinges) {
        limits[i].kind = LimitKind::kHinge;
        limits[i].axis = Vec3::UnitZ();
        limits[i].reference = rest;
        limits[i].min_angle = -0.8;
        limits[i].max_angle = 0.8;
      } else {
        limits[i].kind = LimitKind::kCone;
        limits[i].axis = rest;
        limits[i].half_angle = 0.5;
      }
    }
    TypeParam job;
    job.target = random.vec3(-6, 6);
    if (hinges) job.target.z() = 0.0;
    job.max_iterations = 50;  // the limits hold whether or not the target is reached
    const ChainSolve s = solve_chain(chain, job, limits);
    EXPECT_LE(worst_limit_excess(limits, s.world), 1e-9) << "trial " << trial << ": every limit holds";
    EXPECT_LE(bone_length_error(chain, s.world), 1e-9) << "trial " << trial;
    for (std::size_t i = 0; i < count; ++i) {
      EXPECT_TRUE(vec_near(position_of(s.world[i]), s.positions[i], 1e-9)) << "trial " << trial << " joint " << i;
    }
    EXPECT_LE(s.result.iterations, job.max_iterations);
  }
}

TYPED_TEST_P(ChainSolverTest, run__limits_hold_even_without_iterations) {
  // The input violates a 10-degree cone; a target within tolerance of the
  // end (no iteration runs) still gets a pose within the limit.
  const std::vector<Mat4> chain = chain_from_points({Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(0, 2, 0)});
  std::vector<JointLimit> limits(3);
  limits[0].kind = LimitKind::kCone;
  limits[0].axis = Vec3::UnitX();
  limits[0].half_angle = 10.0 * math::kDegToRad;
  TypeParam job;
  job.target = Vec3(0, 2, 0);
  const ChainSolve s = solve_chain(chain, job, limits);
  EXPECT_LE(worst_limit_excess(limits, s.world), 1e-12) << "the limit holds on return";
}

TYPED_TEST_P(ChainSolverTest, run__degenerate_inputs_never_produce_nan) {
  auto finite = [](const ChainSolve& s) {
    for (const Vec3& p : s.positions) {
      if (!p.allFinite()) return false;
    }
    for (const Quat& q : s.corrections) {
      if (!q.coeffs().allFinite()) return false;
    }
    return std::isfinite(s.result.error);
  };
  {
    TypeParam job;
    job.target = Vec3(0, 0, 0);  // at the root, reachable by folding
    const ChainSolve s = solve_chain(straight_three(), job);
    EXPECT_TRUE(finite(s)) << "target at the root";
    EXPECT_LE(bone_length_error(straight_three(), s.world), 1e-12);
  }
  {
    const std::vector<Mat4> chain =
        chain_from_points({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0)});  // a zero-length bone
    TypeParam job;
    job.target = Vec3(0.5, 1.2, 0.3);
    job.max_iterations = 100;
    const ChainSolve s = solve_chain(chain, job);
    EXPECT_TRUE(finite(s)) << "two joints at one point";
    EXPECT_LE(bone_length_error(chain, s.world), 1e-12);
  }
  {
    const std::vector<Mat4> chain = chain_from_points({Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1)});
    TypeParam job;
    job.target = Vec3(0, 3, 0);
    const ChainSolve s = solve_chain(chain, job);
    EXPECT_TRUE(finite(s)) << "all joints at one point (chain of length 0)";
  }
  {
    TypeParam job;
    job.target = Vec3(1.5, 0, 0);  // on the line of a straight chain
    job.max_iterations = 50;
    const ChainSolve s = solve_chain(straight_three(), job);
    EXPECT_TRUE(finite(s)) << "target on the line of a straight chain";
    EXPECT_LE(bone_length_error(straight_three(), s.world), 1e-12);
  }
}

// Solves along target(t), t in [0, 1], and checks the invariants at every
// step: lengths, reach (or straightness out of reach) or the limits, and
// continuity. An iterative solver's answer can turn fast where the chain is
// redundant (CCD leans on its last joints), so continuity is checked two
// ways: no joint turns more than `max_turn_per_unit` times the target's
// travel in one step (a flip would be pi in one step), and the worst step,
// cut into 10, turns no joint more than 0.35 of its turn in any tenth (a
// Lipschitz path gives about 0.1; a jump gives the whole turn again).
template <typename Job, typename Path>
void sweep_chain(const std::vector<Mat4>& chain, Job base, Path path, int steps, double max_turn_per_unit,
                 const std::vector<JointLimit>& limits = {}) {
  const double length = chain_length(chain);
  auto solve_at = [&](double t) {
    Job job = base;
    job.target = path(t);
    return solve_chain(chain, job, limits);
  };
  std::vector<Mat4> previous;
  double worst_turn = 0.0;
  int worst_step = -1;
  for (int n = 0; n <= steps; ++n) {
    const double t = static_cast<double>(n) / steps;
    const Vec3 target = path(t);
    const ChainSolve s = solve_at(t);
    ASSERT_TRUE(s.ok);
    EXPECT_LE(bone_length_error(chain, s.world), 1e-9) << "step " << n;
    const double distance = (target - position_of(chain[0])).norm();
    if (limits.empty()) {
      if (distance < length) {
        EXPECT_LE(s.result.error, 1e-6 * length) << "step " << n << ": reachable target reached";
      } else {
        EXPECT_TRUE(straight_at(s.world, target, 1e-9)) << "step " << n << ": straight at the target";
      }
    } else {
      EXPECT_LE(worst_limit_excess(limits, s.world), 1e-9) << "step " << n;
    }
    if (!previous.empty()) {
      const double step = (target - path(static_cast<double>(n - 1) / steps)).norm();
      const double turn = largest_turn(previous, s.world);
      EXPECT_LE(turn, max_turn_per_unit * step)
          << "step " << n << ": a joint turned " << turn << " rad for a target step of " << step;
      if (turn > worst_turn) {
        worst_turn = turn;
        worst_step = n;
      }
    }
    previous = s.world;
  }
  if (worst_step < 0 || worst_turn < 1e-9) return;
  std::vector<Mat4> sub_previous = solve_at(static_cast<double>(worst_step - 1) / steps).world;
  double worst_sub_turn = 0.0;
  for (int k = 1; k <= 10; ++k) {
    const std::vector<Mat4> sub = solve_at((worst_step - 1 + k / 10.0) / steps).world;
    worst_sub_turn = std::max(worst_sub_turn, largest_turn(sub_previous, sub));
    sub_previous = sub;
  }
  EXPECT_LE(worst_sub_turn, 0.35 * worst_turn)
      << "the largest turn (" << worst_turn << " rad at step " << worst_step << ") should shrink with the step; "
      << "a tenth of the step still turns " << worst_sub_turn << " rad: a jump";
}

// A gently curved 10-joint chain along +x, curling toward +y.
inline std::vector<Mat4> curled_ten() {
  std::vector<Vec3> points(10, Vec3::Zero());
  for (std::size_t i = 1; i < points.size(); ++i) {
    const double heading = 0.15 * static_cast<double>(i);
    points[i] = points[i - 1] + Vec3(std::cos(heading), std::sin(heading), 0.05 * std::sin(static_cast<double>(i)));
  }
  return chain_from_points(points);
}

TYPED_TEST_P(ChainSolverTest, sweep__circle_is_continuous) {
  TypeParam job;
  job.tolerance = 1e-8;
  job.max_iterations = 5000;
  sweep_chain(
      curled_ten(), job,
      [](double t) { return Vec3(6 + 1.5 * std::cos(2 * kPi * t), 3 + 1.5 * std::sin(2 * kPi * t), 0.5); }, 150, 20.0);
}

TYPED_TEST_P(ChainSolverTest, sweep__out_of_reach_segment_is_straight) {
  TypeParam job;
  sweep_chain(
      curled_ten(), job, [](double t) { return Vec3(12, -5 + 10 * t, 1); }, 200, 1.0);
}

TYPED_TEST_P(ChainSolverTest, sweep__limited_chain_is_continuous_and_within_limits) {
  // Cones of 0.6 rad about each bone's rest direction, and a circle of
  // targets the limited chain can reach. (Under limits a solve is local:
  // far from reach the solver may settle on different poses for nearby
  // targets, which is why this path stays reachable.)
  const std::vector<Mat4> chain = curled_ten();
  std::vector<JointLimit> limits(chain.size());
  for (std::size_t i = 0; i + 1 < chain.size(); ++i) {
    const Mat3 parent = i == 0 ? Mat3::Identity() : frame_of(chain[i - 1]);
    limits[i].kind = LimitKind::kCone;
    limits[i].axis = (parent.transpose() * (position_of(chain[i + 1]) - position_of(chain[i]))).normalized();
    limits[i].half_angle = 0.6;
  }
  TypeParam job;
  job.tolerance = 1e-8;
  job.max_iterations = 5000;
  sweep_chain(
      chain, job, [](double t) { return Vec3(5 + 0.5 * std::cos(2 * kPi * t), 4 + 0.5 * std::sin(2 * kPi * t), 0); },
      100, 20.0, limits);
}

REGISTER_TYPED_TEST_SUITE_P(ChainSolverTest, validate__rejects_each_documented_failure, run__invalid_job_writes_nothing,
                            run__two_bones_reach_the_triangle_by_hand, run__out_of_reach_lies_straight_in_closed_form,
                            run__zero_iterations_returns_the_input, run__corrections_reproduce_the_solved_positions,
                            run__reachable_targets_are_reached_with_lengths_kept,
                            run__unreachable_targets_point_straight, run__cone_limit_by_hand, run__hinge_limit_by_hand,
                            run__limit_frames_follow_parent_world, run__limits_hold_at_the_solution,
                            run__limits_hold_even_without_iterations, run__degenerate_inputs_never_produce_nan,
                            sweep__circle_is_continuous, sweep__out_of_reach_segment_is_straight,
                            sweep__limited_chain_is_continuous_and_within_limits);

}  // namespace rigel::ops::ik::testing
