#include "rigel/ops/util/finger_curl.h"

#include <cmath>

namespace rigel::ops::util {
namespace {

using math::Mat3;
using math::Mat4;
using math::Vec3;

bool usable_axis(const Vec3& axis) { return axis.allFinite() && axis.norm() > 1e-12; }

}  // namespace

Mat4 finger_offset(const Mat4& rest_offset, const Vec3& spread_axis, double spread, const Vec3& bend_axis,
                   double curl) {
  if (spread == 0.0 && curl == 0.0) return rest_offset;
  Mat3 turn = Mat3::Identity();
  if (spread != 0.0) turn = Eigen::AngleAxisd(spread, spread_axis).toRotationMatrix();
  if (curl != 0.0) turn = turn * Eigen::AngleAxisd(curl, bend_axis).toRotationMatrix();
  Mat4 out = rest_offset;
  out.topLeftCorner<3, 3>() = rest_offset.topLeftCorner<3, 3>() * turn;
  return out;
}

bool FingerCurlJob::validate() const { return output.size() >= rest_offset_parent.size(); }

bool FingerCurlJob::run() const {
  if (!validate()) return false;
  using Problem = FingerCurlResult::Problem;
  FingerCurlResult found;
  auto complain = [&](Problem problem, std::size_t i) {
    if (found.problem == Problem::kNone) found = FingerCurlResult{problem, i};
  };
  for (std::size_t i = 0; i < rest_offset_parent.size(); ++i) {
    double curl_i = curl;
    if (i < finger.size()) {
      const std::int64_t k = finger[i];
      const auto index = static_cast<std::size_t>(k);
      if (k >= 0 && index < finger_curl.size()) curl_i += finger_curl[index];
    } else {
      complain(Problem::kMissingFinger, i);
    }
    double spread_i = i < spread_weight.size() ? spread * spread_weight[i] : 0.0;
    if (!std::isfinite(curl_i)) {
      complain(Problem::kCurlNotFinite, i);
      curl_i = 0.0;
    }
    if (!std::isfinite(spread_i)) {
      complain(Problem::kSpreadNotFinite, i);
      spread_i = 0.0;
    }
    Vec3 bend = i < bend_axis.size() ? bend_axis[i] : Vec3(Vec3::Zero());
    Vec3 side = i < spread_axis.size() ? spread_axis[i] : Vec3(Vec3::Zero());
    if (curl_i != 0.0 && !usable_axis(bend)) {
      complain(Problem::kBadBendAxis, i);
      curl_i = 0.0;
    }
    if (spread_i != 0.0 && !usable_axis(side)) {
      complain(Problem::kBadSpreadAxis, i);
      spread_i = 0.0;
    }
    if (curl_i != 0.0) bend.normalize();
    if (spread_i != 0.0) side.normalize();
    output[i] = finger_offset(rest_offset_parent[i], side, math::to_radians(spread_i), bend, math::to_radians(curl_i));
  }
  if (result) *result = found;
  return true;
}

}  // namespace rigel::ops::util
