#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "deform_test_util.h"
#include "rigel/ops/deform/blend_shape.h"

namespace rigel::ops {
namespace {

using testing::points_equal;
using testing::points_identical;
using testing::points_near;
using testing::Random;

void expect_failure(const BlendShapeBuilder& builder, const std::vector<std::string>& parts, const char* why) {
  const Result<BlendShapeTargets> targets = builder.build();
  ASSERT_FALSE(targets.is_ok()) << why;
  EXPECT_EQ(targets.status().code(), ErrorCode::kInvalidArgument) << why;
  for (const std::string& part : parts) {
    EXPECT_NE(targets.status().message().find(part), std::string::npos)
        << why << ": the message should contain \"" << part << "\", it is: " << targets.status().message();
  }
}

TEST(BlendShapeBuilder, build__rejects_a_dense_target_of_the_wrong_length) {
  BlendShapeBuilder builder(4);
  builder.add_dense_target(std::vector<Vec3f>(4, Vec3f::Ones()));
  builder.add_dense_target(std::vector<Vec3f>(3, Vec3f::Ones()));
  expect_failure(builder, {"target 1", "one delta per vertex (4)", "not 3"}, "a dense target covers every vertex");
}

TEST(BlendShapeBuilder, build__rejects_sparse_indices_and_deltas_of_different_lengths) {
  BlendShapeBuilder builder(4);
  builder.add_sparse_target(std::vector<std::int64_t>{0, 1}, std::vector<Vec3f>(1, Vec3f::Ones()));
  expect_failure(builder, {"target 0", "2 indices but 1 deltas"}, "each sparse delta needs its vertex");
}

TEST(BlendShapeBuilder, build__rejects_a_sparse_index_out_of_range) {
  BlendShapeBuilder builder(4);
  builder.add_sparse_target(std::vector<std::int64_t>{1, 4}, std::vector<Vec3f>(2, Vec3f::Ones()));
  expect_failure(builder, {"target 0", "vertex index 4", "4 vertices"}, "an index must name a vertex of the mesh");
}

TEST(BlendShapeBuilder, build__rejects_a_negative_sparse_index) {
  BlendShapeBuilder builder(4);
  builder.add_sparse_target(std::vector<std::int64_t>{-1}, std::vector<Vec3f>(1, Vec3f::Ones()));
  expect_failure(builder, {"target 0", "vertex index -1"}, "a negative index names no vertex");
}

TEST(BlendShapeBuilder, build__rejects_a_vertex_listed_twice_in_a_target) {
  BlendShapeBuilder builder(4);
  builder.add_sparse_target(std::vector<std::int64_t>{2, 0, 2}, std::vector<Vec3f>(3, Vec3f::Ones()));
  expect_failure(builder, {"target 0", "vertex 2 is listed twice"}, "two deltas for one vertex are ambiguous");
}

TEST(BlendShapeBuilder, build__rejects_a_delta_that_is_not_finite) {
  BlendShapeBuilder builder(3);
  std::vector<Vec3f> deltas(3, Vec3f::Zero());
  deltas[1].y() = std::numeric_limits<float>::quiet_NaN();
  builder.add_dense_target(deltas);
  expect_failure(builder, {"target 0", "delta of vertex 1", "not finite"}, "a NaN delta would make the vertex NaN");
  BlendShapeBuilder sparse(3);
  sparse.add_sparse_target(std::vector<std::int64_t>{2},
                           std::vector<Vec3f>{Vec3f(std::numeric_limits<float>::infinity(), 0, 0)});
  expect_failure(sparse, {"target 0", "delta of vertex 2"}, "an infinite delta is refused too");
}

TEST(BlendShapeBuilder, build__chooses_sparse_or_dense_and_drops_zero_deltas) {
  BlendShapeBuilder builder(10);
  std::vector<Vec3f> mostly_zero(10, Vec3f::Zero());
  mostly_zero[7] = Vec3f(1, 2, 3);
  mostly_zero[3] = Vec3f(4, 5, 6);
  builder.add_dense_target(mostly_zero);                            // 2 of 10 move: sparse
  builder.add_dense_target(std::vector<Vec3f>(10, Vec3f::Ones()));  // all move: dense
  builder.add_sparse_target(std::vector<std::int64_t>{9, 1, 5}, std::vector<Vec3f>(3, Vec3f::UnitX()));
  builder.add_dense_target(std::vector<Vec3f>(10, Vec3f::Zero()));  // moves nothing
  const Result<BlendShapeTargets> targets = builder.build();
  ASSERT_TRUE(targets.is_ok()) << targets.status().message();
  ASSERT_EQ(targets->target_count(), 4u);
  const BlendShapeTargets::Target t0 = targets->target(0);
  EXPECT_FALSE(t0.dense) << "a glTF-style dense target that moves 2 of 10 vertices is stored sparse";
  EXPECT_EQ(std::vector<std::uint32_t>(t0.indices.begin(), t0.indices.end()), (std::vector<std::uint32_t>{3, 7}))
      << "zero deltas dropped, indices ascending";
  EXPECT_EQ(t0.deltas[0], Vec3f(4, 5, 6));
  EXPECT_TRUE(targets->target(1).dense) << "a target that moves every vertex stays dense";
  EXPECT_EQ(targets->target(1).deltas.size(), 10u);
  EXPECT_EQ(std::vector<std::uint32_t>(targets->target(2).indices.begin(), targets->target(2).indices.end()),
            (std::vector<std::uint32_t>{1, 5, 9}))
      << "sparse indices are sorted";
  EXPECT_TRUE(targets->target(3).deltas.empty()) << "a target that moves nothing stores nothing";
  EXPECT_EQ(targets->stored_delta_count(), 2u + 10u + 3u);
}

// Base (1, 1, 1) at two vertices; target 0 moves vertex 0 by (2, 0, 0),
// target 1 moves vertex 1 by (0, 4, 0) and vertex 0 by (0, 0, 8).
struct TwoTargets {
  std::vector<Vec3f> base = {Vec3f(1, 1, 1), Vec3f(1, 1, 1)};
  BlendShapeTargets dense;
  BlendShapeTargets sparse;
  TwoTargets() {
    BlendShapeBuilder d(2), s(2);
    d.sparse_below = 0.0;   // keep both dense
    s.sparse_below = 10.0;  // keep both sparse
    const std::vector<Vec3f> t0 = {Vec3f(2, 0, 0), Vec3f(0, 0, 0)};
    const std::vector<Vec3f> t1 = {Vec3f(0, 0, 8), Vec3f(0, 4, 0)};
    d.add_dense_target(t0).add_dense_target(t1);
    s.add_sparse_target(std::vector<std::int64_t>{0}, std::vector<Vec3f>{t0[0]});
    s.add_sparse_target(std::vector<std::int64_t>{1, 0}, std::vector<Vec3f>{t1[1], t1[0]});
    dense = std::move(d.build().value());
    sparse = std::move(s.build().value());
  }
};

TEST(BlendShapeJob, run__adds_weighted_deltas) {
  TwoTargets f;
  ASSERT_TRUE(f.dense.target(0).dense);
  ASSERT_FALSE(f.sparse.target(1).dense);
  struct Case {
    std::vector<float> weights;
    std::vector<Vec3f> expected;
    const char* why;
  };
  const std::vector<Case> cases = {
      {{0.0f, 0.0f}, {{1, 1, 1}, {1, 1, 1}}, "weights 0 leave the base"},
      {{1.0f, 0.0f}, {{3, 1, 1}, {1, 1, 1}}, "weight 1 adds target 0's whole delta"},
      {{0.5f, 0.0f}, {{2, 1, 1}, {1, 1, 1}}, "weight 0.5 adds half"},
      {{0.0f, 1.0f}, {{1, 1, 9}, {1, 5, 1}}, "target 1 alone"},
      {{0.5f, 0.5f}, {{2, 1, 5}, {1, 3, 1}}, "both targets add up"},
      {{1.0f, 1.0f}, {{3, 1, 9}, {1, 5, 1}}, "both at 1"},
      {{-1.0f, 2.0f}, {{-1, 1, 17}, {1, 9, 1}}, "weights outside [0, 1] extrapolate"},
  };
  for (const Case& c : cases) {
    for (const BlendShapeTargets* targets : {&f.dense, &f.sparse}) {
      std::vector<Vec3f> out(2, Vec3f::Zero());
      BlendShapeJob job;
      job.targets = targets;
      job.base = f.base;
      job.weights = c.weights;
      job.out = out;
      ASSERT_TRUE(job.run());
      EXPECT_TRUE(points_equal(out, c.expected)) << c.why << (targets == &f.dense ? " (dense)" : " (sparse)");
    }
  }
}

TEST(BlendShapeJob, validate__rejects_each_documented_failure) {
  TwoTargets f;
  std::vector<float> weights = {0.5f, 0.5f};
  std::vector<Vec3f> out(2, Vec3f::Zero());
  auto job = [&] {
    BlendShapeJob j;
    j.targets = &f.sparse;
    j.base = f.base;
    j.weights = weights;
    j.out = out;
    return j;
  };
  EXPECT_TRUE(job().validate()) << "a well-formed job should validate";
  {
    BlendShapeJob j = job();
    j.targets = nullptr;
    EXPECT_FALSE(j.validate()) << "a job without targets should be rejected";
    EXPECT_FALSE(j.run()) << "run() should refuse a job that does not validate";
    EXPECT_FALSE(j.run_parallel());
  }
  {
    BlendShapeJob j = job();
    j.base = std::span<const Vec3f>(f.base).first(1);
    EXPECT_FALSE(j.validate()) << "base of the wrong size should be rejected";
  }
  {
    BlendShapeJob j = job();
    j.out = std::span<Vec3f>(out).first(1);
    EXPECT_FALSE(j.validate()) << "out of the wrong size should be rejected";
  }
  {
    BlendShapeJob j = job();
    j.weights = std::span<const float>(weights).first(1);
    EXPECT_FALSE(j.validate()) << "one weight per target is needed";
  }
  {
    std::vector<float> bad = {0.5f, std::numeric_limits<float>::quiet_NaN()};
    BlendShapeJob j = job();
    j.weights = bad;
    EXPECT_FALSE(j.validate()) << "a NaN weight should be rejected";
    bad[1] = std::numeric_limits<float>::infinity();
    EXPECT_FALSE(j.validate()) << "an infinite weight should be rejected";
  }
  {
    std::vector<Vec3f> shared = {Vec3f(1, 1, 1), Vec3f(1, 1, 1), Vec3f(1, 1, 1)};
    BlendShapeJob j = job();
    j.base = std::span<const Vec3f>(shared).first(2);
    j.out = std::span<Vec3f>(shared).last(2);
    EXPECT_FALSE(j.validate()) << "out partly over base should be rejected";
    j.out = std::span<Vec3f>(shared).first(2);
    EXPECT_TRUE(j.validate()) << "out exactly over base (in place) is fine";
    ASSERT_TRUE(j.run());
    EXPECT_TRUE(points_equal(std::span<const Vec3f>(shared).first(2), std::vector<Vec3f>{{2, 1, 5}, {1, 3, 1}}))
        << "in place gives the same result";
  }
  {
    BlendShapeJob j = job();
    EXPECT_FALSE(j.run(2, 1)) << "a reversed range should be rejected";
    EXPECT_FALSE(j.run(0, 3)) << "a range past the end should be rejected";
  }
}

TEST(BlendShapeJob, run_parallel__and_ranges_equal_run_bit_for_bit) {
  Random random(31);
  const std::size_t count = 30001;
  BlendShapeBuilder builder(count);
  for (int t = 0; t < 6; ++t) {
    std::vector<std::int64_t> indices;
    std::vector<Vec3f> deltas;
    for (std::size_t v = static_cast<std::size_t>(t) * 997; v < count; v += 3 + static_cast<std::size_t>(t)) {
      indices.push_back(static_cast<std::int64_t>(v));
      deltas.push_back(random.vec3f(-1, 1));
    }
    builder.add_sparse_target(indices, deltas);
  }
  builder.add_dense_target(testing::random_points(random, count, 0.1));
  const Result<BlendShapeTargets> targets = builder.build();
  ASSERT_TRUE(targets.is_ok()) << targets.status().message();
  const std::vector<Vec3f> base = testing::random_points(random, count);
  const std::vector<float> weights = {0.3f, -0.7f, 1.0f, 0.0f, 0.25f, 2.0f, 0.5f};
  std::vector<Vec3f> serial(count), parallel(count), ranged(count);
  BlendShapeJob job;
  job.targets = &*targets;
  job.base = base;
  job.weights = weights;
  job.out = serial;
  ASSERT_TRUE(job.run());
  job.out = parallel;
  ASSERT_TRUE(job.run_parallel(101));
  EXPECT_TRUE(points_identical(parallel, serial));
  job.out = ranged;
  for (std::size_t begin = 0; begin < count; begin += 4096) ASSERT_TRUE(job.run(begin, std::min(count, begin + 4096)));
  EXPECT_TRUE(points_identical(ranged, serial)) << "sparse targets are cut at range ends by binary search";

  // And against a naive sum.
  std::vector<Vec3f> expected = base;
  for (std::size_t t = 0; t < targets->target_count(); ++t) {
    const BlendShapeTargets::Target target = targets->target(t);
    for (std::size_t i = 0; i < target.deltas.size(); ++i) {
      const std::size_t v = target.dense ? i : target.indices[i];
      expected[v] += weights[t] * target.deltas[i];
    }
  }
  EXPECT_TRUE(points_near(serial, expected, 1e-6));
}

}  // namespace
}  // namespace rigel::ops
