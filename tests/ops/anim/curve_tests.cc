#include "rigel/ops/anim/curve.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "anim_test_util.h"

namespace rigel::ops::anim {
namespace {

using testing::bernstein;
using testing::fails_with;
using testing::hermite;
using testing::key;
using testing::KeyColumns;
using testing::make_curve;
using testing::Random;
using testing::succeeded;

constexpr double kTight = 1e-12;

// Largest and smallest value of `curve` sampled densely over [t0, t1].
std::pair<double, double> range_over(const AnimCurve& curve, double t0, double t1, int samples = 2000) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int i = 0; i <= samples; ++i) {
    const double v = curve.evaluate(t0 + (t1 - t0) * i / samples);
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  return {lo, hi};
}

// ---- tangent types -----------------------------------------------------------

TEST(AnimCurve, linear__straight_lines_between_keys) {
  const AnimCurve curve = make_curve({key(0, 0, TangentType::kLinear), key(1, 10, TangentType::kLinear),
                                      key(3, -10, TangentType::kLinear)});
  EXPECT_DOUBLE_EQ(curve.evaluate(0.5), 5.0) << "the midpoint of 0 -> 10 is 5";
  EXPECT_DOUBLE_EQ(curve.evaluate(2.0), 0.0) << "the midpoint of 10 -> -10 is 0";
  EXPECT_NEAR(curve.evaluate(0.25), 2.5, kTight);
  EXPECT_NEAR(curve.evaluate(1.5), 5.0, kTight);
  EXPECT_EQ(curve.evaluate(1.0), 10.0) << "a key's own time gives its value exactly";
  EXPECT_EQ(curve.evaluate(3.0), -10.0) << "the last key's time gives its value exactly";
  EXPECT_EQ(curve.out_slope(0), 10.0);
  EXPECT_EQ(curve.in_slope(1), 10.0);
  EXPECT_EQ(curve.out_slope(1), -10.0);
  EXPECT_EQ(curve.in_slope(2), -10.0);
  EXPECT_EQ(curve.in_slope(0), 0.0) << "an end key's outer linear tangent is flat (Maya)";
  EXPECT_EQ(curve.out_slope(2), 0.0) << "an end key's outer linear tangent is flat (Maya)";
}

TEST(AnimCurve, flat__zero_slope_at_keys) {
  const AnimCurve curve =
      make_curve({key(0, 0, TangentType::kFlat), key(1, 1, TangentType::kFlat), key(2, 0, TangentType::kFlat)});
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(curve.in_slope(i), 0.0);
    EXPECT_EQ(curve.out_slope(i), 0.0);
  }
  // Hermite with zero slopes: v(s) = 3 s^2 - 2 s^3.
  EXPECT_NEAR(curve.evaluate(0.25), 0.15625, kTight);
  EXPECT_NEAR(curve.evaluate(0.5), 0.5, kTight);
  const double h = 1e-6;
  EXPECT_NEAR((curve.evaluate(1 + h) - curve.evaluate(1 - h)) / (2 * h), 0.0, 1e-5)
      << "the curve's derivative at a flat key is zero";
  EXPECT_NEAR((curve.evaluate(h) - curve.evaluate(0)) / h, 0.0, 1e-5) << "and at the first key";
}

TEST(AnimCurve, step__holds_value_until_next_key) {
  const AnimCurve curve =
      make_curve({key(0, 1, TangentType::kStep), key(1, 5, TangentType::kStep), key(2, 3, TangentType::kStep)});
  EXPECT_EQ(curve.evaluate(0.0), 1.0);
  EXPECT_EQ(curve.evaluate(0.999), 1.0) << "a step holds the key's value up to the next key";
  EXPECT_EQ(curve.evaluate(1.0), 5.0) << "and jumps at the next key's time";
  EXPECT_EQ(curve.evaluate(1.5), 5.0);
  EXPECT_EQ(curve.evaluate(2.0), 3.0);
}

TEST(AnimCurve, step_next__takes_next_value_right_after_key) {
  const AnimCurve curve = make_curve(
      {key(0, 1, TangentType::kStepNext), key(1, 5, TangentType::kStepNext), key(2, 3, TangentType::kStepNext)});
  EXPECT_EQ(curve.evaluate(0.0), 1.0) << "at the key itself, the key's value";
  EXPECT_EQ(curve.evaluate(0.001), 5.0) << "right after it, the next key's value";
  EXPECT_EQ(curve.evaluate(1.0), 5.0);
  EXPECT_EQ(curve.evaluate(1.5), 3.0);
  EXPECT_EQ(curve.evaluate(2.0), 3.0);
}

TEST(AnimCurve, step_in_tangent__is_flat) {
  std::vector<Key> keys = {key(0, 0, TangentType::kLinear), key(1, 1, TangentType::kLinear)};
  keys[1].in_type = TangentType::kStep;
  const AnimCurve curve = make_curve(keys);
  EXPECT_EQ(curve.in_slope(1), 0.0) << "only an out tangent steps; an in step tangent is flat";
  EXPECT_NEAR(curve.evaluate(0.5), hermite(0, 0, 1, 1, 1, 0, 0.5), kTight);
}

TEST(AnimCurve, spline__slope_through_neighbours) {
  const AnimCurve curve = make_curve(
      {key(0, 0, TangentType::kSpline), key(1, 2, TangentType::kSpline), key(3, 3, TangentType::kSpline)});
  EXPECT_DOUBLE_EQ(curve.out_slope(0), 2.0) << "first key: toward the next key";
  EXPECT_DOUBLE_EQ(curve.in_slope(1), 1.0) << "(3 - 0) / (3 - 0)";
  EXPECT_DOUBLE_EQ(curve.out_slope(1), 1.0);
  EXPECT_DOUBLE_EQ(curve.in_slope(2), 0.5) << "last key: from the previous key, (3 - 2) / 2";
  // Segment 1 -> 3 at t = 2 (s = 1/2, span 2): 1 + 0.25 + 1.5 - 0.125.
  EXPECT_NEAR(curve.evaluate(2.0), 2.625, kTight);
  // Segment 0 -> 1 at t = 0.5: slopes 2 and 1, span 1: 0 + 0.25 + 1 - 0.125.
  EXPECT_NEAR(curve.evaluate(0.5), 1.125, kTight);
}

TEST(AnimCurve, fixed__uses_given_slopes) {
  std::vector<Key> keys = {key(0, 0, TangentType::kFixed), key(2, 1, TangentType::kFixed)};
  keys[0].out_slope = 2.0;
  keys[1].in_slope = -1.0;
  const AnimCurve curve = make_curve(keys);
  EXPECT_EQ(curve.out_slope(0), 2.0);
  EXPECT_EQ(curve.in_slope(1), -1.0);
  // s = 1/2, span 2: 0.125 * 2 * 2 + 0.5 * 1 - 0.125 * 2 * -1.
  EXPECT_NEAR(curve.evaluate(1.0), 1.25, kTight);
  EXPECT_NEAR(curve.evaluate(0.3), hermite(0, 0, 2, 2, 1, -1, 0.3), kTight);
}

TEST(AnimCurve, clamped__no_overshoot_between_equal_neighbours) {
  const std::vector<double> values = {0, 1, 1, 0};
  std::vector<Key> clamped, spline;
  for (int i = 0; i < 4; ++i) {
    clamped.push_back(key(i, values[i], TangentType::kClamped));
    spline.push_back(key(i, values[i], TangentType::kSpline));
  }
  const auto [spline_lo, spline_hi] = range_over(make_curve(spline), 1, 2);
  ASSERT_GT(spline_hi, 1.01) << "sanity: spline tangents overshoot between the two equal keys";
  const AnimCurve curve = make_curve(clamped);
  EXPECT_EQ(curve.out_slope(1), 0.0) << "a neighbour of equal value makes a clamped tangent flat";
  EXPECT_EQ(curve.in_slope(2), 0.0);
  const auto [lo, hi] = range_over(curve, 0, 3);
  EXPECT_LE(hi, 1.0) << "clamped tangents must not overshoot the equal keys";
  EXPECT_GE(lo, 0.0);
  EXPECT_EQ(curve.evaluate(1.5), 1.0) << "between two equal flat keys the curve is level";
}

TEST(AnimCurve, clamped__is_spline_away_from_equal_neighbours) {
  const AnimCurve clamped = make_curve(
      {key(0, 0, TangentType::kClamped), key(1, 2, TangentType::kClamped), key(3, 3, TangentType::kClamped)});
  const AnimCurve spline = make_curve(
      {key(0, 0, TangentType::kSpline), key(1, 2, TangentType::kSpline), key(3, 3, TangentType::kSpline)});
  for (double t = 0; t <= 3; t += 0.125) EXPECT_EQ(clamped.evaluate(t), spline.evaluate(t)) << "t = " << t;
  // Maya's tolerance: a neighbour within 0.05 counts as equal.
  const AnimCurve near = make_curve(
      {key(0, 0, TangentType::kClamped), key(1, 1, TangentType::kClamped), key(2, 1.04, TangentType::kClamped)});
  EXPECT_EQ(near.out_slope(1), 0.0) << "a neighbour 0.04 away is within kClampedTolerance";
  const AnimCurve far = make_curve(
      {key(0, 0, TangentType::kClamped), key(1, 1, TangentType::kClamped), key(2, 1.06, TangentType::kClamped)});
  EXPECT_DOUBLE_EQ(far.out_slope(1), 0.53) << "0.06 away is not: spline slope (1.06 - 0) / 2";
}

TEST(AnimCurve, auto__limits_slope_flat_at_ends_and_extremes) {
  const AnimCurve curve = make_curve({key(0, 0), key(1, 1), key(2, 10)});
  EXPECT_EQ(curve.out_slope(0), 0.0) << "auto end keys are flat";
  EXPECT_EQ(curve.in_slope(2), 0.0) << "auto end keys are flat";
  // Spline slope would be 10 / 2 = 5; the limit is 3 x the gentler secant (1).
  EXPECT_DOUBLE_EQ(curve.in_slope(1), 3.0);
  EXPECT_DOUBLE_EQ(curve.out_slope(1), 3.0);
  const AnimCurve gentle = make_curve({key(0, 0), key(1, 1), key(2, 2.5)});
  EXPECT_DOUBLE_EQ(gentle.out_slope(1), 1.25) << "below the limit, auto is spline";
  const AnimCurve peak = make_curve({key(0, 0), key(1, 5), key(2, 1)});
  EXPECT_EQ(peak.in_slope(1), 0.0) << "auto is flat at a local extreme";
  EXPECT_EQ(peak.out_slope(1), 0.0);
  const auto [lo, hi] = range_over(peak, 0, 2);
  EXPECT_LE(hi, 5.0);
  EXPECT_GE(lo, 0.0);
}

TEST(AnimCurve, auto__never_overshoots_neighbouring_keys) {
  Random random(7);
  for (int c = 0; c < 200; ++c) {
    std::vector<Key> keys = random.keys(2 + random.index(12));
    for (Key& k : keys) k.in_type = k.out_type = TangentType::kAuto;
    if (c % 3 == 0) {  // plateaus and level keys too
      for (std::size_t i = 1; i < keys.size(); i += 3) keys[i].value = keys[i - 1].value;
    }
    const AnimCurve curve = make_curve(keys);
    for (std::size_t i = 0; i + 1 < keys.size(); ++i) {
      const auto [lo, hi] = range_over(curve, keys[i].time, keys[i + 1].time, 200);
      const double a = keys[i].value, b = keys[i + 1].value;
      const double tolerance = 1e-9 * (1 + std::abs(a) + std::abs(b));
      EXPECT_GE(lo, std::min(a, b) - tolerance) << "curve " << c << " segment " << i << " undershoots";
      EXPECT_LE(hi, std::max(a, b) + tolerance) << "curve " << c << " segment " << i << " overshoots";
    }
  }
}

TEST(AnimCurve, plateau__flat_where_auto_would_limit) {
  const AnimCurve steep = make_curve(
      {key(0, 0, TangentType::kPlateau), key(1, 1, TangentType::kPlateau), key(2, 10, TangentType::kPlateau)});
  EXPECT_EQ(steep.out_slope(1), 0.0) << "auto would limit this slope; plateau flattens it";
  const AnimCurve gentle = make_curve(
      {key(0, 0, TangentType::kPlateau), key(1, 1, TangentType::kPlateau), key(2, 2.5, TangentType::kPlateau)});
  EXPECT_DOUBLE_EQ(gentle.out_slope(1), 1.25) << "below the limit, plateau is spline";
}

TEST(AnimCurve, in_and_out_types__resolve_independently) {
  std::vector<Key> keys = {key(0, 0), key(1, 1), key(2, 3)};
  keys[1].in_type = TangentType::kLinear;
  keys[1].out_type = TangentType::kFlat;
  const AnimCurve curve = make_curve(keys);
  EXPECT_EQ(curve.in_slope(1), 1.0);
  EXPECT_EQ(curve.out_slope(1), 0.0);
  EXPECT_NEAR(curve.evaluate(1.5), hermite(1, 1, 0, 2, 3, 0, 1.5), kTight) << "key 2 is an auto end key: flat";
}

// ---- weighted curves ----------------------------------------------------------

TEST(AnimCurve, weighted__one_third_weights_equal_unweighted_hermite) {
  Random random(11);
  for (int c = 0; c < 100; ++c) {
    std::vector<Key> keys = random.keys(2 + random.index(10));
    for (Key& k : keys) k.in_weight = k.out_weight = kDefaultWeight;
    CurveSettings settings = random.settings(false);
    const AnimCurve hermite_curve = make_curve(keys, settings);
    settings.weighted = true;
    const AnimCurve bezier_curve = make_curve(keys, settings);
    const double t0 = keys.front().time - 1, t1 = keys.back().time + 1;
    for (int i = 0; i <= 300; ++i) {
      const double t = t0 + (t1 - t0) * i / 300;
      const double expected = hermite_curve.evaluate(t);
      EXPECT_NEAR(bezier_curve.evaluate(t), expected, 1e-10 * (1 + std::abs(expected))) << "curve " << c << " t " << t;
    }
  }
}

TEST(AnimCurve, weighted__follows_bezier_in_time_and_value) {
  std::vector<Key> keys = {key(0, 0, TangentType::kFixed), key(1, 1, TangentType::kFixed)};
  keys[0].out_slope = 1.0;
  keys[0].out_weight = 0.5;
  keys[1].in_slope = 0.0;
  keys[1].in_weight = 0.25;
  const AnimCurve curve = make_curve(keys, {.weighted = true});
  // Control points (0, 0), (0.5, 0.5), (0.75, 1), (1, 1).
  EXPECT_NEAR(curve.evaluate(0.59375), 0.6875, kTight) << "u = 1/2: x = 4.75 / 8, y = 5.5 / 8";
  EXPECT_NEAR(curve.evaluate(0.33203125), 0.3671875, kTight) << "u = 1/4";
  for (double u = 0.0; u <= 1.0; u += 1.0 / 64) {
    const double x = bernstein(0, 0.5, 0.75, 1, u);
    EXPECT_NEAR(curve.evaluate(x), bernstein(0, 0.5, 1, 1, u), 1e-11) << "u = " << u;
  }
}

TEST(AnimCurve, weighted__extreme_weights_stay_robust) {
  // Zero-length handles (zero derivative of time at the keys), handles as
  // long as the span, and longer ones (shortened to the span).
  for (const auto& [a, b] : std::vector<std::pair<double, double>>{{0, 0}, {0, 1}, {1, 0}, {1, 1}, {1e-9, 1}, {5, 7}, {0.9, 0.95}}) {
    std::vector<Key> keys = {key(0, 0, TangentType::kFixed), key(2, 1, TangentType::kFixed)};
    keys[0].out_slope = 3.0;
    keys[0].out_weight = a;
    keys[1].in_slope = -2.0;
    keys[1].in_weight = b;
    const AnimCurve curve = make_curve(keys, {.weighted = true});
    const double ea = std::min(a, 1.0), eb = std::min(b, 1.0);
    const double x1 = 2 * ea, x2 = 2 - 2 * eb, y1 = 3.0 * ea * 2, y2 = 1 + 2.0 * eb * 2;
    for (double u = 0.0; u <= 1.0; u += 1.0 / 128) {
      const double t = bernstein(0, x1, x2, 2, u);
      const double value = curve.evaluate(t);
      ASSERT_TRUE(std::isfinite(value)) << "weights " << a << ", " << b << " at t " << t;
      // Where time barely moves with u (a zero-length handle), many u give
      // one t: compare values only where time is well conditioned.
      const double dt = std::abs(bernstein(0, x1, x2, 2, std::min(1.0, u + 1e-4)) - t);
      if (dt > 1e-6) {
        EXPECT_NEAR(value, bernstein(0, y1, y2, 1, u), 1e-6) << "weights " << a << ", " << b << " u " << u;
      }
    }
  }
}

// ---- infinity -------------------------------------------------------------------

// (0, 0) (0.5, 3) (1, 1), linear: v(0.25) = 1.5, v(0.75) = 2.
std::vector<Key> zigzag() {
  return {key(0, 0, TangentType::kLinear), key(0.5, 3, TangentType::kLinear), key(1, 1, TangentType::kLinear)};
}

TEST(AnimCurve, infinity__constant) {
  const AnimCurve curve = make_curve(zigzag());
  EXPECT_EQ(curve.evaluate(-5), 0.0);
  EXPECT_EQ(curve.evaluate(7), 1.0);
}

TEST(AnimCurve, infinity__linear_follows_end_tangents) {
  const AnimCurve curve =
      make_curve({key(0, 0, TangentType::kSpline), key(1, 1, TangentType::kSpline), key(2, 3, TangentType::kSpline)},
                 {.pre_infinity = Infinity::kLinear, .post_infinity = Infinity::kLinear});
  EXPECT_DOUBLE_EQ(curve.evaluate(-1), -1.0) << "first key's in slope (toward the next key) is 1";
  EXPECT_DOUBLE_EQ(curve.evaluate(3), 5.0) << "last key's out slope (from the previous key) is 2";
  const AnimCurve flat = make_curve({key(0, 0), key(1, 1)}, {.pre_infinity = Infinity::kLinear, .post_infinity = Infinity::kLinear});
  EXPECT_EQ(flat.evaluate(-3), 0.0) << "auto end keys are flat, so linear infinity is level";
}

TEST(AnimCurve, infinity__cycle_repeats) {
  const AnimCurve curve = make_curve(zigzag(), {.pre_infinity = Infinity::kCycle, .post_infinity = Infinity::kCycle});
  EXPECT_NEAR(curve.evaluate(1.25), 1.5, kTight);
  EXPECT_NEAR(curve.evaluate(5.75), 2.0, kTight);
  EXPECT_NEAR(curve.evaluate(-0.75), 1.5, kTight);
  EXPECT_NEAR(curve.evaluate(-3.25), 2.0, kTight);
  EXPECT_NEAR(curve.evaluate(2.0), 0.0, kTight) << "whole cycles land on the first key";
}

TEST(AnimCurve, infinity__cycle_offset_accumulates_value_delta) {
  const AnimCurve curve =
      make_curve(zigzag(), {.pre_infinity = Infinity::kCycleOffset, .post_infinity = Infinity::kCycleOffset});
  // Each repetition is offset by last - first = 1.
  EXPECT_NEAR(curve.evaluate(1.25), 2.5, kTight);
  EXPECT_NEAR(curve.evaluate(2.25), 3.5, kTight);
  EXPECT_NEAR(curve.evaluate(10.75), 12.0, kTight) << "10th repetition: v(0.75) + 10";
  EXPECT_NEAR(curve.evaluate(2.0), 2.0, kTight) << "the end of the first repetition is last + 1";
  EXPECT_NEAR(curve.evaluate(-0.75), 0.5, kTight);
  EXPECT_NEAR(curve.evaluate(-1.75), -0.5, kTight);
  EXPECT_NEAR(curve.evaluate(-1.0), -1.0, kTight);
  // Continuous across the seam where the value delta is made up.
  EXPECT_NEAR(curve.evaluate(1.0 + 1e-9), curve.evaluate(1.0), 1e-6);
}

TEST(AnimCurve, infinity__oscillate_mirrors) {
  const AnimCurve curve =
      make_curve(zigzag(), {.pre_infinity = Infinity::kOscillate, .post_infinity = Infinity::kOscillate});
  EXPECT_NEAR(curve.evaluate(1.25), 2.0, kTight) << "first repetition after: mirrored, v(0.75)";
  EXPECT_NEAR(curve.evaluate(2.25), 1.5, kTight) << "second: forward again, v(0.25)";
  EXPECT_NEAR(curve.evaluate(2.0), 0.0, kTight) << "back at the first key after one mirrored repetition";
  EXPECT_NEAR(curve.evaluate(-0.25), 1.5, kTight) << "first repetition before: mirrored, v(0.25)";
  EXPECT_NEAR(curve.evaluate(-1.25), 2.0, kTight) << "second before: forward, v(0.75)";
  for (double d : {0.1, 0.3, 0.7}) {
    EXPECT_NEAR(curve.evaluate(1 + d), curve.evaluate(1 - d), kTight) << "mirror about the last key";
    EXPECT_NEAR(curve.evaluate(-d), curve.evaluate(d), kTight) << "mirror about the first key";
  }
}

TEST(AnimCurve, infinity__single_key_is_constant_in_every_mode) {
  for (int pre = 0; pre < kInfinityCount; ++pre) {
    const CurveSettings settings{.pre_infinity = static_cast<Infinity>(pre), .post_infinity = static_cast<Infinity>(pre)};
    const AnimCurve curve = make_curve({key(1, 4)}, settings);
    EXPECT_EQ(curve.evaluate(-10), 4.0) << "mode " << pre;
    EXPECT_EQ(curve.evaluate(1), 4.0) << "mode " << pre;
    EXPECT_EQ(curve.evaluate(10), 4.0) << "mode " << pre;
  }
}

TEST(AnimCurve, evaluate__empty_curve_nan_and_infinite_time) {
  EXPECT_EQ(AnimCurve().evaluate(3.0), 0.0) << "an empty curve is 0";
  const AnimCurve curve = make_curve(zigzag(), {.pre_infinity = Infinity::kCycle, .post_infinity = Infinity::kLinear});
  EXPECT_TRUE(std::isnan(curve.evaluate(std::numeric_limits<double>::quiet_NaN()))) << "NaN in, NaN out";
  EXPECT_TRUE(std::isnan(curve.evaluate(-std::numeric_limits<double>::infinity()))) << "a cycle has no value at -inf";
  Cursor cursor{12345};
  EXPECT_NEAR(curve.evaluate(0.25, cursor), 1.5, kTight) << "a cursor out of range is only a hint";
}

// ---- cursor --------------------------------------------------------------------

TEST(AnimCurve, cursor__matches_fresh_search_for_any_sequence) {
  Random random(3);
  for (int c = 0; c < 40; ++c) {
    const std::vector<Key> keys = random.keys(1 + random.index(60), random.uniform(-2, 2));
    const AnimCurve curve = make_curve(keys, random.settings(c % 2 == 1));
    const double t0 = keys.front().time - 3, t1 = keys.back().time + 3;
    std::vector<double> times;
    for (double t = t0; t <= t1; t += 1.0 / 30) times.push_back(t);  // forward playback
    for (double t = t1; t >= t0; t -= 1.0 / 24) times.push_back(t);  // backward
    for (int i = 0; i < 500; ++i) times.push_back(random.uniform(t0, t1));  // jumps
    for (const Key& k : keys) times.push_back(k.time);                      // exact keys
    Cursor cursor;
    for (double t : times) {
      const double fresh = curve.evaluate(t);
      const double cached = curve.evaluate(t, cursor);
      ASSERT_TRUE(fresh == cached || (std::isnan(fresh) && std::isnan(cached)))
          << "curve " << c << " t " << t << ": cursor gave " << cached << ", search gave " << fresh;
    }
  }
}

TEST(AnimCurve, cursor__sequential_playback_stays_in_neighbouring_segments) {
  std::vector<Key> keys;
  for (int i = 0; i <= 100; ++i) keys.push_back(key(i * 0.1, std::sin(i * 0.1)));
  const AnimCurve curve = make_curve(keys);
  Cursor cursor;
  for (int frame = 0; frame < 300; ++frame) {
    const double t = frame / 30.0;
    curve.evaluate(t, cursor);
    EXPECT_LE(keys[cursor.key].time, t) << "the cursor names the segment's first key";
    if (t < 10.0) {
      EXPECT_LT(t, keys[cursor.key + 1].time);
    }
  }
}

// ---- validation ----------------------------------------------------------------

TEST(AnimCurve, validate__nan_or_infinite_time) {
  std::vector<Key> keys = {key(0, 0), key(std::numeric_limits<double>::quiet_NaN(), 1)};
  EXPECT_TRUE(fails_with(validate_keys(keys), "keys[1].time: must be finite"));
  keys[1].time = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(fails_with(AnimCurve::build(keys).status(), "keys[1].time"));
}

TEST(AnimCurve, validate__nan_or_infinite_value) {
  std::vector<Key> keys = {key(0, 0), key(1, 1), key(2, std::numeric_limits<double>::quiet_NaN())};
  EXPECT_TRUE(fails_with(AnimCurve::build(keys).status(), "keys[2].value: must be finite"));
  keys[2].value = -std::numeric_limits<double>::infinity();
  EXPECT_TRUE(fails_with(validate_keys(keys), "keys[2].value"));
}

TEST(AnimCurve, validate__unsorted_times) {
  const std::vector<Key> keys = {key(0, 0), key(2, 1), key(1, 2)};
  const Status status = AnimCurve::build(keys).status();
  EXPECT_EQ(status.code(), ErrorCode::kInvalidArgument);
  EXPECT_TRUE(fails_with(status, "keys[2].time: 1 is before keys[1].time 2"));
}

TEST(AnimCurve, validate__duplicate_times) {
  const std::vector<Key> keys = {key(0, 0), key(1, 1), key(1, 2)};
  EXPECT_TRUE(fails_with(AnimCurve::build(keys).status(), "keys[2].time: 1 duplicates keys[1].time 1"));
}

TEST(AnimCurve, validate__bad_tangent_type) {
  std::vector<Key> keys = {key(0, 0), key(1, 1)};
  keys[1].out_type = static_cast<TangentType>(42);
  EXPECT_TRUE(fails_with(AnimCurve::build(keys).status(), "keys[1].outTangentType: 42 is not a tangent type"));
  keys[1].out_type = TangentType::kAuto;
  keys[0].in_type = static_cast<TangentType>(kTangentTypeCount);
  EXPECT_TRUE(fails_with(validate_keys(keys), "keys[0].inTangentType"));
}

TEST(AnimCurve, validate__bad_fixed_slope) {
  std::vector<Key> keys = {key(0, 0), key(1, 1, TangentType::kFixed)};
  keys[1].in_slope = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(fails_with(AnimCurve::build(keys).status(), "keys[1].inSlope: a fixed tangent needs a finite slope"));
  keys[1].in_type = TangentType::kAuto;
  EXPECT_TRUE(succeeded(validate_keys(keys))) << "a slope that is not used (not fixed) is not checked";
}

TEST(AnimCurve, validate__bad_weight) {
  std::vector<Key> keys = {key(0, 0), key(1, 1)};
  keys[0].out_weight = -0.1;
  EXPECT_TRUE(fails_with(AnimCurve::build(keys, {.weighted = true}).status(),
                         "keys[0].outWeight: a weight must be finite and not negative"));
  keys[0].out_weight = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(fails_with(validate_keys(keys, {.weighted = true}), "keys[0].outWeight"));
  EXPECT_TRUE(succeeded(validate_keys(keys))) << "weights are not used (nor checked) on unweighted curves";
}

TEST(AnimCurve, validate__bad_infinity) {
  CurveSettings settings;
  settings.post_infinity = static_cast<Infinity>(9);
  EXPECT_TRUE(fails_with(AnimCurve::build({key(0, 0)}, settings).status(), "postInfinity: 9 is not an infinity mode"));
  settings.post_infinity = Infinity::kConstant;
  settings.pre_infinity = static_cast<Infinity>(5);
  EXPECT_TRUE(fails_with(validate_keys({}, settings), "preInfinity"));
}

TEST(AnimCurve, validate__accepts_empty_and_good_keys) {
  EXPECT_TRUE(succeeded(validate_keys({})));
  EXPECT_TRUE(succeeded(AnimCurve::build(zigzag()).status()));
}

// ---- arrays (node storage) -------------------------------------------------------

TEST(CurveArrays, validate__mismatched_sizes) {
  const std::vector<double> times = {0, 1, 2}, values = {0, 1, 2}, two = {0, 1};
  const std::vector<std::int64_t> types = {0, 1};
  CurveArrays a;
  a.times = times;
  a.values = two;
  EXPECT_TRUE(fails_with(a.validate(), "keyValues has 2 entries but keyTimes has 3"));
  a.values = values;
  EXPECT_TRUE(succeeded(a.validate())) << "empty optional arrays take the defaults";
  struct Case {
    const char* name;
    void (*set)(CurveArrays&, std::span<const double>, std::span<const std::int64_t>);
  };
  const Case cases[] = {
      {"inTangentType", [](CurveArrays& x, auto, auto t) { x.in_types = t; }},
      {"outTangentType", [](CurveArrays& x, auto, auto t) { x.out_types = t; }},
      {"inSlope", [](CurveArrays& x, auto d, auto) { x.in_slopes = d; }},
      {"outSlope", [](CurveArrays& x, auto d, auto) { x.out_slopes = d; }},
      {"inWeight", [](CurveArrays& x, auto d, auto) { x.in_weights = d; }},
      {"outWeight", [](CurveArrays& x, auto d, auto) { x.out_weights = d; }},
  };
  for (const Case& c : cases) {
    CurveArrays b = a;
    c.set(b, two, types);
    EXPECT_TRUE(fails_with(b.validate(), std::string(c.name) + " has 2 entries but keyTimes has 3")) << c.name;
  }
}

TEST(CurveArrays, validate__tangent_type_out_of_range_and_key_checks) {
  const std::vector<double> times = {0, 2, 1}, values = {0, 1, 2};
  const std::vector<std::int64_t> types = {0, -1, 8};
  CurveArrays a;
  a.times = times;
  a.values = values;
  a.in_types = types;
  EXPECT_TRUE(fails_with(a.validate(), "keys[1].inTangentType: -1 is not a tangent type"));
  a.in_types = {};
  EXPECT_TRUE(fails_with(a.validate(), "keys[2].time: 1 is before keys[1].time 2"))
      << "arrays get the same per-key checks as keys";
}

TEST(CurveArrays, validate__agrees_with_validate_keys_on_corrupted_data) {
  // CurveArrays::validate has a fast path over the raw arrays; it must accept
  // and refuse exactly what the per-key validate_keys does.
  Random random(13);
  const double kBad[] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                         -std::numeric_limits<double>::infinity(), -0.5};
  int refused = 0;
  for (int c = 0; c < 2000; ++c) {
    const int n = 1 + random.index(8);
    std::vector<Key> keys = random.keys(n);
    KeyColumns columns;
    columns.append(keys);
    auto& [times, values, in_slopes, out_slopes, in_weights, out_weights, in_types, out_types] = columns;
    std::vector<double>* doubles[] = {&times, &values, &in_slopes, &out_slopes, &in_weights, &out_weights};
    const int corruptions = random.index(3);
    for (int k = 0; k < corruptions; ++k) {
      const int which = random.index(7);
      const std::size_t at = static_cast<std::size_t>(random.index(n));
      if (which == 6) times[at] = times[static_cast<std::size_t>(random.index(n))];  // duplicate or unsorted
      else (*doubles[which])[at] = kBad[random.index(4)];
    }
    CurveSettings settings = random.settings(random.index(2) == 0);
    CurveArrays arrays{times, values, in_types, out_types, in_slopes, out_slopes, in_weights, out_weights, settings};
    if (random.index(4) == 0) arrays.in_types = {};  // defaults: auto, slopes unused
    const Status fast = arrays.validate();
    const Status slow = validate_keys(arrays.keys(), settings);
    ASSERT_EQ(fast.is_ok(), slow.is_ok()) << "case " << c << ": validate says '" << fast.message()
                                          << "', validate_keys says '" << slow.message() << "'";
    if (!slow.is_ok()) {
      ++refused;
      EXPECT_EQ(fast.message(), slow.message()) << "case " << c << ": both name the same first problem";
    }
  }
  EXPECT_GT(refused, 500) << "sanity: many cases are corrupt";
}

TEST(CurveArrays, evaluate_arrays__equals_compiled_curve) {
  Random random(5);
  for (int c = 0; c < 60; ++c) {
    const std::vector<Key> keys = random.keys(1 + random.index(20));
    const CurveSettings settings = random.settings(c % 2 == 0);
    const AnimCurve curve = make_curve(keys, settings);
    KeyColumns k;
    k.append(keys);
    const CurveArrays arrays{k.times, k.values, k.in_types, k.out_types, k.in_slopes, k.out_slopes, k.in_weights, k.out_weights, settings};
    ASSERT_TRUE(succeeded(arrays.validate()));
    for (int i = 0; i < 200; ++i) {
      const double t = random.uniform(keys.front().time - 4, keys.back().time + 4);
      EXPECT_EQ(evaluate_arrays(arrays, t), curve.evaluate(t)) << "curve " << c << " t " << t;
    }
    for (const Key& k : keys) EXPECT_EQ(evaluate_arrays(arrays, k.time), k.value);
  }
}

// ---- SampleCurvesJob ---------------------------------------------------------------

TEST(SampleCurvesJob, validate__rejects_each_documented_failure) {
  std::vector<AnimCurve> curves = {make_curve(zigzag()), make_curve({key(0, 7)})};
  std::vector<Cursor> cursors(2);
  std::vector<double> output(2);
  {
    SampleCurvesJob job;
    job.curves = curves;
    job.cursors = cursors;
    job.output = output;
    EXPECT_TRUE(job.validate()) << "a well-formed job should validate";
  }
  {
    SampleCurvesJob job;
    EXPECT_TRUE(job.validate()) << "an empty job is valid";
    EXPECT_TRUE(job.run()) << "and does nothing";
  }
  {
    SampleCurvesJob job;
    job.curves = curves;
    job.cursors = std::span<Cursor>(cursors).first(1);
    job.output = output;
    EXPECT_FALSE(job.validate()) << "fewer cursors than curves should be rejected";
  }
  {
    SampleCurvesJob job;
    job.curves = curves;
    job.cursors = cursors;
    job.output = std::span<double>(output).first(1);
    EXPECT_FALSE(job.validate()) << "fewer outputs than curves should be rejected";
  }
  {
    SampleCurvesJob job;
    job.curves = curves;
    job.cursors = cursors;
    job.output = output;
    job.time = std::numeric_limits<double>::quiet_NaN();
    EXPECT_FALSE(job.validate()) << "a NaN time should be rejected";
    output = {-1, -1};
    EXPECT_FALSE(job.run()) << "run() should refuse an invalid job";
    EXPECT_EQ(output[0], -1.0) << "an invalid job writes nothing";
  }
  {
    std::vector<double> longer(3, -1.0);
    std::vector<Cursor> more(3);
    SampleCurvesJob job;
    job.curves = curves;
    job.cursors = more;
    job.output = longer;
    EXPECT_TRUE(job.run()) << "longer cursors and outputs are fine";
    EXPECT_EQ(longer[2], -1.0) << "outputs beyond the curves are left alone";
  }
}

TEST(SampleCurvesJob, run__matches_evaluate_over_playback) {
  Random random(9);
  std::vector<AnimCurve> curves;
  for (int c = 0; c < 50; ++c) curves.push_back(make_curve(random.keys(2 + random.index(30)), random.settings(c % 4 == 0)));
  std::vector<Cursor> cursors(curves.size());
  std::vector<double> output(curves.size());
  SampleCurvesJob job;
  job.curves = curves;
  job.cursors = cursors;
  job.output = output;
  for (int frame = -30; frame < 600; ++frame) {
    job.time = frame / 30.0;
    ASSERT_TRUE(job.run());
    for (std::size_t i = 0; i < curves.size(); ++i) {
      const double expected = curves[i].evaluate(job.time);
      ASSERT_TRUE(output[i] == expected || (std::isnan(output[i]) && std::isnan(expected))) << "curve " << i << " frame " << frame;
    }
  }
}

}  // namespace
}  // namespace rigel::ops::anim
