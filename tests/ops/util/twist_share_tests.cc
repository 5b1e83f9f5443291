// TwistShareJob (twist_share.h): a test per documented validate() failure and
// the shares of a twist with swing on top.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "rigel/math/rotation.h"
#include "rigel/math/transform.h"
#include "rigel/ops/util/twist_share.h"

namespace rigel::ops::util {
namespace {

using math::Mat4;
using math::Quat;
using math::Vec3;

Quat about(const Vec3& axis, double degrees) { return Quat(Eigen::AngleAxisd(math::to_radians(degrees), axis.normalized())); }

TEST(TwistShareJob, validate__rejects_each_documented_failure) {
  std::vector<Quat> rotations(3);
  double twist = 0;
  auto valid = [&] {
    TwistShareJob job;
    job.rotations = rotations;
    job.twist = &twist;
    return job;
  };
  EXPECT_TRUE(valid().validate()) << "the fixture job should validate";
  {
    TwistShareJob job = valid();
    job.twist = nullptr;
    EXPECT_FALSE(job.validate()) << "a job without its twist output should be rejected";
  }
  for (int which = 0; which < 4; ++which) {
    TwistShareJob job = valid();
    Mat4& m = which < 2 ? job.start : job.end;
    if (which % 2 == 0) m(1, 2) = std::numeric_limits<double>::infinity();
    else m.topLeftCorner<3, 3>().col(0).setZero();
    EXPECT_FALSE(job.validate()) << "a start or end matrix that is not finite or singular should be rejected (" << which
                                 << ")";
  }
  for (const Quat& rest : {Quat(0, 0, 0, 0), Quat(std::nan(""), 0, 0, 0)}) {
    TwistShareJob job = valid();
    job.rest_relative = rest;
    EXPECT_FALSE(job.validate()) << "a zero or NaN rest_relative should be rejected";
  }
  for (const Vec3& axis : {Vec3(0, 2, 0), Vec3(0, 0, 0), Vec3(std::nan(""), 1, 0)}) {
    TwistShareJob job = valid();
    job.axis = axis;
    EXPECT_FALSE(job.validate()) << "an axis that is not unit length or not finite should be rejected";
  }
  {
    TwistShareJob job = valid();
    job.twist = nullptr;
    rotations.assign(3, Quat(0.5, 0.5, 0.5, 0.5));
    EXPECT_FALSE(job.run()) << "run() should refuse a job that does not validate";
    EXPECT_EQ(rotations[0].coeffs(), Quat(0.5, 0.5, 0.5, 0.5).coeffs()) << "and write nothing";
  }
}

TEST(TwistShareJob, run__shares_the_twist_and_ignores_swing) {
  const Quat rest = about(Vec3(0, 0, 1), 20);
  const Mat4 start = math::trs_matrix(Vec3(1, 0, 0), about(Vec3(1, 1, 0), 50), Vec3(2, 2, 2));
  const Quat turned = about(Vec3(1, 0, 0), 35) * about(Vec3(0, 1, 0), 80) * rest;
  std::vector<Quat> rotations(3);
  double twist = 0;
  TwistShareJob job;
  job.start = start;
  job.end = start * math::trs_matrix(Vec3(0, 3, 0), turned, Vec3::Ones());
  job.rest_relative = rest;
  job.axis = Vec3::UnitY();
  job.rotations = rotations;
  job.twist = &twist;
  ASSERT_TRUE(job.run());
  EXPECT_NEAR(math::to_degrees(twist), 80.0, 1e-9) << "80 degrees of twist under a swing about x";
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(rotations[i].angularDistance(about(Vec3(0, 1, 0), 20.0 * (i + 1))), 0.0, 1e-12)
        << "twist joint " << i << " takes (i + 1) / (count + 1) of it";
  job.rotations = {};
  EXPECT_TRUE(job.run()) << "no twist joints is a valid job";
}

}  // namespace
}  // namespace rigel::ops::util
