#include "rigel/ops/ik/two_bone_keep_plane.h"

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

// A 3-4 arm bent in the xy plane: start at the origin, mid at (3, 0, 0), end
// at (3, 4, 0).
std::vector<Mat4> bent_chain() { return chain_from_points({Vec3(0, 0, 0), Vec3(3, 0, 0), Vec3(3, 4, 0)}); }

TwoBoneKeepPlaneOutput solve(const std::vector<Mat4>& chain, const Vec3& target) {
  TwoBoneKeepPlaneOutput out;
  TwoBoneKeepPlaneJob job;
  job.start_world = &chain[0];
  job.mid_world = &chain[1];
  job.end_world = &chain[2];
  job.target = target;
  job.output = &out;
  EXPECT_TRUE(job.run()) << "the job should be valid";
  return out;
}

// The unit normal of the plane through three points.
Vec3 plane_normal(const Vec3& a, const Vec3& b, const Vec3& c) { return (b - a).cross(c - a).normalized(); }

bool is_rotation(const Mat3& r) {
  return (r.transpose() * r).isIdentity(1e-12) && std::abs(r.determinant() - 1) < 1e-12;
}

TEST(TwoBoneKeepPlaneJob, validate__rejects_each_documented_failure) {
  const std::vector<Mat4> chain = bent_chain();
  TwoBoneKeepPlaneOutput out;
  auto valid = [&] {
    TwoBoneKeepPlaneJob job;
    job.start_world = &chain[0];
    job.mid_world = &chain[1];
    job.end_world = &chain[2];
    job.target = Vec3(4, 2, 0);
    job.output = &out;
    return job;
  };
  EXPECT_TRUE(valid().validate()) << "a well-formed job should validate";
  {
    TwoBoneKeepPlaneJob job;
    EXPECT_FALSE(job.validate()) << "a default job (no joints, no output) should be rejected";
    EXPECT_FALSE(job.run()) << "run() should refuse a job that does not validate";
  }
  for (int which = 0; which < 4; ++which) {
    TwoBoneKeepPlaneJob job = valid();
    if (which == 0) job.start_world = nullptr;
    if (which == 1) job.mid_world = nullptr;
    if (which == 2) job.end_world = nullptr;
    if (which == 3) job.output = nullptr;
    EXPECT_FALSE(job.validate()) << "a null pointer (field " << which << ") should be rejected";
  }
  for (int which = 0; which < 3; ++which) {
    std::vector<Mat4> bad = chain;
    bad[static_cast<std::size_t>(which)](3, 1) = 0.5;
    TwoBoneKeepPlaneJob job = valid();
    job.start_world = &bad[0];
    job.mid_world = &bad[1];
    job.end_world = &bad[2];
    EXPECT_FALSE(job.validate()) << "a matrix that is not affine (joint " << which << ") should be rejected";
    bad = chain;
    bad[static_cast<std::size_t>(which)](0, 3) = kNaN;
    EXPECT_FALSE(job.validate()) << "a matrix that is not finite (joint " << which << ") should be rejected";
  }
  {
    TwoBoneKeepPlaneJob job = valid();
    job.target = Vec3(kNaN, 0, 0);
    EXPECT_FALSE(job.validate()) << "a target that is not finite should be rejected";
  }
}

TEST(TwoBoneKeepPlaneJob, run__reaches_the_target_keeping_lengths_and_the_bend_plane) {
  const std::vector<Mat4> chain = bent_chain();
  const Vec3 start = position_of(chain[0]);
  for (const Vec3& target : {Vec3(4, 2, 0), Vec3(1, 3, 0), Vec3(2, 2, 2), Vec3(-1, 2, 3)}) {
    const TwoBoneKeepPlaneOutput out = solve(chain, target);
    EXPECT_TRUE(out.solved && out.reached) << "a target within reach should be solved and reached";
    EXPECT_TRUE(vec_near(out.end, target, 1e-12)) << "the end should land on the target";
    EXPECT_NEAR((out.mid - start).norm(), 3.0, 1e-12) << "the start bone should keep its length";
    EXPECT_NEAR((out.end - out.mid).norm(), 4.0, 1e-12) << "the mid bone should keep its length";
    // The knee stays on the side it was: its direction perpendicular to
    // start-to-end, carried onto the new start-to-end, keeps pointing the
    // same way as the old knee direction's part perpendicular to it.
    const Vec3 u = (out.end - start).normalized();
    const Vec3 knee = (out.mid - start) - (out.mid - start).dot(u) * u;
    const Vec3 old_knee = Vec3(3, 0, 0) - Vec3(3, 0, 0).dot(Vec3(3, 4, 0).normalized()) * Vec3(3, 4, 0).normalized();
    EXPECT_GT(knee.dot(old_knee - old_knee.dot(u) * u), 0) << "the knee should not flip to the other side";
    EXPECT_TRUE(is_rotation(out.start_turn) && is_rotation(out.mid_turn)) << "the turns should be rotations";
    EXPECT_TRUE(vec_near(out.start_turn * Vec3(3, 0, 0), out.mid - start, 1e-12))
        << "the start turn should take the start bone onto its new direction";
    EXPECT_TRUE(vec_near(out.mid_turn * Vec3(0, 4, 0), out.end - out.mid, 1e-12))
        << "the mid turn should take the mid bone onto its new direction";
  }
  // A target in the chain's plane keeps the plane itself.
  const TwoBoneKeepPlaneOutput out = solve(chain, Vec3(4, 2, 0));
  EXPECT_TRUE(vec_near(plane_normal(start, out.mid, out.end), Vec3(0, 0, 1), 1e-12))
      << "a target in the bend plane should keep the plane and its orientation";
  EXPECT_TRUE(vec_near(out.start_turn * Vec3::UnitZ(), Vec3::UnitZ(), 1e-12))
      << "the plane's normal should not turn";
}

TEST(TwoBoneKeepPlaneJob, run__the_current_end_as_target_changes_nothing) {
  const std::vector<Mat4> chain = bent_chain();
  const TwoBoneKeepPlaneOutput out = solve(chain, Vec3(3, 4, 0));
  EXPECT_TRUE(out.solved && out.reached);
  EXPECT_TRUE(vec_near(out.mid, Vec3(3, 0, 0), 1e-12)) << "the mid joint should stay";
  EXPECT_TRUE(vec_near(out.end, Vec3(3, 4, 0), 1e-12)) << "the end joint should stay";
  EXPECT_TRUE(out.start_turn.isIdentity(1e-12) && out.mid_turn.isIdentity(1e-12)) << "nothing should turn";
}

TEST(TwoBoneKeepPlaneJob, run__straight_chain_bends_toward_the_start_axis_most_perpendicular) {
  // Straight along x; the start's x axis is turned toward y (0.8, 0.6, 0),
  // its z axis stays: z is the axis most perpendicular to the chain.
  std::vector<Mat4> chain = chain_from_points({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)});
  Mat3 r;
  r.col(0) = Vec3(0.8, 0.6, 0).normalized();
  r.col(2) = Vec3(0, 0, 1);
  r.col(1) = r.col(2).cross(r.col(0));
  chain[0].topLeftCorner<3, 3>() = r;
  const TwoBoneKeepPlaneOutput out = solve(chain, Vec3(1.5, 0, 0));
  EXPECT_TRUE(out.solved && out.reached);
  EXPECT_TRUE(vec_near(out.end, Vec3(1.5, 0, 0), 1e-12)) << "the end should land on the target";
  // z is perpendicular to the chain, x and y are not: the knee goes to +z.
  EXPECT_NEAR(out.mid.y(), 0.0, 1e-12) << "the knee should bend in the plane of x and the start's z axis";
  EXPECT_GT(out.mid.z(), 0.5) << "toward +z";
  EXPECT_TRUE(out.mid.allFinite() && out.start_turn.allFinite() && out.mid_turn.allFinite());
}

TEST(TwoBoneKeepPlaneJob, run__out_of_reach_points_at_the_target_fully_stretched_or_folded) {
  const std::vector<Mat4> chain = bent_chain();
  {
    const TwoBoneKeepPlaneOutput out = solve(chain, Vec3(20, 0, 0));
    EXPECT_TRUE(out.solved) << "the chain can still turn";
    EXPECT_FALSE(out.reached) << "a target beyond 7 is out of reach";
    EXPECT_TRUE(vec_near(out.end, Vec3(7, 0, 0), 1e-12)) << "the chain should point at the target, straight";
    EXPECT_TRUE(vec_near(out.mid, Vec3(3, 0, 0), 1e-9)) << "the mid joint on the line";
  }
  {
    // Nearer than |a - b| = 1: folded, pointing at it.
    const TwoBoneKeepPlaneOutput out = solve(chain, Vec3(0, 0.5, 0));
    EXPECT_FALSE(out.reached) << "a target nearer than 1 cannot be reached";
    EXPECT_TRUE(vec_near(out.end, Vec3(0, 1, 0), 1e-12)) << "folded, the end at distance 1 toward the target";
    EXPECT_NEAR((out.mid - position_of(chain[0])).norm(), 3.0, 1e-12) << "lengths kept";
  }
  {
    // The target at the start: the start-to-end direction is kept.
    const TwoBoneKeepPlaneOutput out = solve(chain, Vec3(0, 0, 0));
    EXPECT_FALSE(out.reached);
    EXPECT_TRUE(vec_near(out.end, Vec3(3, 4, 0).normalized(), 1e-12)) << "folded along the old direction";
    EXPECT_TRUE(out.mid.allFinite() && out.start_turn.allFinite()) << "no NaN";
  }
}

TEST(TwoBoneKeepPlaneJob, run__zero_length_bone_solves_nothing) {
  for (const std::vector<Vec3>& points :
       {std::vector<Vec3>{Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(1, 0, 0)},
        std::vector<Vec3>{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 0, 0)},
        std::vector<Vec3>{Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1)}}) {
    const std::vector<Mat4> chain = chain_from_points(points);
    const TwoBoneKeepPlaneOutput out = solve(chain, Vec3(0, 2, 0));
    EXPECT_FALSE(out.solved) << "a chain with a zero-length bone cannot be solved by the two-bone rule";
    EXPECT_FALSE(out.reached);
    EXPECT_TRUE(vec_near(out.mid, points[1], 0) && vec_near(out.end, points[2], 0)) << "nothing moves";
    EXPECT_TRUE(out.start_turn.isIdentity(0) && out.mid_turn.isIdentity(0)) << "nothing turns";
  }
}

}  // namespace
}  // namespace rigel::ops::ik
