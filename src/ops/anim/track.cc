#include "rigel/ops/anim/track.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <type_traits>

namespace rigel::ops::anim {
namespace {

using math::Quat;
using math::Vec3;

constexpr std::array<std::string_view, kInterpolationCount> kInterpolationNames = {"step", "linear", "cubicSpline"};
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// What differs between translation/scale and rotation tracks.
template <typename T>
struct TrackTraits;

template <>
struct TrackTraits<Vec3> {
  static Vec3 zero() { return Vec3::Zero(); }
  static Vec3 nan() { return Vec3::Constant(kNaN); }
  static bool finite(const Vec3& v) { return v.allFinite(); }
  static Vec3 key(const Vec3& v) { return v; }
  static Vec3 linear(const Vec3& a, const Vec3& b, double s) { return a + (b - a) * s; }
  // p = h00 v0 + h10 m0 + h01 v1 + h11 m1 (tangents already scaled by the span)
  static Vec3 hermite(const Vec3& v0, const Vec3& m0, const Vec3& v1, const Vec3& m1, double s) {
    const double s2 = s * s, s3 = s2 * s;
    return (2 * s3 - 3 * s2 + 1) * v0 + (s3 - 2 * s2 + s) * m0 + (-2 * s3 + 3 * s2) * v1 + (s3 - s2) * m1;
  }
};

template <>
struct TrackTraits<Quat> {
  static Quat zero() { return Quat::Identity(); }
  static Quat nan() { return Quat(kNaN, kNaN, kNaN, kNaN); }
  static bool finite(const Quat& q) { return q.coeffs().allFinite(); }
  // Keys read from unvalidated storage (node attributes) are normalised as
  // they are read; Track stores them normalised already, which this keeps.
  static Quat key(const Quat& q) { return q.normalized(); }
  static Quat linear(const Quat& a, const Quat& b, double s) { return slerp_shortest(a, b, s); }
  // glTF: the spline runs on the four components, then is normalised.
  static Quat hermite(const Quat& v0, const Quat& m0, const Quat& v1, const Quat& m1, double s) {
    const double s2 = s * s, s3 = s2 * s;
    Quat q;
    q.coeffs() = (2 * s3 - 3 * s2 + 1) * v0.coeffs() + (s3 - 2 * s2 + s) * m0.coeffs() +
                 (-2 * s3 + 3 * s2) * v1.coeffs() + (s3 - s2) * m1.coeffs();
    const double norm = q.norm();
    if (norm > 0.0) q.coeffs() /= norm;
    else q = Quat::Identity();  // a degenerate spline through the origin
    return q;
  }
};

std::string number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", v);
  return buffer;
}

// The segment [times[i], times[i + 1]) holding t, for t strictly inside
// (times[0], times[n - 1]): the cursor's, the next one, or a binary search.
// The cursor is left on it.
std::size_t find_segment(const double* times, std::size_t n, double t, Cursor& cursor) {
  std::size_t i = cursor.key;
  if (i + 1 < n && t >= times[i] && t < times[i + 1]) {
    // the cursor's segment
  } else if (i + 2 < n && t >= times[i + 1] && t < times[i + 2]) {
    ++i;
  } else {
    const double* it = std::upper_bound(times + 1, times + n - 1, t);
    i = static_cast<std::size_t>(it - times) - 1;
  }
  cursor.key = static_cast<std::uint32_t>(i);
  return i;
}

// The value at t. `kNormalize`: read keys through TrackTraits::key (rotations
// from attributes); Track's own keys are normalised already.
template <typename T, bool kNormalize>
T sample(const TrackArrays<T>& a, double t, Cursor& cursor) {
  using Traits = TrackTraits<T>;
  auto key = [&](std::size_t i) -> T {
    if constexpr (kNormalize) return Traits::key(a.values[i]);
    else return a.values[i];
  };
  const std::size_t n = std::min(a.times.size(), a.values.size());
  if (n == 0) return Traits::zero();
  if (std::isnan(t)) return Traits::nan();
  const double* times = a.times.data();
  if (t <= times[0]) return key(0);
  if (t >= times[n - 1]) return key(n - 1);
  const std::size_t i = find_segment(times, n, t, cursor);
  switch (a.interpolation) {
    case Interpolation::kStep:
      return key(i);
    case Interpolation::kLinear: {
      const double s = (t - times[i]) / (times[i + 1] - times[i]);
      return Traits::linear(key(i), key(i + 1), s);
    }
    case Interpolation::kCubicSpline: {
      if (a.in_tangents.size() < n || a.out_tangents.size() < n) return key(i);  // invalid; never read past
      const double span = times[i + 1] - times[i];
      const double s = (t - times[i]) / span;
      T m0 = a.out_tangents[i], m1 = a.in_tangents[i + 1];
      if constexpr (std::is_same_v<T, Quat>) {
        m0.coeffs() *= span;
        m1.coeffs() *= span;
      } else {
        m0 *= span;
        m1 *= span;
      }
      return Traits::hermite(key(i), m0, key(i + 1), m1, s);
    }
  }
  return key(i);
}

template <typename T>
bool finite_all(std::span<const T> values, const char* name, Status& status) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!TrackTraits<T>::finite(values[i])) {
      status = error(ErrorCode::kInvalidArgument,
                     std::string(name) + "[" + std::to_string(i) + "]: has a NaN or infinite component");
      return false;
    }
  }
  return true;
}

}  // namespace

std::span<const std::string_view> interpolation_names() { return kInterpolationNames; }

namespace detail {

SlerpSpan slerp_span(const Quat& a, const Quat& b) {
  SlerpSpan span;
  double d = a.dot(b);
  span.end = b;
  if (d < 0.0) {  // q and -q are one rotation: go the short way
    d = -d;
    span.end.coeffs() = -span.end.coeffs();
  }
  // Nearly equal (d > 0.9999): sin(theta) ~ 0; a normalised lerp is exact to
  // ~1e-9 there, and theta stays negative.
  if (!(d > 0.9999)) {
    span.theta = std::acos(d);
    span.inv_sin = 1.0 / std::sin(span.theta);
  }
  return span;
}

Quat slerp_along(const Quat& a, const SlerpSpan& span, double s) {
  double wa, wb;
  if (span.theta < 0.0) {
    wa = 1.0 - s;
    wb = s;
  } else {
    wa = std::sin((1.0 - s) * span.theta) * span.inv_sin;
    wb = std::sin(s * span.theta) * span.inv_sin;
  }
  Quat q;
  q.coeffs() = wa * a.coeffs() + wb * span.end.coeffs();
  return q.normalized();
}

}  // namespace detail

Quat slerp_shortest(const Quat& a, const Quat& b, double s) { return detail::slerp_along(a, detail::slerp_span(a, b), s); }

template <typename T>
Status TrackArrays<T>::validate() const {
  const std::size_t n = times.size();
  if (static_cast<int>(interpolation) >= kInterpolationCount) {
    return error(ErrorCode::kInvalidArgument, "interpolation: " + std::to_string(static_cast<int>(interpolation)) +
                                                  " is not an interpolation (0 to " +
                                                  std::to_string(kInterpolationCount - 1) + ")");
  }
  if (values.size() != n) {
    return error(ErrorCode::kInvalidArgument, "keyValues has " + std::to_string(values.size()) +
                                                  " entries but keyTimes has " + std::to_string(n));
  }
  const bool cubic = interpolation == Interpolation::kCubicSpline;
  for (const auto& [tangents, name] : {std::pair{in_tangents, "inTangents"}, std::pair{out_tangents, "outTangents"}}) {
    if (cubic && tangents.size() != n) {
      return error(ErrorCode::kInvalidArgument, std::string(name) + " has " + std::to_string(tangents.size()) +
                                                    " entries but keyTimes has " + std::to_string(n) +
                                                    " (a cubic spline track needs one per key)");
    }
    if (!cubic && !tangents.empty()) {
      return error(ErrorCode::kInvalidArgument, std::string(name) + " has " + std::to_string(tangents.size()) +
                                                    " entries; only cubic spline tracks use tangents");
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::string at = "keys[" + std::to_string(i) + "].time";
    if (!std::isfinite(times[i])) return error(ErrorCode::kInvalidArgument, at + ": must be finite, got " + number(times[i]));
    if (i > 0 && !(times[i] > times[i - 1])) {
      const char* what = times[i] == times[i - 1] ? "duplicates" : "is before";
      return error(ErrorCode::kInvalidArgument, at + ": " + number(times[i]) + " " + what + " keys[" +
                                                    std::to_string(i - 1) + "].time " + number(times[i - 1]) +
                                                    " (key times must increase)");
    }
  }
  Status status;
  if (!finite_all<T>(values, "keyValues", status)) return status;
  if (!finite_all<T>(in_tangents, "inTangents", status)) return status;
  if (!finite_all<T>(out_tangents, "outTangents", status)) return status;
  if constexpr (std::is_same_v<T, Quat>) {
    for (std::size_t i = 0; i < n; ++i) {
      if (!(values[i].norm() >= 1e-6)) {
        return error(ErrorCode::kInvalidArgument, "keyValues[" + std::to_string(i) +
                                                      "]: the zero quaternion is not a rotation (norm " +
                                                      number(values[i].norm()) + ")");
      }
    }
  }
  return Status::ok();
}

template <typename T>
T evaluate_arrays(const TrackArrays<T>& arrays, double t) {
  Cursor cursor;
  cursor.key = std::numeric_limits<std::uint32_t>::max();
  return sample<T, true>(arrays, t, cursor);
}

template <typename T>
Result<Track<T>> Track<T>::build(std::vector<double> times, std::vector<T> values, Interpolation interpolation,
                                 std::vector<T> in_tangents, std::vector<T> out_tangents) {
  const TrackArrays<T> arrays{times, values, in_tangents, out_tangents, interpolation};
  if (Status s = arrays.validate(); !s) return s;
  Track track;
  if constexpr (std::is_same_v<T, Quat>) {
    for (Quat& q : values) q.normalize();
  }
  track.times_ = std::move(times);
  track.values_ = std::move(values);
  track.in_tangents_ = std::move(in_tangents);
  track.out_tangents_ = std::move(out_tangents);
  track.interpolation_ = interpolation;
  if constexpr (std::is_same_v<T, Quat>) {
    if (interpolation == Interpolation::kLinear && track.values_.size() >= 2) {
      track.slerp_.reserve(track.values_.size() - 1);
      for (std::size_t i = 0; i + 1 < track.values_.size(); ++i)
        track.slerp_.push_back(detail::slerp_span(track.values_[i], track.values_[i + 1]));
    }
  }
  return track;
}

template <typename T>
Result<Track<T>> Track<T>::from_gltf(std::span<const double> times, std::span<const T> output,
                                     Interpolation interpolation) {
  const bool cubic = interpolation == Interpolation::kCubicSpline;
  const std::size_t per_key = cubic ? 3 : 1;
  if (output.size() != times.size() * per_key) {
    return error(ErrorCode::kInvalidArgument, "sampler output has " + std::to_string(output.size()) +
                                                  " elements; " + std::to_string(times.size()) + " keys need " +
                                                  std::to_string(times.size() * per_key) +
                                                  (cubic ? " (in-tangent, value, out-tangent per key)" : ""));
  }
  std::vector<T> values, in_tangents, out_tangents;
  values.reserve(times.size());
  for (std::size_t i = 0; i < times.size(); ++i) {
    if (cubic) {
      in_tangents.push_back(output[3 * i]);
      values.push_back(output[3 * i + 1]);
      out_tangents.push_back(output[3 * i + 2]);
    } else {
      values.push_back(output[i]);
    }
  }
  return build(std::vector<double>(times.begin(), times.end()), std::move(values), interpolation,
               std::move(in_tangents), std::move(out_tangents));
}

template <typename T>
T Track<T>::evaluate(double t, Cursor& cursor) const {
  if constexpr (std::is_same_v<T, Quat>) {
    // A linear rotation: sample()'s result through the prepared slerps. Its
    // own path: passing the slerps through sample() measured 10-15% slower
    // per joint (anim/sample/joint_trs).
    const std::size_t n = times_.size();
    if (!slerp_.empty() && !std::isnan(t) && t > times_[0] && t < times_[n - 1]) {
      const std::size_t i = find_segment(times_.data(), n, t, cursor);
      const double s = (t - times_[i]) / (times_[i + 1] - times_[i]);
      return detail::slerp_along(values_[i], slerp_[i], s);
    }
  }
  return sample<T, false>(arrays(), t, cursor);
}

template <typename T>
T Track<T>::evaluate(double t) const {
  Cursor cursor;
  cursor.key = std::numeric_limits<std::uint32_t>::max();
  return sample<T, false>(arrays(), t, cursor);
}

template <typename T>
bool SampleTracksJob<T>::validate() const {
  return cursors.size() >= tracks.size() && output.size() >= tracks.size() && !std::isnan(time);
}

template <typename T>
bool SampleTracksJob<T>::run() const {
  if (!validate()) return false;
  for (std::size_t i = 0; i < tracks.size(); ++i) output[i] = tracks[i].evaluate(time, cursors[i]);
  return true;
}

template struct TrackArrays<Vec3>;
template struct TrackArrays<Quat>;
template Vec3 evaluate_arrays<Vec3>(const TrackArrays<Vec3>&, double);
template Quat evaluate_arrays<Quat>(const TrackArrays<Quat>&, double);
template class Track<Vec3>;
template class Track<Quat>;
template struct SampleTracksJob<Vec3>;
template struct SampleTracksJob<Quat>;

}  // namespace rigel::ops::anim
