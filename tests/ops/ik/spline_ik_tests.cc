#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "ik_test_util.h"
#include "rigel/ops/ik/spline_ik.h"

namespace rigel::ops::ik {
namespace {

using testing::angle_between;
using testing::frame_of;
using testing::kPi;
using testing::position_of;
using testing::vec_near;

struct Splined {
  bool ok = false;
  std::vector<Mat4> world;
  SplineIkResult result;
};

Splined run_spline(const std::vector<Vec3>& control_points, const std::vector<Mat4>& chain, SplineIkJob job,
                   std::size_t samples = 257) {
  Splined s;
  std::vector<double> arc(samples);
  s.world.assign(chain.size(), Mat4::Constant(-1.0));
  job.control_points = control_points;
  job.world = chain;
  job.arc_lengths = arc;
  job.world_out = s.world;
  job.result = &s.result;
  s.ok = job.run();
  EXPECT_TRUE(s.ok) << "the job should be valid";
  return s;
}

// Joints along x with bones 1, 2, 3 (identity frames).
std::vector<Mat4> chain_123() {
  return testing::chain_from_points({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(3, 0, 0), Vec3(6, 0, 0)});
}

// Distance from p to the curve: dense sampling, then a golden-section
// search around the best sample.
double distance_to_curve(const std::vector<Vec3>& cps, const Vec3& p) {
  const int samples = 1000;
  int best = 0;
  double best_distance = 1e300;
  for (int k = 0; k <= samples; ++k) {
    const double d = (bspline_point(cps, static_cast<double>(k) / samples) - p).norm();
    if (d < best_distance) {
      best_distance = d;
      best = k;
    }
  }
  double lo = std::max(0.0, (best - 1.0) / samples), hi = std::min(1.0, (best + 1.0) / samples);
  const double ratio = (std::sqrt(5.0) - 1.0) / 2.0;
  for (int n = 0; n < 200; ++n) {
    const double a = hi - ratio * (hi - lo), b = lo + ratio * (hi - lo);
    if ((bspline_point(cps, a) - p).norm() < (bspline_point(cps, b) - p).norm()) {
      hi = b;
    } else {
      lo = a;
    }
  }
  return (bspline_point(cps, 0.5 * (lo + hi)) - p).norm();
}

TEST(BsplinePoint, four_points_are_a_cubic_bezier_by_hand) {
  const std::vector<Vec3> cps = {Vec3(0, 0, 0), Vec3(1, 2, 0), Vec3(3, 2, 1), Vec3(4, 0, 0)};
  EXPECT_TRUE(vec_near(bspline_point(cps, 0.0), cps[0], 0.0)) << "clamped: starts on the first point";
  EXPECT_TRUE(vec_near(bspline_point(cps, 1.0), cps[3], 1e-15)) << "and ends on the last";
  EXPECT_TRUE(vec_near(bspline_point(cps, 0.5), (cps[0] + 3 * cps[1] + 3 * cps[2] + cps[3]) / 8, 1e-15))
      << "Bezier at 1/2: (P0 + 3 P1 + 3 P2 + P3) / 8";
  Vec3 tangent;
  bspline_point(cps, 0.0, &tangent);
  EXPECT_TRUE(vec_near(tangent, 3 * (cps[1] - cps[0]), 1e-14)) << "C'(0) = 3 (P1 - P0)";
  bspline_point(cps, 1.0, &tangent);
  EXPECT_TRUE(vec_near(tangent, 3 * (cps[3] - cps[2]), 1e-14)) << "C'(1) = 3 (P3 - P2)";
  bspline_point(cps, 0.5, &tangent);
  EXPECT_TRUE(vec_near(tangent, 0.75 * (cps[2] + cps[3] - cps[0] - cps[1]), 1e-14))
      << "C'(1/2) = 3/4 (P2 + P3 - P0 - P1)";
  EXPECT_TRUE(vec_near(bspline_point(cps, -1.0), cps[0], 0.0)) << "u is clamped to [0, 1]";
}

TEST(BsplinePoint, five_points_by_hand) {
  // Knots 0 0 0 0 1/2 1 1 1 1: at u = 1/2 the basis is (0, 1/4, 1/2, 1/4, 0).
  const std::vector<Vec3> cps = {Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(2, 3, 0), Vec3(3, 1, 0), Vec3(4, 0, 1)};
  EXPECT_TRUE(vec_near(bspline_point(cps, 0.5), 0.25 * cps[1] + 0.5 * cps[2] + 0.25 * cps[3], 1e-15));
  EXPECT_TRUE(vec_near(bspline_point(cps, 1.0), cps[4], 1e-15));
}

TEST(BsplinePoint, two_and_three_points_lower_the_degree) {
  const std::vector<Vec3> line = {Vec3(0, 0, 0), Vec3(2, 4, 6)};
  EXPECT_TRUE(vec_near(bspline_point(line, 0.25), Vec3(0.5, 1, 1.5), 1e-15)) << "two points: a line";
  Vec3 tangent;
  bspline_point(line, 0.7, &tangent);
  EXPECT_TRUE(vec_near(tangent, Vec3(2, 4, 6), 1e-15));
  const std::vector<Vec3> quadratic = {Vec3(0, 0, 0), Vec3(1, 2, 0), Vec3(2, 0, 0)};
  EXPECT_TRUE(vec_near(bspline_point(quadratic, 0.5), Vec3(1, 1, 0), 1e-15))
      << "three points: a quadratic Bezier, (P0 + 2 P1 + P2) / 4 at 1/2";
  bspline_point(quadratic, 0.0, &tangent);
  EXPECT_TRUE(vec_near(tangent, Vec3(2, 4, 0), 1e-15)) << "C'(0) = 2 (P1 - P0)";
}

TEST(BsplinePoint, tangent_matches_finite_differences) {
  const std::vector<Vec3> cps = {Vec3(0, 0, 0),  Vec3(1, 2, 0), Vec3(3, 2, 1), Vec3(4, 0, 0),
                                 Vec3(5, -1, 2), Vec3(7, 0, 0), Vec3(8, 3, 1)};
  for (double u : {0.01, 0.13, 0.25, 0.4, 0.5, 0.77, 0.99}) {
    Vec3 tangent;
    bspline_point(cps, u, &tangent);
    const double h = 1e-6;
    const Vec3 numeric = (bspline_point(cps, u + h) - bspline_point(cps, u - h)) / (2 * h);
    EXPECT_TRUE(vec_near(tangent, numeric, 1e-6)) << "u = " << u;
  }
}

TEST(SplineIkJob, validate__rejects_each_documented_failure) {
  const std::vector<Vec3> cps = {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(4, 0, 0), Vec3(6, 0, 0)};
  const std::vector<Mat4> chain = chain_123();
  std::vector<double> arc(33);
  std::vector<Mat4> out(chain.size());
  auto valid = [&] {
    SplineIkJob job;
    job.control_points = cps;
    job.world = chain;
    job.arc_lengths = arc;
    job.world_out = out;
    return job;
  };
  {
    SplineIkJob job = valid();
    EXPECT_TRUE(job.validate()) << "a well-formed job should validate";
    EXPECT_TRUE(job.run()) << "and run";
  }
  {
    SplineIkJob job;
    EXPECT_FALSE(job.validate()) << "an empty job should be rejected";
    EXPECT_FALSE(job.run()) << "run() should refuse a job that does not validate";
  }
  {
    SplineIkJob job = valid();
    job.control_points = std::span<const Vec3>(cps).first(1);
    EXPECT_FALSE(job.validate()) << "a single control point should be rejected";
  }
  {
    std::vector<Vec3> bad = cps;
    bad[2].y() = std::numeric_limits<double>::infinity();
    SplineIkJob job = valid();
    job.control_points = bad;
    EXPECT_FALSE(job.validate()) << "a control point that is not finite should be rejected";
  }
  {
    SplineIkJob job = valid();
    job.world = std::span<const Mat4>(chain).first(1);
    job.world_out = std::span<Mat4>(out).first(1);
    EXPECT_FALSE(job.validate()) << "a chain of one joint should be rejected";
  }
  {
    SplineIkJob job = valid();
    job.world_out = std::span<Mat4>(out).first(3);
    EXPECT_FALSE(job.validate()) << "world_out shorter than world should be rejected";
  }
  {
    std::vector<Mat4> same = chain;
    SplineIkJob job = valid();
    job.world = same;
    job.world_out = same;
    EXPECT_FALSE(job.validate()) << "world_out overlapping world should be rejected";
  }
  {
    SplineIkJob job = valid();
    job.arc_lengths = std::span<double>(arc).first(1);
    EXPECT_FALSE(job.validate()) << "an arc-length table of one entry should be rejected";
  }
  {
    std::vector<Mat4> bad = chain;
    bad[3](3, 1) = 0.25;
    SplineIkJob job = valid();
    job.world = bad;
    EXPECT_FALSE(job.validate()) << "a world matrix that is not affine should be rejected";
  }
  {
    SplineIkJob job = valid();
    job.aim_axis = Vec3(2, 0, 0);
    EXPECT_FALSE(job.validate()) << "an aim_axis that is not unit should be rejected";
    job = valid();
    job.up_axis = Vec3(0, 0.5, 0);
    EXPECT_FALSE(job.validate()) << "an up_axis that is not unit should be rejected";
    job = valid();
    job.up_axis = Vec3(1, 1, 0).normalized();
    EXPECT_FALSE(job.validate()) << "an up_axis not perpendicular to aim_axis should be rejected";
  }
  {
    SplineIkJob job = valid();
    job.up_vector = Vec3::Zero();
    EXPECT_FALSE(job.validate()) << "a zero up_vector should be rejected";
    job.up_vector = Vec3(0, std::numeric_limits<double>::quiet_NaN(), 0);
    EXPECT_FALSE(job.validate()) << "a NaN up_vector should be rejected";
  }
  {
    SplineIkJob job = valid();
    job.start_twist = std::numeric_limits<double>::infinity();
    EXPECT_FALSE(job.validate()) << "an infinite start_twist should be rejected";
    job = valid();
    job.end_twist = std::numeric_limits<double>::quiet_NaN();
    EXPECT_FALSE(job.validate()) << "a NaN end_twist should be rejected";
  }
}

TEST(SplineIkJob, run__straight_curve_by_hand) {
  // A straight curve along +y from (0, 0, 0) to (0, 10, 0): the chain of
  // bones 1, 2, 3 lies along it at 0, 1, 3, 6; aim x -> world +y, up y ->
  // the up vector (+z here), and z -> aim cross up = world +x.
  const std::vector<Vec3> cps = {Vec3(0, 0, 0), Vec3(0, 3, 0), Vec3(0, 7, 0), Vec3(0, 10, 0)};
  SplineIkJob job;
  job.up_vector = Vec3(0, 0, 1);
  const Splined s = run_spline(cps, chain_123(), job);
  const double ys[] = {0, 1, 3, 6};
  Mat3 expected;
  expected.col(0) = Vec3(0, 1, 0);
  expected.col(1) = Vec3(0, 0, 1);
  expected.col(2) = Vec3(1, 0, 0);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_TRUE(vec_near(position_of(s.world[i]), Vec3(0, ys[i], 0), 1e-12)) << "joint " << i;
    EXPECT_LE((s.world[i].topLeftCorner<3, 3>() - expected).cwiseAbs().maxCoeff(), 1e-12) << "joint " << i;
  }
  EXPECT_NEAR(s.result.curve_length, 10.0, 1e-12);
  EXPECT_NEAR(s.result.chain_length, 6.0, 0.0);
  EXPECT_FALSE(s.result.overran);
}

TEST(SplineIkJob, run__stretch_and_squash_by_hand) {
  // The same curve with stretch: the 6-long chain fills the 10-long curve,
  // every bone 10/6 longer; squash scales the other axes by sqrt(6/10).
  const std::vector<Vec3> cps = {Vec3(0, 0, 0), Vec3(0, 3, 0), Vec3(0, 7, 0), Vec3(0, 10, 0)};
  SplineIkJob job;
  job.up_vector = Vec3(0, 0, 1);
  job.stretch = true;
  job.squash = true;
  const Splined s = run_spline(cps, chain_123(), job, 4097);
  const double ys[] = {0, 10.0 / 6.0, 5, 10};
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_TRUE(vec_near(position_of(s.world[i]), Vec3(0, ys[i], 0), 1e-9)) << "joint " << i;
  }
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_NEAR(s.world[i].col(0).head<3>().norm(), 10.0 / 6.0, 1e-9) << "joint " << i << ": aim axis stretched";
    EXPECT_NEAR(s.world[i].col(1).head<3>().norm(), std::sqrt(0.6), 1e-9) << "joint " << i << ": squashed";
    EXPECT_NEAR(s.world[i].col(2).head<3>().norm(), std::sqrt(0.6), 1e-9) << "joint " << i << ": squashed";
  }
  EXPECT_NEAR(s.world[3].col(0).head<3>().norm(), 1.0, 1e-12) << "the end joint has no bone to stretch";

  // The child sits where its parent's stretched aim axis says.
  for (std::size_t i = 0; i < 3; ++i) {
    const double rest = (position_of(chain_123()[i + 1]) - position_of(chain_123()[i])).norm();
    EXPECT_TRUE(
        vec_near(position_of(s.world[i]) + s.world[i].col(0).head<3>() * rest, position_of(s.world[i + 1]), 1e-9));
  }

  job.squash = false;
  const Splined plain = run_spline(cps, chain_123(), job, 4097);
  EXPECT_NEAR(plain.world[0].col(1).head<3>().norm(), 1.0, 1e-12) << "stretch without squash keeps the other axes";

  // A shorter curve compresses the chain (stretch below 1).
  const std::vector<Vec3> short_cps = {Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(0, 2, 0), Vec3(0, 3, 0)};
  const Splined compressed = run_spline(short_cps, chain_123(), job, 4097);
  EXPECT_TRUE(vec_near(position_of(compressed.world[3]), Vec3(0, 3, 0), 1e-9)) << "the end on the curve's end";
  EXPECT_NEAR(compressed.world[0].col(0).head<3>().norm(), 0.5, 1e-9);
}

TEST(SplineIkJob, run__twist_goes_linearly_along_the_chain) {
  const std::vector<Vec3> cps = {Vec3(0, 0, 0), Vec3(0, 3, 0), Vec3(0, 7, 0), Vec3(0, 10, 0)};
  SplineIkJob job;
  job.up_vector = Vec3(0, 0, 1);
  job.start_twist = 0.2;
  job.end_twist = 0.2 + kPi / 2;
  const Splined s = run_spline(cps, chain_123(), job);
  const double fractions[] = {0.0, 1.0 / 6.0, 0.5, 1.0};
  for (std::size_t i = 0; i < 4; ++i) {
    const double twist = 0.2 + kPi / 2 * fractions[i];
    // Up (+z) turned about the aim (+y) by the twist.
    const Vec3 up = Vec3(0, 0, 1) * std::cos(twist) + Vec3(0, 1, 0).cross(Vec3(0, 0, 1)) * std::sin(twist);
    EXPECT_TRUE(vec_near(s.world[i].col(1).head<3>(), up, 1e-12)) << "joint " << i << " twisted by " << twist;
    EXPECT_TRUE(vec_near(s.world[i].col(0).head<3>(), Vec3(0, 1, 0), 1e-12)) << "the aim does not move";
  }
}

TEST(SplineIkJob, run__other_axes_and_joint_scale) {
  // Aim along -z, up along +x; input joints with uniform scale 2.
  const std::vector<Vec3> cps = {Vec3(0, 0, 0), Vec3(3, 0, 0), Vec3(7, 0, 0), Vec3(10, 0, 0)};
  const std::vector<Mat4> chain =
      testing::chain_from_points({Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(0, 3, 0)}, Vec3::UnitZ(), 2.0);
  SplineIkJob job;
  job.aim_axis = Vec3(0, 0, -1);
  job.up_axis = Vec3(1, 0, 0);
  job.up_vector = Vec3(0, 1, 0);
  const Splined s = run_spline(cps, chain, job);
  for (std::size_t i = 0; i < 3; ++i) {
    const Mat3 linear = s.world[i].topLeftCorner<3, 3>();
    EXPECT_TRUE(vec_near(linear * Vec3(0, 0, -1), Vec3(2, 0, 0), 1e-12)) << "joint " << i << ": -z aims down +x";
    EXPECT_TRUE(vec_near(linear * Vec3(1, 0, 0), Vec3(0, 2, 0), 1e-12)) << "joint " << i << ": +x points up (+y)";
    EXPECT_GT(linear.determinant(), 0.0) << "a proper frame";
  }
  EXPECT_TRUE(vec_near(position_of(s.world[2]), Vec3(3, 0, 0), 1e-12));
}

TEST(SplineIkJob, run__curved_curve_keeps_lengths_and_joints_on_the_curve) {
  testing::Random random(51);
  for (int trial = 0; trial < 10; ++trial) {
    std::vector<Vec3> cps(4 + static_cast<std::size_t>(trial % 5));
    for (std::size_t k = 0; k < cps.size(); ++k)
      cps[k] = Vec3(2.0 * static_cast<double>(k), 0, 0) + random.vec3(-1.5, 1.5);
    const std::vector<Mat4> chain = testing::chain_from_points(testing::random_chain_points(random, 12, 0.3));
    SplineIkJob job;
    job.up_vector = Vec3(0.1, 1, 0.2);
    const Splined s = run_spline(cps, chain, job);
    EXPECT_LE(testing::bone_length_error(chain, s.world), 1e-9) << "trial " << trial << ": bone lengths exact";
    for (std::size_t i = 0; i < chain.size(); ++i) {
      ASSERT_TRUE(testing::finite(s.world[i]));
      if (!s.result.overran) {
        EXPECT_LE(distance_to_curve(cps, position_of(s.world[i])), 1e-9) << "trial " << trial << " joint " << i;
      }
      const Mat3 frame = frame_of(s.world[i]);
      EXPECT_LE((frame.transpose() * frame - Mat3::Identity()).cwiseAbs().maxCoeff(), 1e-12) << "orthonormal";
      if (i + 1 < chain.size()) {
        const Vec3 to_child = (position_of(s.world[i + 1]) - position_of(s.world[i])).normalized();
        EXPECT_TRUE(vec_near(frame.col(0), to_child, 1e-12)) << "the aim axis points at the child";
      }
    }
  }
}

TEST(SplineIkJob, run__chain_longer_than_the_curve_continues_straight) {
  const std::vector<Vec3> cps = {Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(2, 1, 0), Vec3(3, 0, 0)};
  std::vector<Vec3> points;
  for (int i = 0; i < 10; ++i) points.push_back(Vec3(0.8 * i, 0, 0));
  const std::vector<Mat4> chain = testing::chain_from_points(points);
  SplineIkJob job;
  const Splined s = run_spline(cps, chain, job);
  EXPECT_TRUE(s.result.overran);
  EXPECT_LE(testing::bone_length_error(chain, s.world), 1e-12) << "lengths are kept past the end too";
  // Past the end the joints are on the line from (3, 0, 0) along the end
  // tangent 3 (P3 - P2) = (3, -3, 0).
  const Vec3 end = cps.back(), tangent = Vec3(1, -1, 0).normalized();
  int beyond = 0;
  for (const Mat4& m : s.world) {
    const Vec3 v = position_of(m) - end;
    if (v.dot(tangent) > 1e-9) {
      ++beyond;
      EXPECT_LE((v - tangent * v.dot(tangent)).norm(), 1e-12) << "on the tangent line";
      EXPECT_TRUE(vec_near(frame_of(m).col(0), tangent, 1e-12)) << "aimed along it";
    }
  }
  EXPECT_GE(beyond, 3) << "a 7.2-long chain on a curve about 4 long runs past its end";
}

TEST(SplineIkJob, run__degenerate_inputs_never_produce_nan) {
  const std::vector<Mat4> chain = chain_123();
  {
    const std::vector<Vec3> cps = {Vec3(0, 0, 0), Vec3(0, 5, 0), Vec3(0, 10, 0)};
    SplineIkJob job;
    job.up_vector = Vec3(0, 1, 0);  // along the curve
    const Splined s = run_spline(cps, chain, job);
    for (const Mat4& m : s.world) EXPECT_TRUE(testing::finite(m)) << "up vector along the aim";
    EXPECT_LE(testing::bone_length_error(chain, s.world), 1e-12);
  }
  {
    const std::vector<Vec3> cps = {Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1)};
    for (bool stretch : {false, true}) {
      SplineIkJob job;
      job.stretch = stretch;
      job.squash = true;
      const Splined s = run_spline(cps, chain, job);
      for (const Mat4& m : s.world) EXPECT_TRUE(testing::finite(m)) << "a curve of length 0, stretch " << stretch;
    }
  }
  {
    const std::vector<Vec3> cps = {Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(3, 0, 0), Vec3(3, 0, 0)};
    SplineIkJob job;
    const Splined s = run_spline(cps, chain, job);
    for (const Mat4& m : s.world) EXPECT_TRUE(testing::finite(m)) << "repeated control points (zero end tangents)";
    EXPECT_LE(testing::bone_length_error(chain, s.world), 1e-12);
  }
  {
    const std::vector<Mat4> folded =
        testing::chain_from_points({Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 0, 0)});
    const std::vector<Vec3> cps = {Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(2, 0, 0)};
    SplineIkJob job;
    job.stretch = true;
    const Splined s = run_spline(cps, folded, job);
    for (const Mat4& m : s.world) EXPECT_TRUE(testing::finite(m)) << "zero-length bones";
  }
  {
    const std::vector<Vec3> cps = {Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(2, 0, 0)};
    SplineIkJob job;
    const Splined s = run_spline(cps, chain, job, 2);  // the smallest table
    for (const Mat4& m : s.world) EXPECT_TRUE(testing::finite(m)) << "a two-entry arc table";
    EXPECT_LE(testing::bone_length_error(chain, s.world), 1e-12) << "lengths do not depend on the table";
  }
}

TEST(SplineIkJob, sweep__moving_a_control_point_is_continuous) {
  std::vector<Vec3> cps = {Vec3(0, 0, 0), Vec3(2, 1, 0), Vec3(4, -1, 0.5), Vec3(6, 1, 0), Vec3(8, 0, 0)};
  std::vector<Vec3> points;
  for (int i = 0; i < 12; ++i) points.push_back(Vec3(0.6 * i, 0, 0));
  const std::vector<Mat4> chain = testing::chain_from_points(points);
  for (bool stretch : {false, true}) {
    std::vector<Mat4> previous;
    Vec3 previous_offset = Vec3::Zero();
    for (int n = 0; n <= 120; ++n) {
      const double t = static_cast<double>(n) / 120;
      // The middle control point travels a loop.
      const Vec3 offset(1.5 * std::sin(2 * kPi * t), 2.0 * std::sin(4 * kPi * t), 1.0 - std::cos(2 * kPi * t));
      std::vector<Vec3> moved = cps;
      moved[2] += offset;
      SplineIkJob job;
      job.up_vector = Vec3(0, 0, 1);
      job.end_twist = 0.5;
      job.stretch = stretch;
      job.squash = stretch;
      const Splined s = run_spline(moved, chain, job);
      if (!stretch) {
        EXPECT_LE(testing::bone_length_error(chain, s.world), 1e-9) << "step " << n;
      }
      if (!previous.empty()) {
        const double step = (offset - previous_offset).norm();
        EXPECT_LT(testing::largest_turn(previous, s.world), 2.0 * step)
            << "step " << n << " (stretch " << stretch << "): joints turn at most 2 rad per unit of control travel";
        double worst_move = 0.0;
        for (std::size_t i = 0; i < chain.size(); ++i) {
          worst_move = std::max(worst_move, (position_of(s.world[i]) - position_of(previous[i])).norm());
        }
        EXPECT_LT(worst_move, 2.0 * step) << "step " << n << ": joints move at most twice the control point";
      }
      previous = s.world;
      previous_offset = offset;
    }
  }
}

}  // namespace
}  // namespace rigel::ops::ik
