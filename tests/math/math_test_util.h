#pragma once
// Shared helpers for the math tests: tolerance comparisons that print both
// sides, explicit axis matrices written out by hand (independent of the code
// under test), and seeded random inputs.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "rigel/math/rotation.h"
#include "rigel/math/transform.h"
#include "rigel/math/types.h"

namespace rigel::math::testing {

inline constexpr RotateOrder kAllOrders[] = {RotateOrder::kXYZ, RotateOrder::kYZX, RotateOrder::kZXY,
                                             RotateOrder::kXZY, RotateOrder::kYXZ, RotateOrder::kZYX};

// Largest absolute entry of a - b.
template <typename A, typename B>
double max_abs_diff(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b) {
  return (a - b).cwiseAbs().maxCoeff();
}

template <typename A, typename B>
::testing::AssertionResult near(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b, double tolerance) {
  const double diff = max_abs_diff(a, b);
  if (diff <= tolerance) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "largest difference " << diff << " exceeds " << tolerance << ":\n"
                                       << a << "\n  vs\n"
                                       << b << "\n";
}

// q and -q are the same rotation.
inline ::testing::AssertionResult same_rotation(const Quat& a, const Quat& b, double tolerance) {
  const double diff = std::min((a.coeffs() - b.coeffs()).cwiseAbs().maxCoeff(),
                               (a.coeffs() + b.coeffs()).cwiseAbs().maxCoeff());
  if (diff <= tolerance) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "quaternions (x y z w) " << a.coeffs().transpose() << " and "
                                       << b.coeffs().transpose() << " differ by " << diff << " (up to sign)";
}

// Right-handed axis rotations, written out entry by entry.
inline Mat3 rot_x(double a) {
  Mat3 m;
  m << 1, 0, 0, 0, std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a);
  return m;
}
inline Mat3 rot_y(double a) {
  Mat3 m;
  m << std::cos(a), 0, std::sin(a), 0, 1, 0, -std::sin(a), 0, std::cos(a);
  return m;
}
inline Mat3 rot_z(double a) {
  Mat3 m;
  m << std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a), 0, 0, 0, 1;
  return m;
}

// The matrix of each rotate order as the product the convention states
// (the first rotation is the rightmost factor).
inline Mat3 expected_euler_matrix(const Vec3& r, RotateOrder order) {
  const Mat3 x = rot_x(r.x()), y = rot_y(r.y()), z = rot_z(r.z());
  switch (order) {
    case RotateOrder::kXYZ: return z * y * x;
    case RotateOrder::kYZX: return x * z * y;
    case RotateOrder::kZXY: return y * x * z;
    case RotateOrder::kXZY: return y * z * x;
    case RotateOrder::kYXZ: return z * x * y;
    case RotateOrder::kZYX: return x * y * z;
  }
  return Mat3::Identity();
}

inline Mat4 to_mat4(const Mat3& linear, const Vec3& translate = Vec3::Zero()) {
  Mat4 m = Mat4::Identity();
  m.topLeftCorner<3, 3>() = linear;
  m.topRightCorner<3, 1>() = translate;
  return m;
}

// Index of the axis an order applies first / second / last.
inline int first_axis(RotateOrder order) {
  constexpr int kFirst[] = {0, 1, 2, 0, 1, 2};
  return kFirst[static_cast<int>(order)];
}
inline int middle_axis(RotateOrder order) {
  constexpr int kMiddle[] = {1, 2, 0, 2, 0, 1};
  return kMiddle[static_cast<int>(order)];
}
inline int last_axis(RotateOrder order) {
  constexpr int kLast[] = {2, 0, 1, 1, 2, 0};
  return kLast[static_cast<int>(order)];
}

class Random {
 public:
  explicit Random(unsigned seed) : engine_(seed) {}

  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(engine_); }
  int index(int count) { return std::uniform_int_distribution<int>(0, count - 1)(engine_); }
  Vec3 vec3(double lo, double hi) { return Vec3(uniform(lo, hi), uniform(lo, hi), uniform(lo, hi)); }
  Vec3 angles() { return vec3(-2.0 * kPi, 2.0 * kPi); }
  Quat quat() {
    Quat q(Eigen::Vector4d(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)));
    return q.normalized();
  }
  // A scale away from zero, each axis negative with probability 1/4 when
  // `allow_negative`.
  Vec3 scale(bool allow_negative) {
    Vec3 s = vec3(0.3, 3.0);
    if (allow_negative) {
      for (int n = 0; n < 3; ++n) {
        if (index(4) == 0) s[n] = -s[n];
      }
    }
    return s;
  }
  std::mt19937& engine() { return engine_; }

 private:
  std::mt19937 engine_;
};

}  // namespace rigel::math::testing
