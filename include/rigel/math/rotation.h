#pragma once
// Euler angles in the six rotate orders, and conversions to and from
// quaternions and rotation matrices.

#include <cstdint>
#include <optional>
#include <string_view>

#include "rigel/math/types.h"

namespace rigel::math {

// The order in which the three axis rotations apply to a point, first to
// last, as Maya's rotateOrder (same enum values: xyz = 0 ... zyx = 5).
// kXYZ rotates about X first, then Y, then Z: R = Rz * Ry * Rx.
enum class RotateOrder : std::uint8_t { kXYZ = 0, kYZX = 1, kZXY = 2, kXZY = 3, kYXZ = 4, kZYX = 5 };

inline constexpr int kRotateOrderCount = 6;

// "xyz", "yzx", ... (lower case).
std::string_view rotate_order_name(RotateOrder order);
// Parses "xyz".."zyx" (case-insensitive); nullopt for anything else.
std::optional<RotateOrder> rotate_order_from_name(std::string_view name);

// Rotation matrix of Euler angles (radians) applied in `order`.
Mat3 euler_to_matrix(const Vec3& radians, RotateOrder order);
Quat euler_to_quat(const Vec3& radians, RotateOrder order);

// Euler angles (radians) that reproduce `rotation` (orthonormal, det +1) in
// `order`. The middle angle lies in [-pi/2, pi/2]; at gimbal lock the first
// angle is set to 0. Round trip: euler_to_matrix(matrix_to_euler(m, o), o)
// equals m within 1e-12.
Vec3 matrix_to_euler(const Mat3& rotation, RotateOrder order);
Vec3 quat_to_euler(const Quat& q, RotateOrder order);

// Of the Euler triples equivalent to `radians`, the one closest to
// `previous` (adds multiples of 2*pi and flips to the alternate solution
// when nearer). Used when keying rotations so curves do not pop.
Vec3 euler_closest(const Vec3& radians, const Vec3& previous, RotateOrder order);

}  // namespace rigel::math
