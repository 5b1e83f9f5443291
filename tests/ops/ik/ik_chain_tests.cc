#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "ik_test_util.h"
#include "rigel/math/transform.h"
#include "rigel/ops/ik/ik_chain.h"

namespace rigel::ops::ik {
namespace {

using testing::kPi;
using testing::vec_near;

Mat4 rot(double angle, const Vec3& axis) { return math::rotation_matrix(Quat(Eigen::AngleAxisd(angle, axis))); }

TEST(JointLimit, joint_limit_error__names_each_documented_failure) {
  EXPECT_EQ(joint_limit_error(JointLimit{}), nullptr) << "the default (no limit) is valid";

  JointLimit hinge;
  hinge.kind = LimitKind::kHinge;
  hinge.min_angle = -1.0;
  hinge.max_angle = 1.0;
  EXPECT_EQ(joint_limit_error(hinge), nullptr) << "a hinge about z from x is valid";

  JointLimit bad_kind;
  bad_kind.kind = static_cast<LimitKind>(7);
  EXPECT_NE(joint_limit_error(bad_kind), nullptr) << "a kind outside LimitKind should be rejected";

  JointLimit h = hinge;
  h.axis = Vec3(0, 0, 2);
  EXPECT_NE(joint_limit_error(h), nullptr) << "a hinge axis of length 2 should be rejected";
  h.axis = Vec3(0, 0, std::numeric_limits<double>::quiet_NaN());
  EXPECT_NE(joint_limit_error(h), nullptr) << "a NaN hinge axis should be rejected";

  h = hinge;
  h.reference = Vec3(0.5, 0, 0);
  EXPECT_NE(joint_limit_error(h), nullptr) << "a hinge reference of length 0.5 should be rejected";
  h.reference = Vec3(1, 0, 1).normalized();
  EXPECT_NE(joint_limit_error(h), nullptr) << "a hinge reference not perpendicular to the axis should be rejected";

  h = hinge;
  h.min_angle = 0.5;
  h.max_angle = 0.4;
  EXPECT_NE(joint_limit_error(h), nullptr) << "min_angle > max_angle should be rejected";
  h.min_angle = -4.0;
  h.max_angle = 0.0;
  EXPECT_NE(joint_limit_error(h), nullptr) << "min_angle below -pi should be rejected";
  h.min_angle = 0.0;
  h.max_angle = 4.0;
  EXPECT_NE(joint_limit_error(h), nullptr) << "max_angle above pi should be rejected";
  h.max_angle = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(joint_limit_error(h), nullptr) << "a NaN angle should be rejected";

  JointLimit cone;
  cone.kind = LimitKind::kCone;
  cone.half_angle = 0.5;
  EXPECT_EQ(joint_limit_error(cone), nullptr) << "a cone of half angle 0.5 about z is valid";
  JointLimit c = cone;
  c.axis = Vec3(1, 1, 0);
  EXPECT_NE(joint_limit_error(c), nullptr) << "a cone axis that is not unit should be rejected";
  c = cone;
  c.half_angle = -0.1;
  EXPECT_NE(joint_limit_error(c), nullptr) << "a negative half angle should be rejected";
  c.half_angle = 3.5;
  EXPECT_NE(joint_limit_error(c), nullptr) << "a half angle above pi should be rejected";
  c.half_angle = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(joint_limit_error(c), nullptr) << "a NaN half angle should be rejected";
}

TEST(JointLimit, constrain_direction__cone_by_hand) {
  JointLimit cone;
  cone.kind = LimitKind::kCone;
  cone.axis = Vec3::UnitX();
  cone.half_angle = kPi / 6;  // 30 degrees
  const Vec3 inside = Vec3(1, 0.1, 0).normalized();
  EXPECT_TRUE(vec_near(constrain_direction(cone, inside), inside, 0.0)) << "a direction inside the cone is kept";
  EXPECT_TRUE(vec_near(constrain_direction(cone, Vec3::UnitY()), Vec3(std::sqrt(3.0) / 2, 0.5, 0), 1e-15))
      << "y is 90 degrees off x: it goes to the cone's edge in the xy plane, (cos 30, sin 30, 0)";
  const Vec3 behind = constrain_direction(cone, -Vec3::UnitX());
  EXPECT_NEAR(behind.dot(Vec3::UnitX()), std::sqrt(3.0) / 2, 1e-15)
      << "straight behind the axis has no plane: any point of the edge will do";
  EXPECT_NEAR(behind.norm(), 1.0, 1e-15) << "the result is a unit vector";
}

TEST(JointLimit, constrain_direction__hinge_by_hand) {
  JointLimit hinge;
  hinge.kind = LimitKind::kHinge;
  hinge.axis = Vec3::UnitZ();
  hinge.reference = Vec3::UnitX();
  hinge.min_angle = 0.0;
  hinge.max_angle = kPi / 4;
  const Vec3 inside = Vec3(std::cos(0.3), std::sin(0.3), 0);
  EXPECT_TRUE(vec_near(constrain_direction(hinge, inside), inside, 1e-15)) << "30 degrees of a 0..45 range is kept";
  EXPECT_TRUE(vec_near(constrain_direction(hinge, Vec3(std::cos(0.3), std::sin(0.3), 1).normalized()), inside, 1e-15))
      << "a direction off the hinge plane is projected onto it";
  EXPECT_TRUE(vec_near(constrain_direction(hinge, Vec3(0, 1, 0)), Vec3(std::sqrt(0.5), std::sqrt(0.5), 0), 1e-15))
      << "90 degrees is clamped to the 45-degree end";
  EXPECT_TRUE(vec_near(constrain_direction(hinge, Vec3(0, -1, 0)), Vec3::UnitX(), 1e-15))
      << "-90 degrees is 90 from the 0 end and 135 from the 45 end: clamped to 0";
  EXPECT_TRUE(vec_near(constrain_direction(hinge, Vec3(-1, -0.1, 0).normalized()),
                       Vec3(std::sqrt(0.5), std::sqrt(0.5), 0), 1e-15))
      << "about -174 degrees is nearer to 45 going round through 180 (141 degrees) than to 0 (174)";
  EXPECT_TRUE(vec_near(constrain_direction(hinge, Vec3::UnitZ()), Vec3::UnitX(), 1e-15))
      << "along the axis counts as angle 0, which the range allows";
}

TEST(ChainCorrectionJob, validate__rejects_each_documented_failure) {
  std::vector<Mat4> local(3, Mat4::Identity());
  std::vector<Quat> corrections(3, Quat::Identity());
  std::vector<double> scale(3, 1.0);
  std::vector<Mat4> local_out(3), world_out(3);
  auto valid = [&] {
    ChainCorrectionJob job;
    job.local = local;
    job.corrections = corrections;
    job.translate_scale = scale;
    job.local_out = local_out;
    job.world_out = world_out;
    return job;
  };
  {
    ChainCorrectionJob job = valid();
    EXPECT_TRUE(job.validate()) << "a well-formed job should validate";
    EXPECT_TRUE(job.run()) << "and run";
    job.translate_scale = {};
    job.world_out = {};
    EXPECT_TRUE(job.validate()) << "translate_scale and world_out are optional";
    job.local_out = local;
    EXPECT_TRUE(job.validate()) << "local_out may be local itself (in place)";
  }
  {
    ChainCorrectionJob job;
    EXPECT_FALSE(job.validate()) << "an empty chain should be rejected";
    EXPECT_FALSE(job.run()) << "run() should refuse a job that does not validate";
  }
  {
    ChainCorrectionJob job = valid();
    job.corrections = std::span<const Quat>(corrections).first(2);
    EXPECT_FALSE(job.validate()) << "fewer corrections than joints should be rejected";
  }
  {
    ChainCorrectionJob job = valid();
    job.local_out = std::span<Mat4>(local_out).first(2);
    EXPECT_FALSE(job.validate()) << "a local_out shorter than local should be rejected";
  }
  {
    ChainCorrectionJob job = valid();
    job.translate_scale = std::span<const double>(scale).first(2);
    EXPECT_FALSE(job.validate()) << "translate_scale of the wrong size should be rejected";
  }
  {
    ChainCorrectionJob job = valid();
    job.world_out = std::span<Mat4>(world_out).first(1);
    EXPECT_FALSE(job.validate()) << "world_out of the wrong size should be rejected";
  }
  {
    ChainCorrectionJob job = valid();
    job.world_out = local_out;
    EXPECT_FALSE(job.validate()) << "world_out overlapping local_out should be rejected";
    job.local_out = local;
    job.world_out = local;
    EXPECT_FALSE(job.validate()) << "world_out overlapping local should be rejected";
  }
  {
    std::vector<Mat4> both(4, Mat4::Identity());
    ChainCorrectionJob job = valid();
    job.local = std::span<const Mat4>(both).first(3);
    job.local_out = std::span<Mat4>(both).last(3);
    job.world_out = {};
    EXPECT_FALSE(job.validate()) << "local_out partly overlapping local should be rejected";
  }
  {
    ChainCorrectionJob job = valid();
    job.parent_world(3, 1) = 1.0;
    EXPECT_FALSE(job.validate()) << "a parent_world that is not affine should be rejected";
  }
}

TEST(ChainCorrectionJob, run__applies_the_correction_between_rotation_and_scale) {
  // local = T * Rz(90) * S(2, 3, 4); correction Rx(90):
  // local' = T * Rz(90) * Rx(90) * S, the scale untouched.
  const Mat4 t = math::translation_matrix(Vec3(1, 2, 3));
  const Mat4 s = math::scale_matrix(Vec3(2, 3, 4));
  std::vector<Mat4> local = {t * rot(kPi / 2, Vec3::UnitZ()) * s};
  std::vector<Quat> corrections = {Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitX()))};
  std::vector<Mat4> out(1), world(1);
  ChainCorrectionJob job;
  job.local = local;
  job.corrections = corrections;
  job.local_out = out;
  job.world_out = world;
  job.parent_world = math::translation_matrix(Vec3(10, 0, 0));
  ASSERT_TRUE(job.run());
  const Mat4 expected = t * rot(kPi / 2, Vec3::UnitZ()) * rot(kPi / 2, Vec3::UnitX()) * s;
  EXPECT_LE((out[0] - expected).cwiseAbs().maxCoeff(), 1e-15) << "T * (Q * C) * U";
  EXPECT_LE((world[0] - job.parent_world * expected).cwiseAbs().maxCoeff(), 1e-15) << "world = parent * local";
}

TEST(ChainCorrectionJob, run__chain_of_identity_corrections_reproduces_world) {
  testing::Random random(5);
  const std::vector<Vec3> points = testing::random_chain_points(random, 6);
  const std::vector<Mat4> world = testing::chain_from_points(points, Vec3::UnitZ(), 1.7);
  const Mat4 parent = math::trs_matrix(Vec3(1, -2, 3), random.quat(), Vec3::Constant(0.5));
  std::vector<Quat> identity(world.size(), Quat::Identity());
  const std::vector<Mat4> back = testing::apply_corrections(world, identity, {}, parent);
  // apply_corrections reads `world` as world matrices under `parent`.
  for (std::size_t i = 0; i < world.size(); ++i) {
    EXPECT_LE((back[i] - world[i]).cwiseAbs().maxCoeff(), 1e-12) << "joint " << i << " should be unchanged";
  }
}

TEST(ChainCorrectionJob, run__translate_scale_lengthens_bones) {
  const std::vector<Mat4> world = testing::chain_from_points({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(3, 0, 0)});
  std::vector<Quat> identity(3, Quat::Identity());
  const std::vector<Mat4> out = testing::apply_corrections(world, identity, {1.0, 1.5, 2.0});
  EXPECT_TRUE(vec_near(testing::position_of(out[1]), Vec3(1.5, 0, 0), 1e-15)) << "bone 0 of length 1 becomes 1.5";
  EXPECT_TRUE(vec_near(testing::position_of(out[2]), Vec3(5.5, 0, 0), 1e-15)) << "bone 1 of length 2 becomes 4";
}

TEST(ChainWorldToLocalJob, validate__rejects_each_documented_failure) {
  std::vector<Mat4> world(3, Mat4::Identity());
  std::vector<Mat4> local(3);
  {
    ChainWorldToLocalJob job;
    job.world = world;
    job.local = local;
    EXPECT_TRUE(job.validate()) << "a well-formed job should validate";
  }
  {
    ChainWorldToLocalJob job;
    EXPECT_FALSE(job.validate()) << "an empty chain should be rejected";
    EXPECT_FALSE(job.run()) << "run() should refuse it";
  }
  {
    ChainWorldToLocalJob job;
    job.world = world;
    job.local = std::span<Mat4>(local).first(2);
    EXPECT_FALSE(job.validate()) << "local shorter than world should be rejected";
  }
  {
    ChainWorldToLocalJob job;
    job.world = world;
    job.local = world;
    EXPECT_FALSE(job.validate()) << "local overlapping world should be rejected";
  }
  {
    ChainWorldToLocalJob job;
    job.world = world;
    job.local = local;
    job.parent_world(3, 0) = 1.0;
    EXPECT_FALSE(job.validate()) << "a parent_world that is not affine should be rejected";
    job.parent_world = math::scale_matrix(Vec3(1, 0, 1));
    EXPECT_FALSE(job.validate()) << "a parent_world that cannot be inverted should be rejected";
  }
  {
    std::vector<Mat4> bad = world;
    bad[1](3, 3) = 2.0;
    ChainWorldToLocalJob job;
    job.world = bad;
    job.local = local;
    EXPECT_FALSE(job.validate()) << "a world matrix that is not affine should be rejected";
    bad[1] = math::scale_matrix(Vec3(0, 0, 0));
    EXPECT_FALSE(job.validate()) << "a world matrix that cannot be inverted should be rejected";
  }
}

TEST(ChainWorldToLocalJob, run__round_trips_with_the_chain_product) {
  testing::Random random(6);
  const std::vector<Mat4> world = testing::chain_from_points(testing::random_chain_points(random, 5));
  const Mat4 parent = math::trs_matrix(Vec3(0, 1, 0), random.quat(), Vec3(1, 2, 0.5));
  std::vector<Mat4> local(world.size());
  ChainWorldToLocalJob job;
  job.world = world;
  job.parent_world = parent;
  job.local = local;
  ASSERT_TRUE(job.run());
  Mat4 product = parent;
  for (std::size_t i = 0; i < world.size(); ++i) {
    product = product * local[i];
    EXPECT_LE((product - world[i]).cwiseAbs().maxCoeff(), 1e-12) << "parent * local[0] * ... * local[i] = world[i]";
    EXPECT_EQ(local[i].row(3), Eigen::RowVector4d(0, 0, 0, 1)) << "local matrices are affine";
  }
}

}  // namespace
}  // namespace rigel::ops::ik
