#include "rigel/math/dual_quat.h"

#include <gtest/gtest.h>

#include <vector>

#include "math_test_util.h"
#include "rigel/math/transform.h"

namespace rigel::math {
namespace {

using testing::near;
using testing::Random;
using testing::same_rotation;
using testing::to_mat4;

DualQuat random_dq(Random& random) { return DualQuat::from_rigid(random.quat(), random.vec3(-10, 10)); }

// real . dual = 0 and |real| = 1.
::testing::AssertionResult is_unit(const DualQuat& dq, double tolerance) {
  const double norm_error = std::abs(dq.real.norm() - 1.0);
  const double dot = std::abs(dq.real.coeffs().dot(dq.dual.coeffs()));
  if (norm_error <= tolerance && dot <= tolerance) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "|real| - 1 = " << norm_error << ", real . dual = " << dot;
}

TEST(DualQuat, defaults_are_identity) {
  const DualQuat identity;
  EXPECT_TRUE(near(identity.to_matrix(), Mat4::Identity(), 0.0)) << "a default dual quaternion is the identity";
  EXPECT_TRUE(near(identity.transform_point(Vec3(1, 2, 3)), Vec3(1, 2, 3), 0.0))
      << "the identity leaves points where they are";
}

TEST(DualQuat, from_rigid__round_trips_rotation_and_translation) {
  Random random(31);
  for (int n = 0; n < 200; ++n) {
    const Quat r = random.quat();
    const Vec3 t = random.vec3(-100, 100);
    const DualQuat dq = DualQuat::from_rigid(r, t);
    EXPECT_TRUE(is_unit(dq, 1e-13)) << "from_rigid should build a unit dual quaternion";
    EXPECT_TRUE(same_rotation(dq.rotation(), r, 1e-15)) << "rotation() should give back the rotation";
    EXPECT_TRUE(near(dq.translation(), t, 1e-12)) << "translation() should give back the translation";
    EXPECT_TRUE(near(dq.to_matrix(), to_mat4(r.toRotationMatrix(), t), 1e-12)) << "to_matrix() should be T * R";
  }
}

TEST(DualQuat, from_rigid__normalises_the_rotation) {
  const Quat r(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()));
  const DualQuat dq = DualQuat::from_rigid(Quat(r.coeffs() * 3.0), Vec3(1, -2, 4));
  EXPECT_TRUE(is_unit(dq, 1e-15)) << "a non-unit rotation should be normalised";
  EXPECT_TRUE(near(dq.translation(), Vec3(1, -2, 4), 1e-14)) << "without changing the translation";
}

TEST(DualQuat, from_matrix__round_trips_rigid_and_drops_scale) {
  Random random(32);
  for (int n = 0; n < 200; ++n) {
    const Quat r = random.quat();
    const Vec3 t = random.vec3(-10, 10);
    const Mat4 rigid = to_mat4(r.toRotationMatrix(), t);
    EXPECT_TRUE(near(DualQuat::from_matrix(rigid).to_matrix(), rigid, 1e-12))
        << "a rigid matrix should survive matrix -> dual quaternion -> matrix";
    const Mat4 scaled = trs_matrix(t, r, random.scale(false));
    EXPECT_TRUE(near(DualQuat::from_matrix(scaled).to_matrix(), rigid_part(scaled), 1e-12))
        << "from_matrix should keep only the rigid part of a scaled matrix";
  }
}

TEST(DualQuat, multiplication__matches_matrix_product) {
  Random random(33);
  for (int n = 0; n < 200; ++n) {
    const DualQuat a = random_dq(random);
    const DualQuat b = random_dq(random);
    const DualQuat ab = a * b;
    EXPECT_TRUE(near(ab.to_matrix(), a.to_matrix() * b.to_matrix(), 1e-12))
        << "(a * b) should apply b first, then a, as the matrix product does";
    EXPECT_TRUE(is_unit(ab, 1e-13)) << "a product of unit dual quaternions should be unit";
  }
}

TEST(DualQuat, conjugate__is_the_inverse) {
  Random random(34);
  for (int n = 0; n < 100; ++n) {
    const DualQuat dq = random_dq(random);
    EXPECT_TRUE(near((dq * dq.conjugate()).to_matrix(), Mat4::Identity(), 1e-12))
        << "dq * conjugate(dq) should be the identity";
    EXPECT_TRUE(near(dq.conjugate().to_matrix(), affine_inverse(dq.to_matrix()), 1e-12))
        << "conjugate() should be the inverse transform";
  }
}

TEST(DualQuat, normalized__restores_unit_without_moving_anything) {
  Random random(35);
  for (int n = 0; n < 100; ++n) {
    const DualQuat dq = random_dq(random);
    DualQuat scaled;
    scaled.real = Quat(dq.real.coeffs() * 2.5);
    scaled.dual = Quat(dq.dual.coeffs() * 2.5);
    const DualQuat back = scaled.normalized();
    EXPECT_TRUE(is_unit(back, 1e-14)) << "normalized() should give a unit dual quaternion";
    EXPECT_TRUE(near(back.real.coeffs(), dq.real.coeffs(), 1e-14)) << "the real part should come back";
    EXPECT_TRUE(near(back.dual.coeffs(), dq.dual.coeffs(), 1e-13)) << "the dual part should come back";
  }
  DualQuat zero;
  zero.real = Quat(0, 0, 0, 0);
  EXPECT_TRUE(near(zero.normalized().to_matrix(), Mat4::Identity(), 0.0))
      << "a zero real part cannot be normalised and should give the identity";
}

TEST(DualQuat, transform_point__matches_matrix) {
  Random random(36);
  for (int n = 0; n < 200; ++n) {
    const DualQuat dq = random_dq(random);
    const Vec3 p = random.vec3(-10, 10);
    EXPECT_TRUE(near(dq.transform_point(p), (dq.to_matrix() * p.homogeneous()).head<3>(), 1e-12))
        << "transform_point should agree with the matrix";
  }
  const DualQuat turn = DualQuat::from_rigid(Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ())), Vec3(0, 0, 1));
  EXPECT_TRUE(near(turn.transform_point(Vec3(1, 0, 0)), Vec3(0, 1, 1), 1e-15))
      << "x turned 90 degrees about z is y, then moved up by 1";
}

TEST(DualQuat, blend__of_equal_inputs_is_that_input) {
  Random random(37);
  for (int n = 0; n < 100; ++n) {
    const DualQuat dq = random_dq(random);
    DualQuat negated;  // the same transform with the opposite sign
    negated.real = Quat(-dq.real.coeffs());
    negated.dual = Quat(-dq.dual.coeffs());
    const DualQuat inputs[] = {dq, dq};
    const double weights[] = {0.3, 0.7};
    EXPECT_TRUE(near(blend(inputs, weights, 2).to_matrix(), dq.to_matrix(), 1e-12))
        << "blending a transform with itself should give it back";
    const DualQuat opposite[] = {dq, negated};
    const double even[] = {0.5, 0.5};
    EXPECT_TRUE(near(blend(opposite, even, 2).to_matrix(), dq.to_matrix(), 1e-12))
        << "q and -q are the same transform: the sign flip should stop them cancelling";
    const double unnormalised[] = {2.0, 5.0};
    EXPECT_TRUE(near(blend(inputs, unnormalised, 2).to_matrix(), dq.to_matrix(), 1e-12))
        << "weights need not sum to one";
  }
}

TEST(DualQuat, blend__halfway_between_two_rotations) {
  const DualQuat a = DualQuat::from_rigid(Quat::Identity(), Vec3::Zero());
  const DualQuat b = DualQuat::from_rigid(Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ())), Vec3::Zero());
  const DualQuat inputs[] = {a, b};
  const double weights[] = {0.5, 0.5};
  const DualQuat mid = blend(inputs, weights, 2);
  EXPECT_TRUE(same_rotation(mid.rotation(), Quat(Eigen::AngleAxisd(kPi / 4, Vec3::UnitZ())), 1e-15))
      << "an even blend of 0 and 90 degrees about z should be 45 degrees";
  EXPECT_TRUE(is_unit(mid, 1e-15)) << "the blend should be normalised";

  // Pure translations blend linearly.
  const DualQuat ta = DualQuat::from_rigid(Quat::Identity(), Vec3(0, 0, 0));
  const DualQuat tb = DualQuat::from_rigid(Quat::Identity(), Vec3(4, 0, 2));
  const DualQuat moves[] = {ta, tb};
  const double quarter[] = {0.75, 0.25};
  EXPECT_TRUE(near(blend(moves, quarter, 2).translation(), Vec3(1, 0, 0.5), 1e-15))
      << "translations alone should blend linearly";
}

TEST(DualQuat, blend__does_not_depend_on_the_sign_of_later_inputs) {
  Random random(38);
  for (int n = 0; n < 100; ++n) {
    const DualQuat a = random_dq(random);
    const DualQuat b = random_dq(random);
    DualQuat b_negated;
    b_negated.real = Quat(-b.real.coeffs());
    b_negated.dual = Quat(-b.dual.coeffs());
    const DualQuat inputs[] = {a, b};
    const DualQuat flipped[] = {a, b_negated};
    const double weights[] = {0.4, 0.6};
    EXPECT_TRUE(near(blend(flipped, weights, 2).to_matrix(), blend(inputs, weights, 2).to_matrix(), 1e-12))
        << "b and -b are the same transform, so the blend should not change when b's sign does";
  }
}

TEST(DualQuat, blend__empty_or_zero_weights_give_identity) {
  const DualQuat dq = DualQuat::from_rigid(Quat(Eigen::AngleAxisd(1.0, Vec3::UnitX())), Vec3(1, 2, 3));
  const double zero[] = {0.0};
  EXPECT_TRUE(near(blend(&dq, zero, 1).to_matrix(), Mat4::Identity(), 0.0))
      << "zero total weight has nothing to normalise and should give the identity";
  EXPECT_TRUE(near(blend(nullptr, nullptr, 0).to_matrix(), Mat4::Identity(), 0.0))
      << "blending nothing should give the identity";
}

}  // namespace
}  // namespace rigel::math
