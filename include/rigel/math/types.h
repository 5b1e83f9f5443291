#pragma once
// Basic maths types. Doubles throughout; column vectors; a matrix maps
// local-space points to its parent's space (glTF convention, not Maya's row
// vectors). Angles are radians everywhere in this layer.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace rigel::math {

using Vec3 = Eigen::Vector3d;
using Vec4 = Eigen::Vector4d;
using Quat = Eigen::Quaterniond;
using Mat3 = Eigen::Matrix3d;
using Mat4 = Eigen::Matrix4d;

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kDegToRad = kPi / 180.0;
inline constexpr double kRadToDeg = 180.0 / kPi;

inline double to_radians(double degrees) { return degrees * kDegToRad; }
inline double to_degrees(double radians) { return radians * kRadToDeg; }
inline Vec3 to_radians(const Vec3& degrees) { return degrees * kDegToRad; }
inline Vec3 to_degrees(const Vec3& radians) { return radians * kRadToDeg; }

}  // namespace rigel::math
