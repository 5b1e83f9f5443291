// FkIkBlendJob (fk_ik_blend.h): a test per documented validate() failure,
// the two ends of the blend, and what it reports for unusable input.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "rigel/math/rotation.h"
#include "rigel/math/transform.h"
#include "rigel/ops/util/fk_ik_blend.h"

namespace rigel::ops::util {
namespace {

using math::Mat4;
using math::Quat;
using math::Vec3;

Mat4 trs(const Vec3& t, const Quat& r) { return math::trs_matrix(t, r, Vec3::Ones()); }
Quat about_z(double degrees) { return Quat(Eigen::AngleAxisd(math::to_radians(degrees), Vec3::UnitZ())); }

// A two-joint chain (bone of length 2 along x) and buffers for its outputs.
struct Chain {
  std::vector<Mat4> offsets{Mat4::Identity(), trs(Vec3(2, 0, 0), Quat::Identity())};
  std::vector<Mat4> fk{trs(Vec3::Zero(), about_z(40)), trs(Vec3::Zero(), about_z(40)) * offsets[1]};
  std::vector<Mat4> ik{trs(Vec3::Zero(), about_z(-40)), trs(Vec3::Zero(), about_z(-40)) * offsets[1]};
  std::vector<Vec3> translations = std::vector<Vec3>(2), scales = std::vector<Vec3>(2), shears = std::vector<Vec3>(2);
  std::vector<Quat> rotations = std::vector<Quat>(2);
  std::vector<Mat4> worlds = std::vector<Mat4>(2);
  FkIkBlendResult result;

  FkIkBlendJob job() {
    FkIkBlendJob j;
    j.fk_world = fk;
    j.ik_world = ik;
    j.rest_offset_parent = offsets;
    j.translations = translations;
    j.rotations = rotations;
    j.scales = scales;
    j.shears = shears;
    j.worlds = worlds;
    j.result = &result;
    return j;
  }
};

TEST(FkIkBlendJob, validate__rejects_each_documented_failure) {
  Chain c;
  EXPECT_TRUE(c.job().validate()) << "the fixture job should validate";
  EXPECT_TRUE(FkIkBlendJob{}.validate()) << "a chain of no joints is a valid, empty blend";
  for (double w : {-0.1, 1.1, std::numeric_limits<double>::quiet_NaN()}) {
    FkIkBlendJob job = c.job();
    job.fk_ik = w;
    EXPECT_FALSE(job.validate()) << "fk_ik " << w << " is outside [0, 1] and should be rejected";
    EXPECT_FALSE(job.run()) << "run() should refuse a job that does not validate";
  }
  for (int which = 0; which < 5; ++which) {
    FkIkBlendJob job = c.job();
    if (which == 0) job.translations = std::span<Vec3>(c.translations).first(1);
    if (which == 1) job.rotations = std::span<Quat>(c.rotations).first(1);
    if (which == 2) job.scales = std::span<Vec3>(c.scales).first(1);
    if (which == 3) job.shears = std::span<Vec3>(c.shears).first(1);
    if (which == 4) job.worlds = std::span<Mat4>(c.worlds).first(1);
    EXPECT_FALSE(job.validate()) << "output " << which << " smaller than the chain should be rejected";
  }
}

TEST(FkIkBlendJob, run__gives_each_side_at_its_end_and_keeps_bone_lengths_between) {
  Chain c;
  for (double w : {0.0, 1.0}) {
    FkIkBlendJob job = c.job();
    job.fk_ik = w;
    ASSERT_TRUE(job.run());
    for (int i = 0; i < 2; ++i)
      EXPECT_LT((c.worlds[i] - (w == 0 ? c.fk : c.ik)[i]).norm(), 1e-12) << "fk_ik " << w << " joint " << i;
    EXPECT_FALSE(c.result.unusable_parent);
    EXPECT_EQ(c.result.unusable_joint, -1);
  }
  FkIkBlendJob job = c.job();
  job.fk_ik = 0.5;
  ASSERT_TRUE(job.run());
  EXPECT_NEAR(math::decompose(c.worlds[0]).rotation.angularDistance(Quat::Identity()), 0.0, 1e-12)
      << "halfway between +40 and -40 degrees is 0";
  EXPECT_NEAR((c.worlds[1].topRightCorner<3, 1>() - c.worlds[0].topRightCorner<3, 1>()).norm(), 2.0, 1e-12)
      << "local blending keeps the bone's length";
}

TEST(FkIkBlendJob, run__takes_the_ik_end_orientation_from_the_control) {
  Chain c;
  FkIkBlendJob job = c.job();
  job.fk_ik = 1.0;
  job.use_ik_end = true;
  job.ik_end = trs(Vec3(5, 5, 5), Quat(Eigen::AngleAxisd(math::to_radians(90), Vec3::UnitX())));
  ASSERT_TRUE(job.run());
  EXPECT_LT((c.worlds[1] - ik_end_world(c.ik[1], job.ik_end)).norm(), 1e-12)
      << "the last joint: translation from the solver, orientation from the control";
}

TEST(FkIkBlendJob, run__reports_unusable_input_and_never_writes_nan) {
  Chain c;
  {
    FkIkBlendJob job = c.job();
    job.parent(0, 0) = 0;
    job.parent(1, 1) = 0;
    ASSERT_TRUE(job.run()) << "bad data is not misuse: the job runs";
    EXPECT_TRUE(c.result.unusable_parent) << "a singular parent should be reported";
    for (const Quat& q : c.rotations) EXPECT_EQ(q.coeffs(), Quat::Identity().coeffs());
  }
  {
    c.fk[1](0, 0) = std::numeric_limits<double>::quiet_NaN();
    FkIkBlendJob job = c.job();
    ASSERT_TRUE(job.run());
    EXPECT_FALSE(c.result.unusable_parent);
    EXPECT_EQ(c.result.unusable_joint, 1) << "the joint with a NaN FK matrix should be named";
    EXPECT_TRUE(c.translations[1].allFinite() && c.rotations[1].coeffs().allFinite()) << "no NaN channels";
    EXPECT_EQ(c.translations[1], Vec3::Zero()) << "the unusable joint takes the identity local matrix";
  }
}

}  // namespace
}  // namespace rigel::ops::util
