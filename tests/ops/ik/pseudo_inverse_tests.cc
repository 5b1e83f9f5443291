#include "rigel/ops/ik/pseudo_inverse.h"

#include <gtest/gtest.h>

#include <limits>
#include <vector>

#include "ik_test_util.h"

namespace rigel::ops::ik {
namespace {

using testing::vec_near;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Spread {
  std::vector<Vec3> solved;
  std::vector<Mat3> turns;
};

Spread spread(const std::vector<Vec3>& positions, const Vec3& target, bool keep_lengths) {
  Spread s;
  s.solved.resize(positions.size());
  s.turns.resize(positions.size());
  PseudoInverseJob job;
  job.positions = positions;
  job.target = target;
  job.keep_lengths = keep_lengths;
  job.solved = s.solved;
  job.turns = s.turns;
  EXPECT_TRUE(job.run()) << "the job should be valid";
  return s;
}

TEST(PseudoInverseJob, validate__rejects_each_documented_failure) {
  std::vector<Vec3> positions{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
  std::vector<Vec3> solved(3);
  std::vector<Mat3> turns(3);
  auto valid = [&] {
    PseudoInverseJob job;
    job.positions = positions;
    job.target = Vec3(2, 1, 0);
    job.solved = solved;
    job.turns = turns;
    return job;
  };
  EXPECT_TRUE(valid().validate()) << "a well-formed job should validate";
  {
    PseudoInverseJob job = valid();
    job.turns = {};
    EXPECT_TRUE(job.validate()) << "turns are optional";
  }
  {
    PseudoInverseJob job;
    EXPECT_FALSE(job.validate()) << "a default job (no joints) should be rejected";
    EXPECT_FALSE(job.run()) << "run() should refuse a job that does not validate";
  }
  {
    PseudoInverseJob job = valid();
    job.positions = std::span<const Vec3>(positions.data(), 1);
    job.solved = std::span<Vec3>(solved.data(), 1);
    job.turns = {};
    EXPECT_FALSE(job.validate()) << "one joint is no chain";
  }
  {
    PseudoInverseJob job = valid();
    job.solved = std::span<Vec3>(solved.data(), 2);
    EXPECT_FALSE(job.validate()) << "solved of the wrong size should be rejected";
  }
  {
    PseudoInverseJob job = valid();
    job.turns = std::span<Mat3>(turns.data(), 2);
    EXPECT_FALSE(job.validate()) << "turns of the wrong size should be rejected";
  }
  {
    PseudoInverseJob job = valid();
    job.solved = positions;
    EXPECT_FALSE(job.validate()) << "solved over positions should be rejected";
  }
  {
    PseudoInverseJob job = valid();
    positions[1].y() = kNaN;
    EXPECT_FALSE(job.validate()) << "a position that is not finite should be rejected";
    positions[1].y() = 0;
    job.target = Vec3(0, kNaN, 0);
    EXPECT_FALSE(job.validate()) << "a target that is not finite should be rejected";
  }
}

TEST(PseudoInverseJob, run__spreads_the_motion_evenly_down_to_the_top) {
  const std::vector<Vec3> positions{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(3, 0, 0), Vec3(4, 0, 0)};
  const Spread s = spread(positions, Vec3(4, 2, 0), false);
  for (std::size_t i = 0; i < positions.size(); ++i)
    EXPECT_TRUE(vec_near(s.solved[i], positions[i] + Vec3(0, 0.5 * static_cast<double>(i), 0), 1e-15))
        << "joint " << i << " of 5 should move by " << i << "/4 of the motion";
  for (std::size_t i = 0; i + 1 < positions.size(); ++i)
    EXPECT_TRUE(vec_near(s.turns[i] * (positions[i + 1] - positions[i]).normalized(),
                         (s.solved[i + 1] - s.solved[i]).normalized(), 1e-12))
        << "turn " << i << " should take the bone onto its new direction";
  EXPECT_TRUE(s.turns.back().isIdentity(0)) << "the end's turn is the identity";
  EXPECT_TRUE(vec_near(s.solved.back(), Vec3(4, 2, 0), 0)) << "the end lands on the target";
}

TEST(PseudoInverseJob, run__keep_lengths_restores_each_bone_from_the_top) {
  const std::vector<Vec3> positions{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(3, 0, 0)};
  const Spread s = spread(positions, Vec3(3, 2, 0), true);
  EXPECT_TRUE(vec_near(s.solved[0], positions[0], 0)) << "the top stays";
  EXPECT_NEAR((s.solved[1] - s.solved[0]).norm(), 1.0, 1e-15) << "bone 0 keeps its length";
  EXPECT_NEAR((s.solved[2] - s.solved[1]).norm(), 2.0, 1e-15) << "bone 1 keeps its length";
  // Joint 1 moves along (1, 1) first, then back to length 1.
  EXPECT_TRUE(vec_near(s.solved[1], Vec3(1, 1, 0).normalized(), 1e-15));
  EXPECT_GT((s.solved[2] - Vec3(3, 2, 0)).norm(), 1e-3) << "the lengths take back part of the motion";
}

TEST(PseudoInverseJob, run__degenerate_chains_produce_no_nan) {
  {
    // Straight, the end pulled back onto the top: every joint meets it.
    const std::vector<Vec3> positions{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
    const Spread s = spread(positions, Vec3(0, 0, 0), true);
    for (const Vec3& p : s.solved) EXPECT_TRUE(p.allFinite());
    EXPECT_TRUE(vec_near(s.solved[1], Vec3(1, 0, 0), 1e-15))
        << "a bone the spread shrinks to nothing keeps its input direction and length";
    EXPECT_TRUE(vec_near(s.solved[2], Vec3(0, 0, 0), 1e-15)) << "the next bone turns back toward the target";
  }
  {
    // Zero-length bones: nothing to turn.
    const std::vector<Vec3> positions{Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1)};
    const Spread s = spread(positions, Vec3(1, 2, 1), false);
    EXPECT_TRUE(vec_near(s.solved[2], Vec3(1, 2, 1), 0));
    for (const Mat3& t : s.turns) EXPECT_TRUE(t.isIdentity(0)) << "a zero-length bone's turn is the identity";
  }
}

}  // namespace
}  // namespace rigel::ops::ik
