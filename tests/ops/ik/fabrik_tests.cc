#include <gtest/gtest.h>

#include <vector>

#include "chain_solver_tests.h"
#include "ik_test_util.h"
#include "rigel/ops/ik/fabrik.h"

namespace rigel::ops::ik {
namespace testing {
// The shared validity, hand-computed, invariant and sweep tests.
INSTANTIATE_TYPED_TEST_SUITE_P(Fabrik, ChainSolverTest, ::testing::Types<FabrikJob>);
}  // namespace testing

namespace {

using testing::chain_from_points;
using testing::ChainSolve;
using testing::solve_chain;
using testing::vec_near;

// FABRIK as the paper writes it, on positions only: the reference the job
// is checked against (no limits).
std::vector<Vec3> naive_fabrik(std::vector<Vec3> p, const Vec3& target, int iterations) {
  std::vector<double> length(p.size() - 1);
  for (std::size_t i = 0; i + 1 < p.size(); ++i) length[i] = (p[i + 1] - p[i]).norm();
  const Vec3 root = p[0];
  for (int n = 0; n < iterations; ++n) {
    p.back() = target;
    for (std::size_t i = p.size() - 1; i-- > 0;) p[i] = p[i + 1] + (p[i] - p[i + 1]).normalized() * length[i];
    p[0] = root;
    for (std::size_t i = 0; i + 1 < p.size(); ++i) p[i + 1] = p[i] + (p[i + 1] - p[i]).normalized() * length[i];
  }
  return p;
}

TEST(FabrikJob, run__one_iteration_by_hand) {
  // (0,0,0), (1,0,0), (1,1,0) toward (0, 1.5, 0), one iteration:
  //   forward:  p2 = t, p1 = t + dir(p1 - t) = (0.5547, 0.6679)
  //   backward: p1 = dir(p1) = (0.638875, 0.769310), p2 = p1 + dir(t - p1)
  const std::vector<Mat4> chain = chain_from_points({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0)});
  FabrikJob job;
  job.target = Vec3(0, 1.5, 0);
  job.max_iterations = 1;
  const ChainSolve s = solve_chain(chain, job);
  EXPECT_TRUE(vec_near(s.positions[0], Vec3(0, 0, 0), 0.0)) << "the root does not move";
  EXPECT_TRUE(vec_near(s.positions[1], Vec3(0.638875309388755, 0.769310300888674, 0), 1e-14));
  EXPECT_TRUE(vec_near(s.positions[2], Vec3(-0.019350224350355, 1.522131094128250, 0), 1e-14));
  EXPECT_EQ(s.result.iterations, 1);
  EXPECT_NEAR(s.result.error, std::hypot(0.019350224350355, 0.022131094128250), 1e-14);
  EXPECT_FALSE(s.result.reached);
}

TEST(FabrikJob, run__matches_the_naive_reference) {
  testing::Random random(31);
  for (int trial = 0; trial < 40; ++trial) {
    const std::vector<Vec3> points = testing::random_chain_points(random, 2 + static_cast<std::size_t>(trial % 12));
    const std::vector<Mat4> chain = chain_from_points(points);
    FabrikJob job;
    job.target = random.unit() * random.uniform(0.2, 0.95) * testing::chain_length(chain);
    job.tolerance = 0.0;  // run exactly max_iterations
    job.max_iterations = 1 + trial % 7;
    const ChainSolve s = solve_chain(chain, job);
    const std::vector<Vec3> expected = naive_fabrik(points, job.target, job.max_iterations);
    for (std::size_t i = 0; i < points.size(); ++i) {
      EXPECT_TRUE(vec_near(s.positions[i], expected[i], 1e-12)) << "trial " << trial << " joint " << i;
    }
    EXPECT_EQ(s.result.iterations, job.max_iterations) << "a zero tolerance runs every iteration";
  }
}

TEST(FabrikJob, run__converges_fast_on_a_ten_joint_chain) {
  // Not a contract, a guard against regressions in convergence: FABRIK
  // reaches 1e-6 on a mildly bent 10-joint chain in a few dozen iterations.
  const std::vector<Mat4> chain = testing::curled_ten();
  FabrikJob job;
  job.target = Vec3(4, 5, 1);
  const ChainSolve s = solve_chain(chain, job);
  EXPECT_TRUE(s.result.reached);
  EXPECT_LE(s.result.iterations, 40);
}

}  // namespace
}  // namespace rigel::ops::ik
