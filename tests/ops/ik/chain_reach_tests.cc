#include "rigel/ops/ik/chain_reach.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "ik_test_util.h"

namespace rigel::ops::ik {
namespace {

using testing::chain_from_points;
using testing::position_of;
using testing::vec_near;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

struct Reach {
  std::vector<Vec3> positions;
  std::vector<Mat3> turns;
};

Reach reach(const std::vector<Mat4>& world, const Vec3& target) {
  Reach r;
  const std::size_t n = world.size();
  r.positions.resize(n);
  r.turns.resize(n);
  std::vector<double> lengths(n - 1);
  std::vector<Quat> corrections(n);
  ChainReachJob job;
  job.world = world;
  job.target = target;
  job.positions = r.positions;
  job.lengths = lengths;
  job.corrections = corrections;
  job.turns = r.turns;
  EXPECT_TRUE(job.run()) << "the job should be valid";
  return r;
}

double length_error(const std::vector<Mat4>& world, const std::vector<Vec3>& p) {
  double worst = 0;
  for (std::size_t i = 0; i + 1 < world.size(); ++i)
    worst = std::max(worst, std::abs((position_of(world[i + 1]) - position_of(world[i])).norm() - (p[i + 1] - p[i]).norm()));
  return worst;
}

std::vector<Mat4> bent_chain() {
  return chain_from_points({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1.8, 0.6, 0), Vec3(2.2, 1.5, 0.1), Vec3(2.0, 2.4, 0.3)});
}

TEST(ChainReachJob, validate__rejects_each_documented_failure) {
  const std::vector<Mat4> world = bent_chain();
  std::vector<Vec3> positions(5);
  std::vector<double> lengths(4);
  std::vector<Quat> corrections(5);
  std::vector<Mat3> turns(5);
  auto valid = [&] {
    ChainReachJob job;
    job.world = world;
    job.target = Vec3(1, 2, 0);
    job.positions = positions;
    job.lengths = lengths;
    job.corrections = corrections;
    job.turns = turns;
    return job;
  };
  EXPECT_TRUE(valid().validate()) << "a well-formed job should validate";
  {
    ChainReachJob job = valid();
    job.turns = {};
    EXPECT_TRUE(job.validate()) << "turns are optional";
  }
  {
    ChainReachJob job;
    EXPECT_FALSE(job.validate()) << "a default job (no joints) should be rejected";
    EXPECT_FALSE(job.run()) << "run() should refuse a job that does not validate";
  }
  {
    ChainReachJob job = valid();
    job.world = std::span<const Mat4>(world.data(), 1);
    job.positions = std::span<Vec3>(positions.data(), 1);
    job.lengths = {};
    job.corrections = std::span<Quat>(corrections.data(), 1);
    job.turns = {};
    EXPECT_FALSE(job.validate()) << "one joint is no chain";
  }
  for (int which = 0; which < 4; ++which) {
    ChainReachJob job = valid();
    if (which == 0) job.positions = job.positions.first(4);
    if (which == 1) job.lengths = job.lengths.first(3);
    if (which == 2) job.corrections = job.corrections.first(4);
    if (which == 3) job.turns = job.turns.first(4);
    EXPECT_FALSE(job.validate()) << "a span of the wrong size (field " << which << ") should be rejected";
  }
  {
    // Overlapping outputs: lengths inside the corrections' memory.
    ChainReachJob job = valid();
    job.lengths = std::span<double>(reinterpret_cast<double*>(corrections.data()), 4);
    EXPECT_FALSE(job.validate()) << "lengths overlapping corrections should be rejected";
    job = valid();
    job.positions = std::span<Vec3>(reinterpret_cast<Vec3*>(turns.data()), 5);
    EXPECT_FALSE(job.validate()) << "positions overlapping turns should be rejected";
    job = valid();
    job.lengths = std::span<double>(reinterpret_cast<double*>(positions.data()) + 1, 4);
    EXPECT_FALSE(job.validate()) << "lengths overlapping positions should be rejected";
  }
  for (int which = 0; which < 2; ++which) {
    std::vector<Mat4> bad = world;
    if (which == 0) bad[2](3, 0) = 0.5;
    if (which == 1) bad[2](1, 3) = kNaN;
    ChainReachJob job = valid();
    job.world = bad;
    EXPECT_FALSE(job.validate()) << (which == 0 ? "a matrix that is not affine" : "a matrix that is not finite")
                                 << " should be rejected";
  }
  {
    ChainReachJob job = valid();
    job.target = Vec3(kInf, 0, 0);
    EXPECT_FALSE(job.validate()) << "a target that is not finite should be rejected";
  }
  for (double tolerance : {-1e-6, kNaN, kInf}) {
    ChainReachJob job = valid();
    job.tolerance = tolerance;
    EXPECT_FALSE(job.validate()) << "tolerance " << tolerance << " should be rejected";
  }
  {
    ChainReachJob job = valid();
    job.max_iterations = -1;
    EXPECT_FALSE(job.validate()) << "a negative iteration count should be rejected";
  }
}

TEST(ChainReachJob, run__reaches_exactly_and_keeps_lengths_within_reach) {
  const std::vector<Mat4> world = bent_chain();
  for (const Vec3& target : {Vec3(1, 2, 0), Vec3(-1, 1, 1), Vec3(2.5, 1.5, 0.5), Vec3(0.2, 0.1, 0.3), Vec3(2, -2, 0)}) {
    const Reach r = reach(world, target);
    EXPECT_TRUE(vec_near(r.positions.back(), target, 1e-12)) << "the end should land on the target to rounding";
    EXPECT_TRUE(vec_near(r.positions.front(), position_of(world[0]), 0)) << "the first joint stays";
    EXPECT_LT(length_error(world, r.positions), 1e-12) << "every bone keeps its length";
    for (std::size_t i = 0; i + 1 < world.size(); ++i) {
      const Vec3 before = (position_of(world[i + 1]) - position_of(world[i])).normalized();
      const Vec3 after = (r.positions[i + 1] - r.positions[i]).normalized();
      EXPECT_TRUE(vec_near(r.turns[i] * before, after, 1e-12)) << "turn " << i << " takes bone " << i << " along";
    }
    EXPECT_TRUE(r.turns.back().isIdentity(0)) << "the end's turn is the identity";
  }
}

TEST(ChainReachJob, run__straight_chain_bends_toward_the_start_axis_most_perpendicular) {
  // Straight along x, the first joint's frame turned about x by 30 degrees:
  // its y axis is the first one perpendicular to the chain.
  std::vector<Mat4> world = chain_from_points({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(3, 0, 0)});
  world[0].topLeftCorner<3, 3>() = Eigen::AngleAxisd(math::kPi / 6, Vec3::UnitX()).toRotationMatrix();
  const Vec3 y = world[0].block<3, 1>(0, 1);
  for (double reach_to : {0.5, 1.5, 2.5, 2.999999}) {
    const Reach r = reach(world, Vec3(reach_to, 0, 0));
    EXPECT_TRUE(vec_near(r.positions.back(), Vec3(reach_to, 0, 0), 1e-12)) << "reached at " << reach_to;
    EXPECT_LT(length_error(world, r.positions), 1e-12) << "lengths kept at " << reach_to;
    for (std::size_t i = 1; i + 1 < world.size(); ++i) {
      const Vec3 off = r.positions[i] - r.positions[i].dot(Vec3::UnitX()) * Vec3::UnitX();
      EXPECT_GT(off.dot(y), 0) << "joint " << i << " should bulge toward the start's y axis";
      EXPECT_NEAR(off.cross(y).norm(), 0, 1e-9) << "in the plane of the chain and that axis";
    }
  }
}

TEST(ChainReachJob, run__out_of_reach_points_straight_at_the_target) {
  const std::vector<Mat4> world = bent_chain();
  const Vec3 target(10, 10, 0);
  const Reach r = reach(world, target);
  std::vector<Mat4> solved(world.size(), Mat4::Identity());
  for (std::size_t i = 0; i < world.size(); ++i) solved[i].topRightCorner<3, 1>() = r.positions[i];
  EXPECT_TRUE(testing::straight_at(solved, target, 1e-9)) << "the chain should point at the target";
  EXPECT_LT(length_error(world, r.positions), 1e-12) << "every bone keeps its length";
}

TEST(ChainReachJob, run__two_joints_point_the_bone_at_the_target) {
  const std::vector<Mat4> world = chain_from_points({Vec3(1, 0, 0), Vec3(3, 0, 0)});
  const Reach r = reach(world, Vec3(1, 5, 0));
  EXPECT_TRUE(vec_near(r.positions[1], Vec3(1, 2, 0), 1e-15)) << "the bone should point at the target, length 2";
  const Reach same = reach(world, Vec3(1, 0, 0));
  EXPECT_TRUE(vec_near(same.positions[1], Vec3(3, 0, 0), 0)) << "a target on the first joint leaves the bone";
}

TEST(ChainReachJob, run__zero_length_bones_produce_no_nan) {
  {
    const std::vector<Mat4> world = chain_from_points({Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1)});
    const Reach r = reach(world, Vec3(2, 1, 1));
    for (const Vec3& p : r.positions) EXPECT_TRUE(vec_near(p, Vec3(1, 1, 1), 0)) << "a chain with no length stays";
    for (const Mat3& t : r.turns) EXPECT_TRUE(t.allFinite());
  }
  {
    const std::vector<Mat4> world =
        chain_from_points({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 0, 0), Vec3(1.5, 0.8, 0), Vec3(2.5, 1, 0)});
    const Reach r = reach(world, Vec3(0.5, 1.5, 0.5));
    for (const Vec3& p : r.positions) EXPECT_TRUE(p.allFinite()) << "no NaN with a zero-length bone";
    EXPECT_LT(length_error(world, r.positions), 1e-12) << "every bone keeps its length";
    EXPECT_TRUE(vec_near(r.positions.back(), Vec3(0.5, 1.5, 0.5), 1e-12)) << "and the target is reached";
  }
}

}  // namespace
}  // namespace rigel::ops::ik
