// ReverseFootJob (reverse_foot.h): a test per documented validate() failure
// and the roll's three phases against hand-computed pivots.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "rigel/math/transform.h"
#include "rigel/ops/util/reverse_foot.h"

namespace rigel::ops::util {
namespace {

using math::Mat4;
using math::Vec3;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

Vec3 pos(const Mat4& m) { return m.topRightCorner<3, 1>(); }

// A foot along +z: heel at z = -1, ball at z = 1, toe tip at z = 2, the
// ankle above the heel's front at (0, 1, 0).
struct Foot {
  Mat4 ankle = Mat4::Identity(), ball = Mat4::Identity();
  ReverseFootJob job() {
    ReverseFootJob j;
    j.pivots.heel = Vec3(0, 0, -1);
    j.pivots.ball = Vec3(0, 0, 1);
    j.pivots.toe = Vec3(0, 0, 2);
    j.pivots.inner = Vec3(-0.5, 0, 0);
    j.pivots.outer = Vec3(0.5, 0, 0);
    j.rest_ankle = math::trs_matrix(Vec3(0, 1, 0), math::Quat::Identity(), Vec3::Ones());
    j.rest_ball = math::trs_matrix(Vec3(0, 0, 1), math::Quat::Identity(), Vec3::Ones());
    j.ankle = &ankle;
    j.ball = &ball;
    return j;
  }
};

TEST(ReverseFootJob, validate__rejects_each_documented_failure) {
  Foot f;
  EXPECT_TRUE(f.job().validate()) << "the fixture job should validate";
  for (int which = 0; which < 2; ++which) {
    ReverseFootJob job = f.job();
    (which == 0 ? job.ankle : job.ball) = nullptr;
    EXPECT_FALSE(job.validate()) << "a job without its " << (which == 0 ? "ankle" : "ball") << " output should be rejected";
  }
  for (int which = 0; which < 7; ++which) {
    ReverseFootJob job = f.job();
    ReverseFootValues& v = job.values;
    double* values[] = {&v.roll, &v.roll_break, &v.bank, &v.heel_twist, &v.toe_twist, &v.ball_twist, &v.toe_tap};
    *values[which] = kNan;
    EXPECT_FALSE(job.validate()) << "a value that is not finite should be rejected (" << which << ")";
  }
  for (int which = 0; which < 5; ++which) {
    ReverseFootJob job = f.job();
    ReverseFootPivots& p = job.pivots;
    Vec3* points[] = {&p.heel, &p.toe, &p.ball, &p.inner, &p.outer};
    (*points[which])[1] = kNan;
    EXPECT_FALSE(job.validate()) << "a pivot that is not finite should be rejected (" << which << ")";
  }
  for (int which = 0; which < 6; ++which) {
    ReverseFootJob job = f.job();
    ReverseFootPivots& p = job.pivots;
    Vec3* axes[] = {&p.roll_axis, &p.bank_axis, &p.twist_axis};
    *axes[which % 3] = which < 3 ? Vec3(Vec3::Zero()) : Vec3(kNan, 0, 0);
    EXPECT_FALSE(job.validate()) << "a zero or non-finite axis should be rejected (" << which << ")";
  }
  {
    ReverseFootJob job = f.job();
    job.values.roll = kNan;
    f.ankle(0, 0) = 7;
    EXPECT_FALSE(job.run()) << "run() should refuse a job that does not validate";
    EXPECT_EQ(f.ankle(0, 0), 7) << "and write nothing";
  }
}

TEST(ReverseFootJob, run__rolls_on_the_heel_the_ball_and_the_toe) {
  Foot f;
  ReverseFootJob job = f.job();
  ASSERT_TRUE(job.run());
  EXPECT_EQ(f.ankle, job.rest_ankle) << "at zero values the rest pose, bit for bit";
  EXPECT_EQ(f.ball, job.rest_ball);
  // Below zero: the foot turns about the heel.
  job.values.roll = -90;
  ASSERT_TRUE(job.run());
  EXPECT_LT((pos(f.ankle) - Vec3(0, 1, -2)).norm(), 1e-12) << "the ankle turns a quarter back about the heel";
  EXPECT_LT((pos(f.ball) - Vec3(0, 2, -1)).norm(), 1e-12) << "the ball swings up about the heel";
  // Up to rollBreak: about the ball; the ball joint stays down.
  job.values.roll = 20;
  ASSERT_TRUE(job.run());
  EXPECT_LT((pos(f.ball) - Vec3(0, 0, 1)).norm(), 1e-12) << "the ball stays where it is while rolling on it";
  EXPECT_GT((pos(f.ankle) - Vec3(0, 1, 0)).norm(), 0.1) << "the ankle lifts";
  // Beyond rollBreak: the toe tip takes the rest; the ball lifts.
  job.values.roll = 50;
  ASSERT_TRUE(job.run());
  EXPECT_GT(pos(f.ball).y(), 0.1) << "past the break the ball lifts about the toe";
  // Axes of any length are normalized.
  ReverseFootJob scaled = f.job();
  scaled.values.roll = 50;
  scaled.pivots.roll_axis *= 3.0;
  Mat4 ankle = f.ankle;
  ASSERT_TRUE(scaled.run());
  EXPECT_LT((f.ankle - ankle).norm(), 1e-12) << "a longer roll axis gives the same pose";
}

}  // namespace
}  // namespace rigel::ops::util
