#pragma once
// The pieces of curve evaluation shared by AnimCurve (compiled segments) and
// evaluate_arrays (one segment built on the fly from a node's attributes):
// tangent resolution, segment construction, segment evaluation and the
// infinity modes. Private to src/ops/anim.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "rigel/ops/anim/curve.h"

namespace rigel::ops::anim::detail {

enum SegmentKind : std::uint32_t {
  kPolynomial = 0,  // c0 + c1 x + c2 x^2 + c3 x^3, x = t - t0 (Hermite, linear, step)
  kStepNext = 1,    // c0 at t0 exactly, c1 after
  kBezier = 2,      // value c(u) where x(u) = (t - t0) / (t1 - t0) (weighted curves)
};

inline double secant(const Key& a, const Key& b) { return (b.value - a.value) / (b.time - a.time); }

// Maya's "spline" slope: the line through both neighbours, or toward the
// only one.
inline double spline_slope(const Key* prev, const Key& key, const Key* next) {
  if (prev && next) return (next->value - prev->value) / (next->time - prev->time);
  if (next) return secant(key, *next);
  if (prev) return secant(*prev, key);
  return 0.0;
}

// The slope of one side of `key` (`in_side`: the side toward `prev`).
inline double side_slope(TangentType type, double fixed_slope, const Key* prev, const Key& key, const Key* next,
                         bool in_side) {
  switch (type) {
    case TangentType::kFixed:
      return fixed_slope;
    case TangentType::kLinear: {
      const Key* other = in_side ? prev : next;
      if (!other) return 0.0;  // Maya: an end key's outer linear tangent is flat
      return in_side ? secant(*other, key) : secant(key, *other);
    }
    case TangentType::kFlat:
    case TangentType::kStep:
    case TangentType::kStepNext:
      return 0.0;
    case TangentType::kSpline:
      return spline_slope(prev, key, next);
    case TangentType::kClamped: {
      const bool near_prev = prev && std::abs(prev->value - key.value) <= kClampedTolerance;
      const bool near_next = next && std::abs(next->value - key.value) <= kClampedTolerance;
      return near_prev || near_next ? 0.0 : spline_slope(prev, key, next);
    }
    case TangentType::kPlateau:
    case TangentType::kAuto: {
      if (!prev || !next) return 0.0;  // end keys are flat
      const double rise_in = key.value - prev->value;
      const double rise_out = next->value - key.value;
      if (rise_in * rise_out <= 0.0) return 0.0;  // an extreme, or level with a neighbour
      // A Hermite segment whose end slopes are at most 3x its secant is
      // monotonic (Fritsch-Carlson), so limiting the slope to 3x the gentler
      // of the two secants keeps both neighbouring segments from
      // overshooting. This is Maya's rule: its Bezier handle (a third of the
      // span long) may not rise past the gentler neighbour's value.
      const double limit = 3.0 * std::min(std::abs(rise_in) / (key.time - prev->time),
                                          std::abs(rise_out) / (next->time - key.time));
      const double slope = spline_slope(prev, key, next);
      if (std::abs(slope) <= limit) return slope;
      return type == TangentType::kPlateau ? 0.0 : std::copysign(limit, slope);
    }
  }
  return 0.0;
}

struct Slopes {
  double in = 0.0, out = 0.0;
};

inline Slopes resolve_slopes(const Key* prev, const Key& key, const Key* next) {
  return {side_slope(key.in_type, key.in_slope, prev, key, next, true),
          side_slope(key.out_type, key.out_slope, prev, key, next, false)};
}

// The segment from k0 to k1 (k0.time < k1.time) with k0's resolved out slope
// and k1's resolved in slope. `bezier` receives the time polynomial of a
// weighted segment (left alone otherwise).
inline Segment make_segment(const Key& k0, double out_slope, const Key& k1, double in_slope, bool weighted,
                            BezierTime* bezier) {
  Segment s;
  s.t0 = k0.time;
  s.t1 = k1.time;
  const double span = k1.time - k0.time;
  if (k0.out_type == TangentType::kStep) {
    s.kind = kPolynomial;
    s.c[0] = k0.value;
    return s;
  }
  if (k0.out_type == TangentType::kStepNext) {
    s.kind = kStepNext;
    s.c[0] = k0.value;
    s.c[1] = k1.value;
    return s;
  }
  if (!weighted) {
    // Hermite in x = t - t0, written with the differences from the secant so
    // that linear tangents give c2 = c3 = 0 exactly.
    const double sec = (k1.value - k0.value) / span;
    const double e0 = sec - out_slope;
    const double e1 = sec - in_slope;
    s.kind = kPolynomial;
    s.c[0] = k0.value;
    s.c[1] = out_slope;
    s.c[2] = (2.0 * e0 + e1) / span;
    s.c[3] = -(e0 + e1) / (span * span);
    return s;
  }
  // Weighted: a Bezier through (0, v0), (a, v0 + m0 a span), (1 - b, v1 - m1 b span), (1, v1)
  // in normalised time. Handles no longer than the span keep time monotonic.
  const double a = std::clamp(k0.out_weight, 0.0, 1.0);
  const double b = std::clamp(k1.in_weight, 0.0, 1.0);
  const double y0 = k0.value;
  const double y1 = k0.value + out_slope * a * span;
  const double y2 = k1.value - in_slope * b * span;
  const double y3 = k1.value;
  s.kind = kBezier;
  s.c[0] = y0;
  s.c[1] = 3.0 * (y1 - y0);
  s.c[2] = 3.0 * (y2 - 2.0 * y1 + y0);
  s.c[3] = y3 - 3.0 * y2 + 3.0 * y1 - y0;
  if (bezier) {
    bezier->x1 = 3.0 * a;
    bezier->x2 = 3.0 * (1.0 - b - 2.0 * a);
    bezier->x3 = 3.0 * (a + b) - 2.0;
  }
  return s;
}

// The u in [0, 1] with x(u) = s, for a monotonic x. Newton's method from
// u = s, kept inside a bracket that shrinks every step; a step that leaves
// the bracket (or a zero derivative, which x has where a handle has length
// 0) falls back to bisection, so it always converges.
inline double solve_bezier_time(const BezierTime& b, double s) {
  if (!(s > 0.0)) return 0.0;
  if (!(s < 1.0)) return 1.0;
  double lo = 0.0, hi = 1.0, u = s;
  for (int iteration = 0; iteration < 100; ++iteration) {
    const double f = ((b.x3 * u + b.x2) * u + b.x1) * u - s;
    if (std::abs(f) <= 1e-15) return u;
    if (f < 0.0) lo = u;
    else hi = u;
    if (hi - lo <= 1e-15) return 0.5 * (lo + hi);
    const double slope = (3.0 * b.x3 * u + 2.0 * b.x2) * u + b.x1;
    double next = u - f / slope;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);  // also catches slope 0 and NaN
    u = next;
  }
  return u;
}

inline double evaluate_special(const Segment& s, const BezierTime* bezier, double t) {
  if (s.kind == kStepNext) return t == s.t0 ? s.c[0] : s.c[1];
  // kBezier
  const double x = (t - s.t0) / (s.t1 - s.t0);
  const double u = bezier ? solve_bezier_time(*bezier, x) : x;
  return ((s.c[3] * u + s.c[2]) * u + s.c[1]) * u + s.c[0];
}

// The value of segment `s` at t in [t0, t1).
inline double evaluate_segment(const Segment& s, const BezierTime* bezier, double t) {
  if (s.kind == kPolynomial) {
    const double x = t - s.t0;
    return ((s.c[3] * x + s.c[2]) * x + s.c[1]) * x + s.c[0];
  }
  return evaluate_special(s, bezier, t);
}

// The value at `t` outside [first_time, last_time] (at least two keys).
// `inside(time)` evaluates the curve at a time within the keys.
template <typename Inside>
double evaluate_outside(const CurveEnds& e, double t, Inside&& inside) {
  const bool pre = t < e.first_time;
  const Infinity mode = pre ? e.pre : e.post;
  if (mode == Infinity::kConstant) return pre ? e.first_value : e.last_value;
  if (mode == Infinity::kLinear) {
    return pre ? e.first_value + e.pre_slope * (t - e.first_time) : e.last_value + e.post_slope * (t - e.last_time);
  }
  const double range = e.last_time - e.first_time;
  // How far past the end, in ranges: `whole` complete repetitions, then a
  // fraction of the next. `cycles` counts the repetition t is in (1 = the
  // one next to the keys).
  const double d = pre ? (e.first_time - t) / range : (t - e.last_time) / range;
  if (!std::isfinite(d)) return std::numeric_limits<double>::quiet_NaN();
  const double whole = std::floor(d);
  const double frac = d - whole;
  const double cycles = whole + 1.0;
  bool backward = pre;  // cycles walk back from the last key before the keys
  if (mode == Infinity::kOscillate) {
    const bool odd = std::fmod(cycles, 2.0) == 1.0;  // odd repetitions are mirrored
    backward = pre ? !odd : odd;
  }
  double local = backward ? e.last_time - frac * range : e.first_time + frac * range;
  local = std::min(std::max(local, e.first_time), e.last_time);  // rounding; not std::clamp, which needs first <= last
  double value = inside(local);
  if (mode == Infinity::kCycleOffset) value += (pre ? -cycles : cycles) * (e.last_value - e.first_value);
  return value;
}

}  // namespace rigel::ops::anim::detail
