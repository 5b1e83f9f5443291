// FingerCurlJob (finger_curl.h): a test per documented validate() failure,
// the curl per finger and what it reports for unusable input.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "rigel/math/transform.h"
#include "rigel/ops/util/finger_curl.h"

namespace rigel::ops::util {
namespace {

using math::Mat4;
using math::Vec3;
using Problem = FingerCurlResult::Problem;

// Two fingers of two controls each, curling about z and spreading about y.
struct Hand {
  std::vector<Mat4> rest = std::vector<Mat4>(4, Mat4::Identity());
  std::vector<std::int64_t> finger{0, 0, 1, 1};
  std::vector<double> finger_curl{0.0, 10.0};
  std::vector<Vec3> bend = std::vector<Vec3>(4, Vec3::UnitZ());
  std::vector<Vec3> side = std::vector<Vec3>(4, Vec3::UnitY());
  std::vector<double> weight{1.0, 0.0, -1.0, 0.0};
  std::vector<Mat4> out = std::vector<Mat4>(4);
  FingerCurlResult result;
  Hand() {
    for (int i = 0; i < 4; ++i) rest[i](0, 3) = i;
  }
  FingerCurlJob job() {
    FingerCurlJob j;
    j.finger_curl = finger_curl;
    j.finger = finger;
    j.rest_offset_parent = rest;
    j.bend_axis = bend;
    j.spread_axis = side;
    j.spread_weight = weight;
    j.output = out;
    j.result = &result;
    return j;
  }
};

TEST(FingerCurlJob, validate__rejects_each_documented_failure) {
  Hand h;
  EXPECT_TRUE(h.job().validate()) << "the fixture job should validate";
  EXPECT_TRUE(FingerCurlJob{}.validate()) << "no controls is a valid, empty job";
  FingerCurlJob job = h.job();
  job.output = std::span<Mat4>(h.out).first(3);
  EXPECT_FALSE(job.validate()) << "an output smaller than the control count should be rejected";
  EXPECT_FALSE(job.run()) << "run() should refuse a job that does not validate";
}

TEST(FingerCurlJob, run__curls_each_finger_and_spreads_by_weight) {
  Hand h;
  FingerCurlJob job = h.job();
  ASSERT_TRUE(job.run());
  for (int i = 0; i < 2; ++i) EXPECT_EQ(h.out[i], h.rest[i]) << "finger 0 has no curl: its rest, exactly";
  EXPECT_EQ(h.result.problem, Problem::kNone);
  job.curl = 30;
  job.spread = 5;
  ASSERT_TRUE(job.run());
  EXPECT_LT((h.out[2] - finger_offset(h.rest[2], Vec3::UnitY(), math::to_radians(-5.0), Vec3::UnitZ(),
                                      math::to_radians(40.0)))
                .norm(),
            1e-15)
      << "finger 1 curls by curl + its own, spreads by its weight";
  EXPECT_LT((h.out[1] - finger_offset(h.rest[1], Vec3::UnitY(), 0.0, Vec3::UnitZ(), math::to_radians(30.0))).norm(),
            1e-15)
      << "a control of weight 0 does not spread";
  EXPECT_EQ(Vec3(h.out[3].topRightCorner<3, 1>()), Vec3(h.rest[3].topRightCorner<3, 1>()))
      << "a control turns about its origin";
}

TEST(FingerCurlJob, run__reports_the_first_unusable_input_and_leaves_that_part_out) {
  Hand h;
  h.bend[1] = Vec3::Zero();
  h.side[2] = Vec3(std::nan(""), 0, 0);
  h.finger.resize(3);
  FingerCurlJob job = h.job();
  job.curl = 30;
  job.spread = 5;
  ASSERT_TRUE(job.run()) << "bad data is not misuse: the job runs";
  EXPECT_EQ(h.result.problem, Problem::kBadBendAxis) << "the first problem is control 1's bend axis";
  EXPECT_EQ(h.result.control, 1u);
  EXPECT_EQ(h.out[1], h.rest[1]) << "no curl (and weight 0: no spread) for that control";
  EXPECT_LT((h.out[2] - finger_offset(h.rest[2], Vec3::UnitY(), 0.0, Vec3::UnitZ(), math::to_radians(40.0))).norm(),
            1e-15)
      << "a bad spread axis leaves the curl";
  EXPECT_LT((h.out[3] - finger_offset(h.rest[3], Vec3::UnitY(), 0.0, Vec3::UnitZ(), math::to_radians(30.0))).norm(),
            1e-15)
      << "a control without a finger index gets the shared curl only";
  h.finger.clear();
  job = h.job();
  job.curl = std::numeric_limits<double>::infinity();
  ASSERT_TRUE(job.run());
  EXPECT_EQ(h.result.problem, Problem::kMissingFinger) << "a missing finger index comes before the curl at control 0";
  EXPECT_EQ(h.result.control, 0u);
  for (const Mat4& m : h.out) EXPECT_TRUE(m.allFinite()) << "never NaN";
}

}  // namespace
}  // namespace rigel::ops::util
