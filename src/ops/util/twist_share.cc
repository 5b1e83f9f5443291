#include "rigel/ops/util/twist_share.h"

#include <cmath>

#include "rigel/math/transform.h"

namespace rigel::ops::util {
namespace {

using math::Mat4;
using math::Quat;
using math::Vec3;

// Finite and not singular.
bool usable(const Mat4& m) {
  if (!m.allFinite()) return false;
  const double scale = m.topLeftCorner<3, 3>().cwiseAbs().maxCoeff();
  return scale > 0 && std::abs(m.topLeftCorner<3, 3>().determinant()) > 1e-12 * scale * scale * scale;
}

}  // namespace

double twist_angle(const Quat& q, const Vec3& axis) {
  Quat u = q.normalized();
  if (u.w() < 0) u.coeffs() = -u.coeffs();  // the short way: angle within (-pi, pi]
  const double along = u.vec().dot(axis);
  if (std::abs(along) < 1e-300 && std::abs(u.w()) < 1e-300) return 0.0;  // a half turn of swing: no twist
  return 2.0 * std::atan2(along, u.w());
}

bool TwistShareJob::validate() const {
  if (!twist) return false;
  if (!usable(start) || !usable(end)) return false;
  if (!rest_relative.coeffs().allFinite() || rest_relative.norm() < 1e-12) return false;
  return axis.allFinite() && std::abs(axis.norm() - 1.0) <= 1e-9;
}

bool TwistShareJob::run() const {
  if (!validate()) return false;
  const Quat relative = math::decompose(start).rotation.conjugate() * math::decompose(end).rotation;
  const double angle = twist_angle(relative * rest_relative.normalized().conjugate(), axis);
  const std::size_t count = rotations.size();
  for (std::size_t i = 0; i < count; ++i)
    rotations[i] = Quat(Eigen::AngleAxisd(angle * double(i + 1) / double(count + 1), axis));
  *twist = angle;
  return true;
}

}  // namespace rigel::ops::util
