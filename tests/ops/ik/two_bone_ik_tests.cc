#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "ik_test_util.h"
#include "rigel/ops/ik/two_bone_ik.h"

namespace rigel::ops::ik {
namespace {

using testing::angle_between;
using testing::frame_of;
using testing::kPi;
using testing::position_of;
using testing::same_rotation;
using testing::vec_near;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// A straight 3-4-5 leg along x with identity frames: start at the origin,
// mid at (3, 0, 0), end at (7, 0, 0). The hinge is z.
std::vector<Mat4> straight_chain() { return testing::chain_from_points({Vec3(0, 0, 0), Vec3(3, 0, 0), Vec3(7, 0, 0)}); }

struct Solved {
  TwoBoneIkOutput output;
  std::vector<Mat4> world;  // the three joints after the corrections
};

// Runs `job` on `chain` (filling its joint pointers and output) and applies
// the result through ChainCorrectionJob.
Solved solve(const std::vector<Mat4>& chain, TwoBoneIkJob job) {
  Solved s;
  job.start_world = &chain[0];
  job.mid_world = &chain[1];
  job.end_world = &chain[2];
  job.output = &s.output;
  EXPECT_TRUE(job.run()) << "the job should be valid";
  s.world = testing::apply_corrections(chain, {s.output.start_correction, s.output.mid_correction, Quat::Identity()},
                                       {1.0, s.output.stretch, s.output.stretch});
  return s;
}

TEST(TwoBoneIkJob, validate__rejects_each_documented_failure) {
  const std::vector<Mat4> chain = straight_chain();
  TwoBoneIkOutput out;
  auto valid = [&] {
    TwoBoneIkJob job;
    job.start_world = &chain[0];
    job.mid_world = &chain[1];
    job.end_world = &chain[2];
    job.output = &out;
    job.target = Vec3(5, 0, 0);
    return job;
  };
  {
    TwoBoneIkJob job = valid();
    EXPECT_TRUE(job.validate()) << "a well-formed job should validate";
    EXPECT_TRUE(job.run()) << "and run";
  }
  {
    TwoBoneIkJob job;
    EXPECT_FALSE(job.validate()) << "a default job (no joints, no output) should be rejected";
    EXPECT_FALSE(job.run()) << "run() should refuse a job that does not validate";
  }
  for (int which = 0; which < 4; ++which) {
    TwoBoneIkJob job = valid();
    if (which == 0) job.start_world = nullptr;
    if (which == 1) job.mid_world = nullptr;
    if (which == 2) job.end_world = nullptr;
    if (which == 3) job.output = nullptr;
    EXPECT_FALSE(job.validate()) << "a null pointer (field " << which << ") should be rejected";
  }
  for (int which = 0; which < 3; ++which) {
    std::vector<Mat4> bad = chain;
    bad[static_cast<std::size_t>(which)](3, 2) = 0.5;
    TwoBoneIkJob job = valid();
    job.start_world = &bad[0];
    job.mid_world = &bad[1];
    job.end_world = &bad[2];
    EXPECT_FALSE(job.validate()) << "joint " << which << " with a matrix that is not affine should be rejected";
  }
  {
    TwoBoneIkJob job = valid();
    job.mid_axis = Vec3(0, 0, 1.1);
    EXPECT_FALSE(job.validate()) << "a mid_axis that is not unit should be rejected";
    job.mid_axis = Vec3::Zero();
    EXPECT_FALSE(job.validate()) << "a zero mid_axis should be rejected";
  }
  {
    TwoBoneIkJob job = valid();
    job.target = Vec3(kNaN, 0, 0);
    EXPECT_FALSE(job.validate()) << "a NaN target should be rejected";
    job = valid();
    job.pole_vector = Vec3(0, kInf, 0);
    EXPECT_FALSE(job.validate()) << "an infinite pole_vector should be rejected";
    job = valid();
    job.twist_angle = kNaN;
    EXPECT_FALSE(job.validate()) << "a NaN twist_angle should be rejected";
  }
  {
    TwoBoneIkJob job = valid();
    job.pole_mode = static_cast<TwoBonePoleMode>(5);
    EXPECT_FALSE(job.validate()) << "a pole_mode outside the enum should be rejected";
  }
  {
    TwoBoneIkJob job = valid();
    job.soft = -0.1;
    EXPECT_FALSE(job.validate()) << "a negative soft should be rejected";
    job.soft = 1.5;
    EXPECT_FALSE(job.validate()) << "soft above 1 should be rejected";
    job.soft = kNaN;
    EXPECT_FALSE(job.validate()) << "a NaN soft should be rejected";
  }
  {
    TwoBoneIkJob job = valid();
    job.weight = -0.1;
    EXPECT_FALSE(job.validate()) << "a negative weight should be rejected";
    job.weight = 1.01;
    EXPECT_FALSE(job.validate()) << "weight above 1 should be rejected";
    job.weight = kNaN;
    EXPECT_FALSE(job.validate()) << "a NaN weight should be rejected";
  }
  {
    TwoBoneIkJob job = valid();
    job.max_stretch = 0.5;
    EXPECT_TRUE(job.validate()) << "max_stretch is not looked at while stretch is off";
    job.stretch = true;
    EXPECT_FALSE(job.validate()) << "max_stretch below 1 with stretch on should be rejected";
    job.max_stretch = kNaN;
    EXPECT_FALSE(job.validate()) << "a NaN max_stretch with stretch on should be rejected";
    job.max_stretch = kInf;
    EXPECT_TRUE(job.validate()) << "an infinite max_stretch means no limit";
  }
}

TEST(TwoBoneIkJob, run__invalid_job_writes_nothing) {
  const std::vector<Mat4> chain = straight_chain();
  TwoBoneIkOutput out;
  out.stretch = 42.0;
  TwoBoneIkJob job;
  job.start_world = &chain[0];
  job.mid_world = &chain[1];
  job.end_world = &chain[2];
  job.output = &out;
  job.soft = 2.0;
  EXPECT_FALSE(job.run());
  EXPECT_EQ(out.stretch, 42.0) << "an invalid job should leave the output untouched";
}

TEST(TwoBoneIkJob, run__three_four_five_triangle_by_hand) {
  // Bones 3 and 4, target at distance 5: the knee is a right angle, and the
  // start bone makes atan2(4, 3) (53.13 degrees) with start-to-target. With
  // the knee pointed down (-y), the mid joint ends at (1.8, -2.4, 0).
  TwoBoneIkJob job;
  job.target = Vec3(5, 0, 0);
  job.pole_vector = Vec3(0, -1, 0);
  const Solved s = solve(straight_chain(), job);
  EXPECT_TRUE(
      same_rotation(s.output.start_correction, Quat(Eigen::AngleAxisd(-std::atan2(4.0, 3.0), Vec3::UnitZ())), 1e-14))
      << "the start turns -53.13 degrees about z";
  EXPECT_TRUE(same_rotation(s.output.mid_correction, Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ())), 1e-14))
      << "the knee bends +90 degrees about mid_axis (z)";
  EXPECT_TRUE(vec_near(position_of(s.world[1]), Vec3(1.8, -2.4, 0), 1e-14)) << "mid joint by hand";
  EXPECT_TRUE(vec_near(position_of(s.world[2]), Vec3(5, 0, 0), 1e-14)) << "the end is on the target";
  EXPECT_TRUE(s.output.reached);
  EXPECT_EQ(s.output.stretch, 1.0);
  EXPECT_GE(s.output.start_correction.w(), 0.0) << "corrections have w >= 0";
  EXPECT_GE(s.output.mid_correction.w(), 0.0) << "corrections have w >= 0";
}

TEST(TwoBoneIkJob, run__pole_picks_the_knee_side) {
  for (const Vec3& pole : {Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(0, 0, -1), Vec3(0, 1, 1).normalized()}) {
    TwoBoneIkJob job;
    job.target = Vec3(5, 0, 0);
    job.pole_vector = pole * 3.0;  // length does not matter
    const Solved s = solve(straight_chain(), job);
    EXPECT_TRUE(vec_near(position_of(s.world[1]), Vec3(1.8, 0, 0) + pole * 2.4, 1e-14))
        << "the knee should be 2.4 from the start-to-target line toward the pole " << pole.transpose();
    EXPECT_TRUE(vec_near(position_of(s.world[2]), Vec3(5, 0, 0), 1e-14));
  }
}

TEST(TwoBoneIkJob, run__plane_normal_mode_aligns_the_hinge) {
  TwoBoneIkJob job;
  job.target = Vec3(5, 0, 0);
  job.pole_mode = TwoBonePoleMode::kPlaneNormal;
  job.pole_vector = Vec3(0, 1, 0);
  const Solved s = solve(straight_chain(), job);
  EXPECT_TRUE(vec_near(position_of(s.world[1]), Vec3(1.8, 0, 2.4), 1e-14))
      << "with the hinge along +y the knee goes along cross(x, y) = +z";
  EXPECT_TRUE(vec_near(frame_of(s.world[1]).col(2), Vec3(0, 1, 0), 1e-14))
      << "the mid joint's z axis (its hinge) is the plane normal";
  job.pole_vector = Vec3(0, 0, 2);  // need not be unit
  const Solved t = solve(straight_chain(), job);
  EXPECT_TRUE(vec_near(position_of(t.world[1]), Vec3(1.8, -2.4, 0), 1e-14))
      << "with the hinge along +z the knee goes along cross(x, z) = -y";
}

TEST(TwoBoneIkJob, run__twist_turns_the_chain_about_start_to_target) {
  TwoBoneIkJob job;
  job.target = Vec3(5, 0, 0);
  job.pole_vector = Vec3(0, -1, 0);
  job.twist_angle = kPi / 2;
  const Solved s = solve(straight_chain(), job);
  EXPECT_TRUE(vec_near(position_of(s.world[1]), Vec3(1.8, 0, -2.4), 1e-14))
      << "the knee at -y turned +90 degrees about x goes to -z";
  EXPECT_TRUE(vec_near(position_of(s.world[2]), Vec3(5, 0, 0), 1e-14)) << "twist keeps the end on the target";
}

TEST(TwoBoneIkJob, run__soft_ik_by_hand) {
  // L = 7, soft = 0.2: ds = 1.4, da = 5.6. A target at 7 is reached at
  // 5.6 + 1.4 * (1 - e^-1) = 6.484968782...
  TwoBoneIkJob job;
  job.target = Vec3(7, 0, 0);
  job.pole_vector = Vec3(0, -1, 0);
  job.soft = 0.2;
  const Solved s = solve(straight_chain(), job);
  const double expected = 5.6 + 1.4 * (1.0 - std::exp(-1.0));
  EXPECT_TRUE(vec_near(position_of(s.world[2]), Vec3(expected, 0, 0), 1e-13)) << "the softened reach";
  EXPECT_FALSE(s.output.reached) << "a softened target is not reached";
  EXPECT_LT(position_of(s.world[1]).y(), -0.1) << "the knee stays bent (toward the pole)";

  job.target = Vec3(5, 0, 0);
  const Solved inside = solve(straight_chain(), job);
  EXPECT_TRUE(vec_near(position_of(inside.world[2]), Vec3(5, 0, 0), 1e-14)) << "below da nothing is softened";
  EXPECT_TRUE(inside.output.reached);
}

TEST(TwoBoneIkJob, run__stretch_by_hand) {
  TwoBoneIkJob job;
  job.target = Vec3(0, 10, 0);
  job.pole_vector = Vec3(0, 0, 1);
  job.stretch = true;
  const Solved s = solve(straight_chain(), job);
  EXPECT_NEAR(s.output.stretch, 10.0 / 7.0, 1e-15) << "a target at 10 stretches a 7-long chain by 10/7";
  EXPECT_TRUE(vec_near(position_of(s.world[1]), Vec3(0, 30.0 / 7.0, 0), 1e-13)) << "the chain is straight";
  EXPECT_TRUE(vec_near(position_of(s.world[2]), Vec3(0, 10, 0), 1e-13)) << "the end is on the target";
  EXPECT_TRUE(s.output.reached);

  job.max_stretch = 1.2;
  const Solved capped = solve(straight_chain(), job);
  EXPECT_EQ(capped.output.stretch, 1.2) << "stretch stops at max_stretch";
  EXPECT_TRUE(vec_near(position_of(capped.world[2]), Vec3(0, 8.4, 0), 1e-13)) << "7 * 1.2 = 8.4 toward the target";
  EXPECT_FALSE(capped.output.reached);

  job.max_stretch = kInf;
  job.soft = 0.2;
  job.target = Vec3(0, 7, 0);
  const Solved soft = solve(straight_chain(), job);
  EXPECT_NEAR(soft.output.stretch, 7.0 / (5.6 + 1.4 * (1.0 - std::exp(-1.0))), 1e-14)
      << "soft and stretch: the bones scale by d / softened reach";
  EXPECT_TRUE(vec_near(position_of(soft.world[2]), Vec3(0, 7, 0), 1e-13)) << "so the end still reaches the target";
  EXPECT_TRUE(soft.output.reached);

  job.soft = 0.0;
  job.target = Vec3(0, 5, 0);
  const Solved within = solve(straight_chain(), job);
  EXPECT_EQ(within.output.stretch, 1.0) << "within reach nothing stretches";
}

TEST(TwoBoneIkJob, run__weight_blends_from_no_correction) {
  TwoBoneIkJob job;
  job.target = Vec3(5, 0, 0);
  job.pole_vector = Vec3(0, -1, 0);
  job.stretch = true;
  job.weight = 0.0;
  const Solved none = solve(straight_chain(), job);
  EXPECT_TRUE(same_rotation(none.output.start_correction, Quat::Identity(), 0.0)) << "weight 0: no correction";
  EXPECT_TRUE(same_rotation(none.output.mid_correction, Quat::Identity(), 0.0));
  job.weight = 0.5;
  const Solved half = solve(straight_chain(), job);
  EXPECT_TRUE(same_rotation(half.output.start_correction,
                            Quat(Eigen::AngleAxisd(-0.5 * std::atan2(4.0, 3.0), Vec3::UnitZ())), 1e-14))
      << "weight 0.5: half of the start's -53.13 degrees";
  EXPECT_TRUE(same_rotation(half.output.mid_correction, Quat(Eigen::AngleAxisd(kPi / 4, Vec3::UnitZ())), 1e-14))
      << "and half of the knee's 90";
  job.target = Vec3(14, 0, 0);
  const Solved stretched = solve(straight_chain(), job);
  EXPECT_NEAR(stretched.output.stretch, 1.5, 1e-15) << "stretch blends from 1 to 2: 1.5";
}

TEST(TwoBoneIkJob, run__bent_input_with_rotated_scaled_frames) {
  // The same geometry from a bent, arbitrarily placed and oriented chain
  // with uniform scale 2: the answer depends only on lengths, target, pole.
  testing::Random random(11);
  for (int trial = 0; trial < 100; ++trial) {
    const Vec3 start = random.vec3(-3, 3);
    const Vec3 normal = random.unit();
    const Vec3 dir = normal.unitOrthogonal();
    const double bend = random.uniform(0.1, 2.5);
    const double l1 = random.uniform(0.5, 2.0), l2 = random.uniform(0.5, 2.0);
    const Vec3 mid = start + dir * l1;
    // Bend positively about `normal`, as mid_axis says.
    const Vec3 end = mid + Eigen::AngleAxisd(bend, normal) * dir * l2;
    std::vector<Mat4> chain = testing::chain_from_points({start, mid, end}, normal, 2.0);
    // Arbitrary roll of every frame about its bone, so the frames are not
    // aligned with anything; mid_axis follows the mid frame.
    for (Mat4& m : chain) {
      const Mat3 r = m.topLeftCorner<3, 3>();
      m.topLeftCorner<3, 3>() = r * Eigen::AngleAxisd(random.uniform(-3, 3), Vec3::UnitX()).toRotationMatrix();
    }
    TwoBoneIkJob job;
    job.mid_axis = (frame_of(chain[1]).transpose() * normal).normalized();
    const double reach = random.uniform(std::abs(l1 - l2) + 0.05, l1 + l2 - 0.05);
    job.target = start + random.unit() * reach;
    job.pole_vector = random.unit();
    if (job.pole_vector.cross((job.target - start).normalized()).norm() < 0.1) continue;  // pole near the line
    const Solved s = solve(chain, job);
    EXPECT_LE(testing::bone_length_error(chain, s.world), 1e-12) << "trial " << trial << ": lengths kept";
    EXPECT_LE((position_of(s.world[2]) - job.target).norm(), 1e-12) << "trial " << trial << ": target reached";
    EXPECT_TRUE(s.output.reached);
    // The knee is in the plane of start, target and pole, on the pole's side.
    const Vec3 k = (job.target - start).normalized();
    const Vec3 knee = position_of(s.world[1]) - start;
    const Vec3 pole_across = (job.pole_vector - k * k.dot(job.pole_vector)).normalized();
    const Vec3 knee_across = knee - k * k.dot(knee);
    EXPECT_LE(std::abs(knee_across.dot(k.cross(pole_across))), 1e-12) << "trial " << trial << ": knee in the plane";
    EXPECT_GT(knee_across.dot(pole_across), 0.0) << "trial " << trial << ": knee on the pole's side";
  }
}

TEST(TwoBoneIkJob, run__hinge_not_perpendicular_to_the_bones_still_reaches) {
  // mid_axis tilted 30 degrees out of the bones' plane: the turn about it
  // moves the end on a cone, and the generalised law of cosines still finds
  // the angle that gives the right distance.
  std::vector<Mat4> chain = straight_chain();
  TwoBoneIkJob job;
  job.mid_axis = Vec3(std::sin(kPi / 6), 0, std::cos(kPi / 6));
  job.target = Vec3(1, 5, 1);
  job.pole_vector = Vec3(0, 0, 1);
  const Solved s = solve(chain, job);
  EXPECT_LE((position_of(s.world[2]) - job.target).norm(), 1e-12) << "the end is on the target";
  EXPECT_LE(testing::bone_length_error(chain, s.world), 1e-12);
}

TEST(TwoBoneIkJob, run__degenerate_inputs_never_produce_nan) {
  auto finite = [](const Solved& s) {
    return s.output.start_correction.coeffs().allFinite() && s.output.mid_correction.coeffs().allFinite() &&
           std::isfinite(s.output.stretch) && testing::finite(s.world[0]) && testing::finite(s.world[1]) &&
           testing::finite(s.world[2]);
  };
  const std::vector<Mat4> bent = testing::chain_from_points({Vec3(0, 0, 0), Vec3(3, 0, 0), Vec3(3, 4, 0)});
  {
    TwoBoneIkJob job;
    job.target = Vec3(0, 0, 0);
    const Solved s = solve(bent, job);
    EXPECT_TRUE(finite(s)) << "target at the start joint";
    EXPECT_LE(testing::bone_length_error(bent, s.world), 1e-12);
    EXPECT_NEAR((position_of(s.world[2]) - Vec3(0, 0, 0)).norm(), 1.0, 1e-12)
        << "the chain folds as far as it can: |3 - 4| = 1 from the start";
    EXPECT_FALSE(s.output.reached);
  }
  {
    TwoBoneIkJob job;
    job.target = Vec3(0, 5, 0);
    job.pole_vector = Vec3(0, 2, 0);  // along start-to-target
    const Solved s = solve(bent, job);
    EXPECT_TRUE(finite(s)) << "pole along start-to-target";
    EXPECT_LE((position_of(s.world[2]) - job.target).norm(), 1e-12) << "still reaches the target";
    EXPECT_LE(testing::bone_length_error(bent, s.world), 1e-12);
  }
  {
    TwoBoneIkJob job;
    job.target = Vec3(0, 5, 0);
    job.pole_vector = Vec3::Zero();
    const Solved s = solve(bent, job);
    EXPECT_TRUE(finite(s)) << "zero pole";
    EXPECT_LE((position_of(s.world[2]) - job.target).norm(), 1e-12) << "still reaches the target";
  }
  {
    const std::vector<Mat4> zero_upper = testing::chain_from_points({Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(4, 0, 0)});
    TwoBoneIkJob job;
    job.target = Vec3(0, 4, 0);
    const Solved s = solve(zero_upper, job);
    EXPECT_TRUE(finite(s)) << "zero-length start bone";
    EXPECT_LE((position_of(s.world[2]) - job.target).norm(), 1e-12) << "the other bone still aims at the target";
  }
  {
    const std::vector<Mat4> zero_lower = testing::chain_from_points({Vec3(0, 0, 0), Vec3(3, 0, 0), Vec3(3, 0, 0)});
    TwoBoneIkJob job;
    job.target = Vec3(0, 3, 0);
    const Solved s = solve(zero_lower, job);
    EXPECT_TRUE(finite(s)) << "zero-length mid bone";
    EXPECT_LE((position_of(s.world[2]) - job.target).norm(), 1e-12);
  }
  {
    const std::vector<Mat4> collapsed = testing::chain_from_points({Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1)});
    TwoBoneIkJob job;
    job.target = Vec3(0, 3, 0);
    const Solved s = solve(collapsed, job);
    EXPECT_TRUE(finite(s)) << "all three joints at one point";
    EXPECT_TRUE(same_rotation(s.output.start_correction, Quat::Identity(), 0.0)) << "nothing to turn";
  }
  {
    TwoBoneIkJob job;
    job.mid_axis = Vec3::UnitX();  // along the mid bone
    job.target = Vec3(2, 2, 0);
    const Solved s = solve(straight_chain(), job);
    EXPECT_TRUE(finite(s)) << "hinge along the bones";
    EXPECT_LE(testing::bone_length_error(straight_chain(), s.world), 1e-12);
    EXPECT_TRUE(testing::straight_at(s.world, job.target, 1e-12))
        << "with no usable hinge the straight chain just aims at the target";
  }
  {
    std::vector<Mat4> squashed = straight_chain();
    squashed[1].topLeftCorner<3, 3>().setZero();  // a collapsed mid frame (cannot go through local matrices)
    TwoBoneIkOutput out;
    TwoBoneIkJob job;
    job.start_world = &squashed[0];
    job.mid_world = &squashed[1];
    job.end_world = &squashed[2];
    job.output = &out;
    job.target = Vec3(2, 2, 0);
    ASSERT_TRUE(job.run());
    EXPECT_TRUE(out.start_correction.coeffs().allFinite() && out.mid_correction.coeffs().allFinite())
        << "a mid joint with zero scale";
  }
}

// --- Swept targets: the invariants along continuous paths -----------------

// A leg hanging down -y from the origin (thigh 3, shin 4), knee bent forward
// (+z), hinge +x (a positive turn about x takes the shin from -y toward -z:
// the knee bends forward as a real knee does).
std::vector<Mat4> leg() {
  const Vec3 hip(0, 0, 0);
  const Vec3 knee = hip + Vec3(0, -std::cos(0.2), std::sin(0.2)) * 3.0;
  const Vec3 ankle = knee + Vec3(0, -std::cos(0.2), -std::sin(0.2)) * 4.0;
  return testing::chain_from_points({hip, knee, ankle}, Vec3::UnitX());
}

struct SweepStats {
  double worst_length = 0.0;          // bone length error
  double worst_reach = 0.0;           // end-to-target distance where reachable
  double worst_turn_per_step = 0.0;   // largest frame turn / target step
  double smallest_pole_side = 1e300;  // knee's offset toward the pole
};

// Solves along target(t) for t in [0, 1] in `steps` steps; checks lengths and
// reach at each, and measures the turn between consecutive solutions.
template <typename Path>
SweepStats sweep(const TwoBoneIkJob& base, Path path, int steps) {
  const std::vector<Mat4> chain = leg();
  const double length = testing::chain_length(chain);
  SweepStats stats;
  std::vector<Mat4> previous;
  Vec3 previous_target = Vec3::Zero();
  for (int n = 0; n <= steps; ++n) {
    TwoBoneIkJob job = base;
    job.target = path(static_cast<double>(n) / steps);
    const Solved s = solve(chain, job);
    if (!job.stretch) stats.worst_length = std::max(stats.worst_length, testing::bone_length_error(chain, s.world));
    const double distance = (job.target - position_of(chain[0])).norm();
    if (distance < length - 1e-9 && distance > 1.0 + 1e-9 && job.soft == 0.0) {
      stats.worst_reach = std::max(stats.worst_reach, (position_of(s.world[2]) - job.target).norm());
    }
    if (!previous.empty()) {
      const double step = (job.target - previous_target).norm();
      stats.worst_turn_per_step = std::max(stats.worst_turn_per_step, testing::largest_turn(previous, s.world) / step);
    }
    const Vec3 k = (job.target - position_of(chain[0])).normalized();
    const Vec3 pole = (job.pole_vector - k * k.dot(job.pole_vector)).normalized();
    stats.smallest_pole_side =
        std::min(stats.smallest_pole_side, (position_of(s.world[1]) - position_of(chain[0])).dot(pole));
    previous = s.world;
    previous_target = job.target;
  }
  return stats;
}

TEST(TwoBoneIkJob, sweep__target_across_the_pole_plane_does_not_flip_the_knee) {
  // The pole is forward (+z); the plane of start, target and pole is x = 0
  // when the target is below the hip. Move the target sideways through it.
  TwoBoneIkJob job;
  job.mid_axis = Vec3::UnitZ();  // the leg frames: x down the bone, z = +x world
  job.pole_vector = Vec3(0, 0, 1);
  const SweepStats s = sweep(
      job, [](double t) { return Vec3(-4 + 8 * t, -5, 0.5); }, 200);
  EXPECT_LE(s.worst_length, 1e-12) << "bone lengths are kept";
  EXPECT_LE(s.worst_reach, 1e-12) << "every target on the path is reachable and reached";
  EXPECT_LT(s.worst_turn_per_step, 1.0) << "no joint turns more than 1 radian per unit of target travel (a flip "
                                           "would be pi in one 0.04 step, 79 per unit)";
  EXPECT_GT(s.smallest_pole_side, 0.1) << "the knee stays on the pole's side all along";
}

TEST(TwoBoneIkJob, sweep__circle_around_the_hip) {
  TwoBoneIkJob job;
  job.mid_axis = Vec3::UnitZ();
  job.pole_vector = Vec3(0, 0, 1);
  // A full circle of radius 5 in the xy plane (perpendicular to the pole,
  // so the pole is defined all the way round).
  const SweepStats s = sweep(
      job, [](double t) { return Vec3(5 * std::sin(2 * kPi * t), -5 * std::cos(2 * kPi * t), 0); }, 360);
  EXPECT_LE(s.worst_length, 1e-12);
  EXPECT_LE(s.worst_reach, 1e-12);
  EXPECT_LT(s.worst_turn_per_step, 1.0) << "a full turn about the hip is continuous";
  EXPECT_GT(s.smallest_pole_side, 0.1);
}

TEST(TwoBoneIkJob, sweep__tilted_circle_with_twist_and_plane_mode) {
  for (TwoBonePoleMode mode : {TwoBonePoleMode::kPoleVector, TwoBonePoleMode::kPlaneNormal}) {
    TwoBoneIkJob job;
    job.mid_axis = Vec3::UnitZ();
    job.pole_mode = mode;
    job.pole_vector = mode == TwoBonePoleMode::kPoleVector ? Vec3(0, 0, 1) : Vec3(-1, 0, 0);
    job.twist_angle = 0.3;
    const Vec3 u = Vec3(1, 0.2, 0).normalized(), v = Vec3(0, -1, 0.3).normalized();
    const SweepStats s = sweep(
        job, [&](double t) { return (u * std::sin(2 * kPi * t) + v * std::cos(2 * kPi * t)) * 4.5; }, 360);
    EXPECT_LE(s.worst_length, 1e-12);
    EXPECT_LE(s.worst_reach, 1e-12);
    // Plane mode turns faster where start-to-target comes near the plane
    // normal (about 1 / (distance * sin of that angle)); never a flip.
    EXPECT_LT(s.worst_turn_per_step, 6.0) << "mode " << static_cast<int>(mode);
  }
}

TEST(TwoBoneIkJob, sweep__out_of_reach_segment_points_straight) {
  TwoBoneIkJob job;
  job.mid_axis = Vec3::UnitZ();
  job.pole_vector = Vec3(0, 0, 1);
  const std::vector<Mat4> chain = leg();
  for (int n = 0; n <= 100; ++n) {
    job.target = Vec3(1, -7.5 - 0.1 * n, 2);  // from 7.8 to 17.7 away: all beyond 7
    const Solved s = solve(chain, job);
    EXPECT_LE(testing::bone_length_error(chain, s.world), 1e-12);
    EXPECT_TRUE(testing::straight_at(s.world, job.target, 1e-12)) << "step " << n << ": straight at the target";
    EXPECT_FALSE(s.output.reached);
  }
}

TEST(TwoBoneIkJob, sweep__into_and_out_of_reach_with_soft_ik_is_smooth) {
  // A hard two-bone solve straightens the knee with infinite speed as the
  // target reaches full extension (the angle goes as the square root of the
  // distance left); soft IK is the cure. Across reach with soft = 0.1 the
  // turn per unit of target travel stays bounded.
  TwoBoneIkJob job;
  job.mid_axis = Vec3::UnitZ();
  job.pole_vector = Vec3(0, 0, 1);
  job.soft = 0.1;
  const SweepStats soft = sweep(
      job, [](double t) { return Vec3(0, -5 - 5 * t, 0.3); }, 500);
  EXPECT_LE(soft.worst_length, 1e-12);
  EXPECT_LT(soft.worst_turn_per_step, 2.0);
  EXPECT_GT(soft.smallest_pole_side, 0.0) << "soft IK never quite straightens the knee";

  // Hard, the same path is still continuous: the largest turn in one step
  // shrinks with the step (as its square root there), it does not jump.
  job.soft = 0.0;
  // Full extension is at y = -6.994 (t = 0.399 of the path): steps of 0.05
  // over the whole path, then steps of 0.0005 over [-6.75, -7.25] around it.
  const SweepStats coarse = sweep(
      job, [](double t) { return Vec3(0, -5 - 5 * t, 0.3); }, 100);
  const SweepStats fine = sweep(
      job, [](double t) { return Vec3(0, -6.75 - 0.5 * t, 0.3); }, 1000);
  const double coarse_turn = coarse.worst_turn_per_step * 0.05;
  const double fine_turn = fine.worst_turn_per_step * 0.0005;
  EXPECT_LE(fine_turn, 0.2 * coarse_turn)
      << "100x smaller steps should give a largest turn about 10x smaller (square root), not the same jump";
}

TEST(TwoBoneIkJob, sweep__stretch_reaches_along_the_whole_segment) {
  TwoBoneIkJob job;
  job.mid_axis = Vec3::UnitZ();
  job.pole_vector = Vec3(0, 0, 1);
  job.stretch = true;
  const std::vector<Mat4> chain = leg();
  std::vector<Mat4> previous;
  for (int n = 0; n <= 200; ++n) {
    job.target = Vec3(0.5, -4 - 0.05 * n, 1);
    const Solved s = solve(chain, job);
    EXPECT_LE((position_of(s.world[2]) - job.target).norm(), 1e-12) << "step " << n << ": stretch always reaches";
    EXPECT_TRUE(s.output.reached);
    const double d = (job.target - position_of(chain[0])).norm();
    EXPECT_NEAR(s.output.stretch, std::max(1.0, d / 7.0), 1e-12);
    if (!previous.empty()) {
      EXPECT_LT(testing::largest_turn(previous, s.world), 0.2) << "step " << n;
    }
    previous = s.world;
  }
}

}  // namespace
}  // namespace rigel::ops::ik
