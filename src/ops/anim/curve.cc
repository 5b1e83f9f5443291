#include "rigel/ops/anim/curve.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "curve_kernels.h"

namespace rigel::ops::anim {
namespace {

constexpr std::array<std::string_view, kTangentTypeCount> kTangentTypeNames = {
    "fixed", "linear", "flat", "step", "stepNext", "spline", "clamped", "plateau", "auto"};
constexpr std::array<std::string_view, kInfinityCount> kInfinityNames = {"constant", "linear", "cycle", "cycleOffset",
                                                                         "oscillate"};

std::string number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", v);
  return buffer;
}

std::string where(std::size_t index, const char* field) { return "keys[" + std::to_string(index) + "]." + field; }

bool valid_tangent_type(TangentType type) { return static_cast<int>(type) < kTangentTypeCount; }

// `side` is "in" or "out". Strings are built only on failure: this runs for
// every key of a node's curve on every compute.
Status check_tangent(std::size_t index, const char* side, TangentType type, double slope, double weight,
                     bool weighted) {
  if (!valid_tangent_type(type)) {
    return error(ErrorCode::kInvalidArgument,
                 where(index, (std::string(side) + "TangentType").c_str()) + ": " +
                     std::to_string(static_cast<int>(type)) + " is not a tangent type (0 to " +
                     std::to_string(kTangentTypeCount - 1) + ")");
  }
  if (type == TangentType::kFixed && !std::isfinite(slope)) {
    return error(ErrorCode::kInvalidArgument, where(index, (std::string(side) + "Slope").c_str()) +
                                                  ": a fixed tangent needs a finite slope, got " + number(slope));
  }
  if (weighted && !(std::isfinite(weight) && weight >= 0.0)) {
    return error(ErrorCode::kInvalidArgument, where(index, (std::string(side) + "Weight").c_str()) +
                                                  ": a weight must be finite and not negative, got " + number(weight));
  }
  return Status::ok();
}

Status check_settings(const CurveSettings& settings) {
  for (const auto& [mode, name] :
       {std::pair{settings.pre_infinity, "preInfinity"}, std::pair{settings.post_infinity, "postInfinity"}}) {
    if (static_cast<int>(mode) >= kInfinityCount) {
      return error(ErrorCode::kInvalidArgument, std::string(name) + ": " + std::to_string(static_cast<int>(mode)) +
                                                    " is not an infinity mode (0 to " +
                                                    std::to_string(kInfinityCount - 1) + ")");
    }
  }
  return Status::ok();
}

// check_key's test without its message: validation runs over every key of a
// node's curve on every compute, so the common case builds no Status.
bool key_ok(const Key& k, const Key* prev, bool weighted) {
  auto tangent_ok = [&](TangentType type, double slope, double weight) {
    return valid_tangent_type(type) && (type != TangentType::kFixed || std::isfinite(slope)) &&
           (!weighted || (std::isfinite(weight) && weight >= 0.0));
  };
  return std::isfinite(k.time) && std::isfinite(k.value) && (!prev || k.time > prev->time) &&
         tangent_ok(k.in_type, k.in_slope, k.in_weight) && tangent_ok(k.out_type, k.out_slope, k.out_weight);
}

// x - x is 0 for finite x and NaN for NaN and infinities; unlike
// std::isfinite it vectorises.
inline bool finite(double x) { return x - x == 0.0; }

// Every per-key check of CurveArrays::validate at once, as plain loops over
// the arrays without early exits (so they vectorise): a node validates its
// whole curve on every compute. Only when this fails does validate() walk
// the keys again to word the first problem.
bool arrays_ok(const CurveArrays& a) {
  const std::size_t n = a.times.size();
  const double* times = a.times.data();
  const double* values = a.values.data();
  bool ok = true;
  for (std::size_t i = 0; i < n; ++i) ok &= finite(times[i]) & finite(values[i]);
  for (std::size_t i = 1; i < n; ++i) ok &= times[i] > times[i - 1];
  auto side_ok = [&](std::span<const std::int64_t> types, std::span<const double> slopes,
                     std::span<const double> weights) {
    bool side = true;
    for (const std::int64_t type : types) {
      side &= static_cast<std::uint64_t>(type) < static_cast<std::uint64_t>(kTangentTypeCount);
    }
    // Slopes matter only for fixed tangents, and the default type is auto.
    if (!types.empty() && !slopes.empty()) {
      for (std::size_t i = 0; i < n; ++i) side &= (types[i] != 0) | finite(slopes[i]);
    }
    if (a.settings.weighted) {
      for (const double w : weights) side &= finite(w) & (w >= 0.0);
    }
    return side;
  };
  ok &= side_ok(a.in_types, a.in_slopes, a.in_weights);
  ok &= side_ok(a.out_types, a.out_slopes, a.out_weights);
  return ok;
}

// Key `i` on its own and against the key before it (`prev`, null for the first).
Status check_key(std::size_t i, const Key& k, const Key* prev, bool weighted) {
  if (!std::isfinite(k.time)) {
    return error(ErrorCode::kInvalidArgument, where(i, "time") + ": must be finite, got " + number(k.time));
  }
  if (!std::isfinite(k.value)) {
    return error(ErrorCode::kInvalidArgument, where(i, "value") + ": must be finite, got " + number(k.value));
  }
  if (prev && !(k.time > prev->time)) {
    const char* what = k.time == prev->time ? "duplicates" : "is before";
    return error(ErrorCode::kInvalidArgument, where(i, "time") + ": " + number(k.time) + " " + what + " keys[" +
                                                  std::to_string(i - 1) + "].time " + number(prev->time) +
                                                  " (key times must increase)");
  }
  if (Status s = check_tangent(i, "in", k.in_type, k.in_slope, k.in_weight, weighted); !s) return s;
  return check_tangent(i, "out", k.out_type, k.out_slope, k.out_weight, weighted);
}

// The key that starts the segment holding t, for t in [times.front(),
// times.back()). Stays in [0, times.size() - 2] even for unsorted times
// (evaluate_arrays on arrays that skipped validation).
std::uint32_t find_segment(std::span<const double> times, double t) {
  auto it = std::upper_bound(times.begin(), times.end() - 1, t);
  if (it == times.begin()) return 0;
  return static_cast<std::uint32_t>(it - times.begin()) - 1;
}

}  // namespace

std::span<const std::string_view> tangent_type_names() { return kTangentTypeNames; }
std::span<const std::string_view> infinity_names() { return kInfinityNames; }

Status validate_keys(std::span<const Key> keys, const CurveSettings& settings) {
  if (Status s = check_settings(settings); !s) return s;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const Key* prev = i > 0 ? &keys[i - 1] : nullptr;
    if (!key_ok(keys[i], prev, settings.weighted)) return check_key(i, keys[i], prev, settings.weighted);
  }
  return Status::ok();
}

// ---- AnimCurve ---------------------------------------------------------------

Result<AnimCurve> AnimCurve::build(std::vector<Key> keys, const CurveSettings& settings) {
  if (Status s = validate_keys(keys, settings); !s) return s;
  AnimCurve curve;
  curve.settings_ = settings;
  const std::size_t n = keys.size();
  curve.times_.resize(n);
  curve.in_slopes_.resize(n);
  curve.out_slopes_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Key* prev = i > 0 ? &keys[i - 1] : nullptr;
    const Key* next = i + 1 < n ? &keys[i + 1] : nullptr;
    const detail::Slopes slopes = detail::resolve_slopes(prev, keys[i], next);
    curve.times_[i] = keys[i].time;
    curve.in_slopes_[i] = slopes.in;
    curve.out_slopes_[i] = slopes.out;
  }
  if (n >= 2) {
    curve.segments_.resize(n - 1);
    if (settings.weighted) curve.bezier_.resize(n - 1);
    for (std::size_t i = 0; i + 1 < n; ++i) {
      curve.segments_[i] = detail::make_segment(keys[i], curve.out_slopes_[i], keys[i + 1], curve.in_slopes_[i + 1],
                                                settings.weighted, settings.weighted ? &curve.bezier_[i] : nullptr);
    }
  }
  if (n > 0) {
    detail::CurveEnds& e = curve.ends_;
    e.first_time = keys.front().time;
    e.last_time = keys.back().time;
    e.first_value = keys.front().value;
    e.last_value = keys.back().value;
    e.pre_slope = curve.in_slopes_.front();
    e.post_slope = curve.out_slopes_.back();
    e.pre = settings.pre_infinity;
    e.post = settings.post_infinity;
  }
  curve.keys_ = std::move(keys);
  return curve;
}

// The hot path: the cursor's segment still holds t. Everything else
// (another segment, the last key, infinities, NaN, an empty curve) is
// evaluate_slow's.
double AnimCurve::evaluate(double t, Cursor& cursor) const {
  const std::size_t i = cursor.key;
  if (i < segments_.size()) {
    const detail::Segment& s = segments_[i];
    if (t >= s.t0 && t < s.t1) return detail::evaluate_segment(s, bezier_.empty() ? nullptr : &bezier_[i], t);
  }
  return evaluate_slow(t, cursor);
}

double AnimCurve::evaluate(double t) const {
  Cursor cursor;
  cursor.key = std::numeric_limits<std::uint32_t>::max();  // no hint
  return evaluate_slow(t, cursor);
}

double AnimCurve::evaluate_slow(double t, Cursor& cursor) const {
  if (keys_.empty()) return 0.0;
  if (std::isnan(t)) return t;
  if (segments_.empty()) return ends_.first_value;  // one key: constant, whatever the infinities
  if (t >= ends_.first_time && t <= ends_.last_time) return evaluate_inside(t, cursor);
  return detail::evaluate_outside(ends_, t, [&](double local) { return evaluate_inside(local, cursor); });
}

// t in [first key time, last key time].
double AnimCurve::evaluate_inside(double t, Cursor& cursor) const {
  if (t >= ends_.last_time) return ends_.last_value;  // the last key itself (Maya: exact key values)
  const std::size_t n = segments_.size();
  std::size_t i = cursor.key;
  if (i < n && t >= segments_[i].t0 && t < segments_[i].t1) {
    // still here (after a cycle's wrap, say)
  } else if (i + 1 < n && t >= segments_[i + 1].t0 && t < segments_[i + 1].t1) {
    ++i;  // playing forward into the next segment
  } else if (i < n && i > 0 && t >= segments_[i - 1].t0 && t < segments_[i - 1].t1) {
    --i;  // playing backward
  } else {
    i = find_segment(times_, t);
  }
  cursor.key = static_cast<std::uint32_t>(i);
  return detail::evaluate_segment(segments_[i], bezier_.empty() ? nullptr : &bezier_[i], t);
}

// ---- CurveArrays -------------------------------------------------------------

Status CurveArrays::validate() const {
  const std::size_t n = times.size();
  auto size_error = [&](const char* name, std::size_t size) {
    return error(ErrorCode::kInvalidArgument, std::string(name) + " has " + std::to_string(size) +
                                                  " entries but keyTimes has " + std::to_string(n) +
                                                  " (optional arrays are empty or one entry per key)");
  };
  if (values.size() != n) {
    return error(ErrorCode::kInvalidArgument, "keyValues has " + std::to_string(values.size()) +
                                                  " entries but keyTimes has " + std::to_string(n));
  }
  if (!in_types.empty() && in_types.size() != n) return size_error("inTangentType", in_types.size());
  if (!out_types.empty() && out_types.size() != n) return size_error("outTangentType", out_types.size());
  if (!in_slopes.empty() && in_slopes.size() != n) return size_error("inSlope", in_slopes.size());
  if (!out_slopes.empty() && out_slopes.size() != n) return size_error("outSlope", out_slopes.size());
  if (!in_weights.empty() && in_weights.size() != n) return size_error("inWeight", in_weights.size());
  if (!out_weights.empty() && out_weights.size() != n) return size_error("outWeight", out_weights.size());
  if (arrays_ok(*this)) return check_settings(settings);
  // Something is wrong: find the first problem, key by key.
  for (const auto& [types, side] : {std::pair{in_types, "inTangentType"}, std::pair{out_types, "outTangentType"}}) {
    for (std::size_t i = 0; i < types.size(); ++i) {
      if (types[i] < 0 || types[i] >= kTangentTypeCount) {
        return error(ErrorCode::kInvalidArgument, where(i, side) + ": " + std::to_string(types[i]) +
                                                      " is not a tangent type (0 to " +
                                                      std::to_string(kTangentTypeCount - 1) + ")");
      }
    }
  }
  if (Status s = check_settings(settings); !s) return s;
  // The per-key checks, one key at a time (no allocation).
  Key prev;
  for (std::size_t i = 0; i < n; ++i) {
    const Key k = key(i);
    if (!key_ok(k, i > 0 ? &prev : nullptr, settings.weighted)) return check_key(i, k, i > 0 ? &prev : nullptr, settings.weighted);
    prev = k;
  }
  return Status::ok();
}

Key CurveArrays::key(std::size_t index) const {
  Key k;
  k.time = times[index];
  k.value = values[index];
  if (!in_types.empty()) k.in_type = static_cast<TangentType>(in_types[index]);
  if (!out_types.empty()) k.out_type = static_cast<TangentType>(out_types[index]);
  if (!in_slopes.empty()) k.in_slope = in_slopes[index];
  if (!out_slopes.empty()) k.out_slope = out_slopes[index];
  if (!in_weights.empty()) k.in_weight = in_weights[index];
  if (!out_weights.empty()) k.out_weight = out_weights[index];
  return k;
}

std::vector<Key> CurveArrays::keys() const {
  std::vector<Key> result(times.size());
  for (std::size_t i = 0; i < times.size(); ++i) result[i] = key(i);
  return result;
}

double evaluate_arrays(const CurveArrays& arrays, double t) {
  const std::size_t n = std::min(arrays.times.size(), arrays.values.size());
  if (n == 0) return 0.0;
  if (std::isnan(t)) return t;
  if (n == 1) return arrays.values[0];
  // Key i with its resolved slopes (reads keys i-1 .. i+1).
  auto slopes_of = [&](std::size_t i) {
    const Key key = arrays.key(i);
    Key prev, next;
    if (i > 0) prev = arrays.key(i - 1);
    if (i + 1 < n) next = arrays.key(i + 1);
    return detail::resolve_slopes(i > 0 ? &prev : nullptr, key, i + 1 < n ? &next : nullptr);
  };
  auto inside = [&](double local) {
    if (local >= arrays.times[n - 1]) return arrays.values[n - 1];
    const std::uint32_t i = find_segment(arrays.times.first(n), local);
    const Key k0 = arrays.key(i);
    const Key k1 = arrays.key(i + 1);
    detail::BezierTime bezier;
    const detail::Segment s = detail::make_segment(k0, slopes_of(i).out, k1, slopes_of(i + 1).in,
                                                   arrays.settings.weighted, &bezier);
    return detail::evaluate_segment(s, &bezier, local);
  };
  if (t >= arrays.times[0] && t <= arrays.times[n - 1]) return inside(t);
  detail::CurveEnds e;
  e.first_time = arrays.times[0];
  e.last_time = arrays.times[n - 1];
  e.first_value = arrays.values[0];
  e.last_value = arrays.values[n - 1];
  e.pre = arrays.settings.pre_infinity;
  e.post = arrays.settings.post_infinity;
  if (t < e.first_time && e.pre == Infinity::kLinear) e.pre_slope = slopes_of(0).in;
  if (t > e.last_time && e.post == Infinity::kLinear) e.post_slope = slopes_of(n - 1).out;
  return detail::evaluate_outside(e, t, inside);
}

// ---- SampleCurvesJob ---------------------------------------------------------

bool SampleCurvesJob::validate() const {
  return cursors.size() >= curves.size() && output.size() >= curves.size() && !std::isnan(time);
}

bool SampleCurvesJob::run() const {
  if (!validate()) return false;
  const std::size_t count = curves.size();
  const AnimCurve* curve = curves.data();
  Cursor* cursor = cursors.data();
  double* out = output.data();
  for (std::size_t i = 0; i < count; ++i) out[i] = curve[i].evaluate(time, cursor[i]);
  return true;
}

}  // namespace rigel::ops::anim
