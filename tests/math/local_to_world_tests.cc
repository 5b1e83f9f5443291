#include "rigel/math/local_to_world.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <vector>

#include "local_to_world_kernels.h"  // src/math: the variants behind run()
#include "math_test_util.h"
#include "rigel/math/transform.h"

namespace rigel::math {
namespace {

using testing::near;
using testing::Random;

// A random affine matrix with modest scale and shear, so long chains stay
// well within double precision.
Mat4 random_local(Random& random) {
  TransformParts p;
  p.translate = random.vec3(-1, 1);
  p.rotate = random.angles();
  p.scale = random.vec3(0.9, 1.1);
  p.shear = random.vec3(-0.05, 0.05);
  return compose(p);
}

// The reference: full 4x4 products, one joint at a time.
std::vector<Mat4> naive_world(const std::vector<std::int32_t>& parents, const std::vector<Mat4>& local,
                              const Mat4& root) {
  std::vector<Mat4> world(local.size());
  for (std::size_t i = 0; i < local.size(); ++i) {
    world[i] = (parents[i] == kNoParent ? root : world[static_cast<std::size_t>(parents[i])]) * local[i];
  }
  return world;
}

::testing::AssertionResult worlds_match(const std::vector<Mat4>& actual, const std::vector<Mat4>& expected,
                                        double tolerance) {
  for (std::size_t i = 0; i < expected.size(); ++i) {
    if (actual[i].row(3) != Eigen::RowVector4d(0, 0, 0, 1)) {
      return ::testing::AssertionFailure() << "joint " << i << " has last row " << actual[i].row(3);
    }
    const double scale = std::max(1.0, expected[i].cwiseAbs().maxCoeff());
    auto result = near(actual[i], expected[i], tolerance * scale);
    if (!result) return result << " (joint " << i << ")";
  }
  return ::testing::AssertionSuccess();
}

TEST(LocalToWorldJob, validate__rejects_each_documented_failure) {
  std::vector<std::int32_t> parents = {kNoParent, 0, 1, 0};
  std::vector<Mat4> local(4, Mat4::Identity());
  std::vector<Mat4> world(4);

  {
    LocalToWorldJob job;
    job.parents = parents;
    job.local = local;
    job.world = world;
    EXPECT_TRUE(job.validate()) << "a well-formed job should validate";
    EXPECT_TRUE(job.run()) << "a well-formed job should run";
  }
  {
    LocalToWorldJob job;
    EXPECT_TRUE(job.validate()) << "an empty job (all spans empty) is valid";
    EXPECT_TRUE(job.run()) << "an empty job runs and does nothing";
  }
  {
    LocalToWorldJob job;
    job.parents = parents;
    job.local = std::span<const Mat4>(local).first(3);
    job.world = world;
    EXPECT_FALSE(job.validate()) << "local shorter than parents should be rejected";
    EXPECT_FALSE(job.run()) << "run() should refuse a job that does not validate";
  }
  {
    LocalToWorldJob job;
    job.parents = parents;
    job.local = local;
    job.world = std::span<Mat4>(world).first(3);
    EXPECT_FALSE(job.validate()) << "world shorter than parents should be rejected";
    EXPECT_FALSE(job.run()) << "run() should refuse a job that does not validate";
  }
  {
    LocalToWorldJob job;
    job.parents = std::span<const std::int32_t>(parents).first(3);
    job.local = local;
    job.world = world;
    EXPECT_FALSE(job.validate()) << "parents shorter than local and world should be rejected";
  }
  {
    LocalToWorldJob job;
    job.local = local;
    job.world = world;
    EXPECT_FALSE(job.validate()) << "empty parents with non-empty local and world should be rejected";
  }
  {
    LocalToWorldJob job;
    job.parents = parents;
    job.world = world;
    EXPECT_FALSE(job.validate()) << "empty local with non-empty parents and world should be rejected";
  }
  {
    LocalToWorldJob job;
    job.parents = parents;
    job.local = local;
    EXPECT_FALSE(job.validate()) << "empty world with non-empty parents and local should be rejected";
  }
  {
    std::vector<std::int32_t> forward = {kNoParent, 2, 0, 1};
    LocalToWorldJob job;
    job.parents = forward;
    job.local = local;
    job.world = world;
    EXPECT_FALSE(job.validate()) << "a parent after its child (1 -> 2) should be rejected";
    EXPECT_FALSE(job.run()) << "run() should refuse a job with a parent after its child";
  }
  {
    std::vector<std::int32_t> self = {kNoParent, 1, 1, 2};
    LocalToWorldJob job;
    job.parents = self;
    job.local = local;
    job.world = world;
    EXPECT_FALSE(job.validate()) << "a joint that is its own parent should be rejected";
  }
  {
    std::vector<std::int32_t> first_has_parent = {0, 0, 1, 2};
    LocalToWorldJob job;
    job.parents = first_has_parent;
    job.local = local;
    job.world = world;
    EXPECT_FALSE(job.validate()) << "the first joint can only be a root";
  }
  {
    std::vector<std::int32_t> negative = {kNoParent, 0, -2, 1};
    LocalToWorldJob job;
    job.parents = negative;
    job.local = local;
    job.world = world;
    EXPECT_FALSE(job.validate()) << "a negative parent index other than kNoParent should be rejected";
  }
  {
    LocalToWorldJob job;
    job.parents = parents;
    job.local = local;
    job.world = world;
    job.root = Mat4::Identity();
    job.root(3, 0) = 0.5;
    EXPECT_FALSE(job.validate()) << "a root whose last row is not 0 0 0 1 should be rejected";
    job.root = Mat4::Identity();
    job.root(3, 3) = 2.0;
    EXPECT_FALSE(job.validate()) << "a root with a projective w should be rejected";
    job.root = translation_matrix(Vec3(1, 2, 3)) * scale_matrix(Vec3(2, -1, 3));
    EXPECT_TRUE(job.validate()) << "any affine root is accepted";
  }
}

TEST(LocalToWorldJob, run__invalid_job_writes_nothing) {
  std::vector<std::int32_t> parents = {kNoParent, 1};
  std::vector<Mat4> local(2, translation_matrix(Vec3(1, 0, 0)));
  std::vector<Mat4> world(2, Mat4::Constant(7.0));
  LocalToWorldJob job;
  job.parents = parents;
  job.local = local;
  job.world = world;
  EXPECT_FALSE(job.run()) << "the job is invalid";
  EXPECT_TRUE(world[0] == Mat4::Constant(7.0) && world[1] == Mat4::Constant(7.0))
      << "an invalid job should leave the outputs untouched";
}

TEST(LocalToWorldJob, run__chain_matches_naive_loop) {
  Random random(41);
  for (std::size_t count : {1u, 2u, 3u, 17u, 1000u}) {
    std::vector<std::int32_t> parents(count);
    std::vector<Mat4> local(count);
    for (std::size_t i = 0; i < count; ++i) {
      parents[i] = static_cast<std::int32_t>(i) - 1;
      local[i] = random_local(random);
    }
    std::vector<Mat4> world(count, Mat4::Constant(-1.0));
    LocalToWorldJob job;
    job.parents = parents;
    job.local = local;
    job.world = world;
    TransformParts root;
    root.translate = random.vec3(-5, 5);
    root.rotate = random.angles();
    job.root = compose(root);
    ASSERT_TRUE(job.run()) << "a chain is a valid job";
    EXPECT_TRUE(worlds_match(world, naive_world(parents, local, job.root), 1e-12))
        << "a chain of " << count << " joints should match the naive 4x4 loop";
  }
}

TEST(LocalToWorldJob, run__random_trees_match_naive_loop) {
  Random random(42);
  for (int tree = 0; tree < 50; ++tree) {
    const int count = 1 + random.index(300);
    std::vector<std::int32_t> parents(static_cast<std::size_t>(count));
    std::vector<Mat4> local(static_cast<std::size_t>(count));
    for (int i = 0; i < count; ++i) {
      // About one joint in ten is a root; the rest hang from any earlier joint.
      parents[static_cast<std::size_t>(i)] = (i == 0 || random.index(10) == 0) ? kNoParent : random.index(i);
      local[static_cast<std::size_t>(i)] = random_local(random);
    }
    std::vector<Mat4> world(static_cast<std::size_t>(count));
    LocalToWorldJob job;
    job.parents = parents;
    job.local = local;
    job.world = world;
    if (tree % 2) job.root = random_local(random);
    ASSERT_TRUE(job.run()) << "a parent-first tree is a valid job";
    EXPECT_TRUE(worlds_match(world, naive_world(parents, local, job.root), 1e-12))
        << "tree " << tree << " of " << count << " joints should match the naive 4x4 loop";
  }
}

TEST(LocalToWorldJob, run__every_instruction_set_variant_matches_naive_loop) {
  struct Variant {
    const char* name;
    void (*kernel)(const LocalToWorldJob&);
  };
  std::vector<Variant> variants = {{"portable", detail::local_to_world_portable}};
#if RIGEL_MATH_X86_KERNELS
  variants.push_back({"sse2", detail::local_to_world_sse2});
  if (detail::avx2_fma_supported()) {
    variants.push_back({"avx2+fma", detail::local_to_world_avx2_fma});
  } else {
    std::printf("note: this CPU lacks AVX2/FMA; that variant is not checked here\n");
  }
#endif
  Random random(43);
  for (int tree = 0; tree < 20; ++tree) {
    const int count = 1 + random.index(200);
    std::vector<std::int32_t> parents(static_cast<std::size_t>(count));
    std::vector<Mat4> local(static_cast<std::size_t>(count));
    for (int i = 0; i < count; ++i) {
      // Mostly chains (the register fast path), with branches and extra roots.
      const int pick = random.index(10);
      parents[static_cast<std::size_t>(i)] = i == 0 || pick == 0 ? kNoParent : pick < 7 ? i - 1 : random.index(i);
      local[static_cast<std::size_t>(i)] = random_local(random);
    }
    Mat4 root = random_local(random);
    const std::vector<Mat4> expected = naive_world(parents, local, root);
    for (const Variant& variant : variants) {
      std::vector<Mat4> world(static_cast<std::size_t>(count), Mat4::Constant(-1.0));
      LocalToWorldJob job;
      job.parents = parents;
      job.local = local;
      job.world = world;
      job.root = root;
      ASSERT_TRUE(job.validate()) << "the generated tree is a valid job";
      variant.kernel(job);
      EXPECT_TRUE(worlds_match(world, expected, 1e-12))
          << "the " << variant.name << " variant should match the naive loop on tree " << tree;
    }
  }
}

TEST(LocalToWorldJob, run__ignores_the_local_last_row) {
  std::vector<std::int32_t> parents = {kNoParent};
  std::vector<Mat4> local = {translation_matrix(Vec3(1, 2, 3))};
  local[0].row(3) = Eigen::RowVector4d(9, 9, 9, 9);  // not affine: documented as a precondition
  std::vector<Mat4> world(1);
  LocalToWorldJob job;
  job.parents = parents;
  job.local = local;
  job.world = world;
  ASSERT_TRUE(job.run()) << "the local matrices are not validated";
  EXPECT_TRUE(near(world[0], translation_matrix(Vec3(1, 2, 3)), 0.0))
      << "the local last row is taken as 0 0 0 1, and the world last row is written as 0 0 0 1";
}

}  // namespace
}  // namespace rigel::math
