#include "rigel/math/transform.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "math_test_util.h"

namespace rigel::math {
namespace {

using testing::expected_euler_matrix;
using testing::kAllOrders;
using testing::near;
using testing::Random;
using testing::rot_x;
using testing::rot_z;
using testing::same_rotation;
using testing::to_mat4;

Mat3 shear3(const Vec3& shear) {
  Mat3 m;
  m << 1, shear[0], shear[1], 0, 1, shear[2], 0, 0, 1;
  return m;
}

// compose() written as the literal product in its header.
Mat4 maya_product(const TransformParts& p) {
  const Mat3 rotate = p.rotate_mode == RotateMode::kQuaternion
                          ? p.rotate_quaternion.normalized().toRotationMatrix()
                          : expected_euler_matrix(p.rotate, p.rotate_order);
  const Mat4 T = translation_matrix(p.translate);
  const Mat4 Rpt = translation_matrix(p.rotate_pivot_translate);
  const Mat4 Rp = translation_matrix(p.rotate_pivot);
  const Mat4 JO = to_mat4(expected_euler_matrix(p.joint_orient, RotateOrder::kXYZ));
  const Mat4 R = to_mat4(rotate);
  const Mat4 RA = to_mat4(expected_euler_matrix(p.rotate_axis, RotateOrder::kXYZ));
  const Mat4 Rp_inv = translation_matrix(-p.rotate_pivot);
  const Mat4 Spt = translation_matrix(p.scale_pivot_translate);
  const Mat4 Sp = translation_matrix(p.scale_pivot);
  const Mat4 SH = to_mat4(shear3(p.shear));
  const Mat4 S = scale_matrix(p.scale);
  const Mat4 Sp_inv = translation_matrix(-p.scale_pivot);
  return T * Rpt * Rp * JO * R * RA * Rp_inv * Spt * Sp * SH * S * Sp_inv;
}

TransformParts random_parts(Random& random, bool pivots) {
  TransformParts p;
  p.translate = random.vec3(-10, 10);
  p.rotate = random.angles();
  p.rotate_order = static_cast<RotateOrder>(random.index(kRotateOrderCount));
  p.scale = random.scale(true);
  p.shear = random.vec3(-1, 1);
  p.rotate_axis = random.angles();
  p.joint_orient = random.angles();
  if (pivots) {
    p.rotate_pivot = random.vec3(-5, 5);
    p.rotate_pivot_translate = random.vec3(-5, 5);
    p.scale_pivot = random.vec3(-5, 5);
    p.scale_pivot_translate = random.vec3(-5, 5);
  }
  return p;
}

// T * R * SH * S from its pieces.
Mat4 trs_shear(const Vec3& t, const Quat& r, const Vec3& shear, const Vec3& s) {
  return to_mat4(r.toRotationMatrix() * shear3(shear) * s.asDiagonal(), t);
}

bool is_affine(const Mat4& m) { return m.row(3) == Eigen::RowVector4d(0, 0, 0, 1); }

TEST(Transform, compose__defaults_give_identity) {
  EXPECT_TRUE(near(compose(TransformParts{}), Mat4::Identity(), 0.0))
      << "every channel at its default should compose to the identity";
}

TEST(Transform, compose__each_channel_alone_matches_hand_computed_matrix) {
  {
    TransformParts p;
    p.translate = Vec3(1, 2, 3);
    Mat4 expected;
    expected << 1, 0, 0, 1, 0, 1, 0, 2, 0, 0, 1, 3, 0, 0, 0, 1;
    EXPECT_TRUE(near(compose(p), expected, 0.0)) << "translate alone is a pure translation";
  }
  {
    TransformParts p;
    p.rotate = Vec3(0, 0, kPi / 2);
    Mat4 expected;
    expected << 0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1;
    EXPECT_TRUE(near(compose(p), expected, 1e-15)) << "rotate z 90 degrees alone takes x to y";
  }
  for (RotateOrder order : kAllOrders) {
    TransformParts p;
    p.rotate = Vec3(0.3, -0.7, 1.2);
    p.rotate_order = order;
    EXPECT_TRUE(near(compose(p), to_mat4(expected_euler_matrix(p.rotate, order)), 1e-15))
        << "rotate alone in order " << rotate_order_name(order) << " is that order's Euler matrix";
  }
  {
    TransformParts p;
    p.rotate_mode = RotateMode::kQuaternion;
    p.rotate_quaternion = Quat(2.0 * std::cos(kPi / 4), 0, 0, 2.0 * std::sin(kPi / 4));  // 90 deg about z, norm 2
    p.rotate = Vec3(1, 2, 3);  // ignored in quaternion mode
    Mat4 expected;
    expected << 0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1;
    EXPECT_TRUE(near(compose(p), expected, 1e-15))
        << "in quaternion mode the (normalised) quaternion is the rotation and the Euler angles are ignored";
  }
  {
    TransformParts p;
    p.scale = Vec3(2, 3, -4);
    Mat4 expected;
    expected << 2, 0, 0, 0, 0, 3, 0, 0, 0, 0, -4, 0, 0, 0, 0, 1;
    EXPECT_TRUE(near(compose(p), expected, 0.0)) << "scale alone is a diagonal matrix";
  }
  {
    TransformParts p;
    p.shear = Vec3(0.5, 0.25, -0.75);
    Mat4 expected;
    expected << 1, 0.5, 0.25, 0, 0, 1, -0.75, 0, 0, 0, 1, 0, 0, 0, 0, 1;
    EXPECT_TRUE(near(compose(p), expected, 0.0))
        << "shear (xy, xz, yz) alone is upper unitriangular: x += xy*y + xz*z, y += yz*z";
  }
  {
    TransformParts p;
    p.rotate_axis = Vec3(0.4, 0.5, 0.6);
    p.rotate_order = RotateOrder::kZYX;  // must not affect the rotate axis
    const Mat3 expected = rot_z(0.6) * testing::rot_y(0.5) * rot_x(0.4);
    EXPECT_TRUE(near(compose(p), to_mat4(expected), 1e-15))
        << "rotate axis alone is an xyz Euler rotation whatever the rotate order";
  }
  {
    TransformParts p;
    p.joint_orient = Vec3(-0.4, 0.1, 0.9);
    p.rotate_order = RotateOrder::kYXZ;  // must not affect the joint orient
    const Mat3 expected = rot_z(0.9) * testing::rot_y(0.1) * rot_x(-0.4);
    EXPECT_TRUE(near(compose(p), to_mat4(expected), 1e-15))
        << "joint orient alone is an xyz Euler rotation whatever the rotate order";
  }
  {
    TransformParts p;
    p.rotate_pivot = Vec3(1, 2, 3);
    p.scale_pivot = Vec3(-3, 4, 5);
    EXPECT_TRUE(near(compose(p), Mat4::Identity(), 0.0))
        << "pivots alone, with nothing to rotate or scale about them, leave the identity";
  }
  {
    TransformParts p;
    p.rotate_pivot_translate = Vec3(1, 0, 0);
    p.scale_pivot_translate = Vec3(0, 2, 0);
    EXPECT_TRUE(near(compose(p), translation_matrix(Vec3(1, 2, 0)), 0.0))
        << "pivot translates alone are translations";
  }
  {
    TransformParts p;
    p.rotate = Vec3(0, 0, kPi / 2);
    p.rotate_pivot = Vec3(1, 0, 0);
    // x -> Rz(x - p) + p: the linear part is Rz, the translation p - Rz p.
    Mat4 expected;
    expected << 0, -1, 0, 1, 1, 0, 0, -1, 0, 0, 1, 0, 0, 0, 0, 1;
    EXPECT_TRUE(near(compose(p), expected, 1e-15)) << "rotating z 90 degrees about (1, 0, 0)";
  }
  {
    TransformParts p;
    p.scale = Vec3(2, 2, 2);
    p.scale_pivot = Vec3(1, 1, 1);
    Mat4 expected;
    expected << 2, 0, 0, -1, 0, 2, 0, -1, 0, 0, 2, -1, 0, 0, 0, 1;
    EXPECT_TRUE(near(compose(p), expected, 0.0)) << "scaling by 2 about (1, 1, 1)";
  }
}

TEST(Transform, compose__pivots_match_maya_order) {
  Random random(11);
  for (int n = 0; n < 500; ++n) {
    TransformParts p = random_parts(random, true);
    if (n % 2) {
      p.rotate_mode = RotateMode::kQuaternion;
      p.rotate_quaternion = Quat(random.quat().coeffs() * random.uniform(0.5, 2.0));
    }
    const Mat4 m = compose(p);
    EXPECT_TRUE(near(m, maya_product(p), 1e-11))
        << "compose should equal T * Rpt * Rp * JO * R * RA * Rp^-1 * Spt * Sp * SH * S * Sp^-1";
    EXPECT_TRUE(is_affine(m)) << "a composed matrix should have last row 0 0 0 1 exactly";
  }
}

TEST(Transform, compose__rotating_about_a_pivot_leaves_it_fixed) {
  Random random(12);
  for (int n = 0; n < 200; ++n) {
    TransformParts p;
    p.rotate = random.angles();
    p.rotate_order = static_cast<RotateOrder>(random.index(kRotateOrderCount));
    p.rotate_axis = random.angles();
    p.joint_orient = random.angles();
    p.rotate_pivot = random.vec3(-5, 5);
    const Vec3 pivot = p.rotate_pivot;
    EXPECT_TRUE(near(compose(p) * pivot.homogeneous(), pivot.homogeneous(), 1e-13))
        << "rotation (with rotate axis and joint orient) about the rotate pivot should not move the pivot";

    TransformParts s;
    s.scale = random.scale(true);
    s.shear = random.vec3(-1, 1);
    s.scale_pivot = random.vec3(-5, 5);
    EXPECT_TRUE(near(compose(s) * s.scale_pivot.homogeneous(), s.scale_pivot.homogeneous(), 1e-13))
        << "scale and shear about the scale pivot should not move the pivot";

    TransformParts all = random_parts(random, true);
    all.scale_pivot = all.rotate_pivot;
    all.scale_pivot_translate = Vec3::Zero();
    const Vec3 expected = all.rotate_pivot + all.rotate_pivot_translate + all.translate;
    EXPECT_TRUE(near(compose(all) * all.rotate_pivot.homogeneous(), expected.homogeneous(), 1e-12))
        << "with both pivots at one point, that point should move by the translates only";
  }
}

TEST(Transform, compose__joint_orient_applies_after_rotate_and_rotate_axis_before) {
  Random random(13);
  for (int n = 0; n < 100; ++n) {
    TransformParts p;
    p.rotate = random.angles();
    p.rotate_order = static_cast<RotateOrder>(random.index(kRotateOrderCount));
    p.rotate_axis = random.angles();
    p.joint_orient = random.angles();
    const Mat3 expected = expected_euler_matrix(p.joint_orient, RotateOrder::kXYZ) *
                          expected_euler_matrix(p.rotate, p.rotate_order) *
                          expected_euler_matrix(p.rotate_axis, RotateOrder::kXYZ);
    EXPECT_TRUE(near(compose(p), to_mat4(expected), 1e-14)) << "the rotation should be JO * R * RA";
  }
  // Order made visible: R = 90 about x, JO = 90 about z. R first: y -> z, then
  // JO leaves z. JO first would take y -> -x, and R would leave -x.
  TransformParts p;
  p.rotate = Vec3(kPi / 2, 0, 0);
  p.joint_orient = Vec3(0, 0, kPi / 2);
  EXPECT_TRUE(near(compose(p) * Vec4(0, 1, 0, 0), Vec4(0, 0, 1, 0), 1e-15))
      << "rotate should apply to a point before joint orient";
  TransformParts q;
  q.rotate = Vec3(0, 0, kPi / 2);
  q.rotate_axis = Vec3(kPi / 2, 0, 0);
  EXPECT_TRUE(near(compose(q) * Vec4(0, 1, 0, 0), Vec4(0, 0, 1, 0), 1e-15))
      << "rotate axis should apply to a point before rotate";
}

TEST(Transform, decompose__round_trips_random_scale_and_shear) {
  Random random(14);
  for (int n = 0; n < 1000; ++n) {
    const Vec3 t = random.vec3(-100, 100);
    const Quat r = random.quat();
    const Vec3 shear = random.vec3(-1, 1);
    const Vec3 s = random.scale(true);
    const Mat4 m = trs_shear(t, r, shear, s);
    const Decomposed d = decompose(m);

    EXPECT_TRUE(near(trs_shear(d.translate, d.rotation, d.shear, d.scale), m, 1e-12))
        << "T * R * SH * S of the decomposed parts should rebuild the matrix";
    EXPECT_NEAR(d.rotation.norm(), 1.0, 1e-14) << "the rotation should be a unit quaternion";
    EXPECT_GT(d.scale.y(), 0.0) << "only scale.x may carry a reflection";
    EXPECT_GT(d.scale.z(), 0.0) << "only scale.x may carry a reflection";
    EXPECT_EQ(d.scale.x() < 0.0, (m.topLeftCorner<3, 3>().determinant() < 0.0))
        << "scale.x should be negative exactly when the determinant is";
    EXPECT_TRUE(near(d.translate, t, 0.0)) << "the translate is the last column";

    if (s.y() > 0 && s.z() > 0) {
      // Already in canonical form: the parts themselves come back.
      EXPECT_TRUE(near(d.scale, s, 1e-12)) << "scale " << s.transpose() << " should come back";
      EXPECT_TRUE(near(d.shear, shear, 1e-12)) << "shear " << shear.transpose() << " should come back";
      EXPECT_TRUE(same_rotation(d.rotation, r, 1e-12)) << "the rotation should come back";
    }
  }
}

TEST(Transform, decompose__negative_determinant_goes_to_scale_x) {
  const Decomposed mirror_y = decompose(scale_matrix(Vec3(1, -1, 1)));
  EXPECT_TRUE(near(mirror_y.scale, Vec3(-1, 1, 1), 1e-15)) << "a mirror in y becomes scale.x = -1 ...";
  EXPECT_TRUE(same_rotation(mirror_y.rotation, Quat(0, 0, 0, 1), 1e-15)) << "... and 180 degrees about z";

  const Decomposed mirror_x = decompose(scale_matrix(Vec3(-2, 3, 4)));
  EXPECT_TRUE(near(mirror_x.scale, Vec3(-2, 3, 4), 1e-15)) << "a negative scale.x is kept as it is";
  EXPECT_TRUE(same_rotation(mirror_x.rotation, Quat::Identity(), 1e-15)) << "with no rotation";
}

TEST(Transform, decompose__collapsed_axis_does_not_produce_nan) {
  const Decomposed d = decompose(scale_matrix(Vec3(2, 0, 3)));
  EXPECT_TRUE(d.rotation.coeffs().allFinite() && d.scale.allFinite() && d.shear.allFinite())
      << "a zero scale should decompose to finite values";
  EXPECT_TRUE(near(trs_shear(d.translate, d.rotation, d.shear, d.scale), scale_matrix(Vec3(2, 0, 3)), 1e-15))
      << "and still rebuild the matrix";

  // A collapsed y whose z column still leans along y.
  Mat3 upper;
  upper << 2, 0, 1, 0, 0, 1, 0, 0, 3;
  const Mat4 leaning = to_mat4(rot_x(0.3) * rot_z(1.1) * upper, Vec3(1, 2, 3));
  const Decomposed l = decompose(leaning);
  EXPECT_TRUE(l.rotation.coeffs().allFinite() && l.scale.allFinite() && l.shear.allFinite())
      << "a zero scale.y with a leaning z column should decompose to finite values";
  EXPECT_TRUE(near(trs_shear(l.translate, l.rotation, l.shear, l.scale), leaning, 1e-14))
      << "and still rebuild the matrix, z column included";
  EXPECT_GT(l.scale.x(), 0.0) << "a collapsed axis should not be read as a reflection";
}

TEST(Transform, decompose_to_parts__compose_round_trips_every_order) {
  Random random(15);
  for (RotateOrder order : kAllOrders) {
    for (int n = 0; n < 300; ++n) {
      const TransformParts source = random_parts(random, n % 2 == 0);
      const Mat4 m = compose(source);
      const TransformParts parts = decompose_to_parts(m, order);
      EXPECT_EQ(parts.rotate_order, order) << "the parts should use the requested rotate order";
      EXPECT_EQ(parts.rotate_mode, RotateMode::kEuler) << "the parts should hold Euler angles";
      EXPECT_TRUE(parts.rotate_pivot.isZero() && parts.scale_pivot.isZero() && parts.rotate_axis.isZero() &&
                  parts.joint_orient.isZero())
          << "decompose_to_parts sets no pivots, rotate axis or joint orient";
      const double size = m.cwiseAbs().maxCoeff();
      EXPECT_TRUE(near(compose(parts), m, 1e-12 * size))
          << "order " << rotate_order_name(order) << ": compose(decompose_to_parts(m)) should give m back";
    }
  }
}

TEST(Transform, trs_matrix__is_translate_times_rotate_times_scale) {
  Random random(16);
  for (int n = 0; n < 50; ++n) {
    const Vec3 t = random.vec3(-10, 10);
    const Quat r = random.quat();
    const Vec3 s = random.scale(true);
    EXPECT_TRUE(near(trs_matrix(t, r, s), translation_matrix(t) * rotation_matrix(r) * scale_matrix(s), 1e-14))
        << "trs_matrix should equal T * R * S";
    EXPECT_TRUE(near(rotation_matrix(r), to_mat4(r.toRotationMatrix()), 1e-15))
        << "rotation_matrix should hold the quaternion's rotation";
  }
  const Vec3 p = trs_matrix(Vec3(1, 0, 0), Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ())), Vec3(2, 2, 2))
                     .topRightCorner<3, 1>();
  EXPECT_TRUE(near(p, Vec3(1, 0, 0), 0.0)) << "the translation column is t itself";
  const Vec4 x = trs_matrix(Vec3(1, 0, 0), Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ())), Vec3(2, 2, 2)) *
                 Vec4(1, 0, 0, 1);
  EXPECT_TRUE(near(x, Vec4(1, 2, 0, 1), 1e-15)) << "x is scaled to 2x, turned to 2y, then moved by +x";
}

TEST(Transform, affine_inverse__inverts_affine_matrices) {
  Random random(17);
  for (int n = 0; n < 200; ++n) {
    const Mat4 m = compose(random_parts(random, true));
    const Mat4 inverse = affine_inverse(m);
    EXPECT_TRUE(near(m * inverse, Mat4::Identity(), 1e-11)) << "m * affine_inverse(m) should be the identity";
    EXPECT_TRUE(near(inverse * m, Mat4::Identity(), 1e-11)) << "affine_inverse(m) * m should be the identity";
    EXPECT_TRUE(is_affine(inverse)) << "the inverse should have last row 0 0 0 1 exactly";
    EXPECT_TRUE(near(inverse, Mat4(m.inverse()), 1e-10 * m.inverse().cwiseAbs().maxCoeff()))
        << "the affine inverse should agree with a general 4x4 inverse";
  }
}

TEST(Transform, rigid_part__removes_scale_and_shear) {
  Random random(18);
  for (int n = 0; n < 200; ++n) {
    const Vec3 t = random.vec3(-10, 10);
    const Quat r = random.quat();
    const Vec3 s = random.scale(false);
    const Mat4 m = trs_shear(t, r, random.vec3(-1, 1), s);
    EXPECT_TRUE(near(rigid_part(m), to_mat4(r.toRotationMatrix(), t), 1e-12))
        << "the rigid part of T * R * SH * S (positive scale) should be T * R";
    const Mat4 mirrored = trs_shear(t, r, Vec3::Zero(), Vec3(s.x(), -s.y(), s.z()));
    EXPECT_NEAR((rigid_part(mirrored).topLeftCorner<3, 3>().determinant()), 1.0, 1e-12)
        << "the rigid part of a mirrored matrix should still be a proper rotation";
  }
}

TEST(Transform, concat_without_scale_shear__keeps_child_scale_and_drops_shear) {
  Random random(19);
  for (int n = 0; n < 300; ++n) {
    const Mat4 parent = trs_shear(random.vec3(-10, 10), random.quat(), random.vec3(-1, 1), random.scale(false));
    const Vec3 child_scale = random.scale(false);
    const Mat4 child = trs_shear(random.vec3(-10, 10), random.quat(), random.vec3(-1, 1), child_scale);
    const Mat4 product = parent * child;
    const Mat4 result = concat_without_scale_shear(parent, child);
    const Decomposed d = decompose(result);
    EXPECT_TRUE(near(d.shear, Vec3::Zero(), 1e-12)) << "the result should carry no shear";
    EXPECT_TRUE(near(d.scale, child_scale, 1e-12))
        << "the result's scale should be the child's scale before the multiplication";
    EXPECT_TRUE(near(result.topRightCorner<3, 1>(), product.topRightCorner<3, 1>(), 1e-12))
        << "the result should sit where the full product puts the child";
    EXPECT_TRUE(near(rigid_part(result), rigid_part(product), 1e-12))
        << "the result's rotation should be the full product's";
    EXPECT_TRUE(is_affine(result)) << "the result should be affine";
  }
}

TEST(Transform, concat_without_scale_shear__equals_rigid_part_of_product_without_child_scale) {
  Random random(20);
  for (int n = 0; n < 200; ++n) {
    const Mat4 rigid_parent = to_mat4(random.quat().toRotationMatrix(), random.vec3(-10, 10));
    const Mat4 rigid_child = to_mat4(random.quat().toRotationMatrix(), random.vec3(-10, 10));
    EXPECT_TRUE(near(concat_without_scale_shear(rigid_parent, rigid_child), rigid_parent * rigid_child, 1e-12))
        << "with no scale or shear anywhere, the result is the plain product";

    const Mat4 scaled_parent =
        trs_shear(random.vec3(-10, 10), random.quat(), random.vec3(-1, 1), random.scale(false));
    EXPECT_TRUE(near(concat_without_scale_shear(scaled_parent, rigid_child), rigid_part(scaled_parent * rigid_child),
                     1e-12))
        << "with an unscaled child, the result is the rigid part of the full product";
  }
  // Scaling the parent moves the child instead of scaling it.
  const Mat4 result = concat_without_scale_shear(scale_matrix(Vec3(2, 2, 2)), translation_matrix(Vec3(1, 0, 0)));
  EXPECT_TRUE(near(result, translation_matrix(Vec3(2, 0, 0)), 1e-15))
      << "a parent scale of 2 should push the child to x = 2 and leave it unscaled";
}

TEST(Transform, is_near__compares_every_entry) {
  Mat4 a = Mat4::Identity();
  Mat4 b = a;
  b(2, 3) = 1e-6;
  EXPECT_TRUE(is_near(a, b, 1e-6)) << "a difference equal to the tolerance is near";
  EXPECT_FALSE(is_near(a, b, 1e-7)) << "a difference above the tolerance is not near";
  b(2, 3) = std::nan("");
  EXPECT_FALSE(is_near(a, b, 1.0)) << "a NaN entry is never near";
}

}  // namespace
}  // namespace rigel::math
