#include "rigel/math/rotation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "math_test_util.h"

namespace rigel::math {
namespace {

using testing::expected_euler_matrix;
using testing::first_axis;
using testing::kAllOrders;
using testing::last_axis;
using testing::middle_axis;
using testing::near;
using testing::Random;
using testing::same_rotation;

std::string order_label(RotateOrder order) { return "rotate order " + std::string(rotate_order_name(order)); }

TEST(Rotation, rotate_order_name__round_trips_and_ignores_case) {
  const char* names[] = {"xyz", "yzx", "zxy", "xzy", "yxz", "zyx"};
  for (int n = 0; n < kRotateOrderCount; ++n) {
    const auto order = static_cast<RotateOrder>(n);
    EXPECT_EQ(rotate_order_name(order), names[n]) << "enum value " << n << " should be named as Maya's rotateOrder";
    EXPECT_EQ(rotate_order_from_name(names[n]), order) << "'" << names[n] << "' should parse back to its order";
  }
  EXPECT_EQ(rotate_order_from_name("ZxY"), RotateOrder::kZXY) << "names should parse case-insensitively";
  EXPECT_FALSE(rotate_order_from_name("xxy").has_value()) << "a name repeating an axis is not an order";
  EXPECT_FALSE(rotate_order_from_name("xy").has_value()) << "a name with two axes is not an order";
  EXPECT_FALSE(rotate_order_from_name("xyzw").has_value()) << "a name with four letters is not an order";
  EXPECT_FALSE(rotate_order_from_name("").has_value()) << "the empty name is not an order";
}

TEST(Rotation, euler_to_matrix__each_order_matches_axis_products) {
  Random random(1);
  for (RotateOrder order : kAllOrders) {
    for (int n = 0; n < 50; ++n) {
      const Vec3 r = random.angles();
      EXPECT_TRUE(near(euler_to_matrix(r, order), expected_euler_matrix(r, order), 1e-14))
          << order_label(order) << ", angles " << r.transpose()
          << ": the matrix should be the product of axis rotations, first axis rightmost";
    }
  }
}

TEST(Rotation, euler_to_matrix__axes_are_right_handed) {
  const double q = kPi / 2;
  for (RotateOrder order : kAllOrders) {
    EXPECT_TRUE(near(euler_to_matrix(Vec3(0, 0, q), order) * Vec3::UnitX(), Vec3::UnitY(), 1e-15))
        << order_label(order) << ": +90 degrees about z should take x to y";
    EXPECT_TRUE(near(euler_to_matrix(Vec3(q, 0, 0), order) * Vec3::UnitY(), Vec3::UnitZ(), 1e-15))
        << order_label(order) << ": +90 degrees about x should take y to z";
    EXPECT_TRUE(near(euler_to_matrix(Vec3(0, q, 0), order) * Vec3::UnitZ(), Vec3::UnitX(), 1e-15))
        << order_label(order) << ": +90 degrees about y should take z to x";
  }
  // xyz: x first. (90, 90, 0) takes z -> (x: z to -y) -> (y: -y stays -y).
  EXPECT_TRUE(near(euler_to_matrix(Vec3(q, q, 0), RotateOrder::kXYZ) * Vec3::UnitZ(), -Vec3::UnitY(), 1e-15))
      << "xyz applies x before y: z goes to -y under x, and y leaves -y alone";
  EXPECT_TRUE(near(euler_to_matrix(Vec3(q, q, 0), RotateOrder::kYXZ) * Vec3::UnitZ(), Vec3::UnitX(), 1e-15))
      << "yxz applies y before x: z goes to x under y, and x leaves x alone";
}

TEST(Rotation, euler_to_quat__matches_matrix) {
  Random random(2);
  for (RotateOrder order : kAllOrders) {
    for (int n = 0; n < 50; ++n) {
      const Vec3 r = random.angles();
      const Quat q = euler_to_quat(r, order);
      EXPECT_NEAR(q.norm(), 1.0, 1e-15) << order_label(order) << ": the quaternion should be unit";
      EXPECT_TRUE(near(q.toRotationMatrix(), expected_euler_matrix(r, order), 1e-14))
          << order_label(order) << ", angles " << r.transpose() << ": quaternion and matrix should agree";
    }
  }
}

TEST(Rotation, matrix_to_euler__round_trips_random_angles) {
  Random random(3);
  for (RotateOrder order : kAllOrders) {
    for (int n = 0; n < 2000; ++n) {
      const Vec3 r = random.angles();
      const Mat3 m = euler_to_matrix(r, order);
      const Vec3 back = matrix_to_euler(m, order);
      EXPECT_TRUE(near(euler_to_matrix(back, order), m, 1e-12))
          << order_label(order) << ", angles " << r.transpose() << " came back as " << back.transpose()
          << ", which should give the same matrix";
      EXPECT_LE(std::abs(back[middle_axis(order)]), kPi / 2) << order_label(order)
                                                             << ": the middle angle should lie in [-pi/2, pi/2]";
    }
  }
}

TEST(Rotation, matrix_to_euler__recovers_canonical_angles) {
  Random random(4);
  for (RotateOrder order : kAllOrders) {
    for (int n = 0; n < 500; ++n) {
      Vec3 r = random.vec3(-kPi * 0.999, kPi * 0.999);
      r[middle_axis(order)] = random.uniform(-kPi / 2 * 0.99, kPi / 2 * 0.99);
      const Vec3 back = matrix_to_euler(euler_to_matrix(r, order), order);
      EXPECT_TRUE(near(back, r, 1e-12)) << order_label(order)
                                        << ": angles already in the canonical ranges should come back unchanged";
    }
  }
}

TEST(Rotation, matrix_to_euler__gimbal_lock_round_trips_with_first_angle_zero) {
  Random random(5);
  for (RotateOrder order : kAllOrders) {
    for (double middle : {kPi / 2, -kPi / 2}) {
      for (int n = 0; n < 200; ++n) {
        Vec3 r = random.angles();
        r[middle_axis(order)] = middle;
        const Mat3 m = euler_to_matrix(r, order);
        const Vec3 back = matrix_to_euler(m, order);
        EXPECT_TRUE(near(euler_to_matrix(back, order), m, 1e-12))
            << order_label(order) << ", gimbal-locked angles " << r.transpose() << " came back as "
            << back.transpose() << ", which should give the same matrix";
        EXPECT_EQ(back[first_axis(order)], 0.0) << order_label(order)
                                                << ": at gimbal lock the first angle should be set to 0";
        EXPECT_NEAR(back[middle_axis(order)], middle, 1e-7)
            << order_label(order) << ": the middle angle should stay at +-90 degrees";
      }
    }
  }
}

TEST(Rotation, matrix_to_euler__near_gimbal_lock_round_trips) {
  Random random(6);
  for (RotateOrder order : kAllOrders) {
    for (double offset : {1e-3, 1e-6, 1e-9, 1e-11, 1e-13, 1e-15}) {
      for (double sign : {1.0, -1.0}) {
        for (int n = 0; n < 50; ++n) {
          Vec3 r = random.angles();
          r[middle_axis(order)] = sign * (kPi / 2 - offset);
          const Mat3 m = euler_to_matrix(r, order);
          const Vec3 back = matrix_to_euler(m, order);
          EXPECT_TRUE(near(euler_to_matrix(back, order), m, 1e-12))
              << order_label(order) << ", angles " << r.transpose() << " (" << offset
              << " from gimbal lock) came back as " << back.transpose() << ", which should give the same matrix";
        }
      }
    }
  }
}

TEST(Rotation, quat_to_euler__round_trips_random_quaternions) {
  Random random(7);
  for (RotateOrder order : kAllOrders) {
    for (int n = 0; n < 1000; ++n) {
      const Quat q = random.quat();
      const Vec3 e = quat_to_euler(q, order);
      EXPECT_TRUE(same_rotation(euler_to_quat(e, order), q, 1e-12))
          << order_label(order) << ": quaternion -> euler -> quaternion should give the same rotation";
      EXPECT_TRUE(near(euler_to_matrix(e, order), q.toRotationMatrix(), 1e-12))
          << order_label(order) << ": quaternion -> euler -> matrix should give the quaternion's matrix";
    }
    // Gimbal lock through the quaternion path.
    for (int n = 0; n < 100; ++n) {
      Vec3 r = random.angles();
      r[middle_axis(order)] = (n % 2 ? 1 : -1) * kPi / 2;
      const Quat q = euler_to_quat(r, order);
      const Vec3 e = quat_to_euler(q, order);
      EXPECT_TRUE(same_rotation(euler_to_quat(e, order), q, 1e-12))
          << order_label(order) << ", gimbal-locked " << r.transpose()
          << ": the quaternion round trip should hold at gimbal lock";
    }
  }
}

TEST(Rotation, quat_to_euler__normalises_its_input) {
  const Quat unit = euler_to_quat(Vec3(0.3, -0.2, 1.1), RotateOrder::kZXY);
  const Quat doubled(unit.coeffs() * 2.0);
  EXPECT_TRUE(near(quat_to_euler(doubled, RotateOrder::kZXY), quat_to_euler(unit, RotateOrder::kZXY), 1e-14))
      << "a non-unit quaternion should be read as its normalised rotation";
  EXPECT_TRUE(near(quat_to_euler(Quat(0, 0, 0, 0), RotateOrder::kXYZ), Vec3::Zero(), 0.0))
      << "the zero quaternion carries no rotation and should give zero angles";
}

TEST(Rotation, euler_closest__adds_whole_turns) {
  const double turn = 2 * kPi;
  const Vec3 r(0.1, -0.2, 0.3);
  const Vec3 previous(0.1 + turn, -0.2 - 2 * turn, 0.25);
  const Vec3 closest = euler_closest(r, previous, RotateOrder::kXYZ);
  EXPECT_TRUE(near(closest, Vec3(0.1 + turn, -0.2 - 2 * turn, 0.3), 1e-12))
      << "each angle should move by whole turns toward the previous key, got " << closest.transpose();
}

TEST(Rotation, euler_closest__flips_to_the_alternate_solution_when_nearer) {
  for (RotateOrder order : kAllOrders) {
    // (a, b, c) and (a + pi, pi - b, c + pi) are the same rotation.
    Vec3 r(0.2, 0.3, -0.4);
    Vec3 alternate = r;
    alternate[first_axis(order)] += kPi;
    alternate[middle_axis(order)] = kPi - alternate[middle_axis(order)];
    alternate[last_axis(order)] += kPi;
    ASSERT_TRUE(near(euler_to_matrix(alternate, order), euler_to_matrix(r, order), 1e-14))
        << order_label(order) << ": the alternate solution should be the same rotation";
    const Vec3 previous = alternate + Vec3(0.01, -0.02, 0.01);
    EXPECT_TRUE(near(euler_closest(r, previous, order), alternate, 1e-12))
        << order_label(order) << ": when the previous key sits near the alternate solution, that should be chosen";
    EXPECT_TRUE(near(euler_closest(r, r + Vec3(0.01, 0.01, -0.01), order), r, 1e-12))
        << order_label(order) << ": when the previous key sits near the input, it should be kept";
  }
}

TEST(Rotation, euler_closest__is_equivalent_and_no_farther_than_simple_candidates) {
  Random random(8);
  for (RotateOrder order : kAllOrders) {
    for (int n = 0; n < 500; ++n) {
      const Vec3 r = random.angles();
      const Vec3 previous = random.vec3(-10.0, 10.0);
      const Vec3 closest = euler_closest(r, previous, order);
      EXPECT_TRUE(near(euler_to_matrix(closest, order), euler_to_matrix(r, order), 1e-12))
          << order_label(order) << ": the closest triple should be the same rotation as the input";
      // Every whole-turn shift of the input, and of its alternate, is no nearer.
      Vec3 alternate = r;
      alternate[first_axis(order)] += kPi;
      alternate[middle_axis(order)] = kPi - alternate[middle_axis(order)];
      alternate[last_axis(order)] += kPi;
      for (const Vec3& candidate : {r, alternate}) {
        for (int a = -3; a <= 3; ++a) {
          for (int b = -3; b <= 3; ++b) {
            for (int c = -3; c <= 3; ++c) {
              const Vec3 shifted = candidate + 2 * kPi * Vec3(a, b, c);
              ASSERT_LE((closest - previous).norm(), (shifted - previous).norm() + 1e-12)
                  << order_label(order) << ": " << shifted.transpose() << " is nearer to " << previous.transpose()
                  << " than the returned " << closest.transpose();
            }
          }
        }
      }
    }
  }
}

TEST(Rotation, euler_closest__at_gimbal_lock_follows_the_previous_key) {
  Random random(9);
  for (RotateOrder order : kAllOrders) {
    for (double middle : {kPi / 2, -kPi / 2}) {
      for (int n = 0; n < 50; ++n) {
        // The previous key is itself at gimbal lock; the input is the
        // canonical form of the same rotation (first angle 0), far from it.
        Vec3 previous = random.vec3(-3.0, 3.0);
        previous[middle_axis(order)] = middle;
        const Vec3 canonical = matrix_to_euler(euler_to_matrix(previous, order), order);
        const Vec3 closest = euler_closest(canonical, previous, order);
        EXPECT_TRUE(near(euler_to_matrix(closest, order), euler_to_matrix(previous, order), 1e-12))
            << order_label(order) << ": the result should still be the input's rotation";
        EXPECT_TRUE(near(closest, previous, 1e-9))
            << order_label(order) << ": at gimbal lock the first and last angles trade off, so the previous key "
            << previous.transpose() << " itself is reachable from " << canonical.transpose();
      }
    }
  }
}

}  // namespace
}  // namespace rigel::math
