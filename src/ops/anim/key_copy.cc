// Keys copied between curves with every field (key_copy.h).
#include "rigel/ops/anim/key_copy.h"

#include <algorithm>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "curve_layout.h"
#include "rigel/math/types.h"
#include "rigel/ops/anim/nodes.h"

namespace rigel::ops::anim {
namespace {

using graph::AttrIndex;
using graph::Graph;
using graph::NodeId;
using graph::Plug;
using graph::Value;
using internal::CurveLayout;
using internal::KeyRange;
using math::Quat;
using math::Vec3;

template <typename T>
struct is_vector : std::false_type {};
template <typename T, typename A>
struct is_vector<std::vector<T, A>> : std::true_type {};

std::size_t size_of(const Value& v) {
  return std::visit(
      [](const auto& a) -> std::size_t {
        if constexpr (is_vector<std::decay_t<decltype(a)>>::value) return a.size();
        else return 0;
      },
      v);
}

// What a key takes in a per-key array left empty (channel_keys.cc's
// defaults: auto tangents, slope 0, weight 1/3; a track's flat tangents).
Value filled(CurveKind kind, AttrIndex a, std::size_t count) {
  if (kind == CurveKind::kScalar) {
    if (a == curve_attr::kInTangentType || a == curve_attr::kOutTangentType)
      return std::vector<std::int64_t>(count, static_cast<std::int64_t>(TangentType::kAuto));
    if (a == curve_attr::kInWeight || a == curve_attr::kOutWeight) return std::vector<double>(count, kDefaultWeight);
    return std::vector<double>(count, 0.0);
  }
  if (kind == CurveKind::kVec3) return std::vector<Vec3>(count, Vec3(Vec3::Zero()));
  return std::vector<Quat>(count, Quat(0, 0, 0, 0));
}

// Elements [begin, end) of a per-key array (its defaults when it is empty).
Value slice(const Value& array, std::size_t count, std::size_t begin, std::size_t end, CurveKind kind, AttrIndex a) {
  if (size_of(array) != count) return filled(kind, a, end - begin);
  return std::visit(
      [&](const auto& v) -> Value {
        using V = std::decay_t<decltype(v)>;
        if constexpr (is_vector<V>::value) return V(v.begin() + static_cast<std::ptrdiff_t>(begin), v.begin() + static_cast<std::ptrdiff_t>(end));
        else return v;
      },
      array);
}

// `array` with [lo, hi) replaced by `part` (same element type).
Value spliced(Value array, std::size_t lo, std::size_t hi, const Value& part) {
  std::visit(
      [&](auto& v) {
        using V = std::decay_t<decltype(v)>;
        if constexpr (is_vector<V>::value) {
          const V& p = std::get<V>(part);
          v.erase(v.begin() + static_cast<std::ptrdiff_t>(lo), v.begin() + static_cast<std::ptrdiff_t>(hi));
          v.insert(v.begin() + static_cast<std::ptrdiff_t>(lo), p.begin(), p.end());
        }
      },
      array);
  return array;
}

// The copied keys: times shifted, and every per-key array's part.
struct Copied {
  CurveKind kind = CurveKind::kOther;
  std::vector<double> times;
  Value values;
  std::vector<Value> per_key;  // layout order, each one per copied key
  std::vector<bool> given;     // whether the source had that array (or left it to defaults)
};

Copied read(const Graph& g, NodeId source, const KeyCopy& c) {
  Copied out;
  out.kind = curve_kind(g, source);
  const graph::Node& n = *g.node(source);
  const CurveLayout l = internal::layout(out.kind);
  const KeyRange r = internal::active_range(n, l);
  const auto& times = std::get<std::vector<double>>(n.value(l.times));
  const std::size_t count = times.size();
  std::size_t begin = r.begin, end = r.begin;
  while (begin < r.end && begin < count && times[begin] < c.first - c.tolerance) ++begin;
  end = begin;
  while (end < r.end && end < count && times[end] <= c.last + c.tolerance) ++end;
  if (size_of(n.value(l.values)) != count) end = begin;  // malformed: nothing to copy (the node reports it)
  for (std::size_t i = begin; i < end; ++i) out.times.push_back(times[i] + c.offset);
  out.values = slice(n.value(l.values), count, begin, end, out.kind, l.values);
  for (AttrIndex a : l.per_key) {
    out.given.push_back(size_of(n.value(a)) == count && count > 0);
    out.per_key.push_back(slice(n.value(a), count, begin, end, out.kind, a));
  }
  return out;
}

const char* type_of(CurveKind kind) {
  return kind == CurveKind::kScalar ? kAnimCurveType : kind == CurveKind::kVec3 ? kAnimCurveVec3Type : kAnimCurveQuatType;
}

// A new curve holding `keys`, with the source's settings, into `target`.
Status create(Graph& g, NodeId source, const Copied& keys, const Plug& target) {
  const graph::Node& t = *g.node(target.node);
  static constexpr const char* kAxis[3] = {"X", "Y", "Z"};
  std::string name = t.name();
  name.append("_").append(t.type().attr(target.attr).name);
  if (target.component >= 0 && target.component < 3) name.append(kAxis[target.component]);
  Result<NodeId> curve = g.create_node(type_of(keys.kind), name);
  if (!curve) return curve.status();
  const CurveLayout l = internal::layout(keys.kind);
  Status s = g.set_value(Plug{*curve, l.times, -1}, keys.times);
  if (s) s = g.set_value(Plug{*curve, l.values, -1}, keys.values);
  for (std::size_t i = 0; i < l.per_key.size() && s; ++i)
    if (keys.given[i]) s = g.set_value(Plug{*curve, l.per_key[i], -1}, keys.per_key[i]);
  const graph::Node& src = *g.node(source);
  const std::vector<AttrIndex> settings =
      keys.kind == CurveKind::kScalar
          ? std::vector<AttrIndex>{curve_attr::kWeighted, curve_attr::kPreInfinity, curve_attr::kPostInfinity}
          : std::vector<AttrIndex>{track_attr::kInterpolation};
  for (AttrIndex a : settings)
    if (s) s = g.set_value(Plug{*curve, a, -1}, src.value(a));
  const AttrIndex out = keys.kind == CurveKind::kScalar ? AttrIndex{curve_attr::kOutput} : AttrIndex{track_attr::kOutput};
  if (s) s = g.connect(Plug{*curve, out, -1}, target);
  return s;
}

// `keys` written into curve `curve`'s active clip over what it has between
// `from` and `to`.
Status merge(Graph& g, NodeId curve, const Copied& keys, double from, double to, const std::string& channel) {
  const graph::Node& n = *g.node(curve);
  const CurveLayout l = internal::layout(keys.kind);
  (void)g.evaluate(Plug{curve, l.clip, -1});  // the active clip, up to date
  const KeyRange r = internal::active_range(n, l);
  if (r.clip == -2)
    return error(ErrorCode::kInvalidArgument,
                 channel + ": the active clip does not animate this channel (curve '" + n.name() + "')");
  const auto& times = std::get<std::vector<double>>(n.value(l.times));
  const std::size_t count = times.size();
  if (size_of(n.value(l.values)) != count)
    return error(ErrorCode::kInvalidArgument, channel + ": curve '" + n.name() + "' has malformed keys");
  std::size_t lo = r.begin;
  while (lo < r.end && times[lo] < from) ++lo;
  std::size_t hi = lo;
  while (hi < r.end && times[hi] <= to) ++hi;
  std::vector<std::optional<Value>> per_key;  // nullopt: left empty (defaults on both sides)
  for (std::size_t i = 0; i < l.per_key.size(); ++i) {
    const Value& old = n.value(l.per_key[i]);
    const bool has = size_of(old) == count && count > 0;
    if (!has && !keys.given[i]) {
      per_key.emplace_back();
      continue;
    }
    per_key.push_back(spliced(has ? old : filled(keys.kind, l.per_key[i], count), lo, hi, keys.per_key[i]));
  }
  Status s = g.set_value(Plug{curve, l.times, -1}, spliced(n.value(l.times), lo, hi, keys.times));
  if (s) s = g.set_value(Plug{curve, l.values, -1}, spliced(n.value(l.values), lo, hi, keys.values));
  for (std::size_t i = 0; i < l.per_key.size() && s; ++i)
    if (per_key[i]) s = g.set_value(Plug{curve, l.per_key[i], -1}, std::move(*per_key[i]));
  const std::int64_t grown = static_cast<std::int64_t>(keys.times.size()) - static_cast<std::int64_t>(hi - lo);
  if (s && r.clip >= 0 && grown != 0) {
    auto offsets = std::get<std::vector<std::int64_t>>(n.value(l.offsets));
    for (std::size_t c = static_cast<std::size_t>(r.clip) + 1; c < offsets.size(); ++c) offsets[c] += grown;
    s = g.set_value(Plug{curve, l.offsets, -1}, std::move(offsets));
  }
  return s;
}

}  // namespace

Status copy_curve_keys(Graph& g, NodeId source, const KeyCopy& copy, const Plug& target, std::size_t* copied) {
  if (copied) *copied = 0;
  if (curve_kind(g, source) == CurveKind::kOther)
    return error(ErrorCode::kInvalidArgument, "copy keys: '" + (g.node(source) ? g.node(source)->name() : std::string("?")) +
                                                  "' is not a time curve");
  const graph::Node* t = g.node(target.node);
  if (!t || target.attr >= t->type().attr_count())
    return error(ErrorCode::kNotFound, "copy keys: no such target channel");
  const std::string channel = g.plug_name(target);
  (void)g.evaluate(Plug{source, internal::layout(curve_kind(g, source)).clip, -1});
  const Copied keys = read(g, source, copy);
  if (keys.times.empty()) return Status::ok();
  // What drives the target: its curve, or nothing.
  std::optional<NodeId> curve;
  for (const graph::Connection& c : t->inputs()) {
    if (c.dst.attr != target.attr) continue;
    const bool same = c.dst == target;
    const bool whole_or_part = c.dst.component < 0 || target.component < 0;
    if (!same && !whole_or_part) continue;  // another component of the channel
    if (!same || curve_kind(g, c.src.node) != keys.kind)
      return error(ErrorCode::kInvalidArgument, channel + " is driven by " + g.plug_name(c.src) +
                                                    ", not by a curve like the source's; it cannot take its keys");
    curve = c.src.node;
  }
  const double from = std::min(copy.first + copy.offset, keys.times.front()) - copy.tolerance;
  const double to = std::max(copy.last + copy.offset, keys.times.back()) + copy.tolerance;
  graph::Transaction tx(g, "copy keys onto " + channel);
  Status s = curve ? merge(g, *curve, keys, from, to, channel) : create(g, source, keys, target);
  if (!s) {
    tx.rollback();
    return s.with_context("copy keys");
  }
  if (copied) *copied = keys.times.size();
  return Status::ok();
}

}  // namespace rigel::ops::anim
