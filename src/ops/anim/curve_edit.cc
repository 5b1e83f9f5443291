// One time curve read and edited key by key (curve_edit.h).
#include "rigel/ops/anim/curve_edit.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <type_traits>

#include "rigel/math/types.h"
#include "rigel/ops/anim/nodes.h"
#include "rigel/ops/anim/track.h"
#include "curve_layout.h"

namespace rigel::ops::anim {
namespace {

using graph::AttrIndex;
using graph::Graph;
using graph::NodeId;
using graph::Plug;
using graph::Value;
using internal::active_range;
using internal::CurveLayout;
using internal::KeyRange;
using internal::layout;
using math::Quat;
using math::Vec3;

constexpr std::int64_t kAutoTangent = static_cast<std::int64_t>(TangentType::kAuto);

template <typename T>
struct is_vector : std::false_type {};
template <typename T, typename A>
struct is_vector<std::vector<T, A>> : std::true_type {};

template <typename F>
void on_array(Value& v, F&& f) {
  std::visit(
      [&](auto& a) {
        if constexpr (is_vector<std::decay_t<decltype(a)>>::value) f(a);
      },
      v);
}

std::size_t size_of(const Value& v) {
  std::size_t n = 0;
  on_array(const_cast<Value&>(v), [&](auto& a) { n = a.size(); });
  return n;
}

// Elements [begin, end) of an array value (the same type).
Value slice(const Value& v, std::size_t begin, std::size_t end) {
  Value out = v;
  on_array(out, [&](auto& a) {
    using A = std::decay_t<decltype(a)>;
    a = A(a.begin() + static_cast<std::ptrdiff_t>(begin), a.begin() + static_cast<std::ptrdiff_t>(end));
  });
  return out;
}

// The elements of `v` in `order` (indices into it).
void permute(Value& v, const std::vector<std::size_t>& order) {
  on_array(v, [&](auto& a) {
    using A = std::decay_t<decltype(a)>;
    A out;
    out.reserve(order.size());
    for (std::size_t i : order) out.push_back(a[i]);
    a = std::move(out);
  });
}

// `prefix` + `middle` + `suffix` of one array type.
Value splice(const Value& whole, std::size_t begin, std::size_t end, const Value& middle) {
  Value out = slice(whole, 0, begin);
  on_array(out, [&](auto& a) {
    using A = std::decay_t<decltype(a)>;
    const A& m = std::get<A>(middle);
    const A& w = std::get<A>(whole);
    a.insert(a.end(), m.begin(), m.end());
    a.insert(a.end(), w.begin() + static_cast<std::ptrdiff_t>(end), w.end());
  });
  return out;
}

Status bad(std::size_t i, const std::string& message) {
  return error(ErrorCode::kInvalidArgument, "changes[" + std::to_string(i) + "]: " + message);
}

// The default element of per-key array `a` of a curve of `kind`.
Value default_element(CurveKind kind, AttrIndex a) {
  if (kind == CurveKind::kScalar) {
    if (a == curve_attr::kInTangentType || a == curve_attr::kOutTangentType) return Value(kAutoTangent);
    if (a == curve_attr::kInWeight || a == curve_attr::kOutWeight) return Value(kDefaultWeight);
    return Value(0.0);
  }
  if (kind == CurveKind::kVec3) return Value(Vec3(Vec3::Zero()));
  return Value(Quat(0, 0, 0, 0));  // a cubic tangent of no length
}

void append(Value& array, const Value& element) {
  on_array(array, [&](auto& a) {
    using E = typename std::decay_t<decltype(a)>::value_type;
    a.push_back(std::get<E>(element));
  });
}

// CurveArrays over keys [r.begin, r.end) of an animCurve node (spans into it).
CurveArrays scalar_arrays(const graph::Node& n, const KeyRange& r) {
  const std::size_t count = std::get<std::vector<double>>(n.value(curve_attr::kKeyTimes)).size();
  auto cut = [&](const auto& v) {
    using E = typename std::decay_t<decltype(v)>::value_type;
    if (v.size() != count) return std::span<const E>();
    return std::span<const E>(v).subspan(r.begin, r.end - r.begin);
  };
  CurveArrays a;
  a.times = cut(std::get<std::vector<double>>(n.value(curve_attr::kKeyTimes)));
  a.values = cut(std::get<std::vector<double>>(n.value(curve_attr::kKeyValues)));
  a.in_types = cut(std::get<std::vector<std::int64_t>>(n.value(curve_attr::kInTangentType)));
  a.out_types = cut(std::get<std::vector<std::int64_t>>(n.value(curve_attr::kOutTangentType)));
  a.in_slopes = cut(std::get<std::vector<double>>(n.value(curve_attr::kInSlope)));
  a.out_slopes = cut(std::get<std::vector<double>>(n.value(curve_attr::kOutSlope)));
  a.in_weights = cut(std::get<std::vector<double>>(n.value(curve_attr::kInWeight)));
  a.out_weights = cut(std::get<std::vector<double>>(n.value(curve_attr::kOutWeight)));
  a.settings.weighted = std::get<bool>(n.value(curve_attr::kWeighted));
  auto infinity = [&](AttrIndex at) {
    return static_cast<Infinity>(std::clamp<std::int64_t>(std::get<std::int64_t>(n.value(at)), 0, kInfinityCount - 1));
  };
  a.settings.pre_infinity = infinity(curve_attr::kPreInfinity);
  a.settings.post_infinity = infinity(curve_attr::kPostInfinity);
  return a;
}

template <typename T>
TrackArrays<T> track_arrays(const graph::Node& n, const KeyRange& r) {
  const std::size_t count = std::get<std::vector<double>>(n.value(track_attr::kKeyTimes)).size();
  auto cut = [&](const auto& v) {
    using E = typename std::decay_t<decltype(v)>::value_type;
    if (v.size() != count) return std::span<const E>();
    return std::span<const E>(v).subspan(r.begin, r.end - r.begin);
  };
  TrackArrays<T> a;
  a.times = cut(std::get<std::vector<double>>(n.value(track_attr::kKeyTimes)));
  a.values = cut(std::get<std::vector<T>>(n.value(track_attr::kKeyValues)));
  a.in_tangents = cut(std::get<std::vector<T>>(n.value(track_attr::kInTangents)));
  a.out_tangents = cut(std::get<std::vector<T>>(n.value(track_attr::kOutTangents)));
  a.interpolation = static_cast<Interpolation>(
      std::clamp<std::int64_t>(std::get<std::int64_t>(n.value(track_attr::kInterpolation)), 0, 2));
  return a;
}

std::vector<double> components(const Vec3& v) { return {v.x(), v.y(), v.z()}; }
std::vector<double> components(const Quat& q) { return {q.x(), q.y(), q.z(), q.w()}; }

template <typename T>
std::vector<std::vector<double>> sample_track(const graph::Node& n, const KeyRange& r, std::span<const double> times) {
  std::vector<std::vector<double>> out;
  out.reserve(times.size());
  if (r.clip == -2) {
    for (std::size_t i = 0; i < times.size(); ++i) out.push_back(components(std::get<T>(n.value(track_attr::kRestValue))));
    return out;
  }
  const TrackArrays<T> a = track_arrays<T>(n, r);
  const bool ok = a.validate().is_ok();
  for (double t : times) out.push_back(components(ok ? evaluate_arrays(a, t) : T(T::Identity())));
  return out;
}

}  // namespace

CurveKeys curve_keys(const Graph& graph, NodeId curve) {
  CurveKeys out;
  out.kind = curve_kind(graph, curve);
  if (out.kind == CurveKind::kOther) return out;
  const graph::Node& n = *graph.node(curve);
  const CurveLayout l = layout(out.kind);
  const KeyRange r = active_range(n, l);
  const auto& times = std::get<std::vector<double>>(n.value(l.times));
  const Value& values = n.value(l.values);
  for (std::size_t i = r.begin; i < r.end && i < times.size() && i < size_of(values); ++i) {
    out.times.push_back(times[i]);
    if (out.kind == CurveKind::kScalar) out.values.push_back({std::get<std::vector<double>>(values)[i]});
    else if (out.kind == CurveKind::kVec3) out.values.push_back(components(std::get<std::vector<Vec3>>(values)[i]));
    else out.values.push_back(components(std::get<std::vector<Quat>>(values)[i]));
  }
  if (out.kind != CurveKind::kScalar) return out;
  std::tie(out.in_types, out.out_types) = curve_key_tangents(graph, curve);
  const CurveArrays arrays = scalar_arrays(n, r);
  Result<AnimCurve> built = arrays.validate() ? AnimCurve::build(arrays.keys(), arrays.settings)
                                              : Result<AnimCurve>(arrays.validate());
  for (std::size_t k = 0; k < out.times.size(); ++k) {
    out.in_slopes.push_back(built ? built->in_slope(k) : 0.0);
    out.out_slopes.push_back(built ? built->out_slope(k) : 0.0);
  }
  return out;
}

std::vector<std::vector<double>> sample_curve(const Graph& graph, NodeId curve, std::span<const double> times) {
  const CurveKind kind = curve_kind(graph, curve);
  if (kind == CurveKind::kOther) return {};
  const graph::Node& n = *graph.node(curve);
  const KeyRange r = active_range(n, layout(kind));
  if (kind == CurveKind::kVec3) return sample_track<Vec3>(n, r, times);
  if (kind == CurveKind::kQuat) return sample_track<Quat>(n, r, times);
  std::vector<std::vector<double>> out;
  out.reserve(times.size());
  if (r.clip == -2) {
    for (std::size_t i = 0; i < times.size(); ++i) out.push_back({std::get<double>(n.value(anim_curve_attr::kRestValue))});
    return out;
  }
  const CurveArrays a = scalar_arrays(n, r);
  const bool ok = a.validate().is_ok();
  for (double t : times) out.push_back({ok ? evaluate_arrays(a, t) : 0.0});
  return out;
}

Status edit_curve(Graph& graph, NodeId curve, std::span<const KeyChange> changes) {
  const CurveKind kind = curve_kind(graph, curve);
  if (kind == CurveKind::kOther)
    return error(ErrorCode::kInvalidArgument,
                 "edit curve: '" + (graph.node(curve) ? graph.node(curve)->name() : std::string("?")) +
                     "' is not a time curve");
  const graph::Node& n = *graph.node(curve);
  const CurveLayout l = layout(kind);
  (void)graph.evaluate(Plug{curve, l.clip, -1});  // the active clip, up to date
  const KeyRange r = active_range(n, l);
  if (r.clip == -2)
    return error(ErrorCode::kInvalidArgument, "edit curve '" + n.name() + "': the active clip has no keys on it");
  std::vector<AttrIndex> attrs{l.times, l.values};
  attrs.insert(attrs.end(), l.per_key.begin(), l.per_key.end());
  const std::size_t total = std::get<std::vector<double>>(n.value(l.times)).size();
  const std::size_t count = r.end - r.begin;
  // The clip's keys, each array filled in where a change needs it.
  std::vector<Value> wholes(attrs.size()), sub(attrs.size());
  std::vector<bool> present(attrs.size());
  auto index_of = [&](AttrIndex a) {
    return static_cast<std::size_t>(std::find(attrs.begin(), attrs.end(), a) - attrs.begin());
  };
  for (std::size_t j = 0; j < attrs.size(); ++j) {
    wholes[j] = n.value(attrs[j]);
    present[j] = size_of(wholes[j]) == total;
    if (!present[j] && size_of(wholes[j]) != 0)
      return error(ErrorCode::kInvalidArgument, "edit curve '" + n.name() + "': its arrays are not one per key");
    sub[j] = present[j] ? slice(wholes[j], r.begin, r.end) : slice(wholes[j], 0, 0);
  }
  // An empty array (every key the default) made one per key, where a change needs it.
  auto fill = [&](AttrIndex a) {
    const std::size_t j = index_of(a);
    if (present[j]) return;
    for (std::size_t i = 0; i < total; ++i) append(wholes[j], default_element(kind, a));
    for (std::size_t i = 0; i < size_of(sub[0]); ++i) append(sub[j], default_element(kind, a));
    present[j] = true;
  };
  const double tolerance = kKeyTimeTolerance;
  std::vector<bool> changed(count, false);
  // New keys: appended, then sorted in with the rest.
  for (std::size_t i = 0; i < changes.size(); ++i) {
    const KeyChange& c = changes[i];
    if (c.key != kNewKey && c.key >= count)
      return bad(i, "key " + std::to_string(c.key) + " is out of range (the curve '" + n.name() + "' has " +
                        std::to_string(count) + " keys)");
    if (c.time && !std::isfinite(*c.time)) return bad(i, "the time is not finite");
    if (c.value && !std::isfinite(*c.value)) return bad(i, "the value is not finite");
    if ((c.in_slope && !std::isfinite(*c.in_slope)) || (c.out_slope && !std::isfinite(*c.out_slope)))
      return bad(i, "a slope is not finite");
    if (c.value && kind == CurveKind::kQuat)
      return bad(i, "'" + n.name() + "' is a rotation track; key its rotation through the channel, not a component");
    if (c.value && kind == CurveKind::kVec3 && (c.component < 0 || c.component > 2))
      return bad(i, "a vector track's value needs a component 0, 1 or 2");
    if (kind != CurveKind::kScalar && (c.in_type || c.out_type || c.in_slope || c.out_slope))
      return bad(i, "'" + n.name() + "' is a track (one interpolation for all its keys); tangents apply to curves");
    if (c.key == kNewKey && !c.time) return bad(i, "a new key needs a time");
  }
  for (std::size_t i = 0; i < changes.size(); ++i) {
    const KeyChange& c = changes[i];
    if (c.key != kNewKey) continue;
    const std::vector<double> at = sample_curve(graph, curve, std::span<const double>(&*c.time, 1)).front();
    for (std::size_t j = 0; j < attrs.size(); ++j) {
      if (!present[j]) continue;
      if (attrs[j] == l.times) append(sub[j], Value(*c.time));
      else if (attrs[j] != l.values) append(sub[j], default_element(kind, attrs[j]));
      else if (kind == CurveKind::kScalar) append(sub[j], Value(at[0]));
      else if (kind == CurveKind::kVec3) append(sub[j], Value(Vec3(at[0], at[1], at[2])));
      else append(sub[j], Value(Quat(at[3], at[0], at[1], at[2])));
    }
    changed.push_back(true);
  }
  // Values and tangents, by index (new keys numbered after the clip's).
  std::size_t next_new = count;
  std::vector<double>& times = std::get<std::vector<double>>(sub[0]);
  for (std::size_t i = 0; i < changes.size(); ++i) {
    const KeyChange& c = changes[i];
    const std::size_t k = c.key == kNewKey ? next_new++ : c.key;
    changed[k] = true;
    if (c.value) {
      if (kind == CurveKind::kScalar) std::get<std::vector<double>>(sub[1])[k] = *c.value;
      else std::get<std::vector<Vec3>>(sub[1])[k][c.component] = *c.value;
    }
    const std::pair<std::optional<TangentType>, std::optional<double>> sides[2] = {{c.in_type, c.in_slope},
                                                                                  {c.out_type, c.out_slope}};
    for (int side = 0; side < 2; ++side) {
      const auto& [type, slope] = sides[side];
      if (!type && !slope) continue;
      const AttrIndex type_attr = side == 0 ? curve_attr::kInTangentType : curve_attr::kOutTangentType;
      fill(type_attr);
      std::get<std::vector<std::int64_t>>(sub[index_of(type_attr)])[k] =
          static_cast<std::int64_t>(slope ? TangentType::kFixed : *type);
      if (slope) {
        const AttrIndex slope_attr = side == 0 ? curve_attr::kInSlope : curve_attr::kOutSlope;
        fill(slope_attr);
        std::get<std::vector<double>>(sub[index_of(slope_attr)])[k] = *slope;
      }
    }
    if (c.time) times[k] = *c.time;
  }
  // Time order; a moved key takes the place of one that stays.
  std::vector<std::size_t> order(times.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return times[a] < times[b]; });
  std::vector<std::size_t> kept;
  for (std::size_t k : order) {
    if (!kept.empty() && std::abs(times[k] - times[kept.back()]) <= tolerance) {
      if (changed[k] && changed[kept.back()])
        return error(ErrorCode::kInvalidArgument, "edit curve '" + n.name() + "': two keys changed to one time (" +
                                                      std::to_string(times[k]) + " s)");
      if (changed[k]) kept.back() = k;
      continue;
    }
    kept.push_back(k);
  }
  for (std::size_t j = 0; j < attrs.size(); ++j)
    if (present[j]) permute(sub[j], kept);
  if (kind == CurveKind::kQuat) {
    auto& qs = std::get<std::vector<Quat>>(sub[1]);
    for (std::size_t k = 1; k < qs.size(); ++k)
      if (qs[k].dot(qs[k - 1]) < 0) qs[k].coeffs() = -qs[k].coeffs();
  }
  graph::Transaction tx(graph, "edit curve " + n.name());
  Status s;
  for (std::size_t j = 0; j < attrs.size() && s; ++j) {
    if (present[j]) s = graph.set_value(Plug{curve, attrs[j], -1}, splice(wholes[j], r.begin, r.end, sub[j]));
  }
  if (s && r.clip >= 0 && kept.size() != count) {
    auto offsets = std::get<std::vector<std::int64_t>>(n.value(l.offsets));
    const auto delta = static_cast<std::int64_t>(kept.size()) - static_cast<std::int64_t>(count);
    for (std::size_t c = static_cast<std::size_t>(r.clip) + 1; c < offsets.size(); ++c) offsets[c] += delta;
    s = graph.set_value(Plug{curve, l.offsets, -1}, std::move(offsets));
  }
  if (!s) tx.rollback();
  return s;
}

}  // namespace rigel::ops::anim
