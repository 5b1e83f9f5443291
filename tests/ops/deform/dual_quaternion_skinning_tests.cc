#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "deform_test_util.h"
#include "rigel/math/dual_quat.h"
#include "rigel/math/transform.h"
#include "rigel/ops/deform/skinning.h"
#include "skinning_kernels.h"  // src/ops/deform: the variants behind run()

namespace rigel::ops {
namespace {

using testing::Mat3;
using testing::Mat4;
using testing::points_identical;
using testing::points_near;
using testing::Quat;
using testing::Random;
using testing::Vec3;

struct Buffers {
  std::vector<DualQuatSkinMatrix> matrices;
  std::vector<Vec3f> in, out, in_normals, out_normals;

  DualQuaternionSkinningJob job(const Skin& skin, bool normals = false) {
    DualQuaternionSkinningJob j;
    j.skin = &skin;
    j.matrices = matrices;
    j.in_positions = in;
    j.out_positions = out;
    if (normals) {
      j.in_normals = in_normals;
      j.out_normals = out_normals;
    }
    return j;
  }
};

Buffers random_buffers(Random& random, std::size_t vertices, std::size_t joints, bool rigid) {
  Buffers b;
  std::vector<Mat4> m;
  for (std::size_t j = 0; j < joints; ++j) m.push_back(rigid ? random.rigid() : random.affine());
  b.matrices = testing::dual_quat_matrices(m);
  b.in = testing::random_points(random, vertices);
  b.out.assign(vertices, Vec3f::Zero());
  b.in_normals = testing::random_normals(random, vertices);
  b.out_normals.assign(vertices, Vec3f::Zero());
  return b;
}

TEST(DualQuaternionSkinningJob, validate__rejects_each_documented_failure) {
  const Skin skin = testing::build_or_die(std::vector<std::vector<SkinInfluence>>{{{0, 1.0}}, {{1, 1.0}}}, 2);
  Buffers b;
  b.matrices.resize(2);
  b.in.assign(2, Vec3f::Ones());
  b.out.assign(2, Vec3f::Zero());
  b.in_normals.assign(2, Vec3f::UnitZ());
  b.out_normals.assign(2, Vec3f::Zero());
  EXPECT_TRUE(b.job(skin, true).validate()) << "a well-formed job should validate";
  EXPECT_TRUE(b.job(skin, true).run()) << "and run";
  {
    DualQuaternionSkinningJob job = b.job(skin);
    job.skin = nullptr;
    EXPECT_FALSE(job.validate()) << "a job without a skin should be rejected";
    EXPECT_FALSE(job.run()) << "run() should refuse a job that does not validate";
    EXPECT_FALSE(job.run_parallel());
  }
  {
    DualQuaternionSkinningJob job = b.job(skin);
    job.matrices = std::span<const DualQuatSkinMatrix>(b.matrices).first(1);
    EXPECT_FALSE(job.validate()) << "fewer matrices than the skin's joints should be rejected";
  }
  {
    DualQuaternionSkinningJob job = b.job(skin);
    job.in_positions = std::span<const Vec3f>(b.in).first(1);
    EXPECT_FALSE(job.validate()) << "in_positions of the wrong size should be rejected";
  }
  {
    DualQuaternionSkinningJob job = b.job(skin);
    job.out_positions = std::span<Vec3f>(b.out).first(1);
    EXPECT_FALSE(job.validate()) << "out_positions of the wrong size should be rejected";
  }
  {
    DualQuaternionSkinningJob job = b.job(skin, true);
    job.in_normals = std::span<const Vec3f>(b.in_normals).first(1);
    job.out_normals = std::span<Vec3f>(b.out_normals).first(1);
    EXPECT_FALSE(job.validate()) << "normals that are neither empty nor one per vertex should be rejected";
  }
  {
    DualQuaternionSkinningJob job = b.job(skin, true);
    job.out_normals = std::span<Vec3f>(b.out_normals).first(1);
    EXPECT_FALSE(job.validate()) << "out_normals of another size than in_normals should be rejected";
  }
  {
    DualQuaternionSkinningJob job = b.job(skin);
    job.out_positions = b.in;
    EXPECT_FALSE(job.validate()) << "out_positions over in_positions should be rejected";
  }
  {
    DualQuaternionSkinningJob job = b.job(skin, true);
    job.out_normals = b.in_normals;
    EXPECT_FALSE(job.validate()) << "out_normals over in_normals should be rejected";
  }
  {
    DualQuaternionSkinningJob job = b.job(skin);
    EXPECT_FALSE(job.run(1, 0)) << "a reversed range should be rejected";
    EXPECT_FALSE(job.run(0, 3)) << "a range past the end should be rejected";
  }
}

TEST(DualQuaternionSkinningJob, run__identity_leaves_points_unchanged) {
  Random random(21);
  const auto lists = random.influences(100, 6, 5);
  const Skin skin = testing::build_or_die(lists, 6);
  Buffers b = random_buffers(random, 100, 6, true);
  b.matrices.assign(6, DualQuatSkinMatrix{});
  ASSERT_TRUE(b.job(skin, true).run());
  EXPECT_TRUE(points_near(b.out, b.in, 1e-6));
  EXPECT_TRUE(points_near(b.out_normals, b.in_normals, 1e-6));
}

TEST(DualQuaternionSkinningJob, run__a_single_influence_is_the_matrix_transform) {
  Random random(22);
  for (bool rigid : {true, false}) {
    std::vector<Mat4> m;
    for (int j = 0; j < 4; ++j) m.push_back(rigid ? random.rigid() : random.affine());
    std::vector<std::vector<SkinInfluence>> lists;
    for (int v = 0; v < 40; ++v) lists.push_back({{v % 4, 1.0}});
    const Skin skin = testing::build_or_die(lists, 4);
    Buffers b = random_buffers(random, 40, 4, rigid);
    b.matrices = testing::dual_quat_matrices(m);
    std::vector<Vec3f> expected;
    for (int v = 0; v < 40; ++v) {
      const Mat4& mv = m[static_cast<std::size_t>(v % 4)];
      expected.push_back((mv.topLeftCorner<3, 3>() * b.in[v].cast<double>() + mv.topRightCorner<3, 1>()).cast<float>());
    }
    ASSERT_TRUE(b.job(skin).run());
    EXPECT_TRUE(points_near(b.out, expected, 1e-5)) << (rigid ? "rigid" : "scaled and sheared: M = rigid * stretch");
  }
}

// Joint 1 twists 180 degrees about x; half weights. The blended rotation is
// 90 degrees about x, so (x, 0, 1) goes to (x, -1, 0): the radius stays 1,
// where linear blending collapses it to 0 (linear_blend_skinning_tests.cc).
TEST(DualQuaternionSkinningJob, run__two_half_weights_keep_the_radius_of_a_180_degree_twist) {
  const Skin skin =
      testing::build_or_die(std::vector<std::vector<SkinInfluence>>{{{0, 0.5}, {1, 0.5}}, {{0, 0.5}, {1, 0.5}}}, 2);
  Buffers b;
  b.matrices =
      testing::dual_quat_matrices(std::vector<Mat4>{Mat4::Identity(), testing::to_mat4(testing::rot_x(math::kPi))});
  b.in = {Vec3f(0.5f, 0.0f, 1.0f), Vec3f(2.0f, 1.0f, 0.0f)};
  b.out.assign(2, Vec3f::Zero());
  ASSERT_TRUE(b.job(skin).run());
  EXPECT_TRUE(points_near(b.out, std::vector<Vec3f>{{0.5f, -1.0f, 0.0f}, {2.0f, 0.0f, 1.0f}}, 1e-6))
      << "a 90 degree rotation of each point about x";
  for (const Vec3f& p : b.out) EXPECT_NEAR(std::hypot(p.y(), p.z()), 1.0f, 1e-6f) << "the radius is kept";
}

TEST(DualQuaternionSkinningJob, run__matches_math_blend_for_rigid_joints) {
  Random random(23);
  const auto lists = random.influences(300, 10, 6);
  const Skin skin = testing::build_or_die(lists, 10);
  std::vector<Mat4> m;
  for (int j = 0; j < 10; ++j) m.push_back(random.rigid());
  Buffers b = random_buffers(random, 300, 10, true);
  b.matrices = testing::dual_quat_matrices(m);
  ASSERT_TRUE(b.job(skin).run());
  std::vector<math::DualQuat> dqs;
  for (const Mat4& mj : m) dqs.push_back(math::DualQuat::from_matrix(mj));
  std::vector<Vec3f> expected;
  for (std::size_t v = 0; v < 300; ++v) {
    std::vector<math::DualQuat> picked;
    std::vector<double> weights;
    for (std::uint32_t k = skin.offsets()[v]; k < skin.offsets()[v + 1]; ++k) {
      picked.push_back(dqs[skin.joints()[k]]);
      weights.push_back(skin.weights()[k]);
    }
    const math::DualQuat blended = math::blend(picked.data(), weights.data(), static_cast<int>(picked.size()));
    expected.push_back(blended.transform_point(b.in[v].cast<double>()).cast<float>());
  }
  EXPECT_TRUE(points_near(b.out, expected, 1e-5)) << "the kernel is math::blend + transform_point, inlined";
}

TEST(DualQuaternionSkinningJob, run__handles_antipodal_quaternions) {
  // q and -q are the same rotation: negating a joint's dual quaternion must
  // not change the result (without the hemisphere test they would cancel).
  Random random(24);
  const auto lists = random.influences(200, 5, 4);
  const Skin skin = testing::build_or_die(lists, 5);
  Buffers b = random_buffers(random, 200, 5, true);
  ASSERT_TRUE(b.job(skin).run());
  const std::vector<Vec3f> before = b.out;
  for (int n = 0; n < 4; ++n) {
    b.matrices[2].real[n] = -b.matrices[2].real[n];
    b.matrices[2].dual[n] = -b.matrices[2].dual[n];
  }
  ASSERT_TRUE(b.job(skin).run());
  EXPECT_TRUE(points_near(b.out, before, 1e-5));
}

TEST(DualQuaternionSkinningJob, run__blends_stretch_linearly) {
  // Two joints with the same uniform scale 2 and different rotations: the
  // stretch phase scales the bind point by 2 whatever the weights.
  const Skin skin = testing::build_or_die(std::vector<std::vector<SkinInfluence>>{{{0, 0.25}, {1, 0.75}}}, 2);
  Buffers b;
  const Mat3 scale = Mat3::Identity() * 2.0;
  b.matrices = testing::dual_quat_matrices(
      std::vector<Mat4>{testing::to_mat4(scale), testing::to_mat4(testing::rot_x(math::kPi / 2) * scale)});
  ASSERT_TRUE(b.matrices[0].has_stretch);
  b.in = {Vec3f(0.0f, 0.0f, 1.0f)};
  b.out = {Vec3f::Zero()};
  ASSERT_TRUE(b.job(skin).run());
  // Blended rotation: 0.75 of the way to 90 degrees by quaternion blending,
  // applied to (0, 0, 2): radius 2 about x.
  EXPECT_NEAR(std::hypot(b.out[0].y(), b.out[0].z()), 2.0f, 1e-5f) << "scaled by 2, then rotated rigidly";
  EXPECT_NEAR(b.out[0].x(), 0.0f, 1e-6f);
}

TEST(DualQuaternionSkinningJob, run__normals_rotate_with_the_blend) {
  const Skin skin = testing::build_or_die(std::vector<std::vector<SkinInfluence>>{{{0, 1.0}}, {{1, 1.0}}}, 2);
  Buffers b;
  const Mat3 rotation = Eigen::AngleAxisd(1.1, Vec3(0, 1, 1).normalized()).toRotationMatrix();
  const Mat3 squash = Vec3(4.0, 1.0, 0.5).asDiagonal();
  b.matrices = testing::dual_quat_matrices(
      std::vector<Mat4>{testing::to_mat4(rotation, Vec3(5, 5, 5)), testing::to_mat4(rotation * squash)});
  const Vec3 n = Vec3(1, 1, 1).normalized();
  b.in.assign(2, Vec3f::Zero());
  b.out.assign(2, Vec3f::Zero());
  b.in_normals.assign(2, n.cast<float>());
  b.out_normals.assign(2, Vec3f::Zero());
  ASSERT_TRUE(b.job(skin, true).run());
  const std::vector<Vec3f> expected = {(rotation * n).cast<float>(),
                                       (rotation * (squash.inverse().transpose() * n).normalized()).cast<float>()};
  EXPECT_TRUE(points_near(b.out_normals, expected, 1e-6)) << "rotated; squashed by the inverse transpose, then rotated";
}

TEST(DualQuaternionSkinningJob, run__every_variant_tracks_the_portable_one) {
  struct Variant {
    const char* name;
    detail::DqsKernel kernel;
  };
  std::vector<Variant> variants = {{"portable", detail::dqs_portable}};
#if RIGEL_DEFORM_X86_KERNELS
  if (detail::avx2_fma_supported()) variants.push_back({"avx2_fma", detail::dqs_avx2_fma});
#endif
  Random random(26);
  const auto lists = random.influences(301, 12, 6);
  const Skin skin = testing::build_or_die(lists, 12);
  for (bool rigid : {true, false}) {
    Buffers b = random_buffers(random, 301, 12, rigid);
    variants[0].kernel(b.job(skin, true), 0, 301);
    const std::vector<Vec3f> portable = b.out;
    const std::vector<Vec3f> portable_normals = b.out_normals;
    for (const Variant& variant : variants) {
      variant.kernel(b.job(skin, true), 0, 301);
      EXPECT_TRUE(points_near(b.out, portable, 1e-5)) << variant.name << (rigid ? ", rigid" : ", stretched");
      EXPECT_TRUE(points_near(b.out_normals, portable_normals, 1e-5)) << variant.name;
      const std::vector<Vec3f> whole = b.out;
      std::fill(b.out.begin(), b.out.end(), Vec3f::Zero());
      for (std::size_t begin = 0; begin < 301; begin += 7)
        variant.kernel(b.job(skin, true), begin, std::min<std::size_t>(301, begin + 7));
      EXPECT_TRUE(points_identical(b.out, whole)) << variant.name << ": a vertex's bits do not depend on its range";
    }
  }
  if (variants.size() < 2) GTEST_SKIP() << "this CPU lacks AVX2 + FMA: only the portable variant checked";
}

TEST(DualQuaternionSkinningJob, run_parallel__equals_run_bit_for_bit) {
  Random random(25);
  const auto lists = random.influences(20011, 30, 4);
  const Skin skin = testing::build_or_die(lists, 30);
  for (bool rigid : {true, false}) {
    Buffers b = random_buffers(random, 20011, 30, rigid);
    ASSERT_TRUE(b.job(skin, true).run());
    const std::vector<Vec3f> serial = b.out;
    const std::vector<Vec3f> serial_normals = b.out_normals;
    for (std::size_t grain : {std::size_t{0}, std::size_t{13}}) {
      std::fill(b.out.begin(), b.out.end(), Vec3f::Zero());
      ASSERT_TRUE(b.job(skin, true).run_parallel(grain));
      EXPECT_TRUE(points_identical(b.out, serial)) << "grain " << grain << (rigid ? ", rigid" : ", stretched");
      EXPECT_TRUE(points_identical(b.out_normals, serial_normals)) << "grain " << grain;
    }
    std::fill(b.out.begin(), b.out.end(), Vec3f::Zero());
    for (std::size_t begin = 0; begin < 20011; begin += 4999)
      ASSERT_TRUE(b.job(skin).run(begin, std::min<std::size_t>(20011, begin + 4999)));
    EXPECT_TRUE(points_identical(b.out, serial)) << "ranges give the whole run's bits";
  }
}

}  // namespace
}  // namespace rigel::ops
