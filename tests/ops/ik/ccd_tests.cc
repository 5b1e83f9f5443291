#include <gtest/gtest.h>

#include <vector>

#include "chain_solver_tests.h"
#include "ik_test_util.h"
#include "rigel/ops/ik/ccd.h"

namespace rigel::ops::ik {
namespace testing {
// The shared validity, hand-computed, invariant and sweep tests.
INSTANTIATE_TYPED_TEST_SUITE_P(Ccd, ChainSolverTest, ::testing::Types<CcdJob>);
}  // namespace testing

namespace {

using testing::chain_from_points;
using testing::ChainSolve;
using testing::same_rotation;
using testing::solve_chain;
using testing::vec_near;

// CCD as textbooks write it, on positions only: the reference the job is
// checked against (no limits).
std::vector<Vec3> naive_ccd(std::vector<Vec3> p, const Vec3& target, int sweeps) {
  for (int n = 0; n < sweeps; ++n) {
    for (std::size_t i = p.size() - 1; i-- > 0;) {
      const Quat g = Quat::FromTwoVectors(p.back() - p[i], target - p[i]);
      for (std::size_t k = i + 1; k < p.size(); ++k) p[k] = p[i] + g * (p[k] - p[i]);
    }
  }
  return p;
}

TEST(CcdJob, run__one_sweep_by_hand) {
  // (0,0,0), (1,0,0), (2,0,0) toward (0.5, 1.5, 0), one sweep:
  //   joint 1 turns the end from +x to dir(-0.5, 1.5): 1.892547 rad about z;
  //   joint 0 then turns (0.683772, 0.948683) onto dir(0.5, 1.5): 0.302772 rad.
  const std::vector<Mat4> chain = chain_from_points({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)});
  CcdJob job;
  job.target = Vec3(0.5, 1.5, 0);
  job.max_iterations = 1;
  const ChainSolve s = solve_chain(chain, job);
  EXPECT_TRUE(vec_near(s.positions[1], Vec3(0.954513538836348, 0.298167577342190, 0), 1e-14));
  EXPECT_TRUE(vec_near(s.positions[2], Vec3(0.369803254172584, 1.109409762517751, 0), 1e-14));
  EXPECT_TRUE(same_rotation(s.corrections[0], Quat(Eigen::AngleAxisd(0.302772331802485, Vec3::UnitZ())), 1e-14))
      << "joint 0's turn";
  EXPECT_TRUE(same_rotation(s.corrections[1], Quat(Eigen::AngleAxisd(1.892546881191539, Vec3::UnitZ())), 1e-14))
      << "joint 1's turn, in its own frame";
  EXPECT_EQ(s.result.iterations, 1);
  EXPECT_NEAR(s.result.error, 0.41171826075665974, 1e-14);
}

TEST(CcdJob, run__matches_the_naive_reference) {
  testing::Random random(41);
  for (int trial = 0; trial < 40; ++trial) {
    const std::vector<Vec3> points = testing::random_chain_points(random, 2 + static_cast<std::size_t>(trial % 12));
    const std::vector<Mat4> chain = chain_from_points(points);
    CcdJob job;
    job.target = random.unit() * random.uniform(0.2, 0.95) * testing::chain_length(chain);
    job.tolerance = 0.0;
    job.max_iterations = 1 + trial % 5;
    const ChainSolve s = solve_chain(chain, job);
    const std::vector<Vec3> expected = naive_ccd(points, job.target, job.max_iterations);
    for (std::size_t i = 0; i < points.size(); ++i) {
      EXPECT_TRUE(vec_near(s.positions[i], expected[i], 1e-10)) << "trial " << trial << " joint " << i;
    }
  }
}

TEST(CcdJob, run__lengths_do_not_drift_over_many_sweeps) {
  // An unreachable target under a limit runs every sweep; positions are
  // rebuilt from the rotations, so 5,000 sweeps leave lengths exact.
  const std::vector<Mat4> chain = testing::curled_ten();
  std::vector<JointLimit> limits(chain.size());
  limits[3].kind = LimitKind::kCone;
  limits[3].axis = Vec3::UnitX();
  limits[3].half_angle = 0.2;
  CcdJob job;
  job.target = Vec3(-30, -80, 20);  // far out of reach: never within tolerance
  job.max_iterations = 5000;
  const ChainSolve s = solve_chain(chain, job, limits);
  EXPECT_EQ(s.result.iterations, 5000);
  EXPECT_LE(testing::bone_length_error(chain, s.world), 1e-12);
  for (std::size_t i = 0; i + 1 < chain.size(); ++i) {
    const double before = (testing::position_of(chain[i + 1]) - testing::position_of(chain[i])).norm();
    EXPECT_NEAR((s.positions[i + 1] - s.positions[i]).norm(), before, 1e-13) << "bone " << i;
  }
}

}  // namespace
}  // namespace rigel::ops::ik
