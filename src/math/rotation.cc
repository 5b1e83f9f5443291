#include "rigel/math/rotation.h"

#include <array>
#include <cctype>
#include <cmath>
#include <limits>

namespace rigel::math {
namespace {

// The three axes of a rotate order, in the order they apply to a point, and
// the parity of that permutation of (x, y, z): +1 for the cyclic orders
// (xyz, yzx, zxy), -1 for the others.
struct OrderAxes {
  std::array<int, 3> axis;  // axis[0] applies first, axis[2] last
  double parity;
};

OrderAxes order_axes(RotateOrder order) {
  switch (order) {
    case RotateOrder::kXYZ: return {{0, 1, 2}, 1.0};
    case RotateOrder::kYZX: return {{1, 2, 0}, 1.0};
    case RotateOrder::kZXY: return {{2, 0, 1}, 1.0};
    case RotateOrder::kXZY: return {{0, 2, 1}, -1.0};
    case RotateOrder::kYXZ: return {{1, 0, 2}, -1.0};
    case RotateOrder::kZYX: return {{2, 1, 0}, -1.0};
  }
  return {{0, 1, 2}, 1.0};  // unreachable for valid enum values
}

constexpr std::array<std::string_view, kRotateOrderCount> kOrderNames = {"xyz", "yzx", "zxy",
                                                                          "xzy", "yxz", "zyx"};

// Rotation by `angle` about the coordinate axis `axis` (0 = x, 1 = y, 2 = z).
Mat3 axis_matrix(int axis, double angle) {
  const double c = std::cos(angle);
  const double s = std::sin(angle);
  Mat3 m = Mat3::Identity();
  const int u = (axis + 1) % 3;  // the two axes spanning the rotation plane,
  const int v = (axis + 2) % 3;  // in right-handed order
  m(u, u) = c;
  m(u, v) = -s;
  m(v, u) = s;
  m(v, v) = c;
  return m;
}

// Below this, cos(middle angle) is treated as zero: the first and last axes
// line up and only their sum (or difference) is determined. Forcing the first
// angle to zero there moves the reconstructed matrix by at most this much.
constexpr double kGimbalEpsilon = 1e-13;

constexpr double kTwoPi = 2.0 * kPi;

// `x` plus the multiple of 2*pi that brings it nearest to `target`.
double wrap_near(double x, double target) { return x + kTwoPi * std::round((target - x) / kTwoPi); }

}  // namespace

std::string_view rotate_order_name(RotateOrder order) {
  const auto index = static_cast<std::size_t>(order);
  return index < kOrderNames.size() ? kOrderNames[index] : std::string_view("xyz");
}

std::optional<RotateOrder> rotate_order_from_name(std::string_view name) {
  if (name.size() != 3) return std::nullopt;
  std::array<char, 3> lower{};
  for (std::size_t i = 0; i < 3; ++i) {
    lower[i] = static_cast<char>(std::tolower(static_cast<unsigned char>(name[i])));
  }
  const std::string_view key(lower.data(), lower.size());
  for (std::size_t i = 0; i < kOrderNames.size(); ++i) {
    if (kOrderNames[i] == key) return static_cast<RotateOrder>(i);
  }
  return std::nullopt;
}

Mat3 euler_to_matrix(const Vec3& radians, RotateOrder order) {
  const std::array<int, 3> axis = order_axes(order).axis;
  // Column vectors: the first rotation is the rightmost factor.
  return axis_matrix(axis[2], radians[axis[2]]) * axis_matrix(axis[1], radians[axis[1]]) *
         axis_matrix(axis[0], radians[axis[0]]);
}

Quat euler_to_quat(const Vec3& radians, RotateOrder order) {
  const std::array<int, 3> axis = order_axes(order).axis;
  const auto q = [&](int a) { return Quat(Eigen::AngleAxisd(radians[a], Vec3::Unit(a))); };
  return q(axis[2]) * q(axis[1]) * q(axis[0]);
}

Vec3 matrix_to_euler(const Mat3& rotation, RotateOrder order) {
  // Relabel the axes so that the order reads xyz: with P the permutation
  // sending the first/second/third axis to x/y/z, P * Ri(a) * P^T = Rx(p * a)
  // where p = det(P) = the parity (a reflection reverses the sense of
  // rotation). So m' = P * rotation * P^T = Rz(p c) * Ry(p b) * Rx(p a), and
  // one xyz extraction serves all six orders.
  const OrderAxes axes = order_axes(order);
  const std::array<int, 3>& axis = axes.axis;
  const double parity = axes.parity;
  const auto m = [&](int r, int c) { return rotation(axis[r], axis[c]); };

  // m' = Rz(c) Ry(b) Rx(a) =
  //   [ cb cc   sa sb cc - ca sc   ca sb cc + sa sc ]
  //   [ cb sc   sa sb sc + ca cc   ca sb sc - sa cc ]
  //   [ -sb     sa cb              ca cb            ]
  const double cos_b = std::hypot(m(2, 1), m(2, 2));
  // At gimbal lock (cos b ~ 0) row 2 no longer determines a: take a = 0.
  const double a = cos_b > kGimbalEpsilon ? std::atan2(m(2, 1), m(2, 2)) : 0.0;
  const double b = std::atan2(-m(2, 0), cos_b);  // in [-pi/2, pi/2] since cos_b >= 0
  // Take c from m' * Rx(a)^T = Rz(c) Ry(b), whose column 1 is (-sc, cc, 0):
  // this c is consistent with whatever a was chosen, so the round trip stays
  // exact even near gimbal lock, where a itself is poorly conditioned.
  const double sa = std::sin(a);
  const double ca = std::cos(a);
  const double c = std::atan2(-(m(0, 1) * ca - m(0, 2) * sa), m(1, 1) * ca - m(1, 2) * sa);

  Vec3 out;
  out[axis[0]] = parity * a;
  out[axis[1]] = parity * b;
  out[axis[2]] = parity * c;
  return out + Vec3::Zero();  // + 0 turns -0.0 into 0.0
}

Vec3 quat_to_euler(const Quat& q, RotateOrder order) {
  const double norm = q.norm();
  if (!(norm > 0.0)) return Vec3::Zero();  // the zero quaternion has no rotation: identity
  return matrix_to_euler(Quat(q.coeffs() / norm).toRotationMatrix(), order);
}

Vec3 euler_closest(const Vec3& radians, const Vec3& previous, RotateOrder order) {
  const OrderAxes axes = order_axes(order);
  const std::array<int, 3>& axis = axes.axis;
  const double parity = axes.parity;
  const int i = axis[0];
  const int j = axis[1];
  const int k = axis[2];

  const auto wrapped = [&](Vec3 e) {
    for (int n = 0; n < 3; ++n) e[n] = wrap_near(e[n], previous[n]);
    return e;
  };

  // At gimbal lock the first and last rotations turn about the same line, so a
  // whole family of triples is equivalent: (a + t, b, c + sigma * t) for any
  // t, with sigma = parity * sign(sin b). Pick the t nearest `previous`.
  if (std::abs(std::cos(radians[j])) < 1e-12) {
    const double sigma = parity * (std::sin(radians[j]) > 0.0 ? 1.0 : -1.0);
    Vec3 best = radians;
    double best_distance = std::numeric_limits<double>::infinity();
    // After wrapping, one whole turn of c (with t absorbing turns of a) can
    // still be traded: try the neighbouring turns too.
    for (int turn = -1; turn <= 1; ++turn) {
      Vec3 e = wrapped(radians);
      e[k] += turn * kTwoPi;
      const double t = ((previous[i] - e[i]) + sigma * (previous[k] - e[k])) / 2.0;
      e[i] += t;
      e[k] += sigma * t;
      const double distance = (e - previous).squaredNorm();
      if (distance < best_distance) {
        best_distance = distance;
        best = e;
      }
    }
    return best;
  }

  // Otherwise there are two solutions, each up to whole turns per angle:
  // (a, b, c) and (a + pi, pi - b, c + pi), for every rotate order.
  const Vec3 direct = wrapped(radians);
  Vec3 alternate = radians;
  alternate[i] += kPi;
  alternate[j] = kPi - alternate[j];
  alternate[k] += kPi;
  alternate = wrapped(alternate);
  return (alternate - previous).squaredNorm() < (direct - previous).squaredNorm() ? alternate : direct;
}

}  // namespace rigel::math
