// Constraint kernels: a test per documented validate() failure of each job,
// and behaviour against hand-computed answers.

#include "rigel/ops/constraints/constraints.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace rigel::ops::constraints {
namespace {

using math::Mat3;
using math::kPi;

constexpr double kTol = 1e-9;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

Quat axis_angle(double radians, const Vec3& axis) { return Quat(Eigen::AngleAxisd(radians, axis.normalized())); }

Mat4 trs(const Vec3& t, const Quat& r, const Vec3& s) { return math::trs_matrix(t, r, s); }

// Same rotation (q and -q are the same rotation).
::testing::AssertionResult same_rotation(const Quat& a, const Quat& b, double tol = kTol) {
  const double d = std::abs(a.normalized().dot(b.normalized()));
  if (d > 1.0 - tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "rotations differ: |dot| = " << d << " a=" << a.coeffs().transpose()
                                       << " b=" << b.coeffs().transpose();
}

::testing::AssertionResult near_mat(const Mat4& a, const Mat4& b, double tol = kTol) {
  if (math::is_near(a, b, tol)) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "\n" << a << "\n!=\n" << b;
}

::testing::AssertionResult near_vec(const Vec3& a, const Vec3& b, double tol = kTol) {
  if ((a - b).cwiseAbs().maxCoeff() <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << a.transpose() << " != " << b.transpose();
}

// Two targets, a job's spans point at these.
struct Fixture {
  std::vector<Mat4> world = {trs(Vec3(1, 2, 3), axis_angle(0.3, Vec3(0, 0, 1)), Vec3::Ones()),
                             trs(Vec3(-1, 0, 2), axis_angle(-0.4, Vec3(1, 1, 0)), Vec3::Ones())};
  std::vector<double> weights = {1.0, 1.0};
  std::vector<Mat4> offsets = {Mat4::Identity(), Mat4::Identity()};
  TargetSpans spans() const { return {world, weights, offsets}; }
};

Mat4 not_affine() {
  Mat4 m = Mat4::Identity();
  m(3, 0) = 0.5;
  return m;
}
Mat4 not_finite() {
  Mat4 m = Mat4::Identity();
  m(0, 3) = kNaN;
  return m;
}

// The target-span failures every job documents. `make` returns a valid job
// over the fixture's spans (which this function edits between checks).
template <typename Job, typename Make>
void expect_target_failures(Fixture& f, Make make, bool offsets_optional) {
  {
    Job job = make();
    EXPECT_TRUE(job.validate()) << "the fixture job should be valid";
  }
  {
    Job job = make();
    job.targets = TargetSpans{};
    EXPECT_FALSE(job.validate()) << "a job without targets should be rejected";
    EXPECT_FALSE(job.run()) << "run() should refuse an invalid job";
  }
  {
    Job job = make();
    job.targets.weights = std::span<const double>(f.weights).first(1);
    EXPECT_FALSE(job.validate()) << "fewer weights than targets should be rejected";
  }
  {
    Job job = make();
    job.targets.offsets = std::span<const Mat4>(f.offsets).first(1);
    EXPECT_FALSE(job.validate()) << "fewer offsets than targets should be rejected";
  }
  {
    Job job = make();
    job.targets.offsets = {};
    EXPECT_EQ(job.validate(), offsets_optional) << "empty offsets are allowed only where documented";
  }
  for (const double bad : {-0.5, kNaN, std::numeric_limits<double>::infinity()}) {
    f.weights[1] = bad;
    Job job = make();
    EXPECT_FALSE(job.validate()) << "weight " << bad << " should be rejected";
    f.weights[1] = 1.0;
  }
  for (const Mat4& bad : {not_affine(), not_finite()}) {
    const Mat4 keep_world = f.world[1];
    f.world[1] = bad;
    EXPECT_FALSE(make().validate()) << "a non-affine or non-finite target world matrix should be rejected";
    f.world[1] = keep_world;
    f.offsets[0] = bad;
    EXPECT_FALSE(make().validate()) << "a non-affine or non-finite offset should be rejected";
    f.offsets[0] = Mat4::Identity();
  }
}

template <typename Job, typename Make>
void expect_matrix_field_failures(Make make, Mat4 Job::*field, const char* name) {
  for (const Mat4& bad : {not_affine(), not_finite()}) {
    Job job = make();
    job.*field = bad;
    EXPECT_FALSE(job.validate()) << name << " not affine or not finite should be rejected";
  }
}

// ---- parent: validate ---------------------------------------------------------

struct ParentMake {
  Fixture* f;
  Mat4* out;
  ParentConstraintJob operator()() const {
    ParentConstraintJob job;
    job.targets = f->spans();
    job.output = out;
    return job;
  }
};

TEST(ParentConstraintJob, validate__rejects_null_output) {
  Fixture f;
  Mat4 out;
  ParentConstraintJob job = ParentMake{&f, &out}();
  job.output = nullptr;
  EXPECT_FALSE(job.validate()) << "a null output should be rejected";
}

TEST(ParentConstraintJob, validate__rejects_bad_targets) {
  Fixture f;
  Mat4 out;
  expect_target_failures<ParentConstraintJob>(f, ParentMake{&f, &out}, false);
}

TEST(ParentConstraintJob, validate__rejects_bad_parent_inverse_and_rest) {
  Fixture f;
  Mat4 out;
  expect_matrix_field_failures(ParentMake{&f, &out}, &ParentConstraintJob::parent_inverse, "parent_inverse");
  expect_matrix_field_failures(ParentMake{&f, &out}, &ParentConstraintJob::rest_local, "rest_local");
}

TEST(ParentConstraintJob, run__invalid_job_writes_nothing) {
  Fixture f;
  Mat4 out = Mat4::Constant(42.0);
  ParentConstraintJob job = ParentMake{&f, &out}();
  job.parent_inverse = not_affine();
  EXPECT_FALSE(job.run());
  EXPECT_EQ(out(0, 0), 42.0) << "an invalid job should leave the output untouched";
}

// ---- parent: behaviour --------------------------------------------------------

Mat4 run_parent(const ParentConstraintJob& job) {
  Mat4 out = Mat4::Constant(kNaN);
  ParentConstraintJob j = job;
  j.output = &out;
  EXPECT_TRUE(j.run());
  return out;
}

TEST(ParentConstraintJob, run__single_target_reproduces_its_world_matrix) {
  // A scaled, sheared, rotated target: the decompose/blend/compose round trip
  // must give it back.
  math::TransformParts parts;
  parts.translate = Vec3(3, -2, 1);
  parts.rotate = Vec3(0.3, -0.7, 1.1);
  parts.scale = Vec3(2, 0.5, 3);
  parts.shear = Vec3(0.2, -0.1, 0.3);
  const std::vector<Mat4> world = {math::compose(parts)};
  const std::vector<double> weights = {1.0};
  const std::vector<Mat4> offsets = {Mat4::Identity()};
  ParentConstraintJob job;
  job.targets = {world, weights, offsets};
  EXPECT_TRUE(near_mat(run_parent(job), world[0])) << "one target at weight 1 is the target";

  const Mat4 parent_world = trs(Vec3(1, 1, 1), axis_angle(0.5, Vec3(0, 1, 0)), Vec3(2, 2, 2));
  job.parent_inverse = math::affine_inverse(parent_world);
  EXPECT_TRUE(near_mat(parent_world * run_parent(job), world[0]))
      << "the local matrix under a parent should put the driven on the target in world";
}

TEST(ParentConstraintJob, run__two_halves_give_midpoint_and_half_way_rotation) {
  const Quat qa = axis_angle(0.2, Vec3(0, 0, 1));
  const Quat qb = axis_angle(1.4, Vec3(1, 2, 0));
  const std::vector<Mat4> world = {trs(Vec3(0, 0, 0), qa, Vec3::Ones()), trs(Vec3(2, 4, -6), qb, Vec3(3, 3, 3))};
  const std::vector<double> weights = {0.5, 0.5};
  const std::vector<Mat4> offsets(2, Mat4::Identity());
  ParentConstraintJob job;
  job.targets = {world, weights, offsets};
  const math::Decomposed d = math::decompose(run_parent(job));
  EXPECT_TRUE(near_vec(d.translate, Vec3(1, 2, -3))) << "the midpoint";
  EXPECT_TRUE(same_rotation(d.rotation, qa.slerp(0.5, qb))) << "for two targets the blend is the slerp half-way";
  EXPECT_TRUE(near_vec(d.scale, Vec3(2, 2, 2))) << "the mean scale";
}

TEST(ParentConstraintJob, run__weights_are_normalised) {
  Fixture f;
  ParentConstraintJob job;
  f.weights = {3.0, 1.0};
  job.targets = f.spans();
  const Mat4 unnormalised = run_parent(job);
  f.weights = {0.75, 0.25};
  EXPECT_TRUE(near_mat(run_parent(job), unnormalised)) << "weights 3:1 should act as 0.75:0.25";
  EXPECT_TRUE(near_vec(unnormalised.topRightCorner<3, 1>(), 0.75 * Vec3(1, 2, 3) + 0.25 * Vec3(-1, 0, 2)));
  f.weights = {2.0, 0.0};
  EXPECT_TRUE(near_mat(run_parent(job), f.world[0])) << "a lone weighted target at any weight is followed fully";
}

TEST(ParentConstraintJob, run__zero_total_weight_keeps_the_rest) {
  Fixture f;
  f.weights = {0.0, 0.0};
  ParentConstraintJob job;
  job.targets = f.spans();
  job.rest_local = trs(Vec3(5, 6, 7), axis_angle(0.1, Vec3(1, 0, 0)), Vec3::Ones());
  EXPECT_TRUE(near_mat(run_parent(job), job.rest_local, 0.0)) << "all weights 0: the driven stays at its rest";
}

TEST(ParentConstraintJob, run__maintain_offset_keeps_driven_then_follows) {
  const std::vector<Mat4> world0 = {trs(Vec3(1, 2, 3), axis_angle(0.7, Vec3(0, 1, 1)), Vec3(1, 2, 1))};
  const Mat4 driven_world = trs(Vec3(-4, 0, 1), axis_angle(-0.3, Vec3(1, 0, 0)), Vec3(1, 1, 1));
  const Mat4 parent_world = trs(Vec3(0, 1, 0), axis_angle(0.2, Vec3(0, 0, 1)), Vec3::Ones());
  const std::vector<double> weights = {1.0};
  const std::vector<Mat4> offsets = {compute_offset(world0[0], driven_world)};
  ParentConstraintJob job;
  job.targets = {world0, weights, offsets};
  job.parent_inverse = math::affine_inverse(parent_world);
  EXPECT_TRUE(near_mat(parent_world * run_parent(job), driven_world)) << "at creation the driven does not move";

  const Mat4 move = trs(Vec3(0, 0, 5), axis_angle(1.0, Vec3(0, 1, 0)), Vec3::Ones());
  const std::vector<Mat4> world1 = {move * world0[0]};
  job.targets.world = world1;
  EXPECT_TRUE(near_mat(parent_world * run_parent(job), move * driven_world))
      << "after the target moves, the driven moves with it as if parented";
}

TEST(ParentConstraintJob, run__blends_q_and_minus_q_the_short_way) {
  // +170 and -170 degrees about z: the short way between them passes through
  // 180 degrees, not 0. Their quaternions have a negative dot product.
  const std::vector<Mat4> world = {trs(Vec3::Zero(), axis_angle(170.0 * math::kDegToRad, Vec3::UnitZ()), Vec3::Ones()),
                                   trs(Vec3::Zero(), axis_angle(-170.0 * math::kDegToRad, Vec3::UnitZ()), Vec3::Ones())};
  const std::vector<double> weights = {0.5, 0.5};
  const std::vector<Mat4> offsets(2, Mat4::Identity());
  ParentConstraintJob job;
  job.targets = {world, weights, offsets};
  const Mat4 out = run_parent(job);
  EXPECT_TRUE(near_vec(out.topLeftCorner<3, 3>() * Vec3::UnitX(), -Vec3::UnitX())) << "half-way is 180 degrees";
}

TEST(ParentConstraintJob, run__rigid_keeps_driven_scale_and_no_shear) {
  math::TransformParts parts;
  parts.translate = Vec3(1, 0, 0);
  parts.rotate = Vec3(0, 0, 0.5);
  parts.scale = Vec3(2, 3, 4);
  parts.shear = Vec3(0.5, 0.0, 0.25);
  const std::vector<Mat4> world = {math::compose(parts)};
  const std::vector<double> weights = {1.0};
  std::vector<Mat4> offsets = {Mat4::Identity()};
  ParentConstraintJob job;
  job.targets = {world, weights, offsets};
  job.rigid = true;
  {
    const math::Decomposed d = math::decompose(run_parent(job));
    EXPECT_TRUE(near_vec(d.scale, Vec3::Ones())) << "no offset: the driven's own scale (1), not the target's";
    EXPECT_TRUE(near_vec(d.shear, Vec3::Zero())) << "and no shear";
    EXPECT_TRUE(same_rotation(d.rotation, axis_angle(0.5, Vec3::UnitZ()))) << "the target's rotation";
  }
  // Maintain offset with a driven of scale 0.5: in place at creation; when
  // the target then scales, the driven is moved by it but keeps scale 0.5.
  const Mat4 driven_world = trs(Vec3(2, 1, 0), axis_angle(0.2, Vec3::UnitX()), Vec3(0.5, 0.5, 0.5));
  offsets[0] = compute_offset(world[0], driven_world, true);
  EXPECT_TRUE(near_mat(run_parent(job), driven_world)) << "rigid maintain offset keeps the driven in place";
  parts.scale = Vec3(5, 1, 2);
  const std::vector<Mat4> scaled = {math::compose(parts)};
  job.targets.world = scaled;
  const Mat4 out = run_parent(job);
  const math::Decomposed d = math::decompose(out);
  EXPECT_TRUE(near_vec(d.scale, Vec3(0.5, 0.5, 0.5))) << "the driven keeps its own scale";
  EXPECT_TRUE(near_vec(d.shear, Vec3::Zero())) << "and gets no shear";
  const Vec3 expected_position =
      (scaled[0] * math::affine_inverse(world[0]) * driven_world).topRightCorner<3, 1>();
  EXPECT_TRUE(near_vec(out.topRightCorner<3, 1>(), expected_position)) << "the target's scale repositions it";
  ParentConstraintJob plain = job;
  plain.rigid = false;
  plain.targets.offsets = std::span<const Mat4>(offsets);
  EXPECT_FALSE(math::is_near(run_parent(plain), out, 1e-3)) << "the non-rigid variant would scale it";
}

TEST(RigidConcat, matches_concat_without_scale_shear_for_uniform_scale) {
  const Mat4 parent = trs(Vec3(1, 2, 3), axis_angle(0.8, Vec3(1, 1, 1)), Vec3(2, 2, 2));
  const Mat4 child = trs(Vec3(-1, 0, 4), axis_angle(-0.4, Vec3(0, 1, 0)), Vec3(1, 3, 0.5));
  EXPECT_TRUE(near_mat(rigid_concat(parent, child), math::concat_without_scale_shear(parent, child)))
      << "seed 001's concatMatrices and rigid_concat agree without non-uniform scale or shear";
}

TEST(ComputeOffset, singular_target_gives_identity) {
  Mat4 singular = Mat4::Identity();
  singular(1, 1) = 0.0;
  EXPECT_FALSE(is_offset_computable(singular));
  EXPECT_FALSE(is_offset_computable(not_finite()));
  EXPECT_TRUE(near_mat(compute_offset(singular, trs(Vec3(1, 1, 1), Quat::Identity(), Vec3::Ones())),
                       Mat4::Identity(), 0.0));
}

// ---- point ------------------------------------------------------------------

struct PointMake {
  Fixture* f;
  Vec3* out;
  PointConstraintJob operator()() const {
    PointConstraintJob job;
    job.targets = f->spans();
    job.output = out;
    return job;
  }
};

TEST(PointConstraintJob, validate__rejects_null_output) {
  Fixture f;
  Vec3 out;
  PointConstraintJob job = PointMake{&f, &out}();
  job.output = nullptr;
  EXPECT_FALSE(job.validate());
}

TEST(PointConstraintJob, validate__rejects_bad_targets) {
  Fixture f;
  Vec3 out;
  expect_target_failures<PointConstraintJob>(f, PointMake{&f, &out}, false);
}

TEST(PointConstraintJob, validate__rejects_bad_parent_inverse_and_rest) {
  Fixture f;
  Vec3 out;
  expect_matrix_field_failures(PointMake{&f, &out}, &PointConstraintJob::parent_inverse, "parent_inverse");
  PointConstraintJob job = PointMake{&f, &out}();
  job.rest_translate = Vec3(kNaN, 0, 0);
  EXPECT_FALSE(job.validate()) << "a non-finite rest translate should be rejected";
}

TEST(PointConstraintJob, run__midpoint_offset_parent_and_rest) {
  Fixture f;
  f.weights = {1.0, 3.0};
  Vec3 out;
  PointConstraintJob job = PointMake{&f, &out}();
  ASSERT_TRUE(job.run());
  EXPECT_TRUE(near_vec(out, 0.25 * Vec3(1, 2, 3) + 0.75 * Vec3(-1, 0, 2))) << "weighted mean, normalised";
  // A maintain offset of (1,0,0) in target 0's space (rotated 0.3 about z).
  f.weights = {1.0, 0.0};
  f.offsets[0] = trs(Vec3(1, 0, 0), Quat::Identity(), Vec3::Ones());
  job.parent_inverse = trs(Vec3(0, 0, -3), Quat::Identity(), Vec3::Ones());
  ASSERT_TRUE(job.run());
  EXPECT_TRUE(near_vec(out, Vec3(1 + std::cos(0.3), 2 + std::sin(0.3), 0)));
  f.weights = {0.0, 0.0};
  job.rest_translate = Vec3(9, 8, 7);
  ASSERT_TRUE(job.run());
  EXPECT_TRUE(near_vec(out, Vec3(9, 8, 7), 0.0)) << "zero total weight: rest";
}

// ---- orient -----------------------------------------------------------------

struct OrientMake {
  Fixture* f;
  Quat* out;
  OrientConstraintJob operator()() const {
    OrientConstraintJob job;
    job.targets = f->spans();
    job.output = out;
    return job;
  }
};

TEST(OrientConstraintJob, validate__rejects_null_output) {
  Fixture f;
  Quat out;
  OrientConstraintJob job = OrientMake{&f, &out}();
  job.output = nullptr;
  EXPECT_FALSE(job.validate());
}

TEST(OrientConstraintJob, validate__rejects_bad_targets) {
  Fixture f;
  Quat out;
  expect_target_failures<OrientConstraintJob>(f, OrientMake{&f, &out}, false);
}

TEST(OrientConstraintJob, validate__rejects_bad_parent_inverse_and_rest) {
  Fixture f;
  Quat out;
  expect_matrix_field_failures(OrientMake{&f, &out}, &OrientConstraintJob::parent_inverse, "parent_inverse");
  for (const Quat& bad : {Quat(0, 0, 0, 0), Quat(kNaN, 0, 0, 0)}) {
    OrientConstraintJob job = OrientMake{&f, &out}();
    job.rest_rotation = bad;
    EXPECT_FALSE(job.validate()) << "a zero or non-finite rest rotation should be rejected";
  }
}

TEST(OrientConstraintJob, run__shortest_path_parent_and_rest) {
  Fixture f;
  f.world = {trs(Vec3(1, 0, 0), axis_angle(170.0 * math::kDegToRad, Vec3::UnitZ()), Vec3(2, 2, 2)),
             trs(Vec3(0, 5, 0), axis_angle(-170.0 * math::kDegToRad, Vec3::UnitZ()), Vec3::Ones())};
  Quat out;
  OrientConstraintJob job = OrientMake{&f, &out}();
  ASSERT_TRUE(job.run());
  EXPECT_TRUE(same_rotation(out, axis_angle(kPi, Vec3::UnitZ()))) << "q and -q neighbours blend the short way";
  EXPECT_GE(out.w(), 0.0);
  f.weights = {1.0, 0.0};
  const Quat parent = axis_angle(0.4, Vec3::UnitX());
  job.parent_inverse = math::affine_inverse(trs(Vec3(3, 3, 3), parent, Vec3(2, 2, 2)));
  ASSERT_TRUE(job.run());
  EXPECT_TRUE(same_rotation(parent * out, axis_angle(170.0 * math::kDegToRad, Vec3::UnitZ())))
      << "the local rotation under the parent gives the target's world rotation";
  f.weights = {0.0, 0.0};
  job.rest_rotation = Quat(-2, 0, 0, 0);
  ASSERT_TRUE(job.run());
  EXPECT_TRUE(same_rotation(out, Quat::Identity())) << "rest, normalised";
}

// ---- scale ------------------------------------------------------------------

struct ScaleMake {
  Fixture* f;
  Vec3* out;
  ScaleConstraintJob operator()() const {
    ScaleConstraintJob job;
    job.targets = f->spans();
    job.output = out;
    return job;
  }
};

TEST(ScaleConstraintJob, validate__rejects_null_output) {
  Fixture f;
  Vec3 out;
  ScaleConstraintJob job = ScaleMake{&f, &out}();
  job.output = nullptr;
  EXPECT_FALSE(job.validate());
}

TEST(ScaleConstraintJob, validate__rejects_bad_targets) {
  Fixture f;
  Vec3 out;
  expect_target_failures<ScaleConstraintJob>(f, ScaleMake{&f, &out}, false);
}

TEST(ScaleConstraintJob, validate__rejects_bad_parent_inverse_and_rest) {
  Fixture f;
  Vec3 out;
  expect_matrix_field_failures(ScaleMake{&f, &out}, &ScaleConstraintJob::parent_inverse, "parent_inverse");
  ScaleConstraintJob job = ScaleMake{&f, &out}();
  job.rest_scale = Vec3(1, kNaN, 1);
  EXPECT_FALSE(job.validate()) << "a non-finite rest scale should be rejected";
}

TEST(ScaleConstraintJob, run__weighted_scale_parent_and_rest) {
  Fixture f;
  f.world = {trs(Vec3(1, 0, 0), axis_angle(0.3, Vec3::UnitY()), Vec3(2, 4, 6)),
             trs(Vec3(0, 5, 0), Quat::Identity(), Vec3(4, 2, 2))};
  Vec3 out;
  ScaleConstraintJob job = ScaleMake{&f, &out}();
  ASSERT_TRUE(job.run());
  EXPECT_TRUE(near_vec(out, Vec3(3, 3, 4)));
  job.parent_inverse = math::affine_inverse(trs(Vec3::Zero(), Quat::Identity(), Vec3(2, 2, 2)));
  ASSERT_TRUE(job.run());
  EXPECT_TRUE(near_vec(out, Vec3(1.5, 1.5, 2))) << "a parent scaled by 2 halves the local scale";
  f.weights = {0.0, 0.0};
  job.rest_scale = Vec3(7, 7, 7);
  ASSERT_TRUE(job.run());
  EXPECT_TRUE(near_vec(out, Vec3(7, 7, 7), 0.0));
}

// ---- aim --------------------------------------------------------------------

struct AimMake {
  Fixture* f;
  Quat* out;
  AimConstraintJob operator()() const {
    AimConstraintJob job;
    job.targets = f->spans();
    job.output = out;
    return job;
  }
};

TEST(AimConstraintJob, validate__rejects_null_output) {
  Fixture f;
  Quat out;
  AimConstraintJob job = AimMake{&f, &out}();
  job.output = nullptr;
  EXPECT_FALSE(job.validate());
}

TEST(AimConstraintJob, validate__rejects_bad_targets) {
  Fixture f;
  Quat out;
  expect_target_failures<AimConstraintJob>(f, AimMake{&f, &out}, true);
}

TEST(AimConstraintJob, validate__rejects_bad_axes) {
  Fixture f;
  Quat out;
  const AimMake make{&f, &out};
  for (const Vec3& bad : {Vec3(0, 0, 0), Vec3(1e-12, 0, 0), Vec3(kNaN, 1, 0)}) {
    AimConstraintJob job = make();
    job.aim_vector = bad;
    EXPECT_FALSE(job.validate()) << "aim vector " << bad.transpose() << " should be rejected";
    job = make();
    job.up_vector = bad;
    EXPECT_FALSE(job.validate()) << "up vector " << bad.transpose() << " should be rejected";
  }
  AimConstraintJob job = make();
  job.aim_vector = Vec3(0, 2, 0);
  EXPECT_FALSE(job.validate()) << "an aim vector parallel to the up vector should be rejected";
  job.aim_vector = Vec3(0, -2, 0);
  EXPECT_FALSE(job.validate()) << "antiparallel too";
}

TEST(AimConstraintJob, validate__rejects_bad_world_up_and_other_fields) {
  Fixture f;
  Quat out;
  const AimMake make{&f, &out};
  AimConstraintJob job = make();
  job.world_up_type = static_cast<WorldUpType>(kWorldUpTypeCount);
  EXPECT_FALSE(job.validate()) << "an unknown world-up type should be rejected";
  job = make();
  job.world_up_vector = Vec3(kNaN, 0, 0);
  EXPECT_FALSE(job.validate()) << "a non-finite world-up vector should be rejected";
  job = make();
  job.driven_position = Vec3(0, kNaN, 0);
  EXPECT_FALSE(job.validate()) << "a non-finite driven position should be rejected";
  for (const Quat& bad : {Quat(0, 0, 0, 0), Quat(kNaN, 0, 0, 0)}) {
    job = make();
    job.rest_rotation = bad;
    EXPECT_FALSE(job.validate()) << "a zero or non-finite rest rotation should be rejected";
    job = make();
    job.offset = bad;
    EXPECT_FALSE(job.validate()) << "a zero or non-finite offset should be rejected";
  }
  expect_matrix_field_failures(make, &AimConstraintJob::world_up_matrix, "world_up_matrix");
  expect_matrix_field_failures(make, &AimConstraintJob::parent_inverse, "parent_inverse");
}

Quat run_aim(AimConstraintJob job) {
  Quat out(kNaN, kNaN, kNaN, kNaN);
  job.output = &out;
  EXPECT_TRUE(job.run());
  EXPECT_TRUE(out.coeffs().allFinite()) << "never NaN";
  return out;
}

// One target at `target`, no offsets.
struct AimScene {
  std::vector<Mat4> world;
  std::vector<double> weights = {1.0};
  explicit AimScene(const Vec3& target) : world{trs(target, Quat::Identity(), Vec3::Ones())} {}
  AimConstraintJob job() const {
    AimConstraintJob j;
    j.targets = {world, weights, {}};
    return j;
  }
};

// The direction the up axis should take: world up without its aim component.
Vec3 projected(const Vec3& up, const Vec3& aim) { return (up - up.dot(aim.normalized()) * aim.normalized()).normalized(); }

TEST(AimConstraintJob, run__aims_in_every_world_up_mode) {
  const Vec3 driven(1, 1, 1);
  const Vec3 target(4, 2, -1);
  const Vec3 dir = (target - driven).normalized();
  AimScene scene(target);
  const Mat4 up_object = trs(Vec3(1, 1, 6), axis_angle(kPi / 2, Vec3::UnitX()), Vec3::Ones());
  struct Case {
    WorldUpType type;
    Vec3 expected_up;  // the world up before projection; zero for none
  };
  const Case cases[] = {
      {WorldUpType::kScene, Vec3::UnitY()},
      {WorldUpType::kObject, Vec3(0, 0, 5)},                 // toward the up object's position
      {WorldUpType::kObjectRotation, Vec3(0, 0, 1)},         // +Y turned 90 degrees about X
      {WorldUpType::kVector, Vec3(1, 0, 1)},
      {WorldUpType::kNone, Vec3::Zero()},
  };
  for (const Case& c : cases) {
    AimConstraintJob job = scene.job();
    job.driven_position = driven;
    job.aim_vector = Vec3(0, 0, 2);  // aim with +z, up +x: not the defaults
    job.up_vector = Vec3(1, 0, 0.5);
    job.world_up_type = c.type;
    job.world_up_vector = c.type == WorldUpType::kVector ? Vec3(1, 0, 1) : Vec3::UnitY();
    job.world_up_matrix = up_object;
    const Quat q = run_aim(job);
    const int mode = static_cast<int>(c.type);
    EXPECT_TRUE(near_vec(q * Vec3::UnitZ(), dir)) << "mode " << mode << ": the aim axis points at the target";
    const Vec3 up_axis = q * Vec3::UnitX();
    if (c.type == WorldUpType::kNone) {
      EXPECT_TRUE(same_rotation(q, Quat::FromTwoVectors(Vec3::UnitZ(), dir))) << "none: the smallest rotation";
    } else {
      EXPECT_TRUE(near_vec(up_axis, projected(c.expected_up, dir)))
          << "mode " << mode << ": the up axis is the world up made perpendicular to the aim";
    }
  }
}

TEST(AimConstraintJob, run__stable_when_target_crosses_the_up_direction) {
  // The target passes straight over the driven along x, through (0, 10, 0)
  // where the aim is parallel to the scene up.
  for (int i = -4; i <= 4; ++i) {
    const Vec3 target(i * 1e-7, 10.0, 0.0);
    AimScene scene(target);
    const Quat q = run_aim(scene.job());
    EXPECT_TRUE(near_vec(q * Vec3::UnitX(), target.normalized(), 1e-9)) << "step " << i << ": aim holds";
    EXPECT_NEAR((q * Vec3::UnitY()).dot(q * Vec3::UnitX()), 0.0, 1e-12) << "frame stays orthogonal";
  }
  // Straight down, antiparallel to the up and to the aim axis in kNone.
  AimScene below(Vec3(0, -3, 0));
  EXPECT_TRUE(near_vec(run_aim(below.job()) * Vec3::UnitX(), -Vec3::UnitY()));
  AimScene behind(Vec3(-3, 0, 0));
  AimConstraintJob job = behind.job();
  job.world_up_type = WorldUpType::kNone;
  EXPECT_TRUE(near_vec(run_aim(job) * Vec3::UnitX(), -Vec3::UnitX())) << "a half turn, no NaN";
}

TEST(AimConstraintJob, run__parent_offset_rest_and_weights) {
  AimScene scene(Vec3(0, 0, -5));
  AimConstraintJob job = scene.job();
  const Quat parent = axis_angle(0.6, Vec3(0, 1, 1));
  job.parent_inverse = math::affine_inverse(trs(Vec3(0, 0, 1), parent, Vec3::Ones()));
  const Quat world = run_aim(scene.job());
  EXPECT_TRUE(same_rotation(parent * run_aim(job), world)) << "local rotation under the parent";
  job = scene.job();
  job.offset = axis_angle(0.25, Vec3::UnitX());
  EXPECT_TRUE(same_rotation(run_aim(job), world * job.offset)) << "offset applied in the driven's space";
  job = scene.job();
  job.rest_rotation = axis_angle(0.5, Vec3::UnitY());
  job.driven_position = Vec3(0, 0, -5);
  EXPECT_TRUE(same_rotation(run_aim(job), job.rest_rotation)) << "target on the driven: rest";
  scene.weights = {0.0};
  job = scene.job();
  job.rest_rotation = axis_angle(0.5, Vec3::UnitY());
  EXPECT_TRUE(same_rotation(run_aim(job), job.rest_rotation)) << "zero weight: rest";
}

// ---- pole vector ------------------------------------------------------------

struct PoleMake {
  Fixture* f;
  Vec3* out;
  PoleVectorConstraintJob operator()() const {
    PoleVectorConstraintJob job;
    job.targets = f->spans();
    job.handle_position = Vec3(4, 0, 0);
    job.output = out;
    return job;
  }
};

TEST(PoleVectorConstraintJob, validate__rejects_null_output) {
  Fixture f;
  Vec3 out;
  PoleVectorConstraintJob job = PoleMake{&f, &out}();
  job.output = nullptr;
  EXPECT_FALSE(job.validate());
}

TEST(PoleVectorConstraintJob, validate__rejects_bad_targets) {
  Fixture f;
  Vec3 out;
  expect_target_failures<PoleVectorConstraintJob>(f, PoleMake{&f, &out}, true);
}

TEST(PoleVectorConstraintJob, validate__rejects_bad_positions_and_parent_inverse) {
  Fixture f;
  Vec3 out;
  const PoleMake make{&f, &out};
  PoleVectorConstraintJob job = make();
  job.start_position = Vec3(kNaN, 0, 0);
  EXPECT_FALSE(job.validate()) << "a non-finite start should be rejected";
  job = make();
  job.handle_position = Vec3(0, 0, kNaN);
  EXPECT_FALSE(job.validate()) << "a non-finite handle should be rejected";
  job = make();
  job.rest_pole_vector = Vec3(0, kNaN, 0);
  EXPECT_FALSE(job.validate()) << "a non-finite rest pole vector should be rejected";
  expect_matrix_field_failures(make, &PoleVectorConstraintJob::parent_inverse, "parent_inverse");
}

TEST(PoleVectorConstraintJob, run__hand_cases) {
  Fixture f;
  f.world = {trs(Vec3(1, 2, 3), Quat::Identity(), Vec3::Ones()), trs(Vec3(3, 2, 3), Quat::Identity(), Vec3::Ones())};
  f.weights = {1.0, 0.0};
  Vec3 out;
  PoleVectorConstraintJob job = PoleMake{&f, &out}();
  ASSERT_TRUE(job.run());
  EXPECT_TRUE(near_vec(out, Vec3(0, 2, 3))) << "start 0, handle on +x, pole (1,2,3): its offset from the x axis";
  f.weights = {1.0, 1.0};
  job.start_position = Vec3(1, 0, 0);
  job.handle_position = Vec3(1, 0, 4);
  ASSERT_TRUE(job.run());
  EXPECT_TRUE(near_vec(out, Vec3(1, 2, 0))) << "pole (2,2,3) from start (1,0,0), line along z";
  job.handle_position = job.start_position;
  ASSERT_TRUE(job.run());
  EXPECT_TRUE(near_vec(out, Vec3(1, 2, 3))) << "handle on the start: the whole offset";
  job.parent_inverse = trs(Vec3(9, 9, 9), axis_angle(kPi / 2, Vec3::UnitZ()), Vec3::Ones());
  ASSERT_TRUE(job.run());
  EXPECT_TRUE(near_vec(out, Vec3(-2, 1, 3))) << "a direction: parent_inverse turns it, its translation does not";
  job.parent_inverse = Mat4::Identity();
  job.handle_position = Vec3(3, 4, 6);  // the pole (2,2,3) lies on the start-handle line
  ASSERT_TRUE(job.run());
  EXPECT_TRUE(near_vec(out, Vec3::Zero())) << "pole on the line: zero";
  f.weights = {0.0, 0.0};
  job.rest_pole_vector = Vec3(0, 0, 1);
  ASSERT_TRUE(job.run());
  EXPECT_TRUE(near_vec(out, Vec3(0, 0, 1), 0.0)) << "zero weight: rest";
}

}  // namespace
}  // namespace rigel::ops::constraints
