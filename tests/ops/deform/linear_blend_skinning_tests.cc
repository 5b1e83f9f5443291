#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "deform_test_util.h"
#include "rigel/math/transform.h"
#include "rigel/ops/deform/skinning.h"
#include "skinning_kernels.h"  // src/ops/deform: the variants behind run()

namespace rigel::ops {
namespace {

using testing::Mat3;
using testing::Mat4;
using testing::points_equal;
using testing::points_identical;
using testing::points_near;
using testing::Random;
using testing::Vec3;

struct Variant {
  const char* name;
  detail::LbsKernel kernel;
};

// Every variant this machine can run.
std::vector<Variant> variants() {
  std::vector<Variant> out = {{"portable", detail::lbs_portable}};
#if RIGEL_DEFORM_X86_KERNELS
  if (detail::avx2_fma_supported()) out.push_back({"avx2_fma", detail::lbs_avx2_fma});
  if (detail::avx512_supported()) out.push_back({"avx512", detail::lbs_avx512});
#endif
  return out;
}

// A job over caller-owned buffers.
struct Buffers {
  std::vector<SkinMatrix> matrices;
  std::vector<Vec3f> in, out, in_normals, out_normals;

  LinearBlendSkinningJob job(const Skin& skin, bool normals = false) {
    LinearBlendSkinningJob j;
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

Buffers random_buffers(Random& random, std::size_t vertices, std::size_t joints) {
  Buffers b;
  std::vector<Mat4> m;
  for (std::size_t j = 0; j < joints; ++j) m.push_back(random.affine());
  b.matrices = testing::linear_matrices(m);
  b.in = testing::random_points(random, vertices);
  b.out.assign(vertices, Vec3f::Zero());
  b.in_normals = testing::random_normals(random, vertices);
  b.out_normals.assign(vertices, Vec3f::Zero());
  return b;
}

TEST(LinearBlendSkinningJob, validate__rejects_each_documented_failure) {
  const Skin skin =
      testing::build_or_die(std::vector<std::vector<SkinInfluence>>{{{0, 1.0}}, {{1, 1.0}}, {{0, 0.5}, {1, 0.5}}}, 2);
  Buffers b;
  b.matrices.resize(2);
  b.in.assign(3, Vec3f::Ones());
  b.out.assign(3, Vec3f::Zero());
  b.in_normals.assign(3, Vec3f::UnitZ());
  b.out_normals.assign(3, Vec3f::Zero());

  EXPECT_TRUE(b.job(skin).validate()) << "a well-formed job should validate";
  EXPECT_TRUE(b.job(skin, true).validate()) << "with normals too";
  EXPECT_TRUE(b.job(skin, true).run()) << "and run";
  {
    LinearBlendSkinningJob job = b.job(skin);
    job.skin = nullptr;
    EXPECT_FALSE(job.validate()) << "a job without a skin should be rejected";
    EXPECT_FALSE(job.run()) << "run() should refuse a job that does not validate";
    EXPECT_FALSE(job.run_parallel()) << "run_parallel() too";
  }
  {
    LinearBlendSkinningJob job = b.job(skin);
    job.matrices = std::span<const SkinMatrix>(b.matrices).first(1);
    EXPECT_FALSE(job.validate()) << "fewer matrices than the skin's joints should be rejected";
  }
  {
    std::vector<SkinMatrix> more(5);
    LinearBlendSkinningJob job = b.job(skin);
    job.matrices = more;
    EXPECT_TRUE(job.validate()) << "more matrices than joints is fine (the skin uses the first ones)";
  }
  {
    LinearBlendSkinningJob job = b.job(skin);
    job.in_positions = std::span<const Vec3f>(b.in).first(2);
    EXPECT_FALSE(job.validate()) << "in_positions shorter than the skin should be rejected";
  }
  {
    std::vector<Vec3f> longer(4);
    LinearBlendSkinningJob job = b.job(skin);
    job.out_positions = longer;
    EXPECT_FALSE(job.validate()) << "out_positions of another size than the skin should be rejected";
  }
  {
    LinearBlendSkinningJob job = b.job(skin, true);
    job.in_normals = std::span<const Vec3f>(b.in_normals).first(2);
    job.out_normals = std::span<Vec3f>(b.out_normals).first(2);
    EXPECT_FALSE(job.validate()) << "normals that are neither empty nor one per vertex should be rejected";
  }
  {
    LinearBlendSkinningJob job = b.job(skin, true);
    job.out_normals = {};
    EXPECT_FALSE(job.validate()) << "in_normals without out_normals should be rejected";
  }
  {
    LinearBlendSkinningJob job = b.job(skin);
    job.out_normals = b.out_normals;
    EXPECT_FALSE(job.validate()) << "out_normals without in_normals should be rejected";
  }
  {
    LinearBlendSkinningJob job = b.job(skin);
    job.out_positions = b.in;
    EXPECT_FALSE(job.validate()) << "skinning in place (out_positions over in_positions) should be rejected";
  }
  {
    std::vector<Vec3f> shared(4, Vec3f::Ones());
    LinearBlendSkinningJob job = b.job(skin);
    job.in_positions = std::span<const Vec3f>(shared).first(3);
    job.out_positions = std::span<Vec3f>(shared).last(3);
    EXPECT_FALSE(job.validate()) << "partly overlapping positions should be rejected";
  }
  {
    LinearBlendSkinningJob job = b.job(skin, true);
    job.out_normals = b.out;
    EXPECT_FALSE(job.validate()) << "out_normals over out_positions should be rejected";
  }
  {
    LinearBlendSkinningJob job = b.job(skin, true);
    job.out_positions = b.in_normals;
    EXPECT_FALSE(job.validate()) << "out_positions over in_normals should be rejected";
  }
  {
    LinearBlendSkinningJob job = b.job(skin);
    EXPECT_FALSE(job.run(2, 1)) << "a range that ends before it starts should be rejected";
    EXPECT_FALSE(job.run(0, 4)) << "a range past the last vertex should be rejected";
    EXPECT_TRUE(job.run(3, 3)) << "an empty range at the end is fine";
  }
  {
    const Skin empty = testing::build_or_die(std::vector<std::vector<SkinInfluence>>{}, 0);
    LinearBlendSkinningJob job;
    job.skin = &empty;
    EXPECT_TRUE(job.run()) << "an empty skin with empty spans is valid";
    EXPECT_TRUE(job.run_parallel());
  }
}

TEST(LinearBlendSkinningJob, run__identity_matrices_leave_points_unchanged) {
  Random random(1);
  const auto lists = random.influences(200, 8, 6);
  const Skin skin = testing::build_or_die(lists, 8);
  Buffers b = random_buffers(random, 200, 8);
  b.matrices.assign(8, SkinMatrix{});  // default: identity
  for (const Variant& variant : variants()) {
    std::fill(b.out.begin(), b.out.end(), Vec3f::Zero());
    variant.kernel(b.job(skin), 0, 200);
    // The weights sum to 1 only to float rounding, so a point may move by
    // about an ulp of its coordinates.
    EXPECT_TRUE(points_near(b.out, b.in, 1e-6)) << variant.name;
  }
  const Skin single = testing::build_or_die(std::vector<std::vector<SkinInfluence>>(200, {{3, 1.0}}), 8);
  for (const Variant& variant : variants()) {
    variant.kernel(b.job(single), 0, 200);
    EXPECT_TRUE(points_equal(b.out, b.in)) << variant.name << ": one influence of weight 1 is exact";
  }
}

TEST(LinearBlendSkinningJob, run__a_single_influence_is_the_matrix_transform) {
  Random random(2);
  std::vector<std::vector<SkinInfluence>> lists;
  for (int v = 0; v < 64; ++v) lists.push_back({{v % 5, 1.0}});
  const Skin skin = testing::build_or_die(lists, 5);
  Buffers b = random_buffers(random, 64, 5);
  std::vector<Vec3f> expected;
  for (int v = 0; v < 64; ++v) {
    const Mat4 m = b.matrices[static_cast<std::size_t>(v % 5)].to_mat4();
    expected.push_back((m.topLeftCorner<3, 3>() * b.in[v].cast<double>() + m.topRightCorner<3, 1>()).cast<float>());
  }
  for (const Variant& variant : variants()) {
    variant.kernel(b.job(skin), 0, 64);
    EXPECT_TRUE(points_near(b.out, expected, 2e-6)) << variant.name;
  }
}

// Joint 0 stays put, joint 1 twists 180 degrees about x (the bone's axis).
// A point at radius 1, weighted half and half: linear blending averages
// (x, 0, 1) and (x, 0, -1), and the radius collapses to 0 (the candy
// wrapper). dual_quaternion_skinning_tests.cc checks that DQS keeps it.
TEST(LinearBlendSkinningJob, run__two_half_weights_collapse_a_180_degree_twist) {
  const Skin skin =
      testing::build_or_die(std::vector<std::vector<SkinInfluence>>{{{0, 0.5}, {1, 0.5}}, {{0, 0.5}, {1, 0.5}}}, 2);
  Buffers b;
  b.matrices =
      testing::linear_matrices(std::vector<Mat4>{Mat4::Identity(), testing::to_mat4(testing::rot_x(math::kPi))});
  b.in = {Vec3f(0.5f, 0.0f, 1.0f), Vec3f(2.0f, 1.0f, 0.0f)};
  b.out.assign(2, Vec3f::Zero());
  for (const Variant& variant : variants()) {
    variant.kernel(b.job(skin), 0, 2);
    // 0.5 (x, 0, 1) + 0.5 (x, 0, -1) = (x, 0, 0); cos(pi) is -1 exactly in
    // double, sin(pi) is 1.2e-16 (0 once rounded to float... nearly).
    EXPECT_TRUE(points_near(b.out, std::vector<Vec3f>{{0.5f, 0.0f, 0.0f}, {2.0f, 0.0f, 0.0f}}, 1e-7))
        << variant.name << ": linear blending collapses the radius";
  }
  // 90 degrees: 0.5 (0, 0, 1) + 0.5 (0, -1, 0) = (0, -0.5, 0.5), radius 0.707.
  b.matrices =
      testing::linear_matrices(std::vector<Mat4>{Mat4::Identity(), testing::to_mat4(testing::rot_x(math::kPi / 2))});
  b.in = {Vec3f(0.0f, 0.0f, 1.0f), Vec3f(0.0f, 1.0f, 0.0f)};
  for (const Variant& variant : variants()) {
    variant.kernel(b.job(skin), 0, 2);
    EXPECT_TRUE(points_near(b.out, std::vector<Vec3f>{{0.0f, -0.5f, 0.5f}, {0.0f, 0.5f, 0.5f}}, 1e-7))
        << variant.name << ": a 90 degree twist shrinks the radius to sqrt(0.5)";
  }
}

TEST(LinearBlendSkinningJob, run__normalised_weights_blend_like_the_normalised_input) {
  // 0.3 / 0.3 is normalised to 0.5 / 0.5 by the builder.
  const Skin thirds = testing::build_or_die(std::vector<std::vector<SkinInfluence>>{{{0, 0.3}, {1, 0.3}}}, 2);
  const Skin halves = testing::build_or_die(std::vector<std::vector<SkinInfluence>>{{{0, 0.5}, {1, 0.5}}}, 2);
  Buffers b;
  b.matrices = testing::linear_matrices(std::vector<Mat4>{testing::to_mat4(Mat3::Identity(), Vec3(2, 0, 0)),
                                                          testing::to_mat4(Mat3::Identity(), Vec3(0, 4, 0))});
  b.in = {Vec3f(1.0f, 1.0f, 1.0f)};
  b.out = {Vec3f::Zero()};
  ASSERT_TRUE(b.job(thirds).run());
  EXPECT_TRUE(points_equal(b.out, std::vector<Vec3f>{{2.0f, 3.0f, 1.0f}})) << "p + 0.5 (2, 0, 0) + 0.5 (0, 4, 0)";
  std::vector<Vec3f> from_thirds = b.out;
  ASSERT_TRUE(b.job(halves).run());
  EXPECT_TRUE(points_equal(b.out, from_thirds));
}

TEST(LinearBlendSkinningJob, run__many_influences_equal_the_weighted_sum) {
  // 12 influences per vertex, as a glTF file with three JOINTS sets.
  Random random(12);
  std::vector<std::vector<SkinInfluence>> lists(37);
  for (auto& list : lists) {
    for (int k = 0; k < 12; ++k) list.push_back({k, random.uniform(0.01, 1.0)});
  }
  const Skin skin = testing::build_or_die(lists, 12);
  ASSERT_EQ(skin.max_influences(), 12u);
  Buffers b = random_buffers(random, 37, 12);
  const std::vector<Vec3f> expected = testing::reference_lbs(skin, b.matrices, b.in);
  for (const Variant& variant : variants()) {
    variant.kernel(b.job(skin), 0, 37);
    EXPECT_TRUE(points_near(b.out, expected, 1e-5)) << variant.name;
  }
}

TEST(LinearBlendSkinningJob, run__matches_the_reference_for_every_vertex_count) {
  // 0..13 vertices: every split into blocks of 4 and a tail.
  Random random(13);
  for (std::size_t count = 0; count <= 13; ++count) {
    const auto lists = random.influences(count, 6, 4);
    const Skin skin = testing::build_or_die(lists, 6);
    Buffers b = random_buffers(random, count, 6);
    const std::vector<Vec3f> expected = testing::reference_lbs(skin, b.matrices, b.in);
    for (const Variant& variant : variants()) {
      std::fill(b.out.begin(), b.out.end(), Vec3f::Constant(-7.0f));
      if (count > 0) variant.kernel(b.job(skin), 0, count);
      EXPECT_TRUE(points_near(b.out, expected, 1e-5)) << variant.name << ", " << count << " vertices";
    }
  }
}

TEST(LinearBlendSkinningJob, run__fixed_layout_equals_general_layout) {
  Random random(14);
  const auto lists = random.influences(1001, 40, 4);
  const Skin fixed = testing::build_or_die(lists, 40, true);
  const Skin general = testing::build_or_die(lists, 40, false);
  ASSERT_TRUE(fixed.has_fixed_layout());
  ASSERT_FALSE(general.has_fixed_layout());
  Buffers b = random_buffers(random, 1001, 40);
  for (const Variant& variant : variants()) {
    variant.kernel(b.job(fixed, true), 0, 1001);
    const std::vector<Vec3f> fixed_out = b.out;
    const std::vector<Vec3f> fixed_normals = b.out_normals;
    variant.kernel(b.job(general, true), 0, 1001);
    EXPECT_TRUE(points_equal(b.out, fixed_out)) << variant.name << ": the fast path's padding adds exactly 0";
    EXPECT_TRUE(points_equal(b.out_normals, fixed_normals)) << variant.name;
  }
}

TEST(LinearBlendSkinningJob, run__every_variant_tracks_the_portable_one) {
  Random random(15);
  const auto lists = random.influences(517, 30, 7);
  const Skin skin = testing::build_or_die(lists, 30);
  Buffers b = random_buffers(random, 517, 30);
  const std::vector<Variant> all = variants();
  all[0].kernel(b.job(skin, true), 0, 517);
  const std::vector<Vec3f> portable = b.out;
  const std::vector<Vec3f> portable_normals = b.out_normals;
  for (std::size_t i = 1; i < all.size(); ++i) {
    all[i].kernel(b.job(skin, true), 0, 517);
    EXPECT_TRUE(points_near(b.out, portable, 1e-5))
        << all[i].name << " vs portable: fused multiply-adds round differently";
    EXPECT_TRUE(points_near(b.out_normals, portable_normals, 1e-5)) << all[i].name;
  }
  if (all.size() < 3) GTEST_SKIP() << "this CPU lacks a vector variant: only " << all.size() << " checked";
}

TEST(LinearBlendSkinningJob, run_parallel__equals_run_bit_for_bit) {
  Random random(16);
  const auto lists = random.influences(20011, 50, 4);
  for (bool fixed_layout : {true, false}) {
    const Skin skin = testing::build_or_die(lists, 50, fixed_layout);
    Buffers b = random_buffers(random, 20011, 50);
    ASSERT_TRUE(b.job(skin, true).run());
    const std::vector<Vec3f> serial = b.out;
    const std::vector<Vec3f> serial_normals = b.out_normals;
    for (std::size_t grain : {std::size_t{0}, std::size_t{7}, std::size_t{1000}}) {
      std::fill(b.out.begin(), b.out.end(), Vec3f::Zero());
      std::fill(b.out_normals.begin(), b.out_normals.end(), Vec3f::Zero());
      ASSERT_TRUE(b.job(skin, true).run_parallel(grain));
      EXPECT_TRUE(points_identical(b.out, serial)) << "grain " << grain << ", fixed layout " << fixed_layout;
      EXPECT_TRUE(points_identical(b.out_normals, serial_normals)) << "grain " << grain;
    }
  }
}

TEST(LinearBlendSkinningJob, run__a_range_writes_only_its_vertices) {
  Random random(17);
  const auto lists = random.influences(50, 10, 4);
  const Skin skin = testing::build_or_die(lists, 10);
  Buffers b = random_buffers(random, 50, 10);
  ASSERT_TRUE(b.job(skin).run());
  const std::vector<Vec3f> whole = b.out;
  for (const Variant& variant : variants()) {
    const Vec3f sentinel(-9.0f, -9.0f, -9.0f);
    std::fill(b.out.begin(), b.out.end(), sentinel);
    variant.kernel(b.job(skin), 13, 30);
    for (std::size_t v = 0; v < 50; ++v) {
      if (v < 13 || v >= 30) {
        EXPECT_EQ(b.out[v], sentinel) << variant.name << ": vertex " << v << " is outside the range";
      }
    }
  }
  std::fill(b.out.begin(), b.out.end(), Vec3f::Zero());
  for (std::size_t begin = 0; begin < 50; begin += 9)
    ASSERT_TRUE(b.job(skin).run(begin, std::min<std::size_t>(50, begin + 9)));
  EXPECT_TRUE(points_identical(b.out, whole)) << "ranges of 9 give the whole run's bits";
  for (const Variant& variant : variants()) {
    // Ranges of 9 put each vertex in another block of 4 than a whole run does.
    variant.kernel(b.job(skin, true), 0, 50);
    const std::vector<Vec3f> variant_whole = b.out;
    const std::vector<Vec3f> variant_normals = b.out_normals;
    std::fill(b.out.begin(), b.out.end(), Vec3f::Zero());
    for (std::size_t begin = 0; begin < 50; begin += 9)
      variant.kernel(b.job(skin, true), begin, std::min<std::size_t>(50, begin + 9));
    EXPECT_TRUE(points_identical(b.out, variant_whole))
        << variant.name << ": a vertex's bits do not depend on its range";
    EXPECT_TRUE(points_identical(b.out_normals, variant_normals)) << variant.name;
  }
}

TEST(LinearBlendSkinningJob, run__normals_follow_the_inverse_transpose) {
  const Skin skin =
      testing::build_or_die(std::vector<std::vector<SkinInfluence>>{{{0, 1.0}}, {{1, 1.0}}, {{2, 1.0}}, {{3, 1.0}}}, 4);
  Buffers b;
  const Mat3 rotation = Eigen::AngleAxisd(0.6, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const Mat3 squash = Vec3(4.0, 1.0, 0.5).asDiagonal();
  Mat3 mirror = Mat3::Identity();
  mirror(0, 0) = -1.0;
  b.matrices =
      testing::linear_matrices(std::vector<Mat4>{testing::to_mat4(rotation, Vec3(1, 2, 3)), testing::to_mat4(squash),
                                                 testing::to_mat4(mirror), testing::to_mat4(Mat3::Zero())});
  const Vec3 n = Vec3(1, 1, 1).normalized();
  b.in.assign(4, Vec3f::Zero());
  b.out.assign(4, Vec3f::Zero());
  b.in_normals.assign(4, n.cast<float>());
  b.out_normals.assign(4, Vec3f::Zero());
  const std::vector<Vec3f> expected = {
      (rotation * n).cast<float>(),                                   // rotated, not translated
      (squash.inverse().transpose() * n).normalized().cast<float>(),  // perpendicular to the squashed surface
      Vec3(-n.x(), n.y(), n.z()).cast<float>(),                       // mirrored: (A^-T n), outward kept
      Vec3f::Zero(),                                                  // a collapsed matrix gives no direction
  };
  for (const Variant& variant : variants()) {
    variant.kernel(b.job(skin, true), 0, 4);
    EXPECT_TRUE(points_near(b.out_normals, expected, 1e-6)) << variant.name;
  }
  // Perpendicularity under a random affine matrix: a tangent t of the bind
  // surface (t . n = 0) maps to A t, and the skinned normal stays
  // perpendicular to it.
  Random random(18);
  for (int trial = 0; trial < 20; ++trial) {
    const Mat4 m = random.affine(0.3, 3.0);
    b.matrices = testing::linear_matrices(std::vector<Mat4>(4, m));
    ASSERT_TRUE(b.job(skin, true).run());
    const Vec3 tangent = n.unitOrthogonal();
    const Vec3 skinned_tangent = b.matrices[0].to_mat4().topLeftCorner<3, 3>() * tangent;
    EXPECT_NEAR(b.out_normals[0].cast<double>().dot(skinned_tangent.normalized()), 0.0, 1e-6);
    EXPECT_NEAR(b.out_normals[0].norm(), 1.0f, 1e-6f) << "normals are unit length";
  }
}

}  // namespace
}  // namespace rigel::ops
