#include <gtest/gtest.h>

#include <limits>
#include <vector>

#include "deform_test_util.h"
#include "rigel/math/dual_quat.h"
#include "rigel/math/transform.h"
#include "rigel/ops/deform/skinning.h"

namespace rigel::ops {
namespace {

using testing::Mat3;
using testing::Mat4;
using testing::Quat;
using testing::Random;
using testing::Vec3;

::testing::AssertionResult matrices_near(const Mat4& a, const Mat4& b, double tolerance) {
  const double diff = (a - b).cwiseAbs().maxCoeff();
  if (diff <= tolerance) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "difference " << diff << " > " << tolerance << ":\n" << a << "\nvs\n" << b;
}

TEST(SkinningMatricesJob, validate__rejects_each_documented_failure) {
  std::vector<Mat4> world(3, Mat4::Identity());
  std::vector<Mat4> bind(3, Mat4::Identity());
  std::vector<Mat4> out(3);
  std::vector<SkinMatrix> linear(3);
  std::vector<DualQuatSkinMatrix> dual(3);
  auto job = [&] {
    SkinningMatricesJob j;
    j.joint_world = world;
    j.inverse_bind = bind;
    j.matrices = out;
    j.linear = linear;
    j.dual_quat = dual;
    return j;
  };
  EXPECT_TRUE(job().validate()) << "a well-formed job should validate";
  EXPECT_TRUE(job().run()) << "and run";
  EXPECT_TRUE(SkinningMatricesJob{}.run()) << "an empty job is valid and does nothing";
  {
    SkinningMatricesJob j = job();
    j.matrices = {};
    j.linear = {};
    j.dual_quat = {};
    EXPECT_TRUE(j.run()) << "a job without outputs is valid";
  }
  {
    SkinningMatricesJob j = job();
    j.inverse_bind = std::span<const Mat4>(bind).first(2);
    EXPECT_FALSE(j.validate()) << "inverse_bind shorter than joint_world should be rejected";
    EXPECT_FALSE(j.run()) << "run() should refuse a job that does not validate";
  }
  {
    SkinningMatricesJob j = job();
    j.matrices = std::span<Mat4>(out).first(2);
    EXPECT_FALSE(j.validate()) << "a matrices output of the wrong size should be rejected";
  }
  {
    SkinningMatricesJob j = job();
    j.linear = std::span<SkinMatrix>(linear).first(1);
    EXPECT_FALSE(j.validate()) << "a linear output of the wrong size should be rejected";
  }
  {
    SkinningMatricesJob j = job();
    j.dual_quat = std::span<DualQuatSkinMatrix>(dual).first(2);
    EXPECT_FALSE(j.validate()) << "a dual_quat output of the wrong size should be rejected";
  }
  {
    SkinningMatricesJob j = job();
    j.world_to_mesh(3, 0) = 0.5;
    EXPECT_FALSE(j.validate()) << "a projective world_to_mesh should be rejected";
  }
  {
    world[1](3, 2) = 1.0;
    EXPECT_FALSE(job().validate()) << "a joint world matrix that is not affine should be rejected";
    world[1] = Mat4::Identity();
  }
  {
    bind[2](0, 3) = std::numeric_limits<double>::quiet_NaN();
    EXPECT_FALSE(job().validate()) << "an inverse bind matrix holding NaN should be rejected";
    bind[2] = Mat4::Identity();
  }
  {
    world[0](1, 1) = std::numeric_limits<double>::infinity();
    EXPECT_FALSE(job().validate()) << "a joint world matrix holding infinity should be rejected";
    world[0] = Mat4::Identity();
  }
  EXPECT_TRUE(job().validate()) << "the job is valid again once every matrix is restored";
}

TEST(SkinningMatricesJob, run__multiplies_world_to_mesh_joint_world_and_inverse_bind) {
  Random random(3);
  std::vector<Mat4> world, bind;
  for (int j = 0; j < 5; ++j) {
    world.push_back(random.affine());
    bind.push_back(random.affine());
  }
  const Mat4 mesh_world = random.rigid();
  std::vector<Mat4> out(5);
  std::vector<SkinMatrix> linear(5);
  SkinningMatricesJob job;
  job.joint_world = world;
  job.inverse_bind = bind;
  job.world_to_mesh = math::affine_inverse(mesh_world);
  job.matrices = out;
  job.linear = linear;
  ASSERT_TRUE(job.run());
  for (int j = 0; j < 5; ++j) {
    const Mat4 expected = math::affine_inverse(mesh_world) * world[j] * bind[j];
    EXPECT_TRUE(matrices_near(out[j], expected, 1e-12)) << "joint " << j;
    EXPECT_TRUE(matrices_near(linear[j].to_mat4(), expected, 1e-6 * expected.cwiseAbs().maxCoeff()))
        << "joint " << j << ": the float matrix is the product rounded once";
    EXPECT_EQ(linear[j].m[3], 0.0f) << "the padding row is 0";
  }
}

TEST(SkinningMatricesJob, run__gives_identity_in_the_bind_pose) {
  // glTF: the inverse bind matrices are the inverses of the joints' world
  // matrices at bind time, so the bind pose skins to itself.
  Random random(4);
  std::vector<Mat4> world, bind;
  for (int j = 0; j < 4; ++j) {
    world.push_back(random.affine());
    bind.push_back(math::affine_inverse(world.back()));
  }
  std::vector<Mat4> out(4);
  SkinningMatricesJob job;
  job.joint_world = world;
  job.inverse_bind = bind;
  job.matrices = out;
  ASSERT_TRUE(job.run());
  for (int j = 0; j < 4; ++j) EXPECT_TRUE(matrices_near(out[j], Mat4::Identity(), 1e-12)) << "joint " << j;
}

TEST(SkinMatrix, from__and_to_mat4_round_trip_a_float_matrix) {
  Mat4 m = Mat4::Identity();
  m.topRows<3>() << 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12;
  const SkinMatrix s = SkinMatrix::from(m);
  const float expected[16] = {1, 5, 9, 0, 2, 6, 10, 0, 3, 7, 11, 0, 4, 8, 12, 0};
  for (int n = 0; n < 16; ++n) EXPECT_EQ(s.m[n], expected[n]) << "entry " << n << ": column-major, rows padded with 0";
  EXPECT_TRUE(matrices_near(s.to_mat4(), m, 0.0)) << "small integers round-trip exactly";
  EXPECT_EQ(alignof(SkinMatrix), 64u) << "one matrix per cache line";
}

TEST(DualQuatSkinMatrix, from__splits_a_matrix_into_rigid_and_stretch) {
  Random random(6);
  for (int n = 0; n < 50; ++n) {
    const Mat4 m = random.affine(0.3, 3.0);
    const DualQuatSkinMatrix dq = DualQuatSkinMatrix::from(m);
    math::DualQuat rigid;
    rigid.real = Quat(dq.real[3], dq.real[0], dq.real[1], dq.real[2]);
    rigid.dual = Quat(dq.dual[3], dq.dual[0], dq.dual[1], dq.dual[2]);
    Mat3 stretch;
    for (int c = 0; c < 3; ++c) {
      for (int r = 0; r < 3; ++r) stretch(r, c) = dq.stretch[3 * c + r];
    }
    EXPECT_TRUE(matrices_near(rigid.to_matrix() * testing::to_mat4(stretch), m, 1e-12))
        << "rigid * stretch should give the matrix back";
    EXPECT_NEAR(rigid.real.norm(), 1.0, 1e-14) << "the dual quaternion is unit";
    EXPECT_TRUE(dq.has_stretch) << "a scaled matrix has a stretch";
  }
  const DualQuatSkinMatrix rigid = DualQuatSkinMatrix::from(random.rigid());
  EXPECT_FALSE(rigid.has_stretch) << "a rigid matrix has none";
}

TEST(DualQuatSkinMatrix, from__keeps_a_mirror_in_the_stretch) {
  Mat4 mirror = Mat4::Identity();
  mirror(0, 0) = -1.0;
  const DualQuatSkinMatrix dq = DualQuatSkinMatrix::from(mirror);
  EXPECT_TRUE(dq.has_stretch) << "a reflection is not a rotation";
  Mat3 stretch;
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) stretch(r, c) = dq.stretch[3 * c + r];
  }
  EXPECT_LT(stretch.determinant(), 0.0) << "the stretch carries the negative determinant";
}

}  // namespace
}  // namespace rigel::ops
