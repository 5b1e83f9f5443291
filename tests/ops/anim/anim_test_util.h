#pragma once
// Helpers for the animation tests: Status as an assertion, keys written
// tersely, seeded random curves, and reference formulas written out
// independently of the code under test (Hermite and Bezier in Bernstein
// form).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/ops/anim/curve.h"

namespace rigel::ops::anim::testing {

inline ::testing::AssertionResult succeeded(const Status& status) {
  if (status.is_ok()) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "failed (" << error_code_name(status.code()) << "): " << status.message();
}

// A failure whose message contains `text`.
inline ::testing::AssertionResult fails_with(const Status& status, const std::string& text) {
  if (status.is_ok()) return ::testing::AssertionFailure() << "succeeded; expected a failure mentioning '" << text << "'";
  if (status.message().find(text) == std::string::npos)
    return ::testing::AssertionFailure() << "message '" << status.message() << "' does not mention '" << text << "'";
  return ::testing::AssertionSuccess();
}

inline Key key(double time, double value, TangentType type = TangentType::kAuto) {
  Key k;
  k.time = time;
  k.value = value;
  k.in_type = type;
  k.out_type = type;
  return k;
}

inline AnimCurve make_curve(std::vector<Key> keys, CurveSettings settings = {}) {
  Result<AnimCurve> curve = AnimCurve::build(std::move(keys), settings);
  EXPECT_TRUE(succeeded(curve.status()));
  return curve ? std::move(curve).value() : AnimCurve();
}

// Keys as an animCurve node's per-key arrays (CurveArrays' storage).
struct KeyColumns {
  std::vector<double> times, values, in_slopes, out_slopes, in_weights, out_weights;
  std::vector<std::int64_t> in_types, out_types;
  void append(const std::vector<Key>& keys) {
    for (const Key& k : keys) {
      times.push_back(k.time);
      values.push_back(k.value);
      in_types.push_back(static_cast<std::int64_t>(k.in_type));
      out_types.push_back(static_cast<std::int64_t>(k.out_type));
      in_slopes.push_back(k.in_slope);
      out_slopes.push_back(k.out_slope);
      in_weights.push_back(k.in_weight);
      out_weights.push_back(k.out_weight);
    }
  }
};

// Cubic Hermite on [t0, t1] with end slopes m0, m1 (per time unit).
inline double hermite(double t0, double v0, double m0, double t1, double v1, double m1, double t) {
  const double span = t1 - t0, s = (t - t0) / span, s2 = s * s, s3 = s2 * s;
  return (2 * s3 - 3 * s2 + 1) * v0 + (s3 - 2 * s2 + s) * span * m0 + (-2 * s3 + 3 * s2) * v1 + (s3 - s2) * span * m1;
}

inline double bernstein(double p0, double p1, double p2, double p3, double u) {
  const double w = 1 - u;
  return w * w * w * p0 + 3 * w * w * u * p1 + 3 * w * u * u * p2 + u * u * u * p3;
}

class Random {
 public:
  explicit Random(unsigned seed) : engine_(seed) {}
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(engine_); }
  int index(int count) { return std::uniform_int_distribution<int>(0, count - 1)(engine_); }

  // Keys at increasing random times from `start`, random values, random
  // tangent types (fixed slopes and weights random too).
  std::vector<Key> keys(int count, double start = 0.0) {
    std::vector<Key> result;
    double t = start;
    for (int i = 0; i < count; ++i) {
      Key k;
      k.time = t;
      k.value = uniform(-10, 10);
      k.in_type = static_cast<TangentType>(index(kTangentTypeCount));
      k.out_type = static_cast<TangentType>(index(kTangentTypeCount));
      k.in_slope = uniform(-20, 20);
      k.out_slope = uniform(-20, 20);
      k.in_weight = uniform(0.0, 1.2);
      k.out_weight = uniform(0.0, 1.2);
      result.push_back(k);
      t += uniform(0.01, 1.0);
    }
    return result;
  }
  CurveSettings settings(bool weighted) {
    CurveSettings s;
    s.weighted = weighted;
    s.pre_infinity = static_cast<Infinity>(index(kInfinityCount));
    s.post_infinity = static_cast<Infinity>(index(kInfinityCount));
    return s;
  }
  std::mt19937& engine() { return engine_; }

 private:
  std::mt19937 engine_;
};

}  // namespace rigel::ops::anim::testing
