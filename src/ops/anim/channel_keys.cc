// Keys on transform channels (channel_keys.h), moved here from the
// ephemeral layer's keying so rig updates and tools share them.
#include "rigel/ops/anim/channel_keys.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <type_traits>

#include "rigel/math/types.h"
#include "rigel/ops/anim/nodes.h"
#include "rigel/scene/transform_types.h"
#include "curve_layout.h"

namespace rigel::ops::anim {
namespace {

using graph::AttrIndex;
using graph::Graph;
using graph::NodeId;
using graph::Plug;
using graph::Value;
using math::Quat;
using math::Vec3;
namespace xform = scene::xform;
using internal::active_range;
using internal::CurveLayout;
using internal::KeyRange;
using internal::layout;

// curve_attr tangent type "auto" (fixed linear flat step stepNext spline clamped plateau auto).
constexpr std::int64_t kAutoTangent = 8;

std::string frame_at(const Graph& graph, double t) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "frame %g", t * graph.fps());
  return buffer;
}

std::optional<Plug> source_of(const graph::Node& node, const Plug& dst) {
  for (const graph::Connection& c : node.inputs())
    if (c.dst == dst) return c.src;
  return std::nullopt;
}



// Whether a key at `key` is the key at `t`.
bool same_time(double key, double t) { return std::abs(key - t) <= kKeyTimeTolerance; }

// Index of the key at `t` in the range, or -1.
long key_at(const std::vector<double>& times, const KeyRange& r, double t) {
  for (std::size_t i = r.begin; i < r.end && i < times.size(); ++i)
    if (same_time(times[i], t)) return static_cast<long>(i);
  return -1;
}

// Sets element `i` of a per-key array value to `v`, or inserts `v` at `i`.
template <typename T>
void put(Value& array, std::size_t i, const T& v, bool insert) {
  auto& a = std::get<std::vector<T>>(array);
  if (insert) a.insert(a.begin() + static_cast<std::ptrdiff_t>(i), v);
  else a[i] = v;
}

template <typename T>
struct is_vector : std::false_type {};
template <typename T, typename A>
struct is_vector<std::vector<T, A>> : std::true_type {};

void erase_at(Value& array, std::size_t i) {
  std::visit(
      [&](auto& a) {
        if constexpr (is_vector<std::decay_t<decltype(a)>>::value) {
          if (i < a.size()) a.erase(a.begin() + static_cast<std::ptrdiff_t>(i));
        }
      },
      array);
}

std::size_t array_size(const Value& v) {
  return std::visit(
      [](const auto& a) -> std::size_t {
        if constexpr (is_vector<std::decay_t<decltype(a)>>::value) return a.size();
        else return 0;
      },
      v);
}

// Writes `value` at time `t` on a curve node (update, or insert when
// allowed). `value` is a double (scalar), Vec3 or Quat.
Status curve_write(Graph& graph, NodeId curve, CurveKind kind, double t, const Value& value, bool insert,
                   const std::string& channel) {
  const graph::Node& n = *graph.node(curve);
  const CurveLayout l = layout(kind);
  (void)graph.evaluate(Plug{curve, l.clip, -1});  // the active clip, up to date
  const KeyRange r = active_range(n, l);
  if (r.clip == -2)
    return error(ErrorCode::kInvalidArgument,
                 channel + ": the active clip does not animate this channel (curve '" + n.name() + "')");
  Value times = n.value(l.times);
  Value values = n.value(l.values);
  auto& tv = std::get<std::vector<double>>(times);
  const std::size_t count = tv.size();
  const long at = key_at(tv, r, t);
  if (at < 0 && !insert)
    return error(ErrorCode::kInvalidArgument, channel + " is keyed and " + frame_at(graph, t) +
                                                  " has no key; set a key there or turn auto-key on");
  const bool inserting = at < 0;
  std::size_t i = inserting ? r.begin : static_cast<std::size_t>(at);
  if (inserting)
    while (i < r.end && tv[i] < t) ++i;
  if (inserting) tv.insert(tv.begin() + static_cast<std::ptrdiff_t>(i), t);
  if (kind == CurveKind::kScalar) put(values, i, std::get<double>(value), inserting);
  else if (kind == CurveKind::kVec3) put(values, i, std::get<Vec3>(value), inserting);
  else {
    // Keep quaternion keys sign-continuous with their neighbour.
    Quat q = std::get<Quat>(value);
    const auto& qs = std::get<std::vector<Quat>>(values);
    const std::size_t ref = i > r.begin ? i - 1 : (inserting ? i : i + 1);
    if (ref < qs.size() && ref != i && q.dot(qs[ref]) < 0) q.coeffs() = -q.coeffs();
    put(values, i, q, inserting);
  }
  graph::Transaction tx(graph, "key " + channel);
  Status s;
  if (inserting) {
    s = graph.set_value(Plug{curve, l.times, -1}, std::move(times));
    for (AttrIndex a : l.per_key) {
      if (!s) break;
      Value arr = n.value(a);
      if (array_size(arr) != count) continue;  // empty: defaults for every key
      if (kind == CurveKind::kScalar) {
        if (a == curve_attr::kInTangentType || a == curve_attr::kOutTangentType) put(arr, i, kAutoTangent, true);
        else if (a == curve_attr::kInWeight || a == curve_attr::kOutWeight) put(arr, i, 1.0 / 3.0, true);
        else put(arr, i, 0.0, true);
      } else if (kind == CurveKind::kVec3) {
        put(arr, i, Vec3(Vec3::Zero()), true);
      } else {
        put(arr, i, Quat(0, 0, 0, 0), true);  // cubic tangents: flat
      }
      s = graph.set_value(Plug{curve, a, -1}, std::move(arr));
    }
    if (s && r.clip >= 0) {
      auto offsets = std::get<std::vector<std::int64_t>>(n.value(l.offsets));
      for (std::size_t c = static_cast<std::size_t>(r.clip) + 1; c < offsets.size(); ++c) ++offsets[c];
      s = graph.set_value(Plug{curve, l.offsets, -1}, std::move(offsets));
    }
  }
  if (s) s = graph.set_value(Plug{curve, l.values, -1}, std::move(values));
  if (!s) tx.rollback();
  return s;
}

// Removes the key at `t`; deletes the curve when no key is left (the
// channel keeps `keep`). Ok and `removed` false when there is no key there.
Status delete_key_impl(Graph& graph, NodeId curve, double t, const Plug& channel, const Value& keep, bool& removed) {
  const graph::Node& n = *graph.node(curve);
  const CurveLayout l = layout(curve_kind(graph, curve));
  const KeyRange r = active_range(n, l);
  const auto& times = std::get<std::vector<double>>(n.value(l.times));
  const long at = key_at(times, r, t);
  removed = at >= 0;
  if (!removed) return Status::ok();
  const std::size_t count = times.size();
  if (count == 1) {
    Status s = graph.delete_node(curve);
    if (s) s = graph.set_value(channel, keep);
    return s;
  }
  Status s;
  for (AttrIndex a : l.per_key) {
    Value arr = n.value(a);
    if (array_size(arr) != count) continue;
    erase_at(arr, static_cast<std::size_t>(at));
    if (s) s = graph.set_value(Plug{curve, a, -1}, std::move(arr));
  }
  for (AttrIndex a : {l.times, l.values}) {
    Value arr = n.value(a);
    erase_at(arr, static_cast<std::size_t>(at));
    if (s) s = graph.set_value(Plug{curve, a, -1}, std::move(arr));
  }
  if (s && r.clip >= 0) {
    auto offsets = std::get<std::vector<std::int64_t>>(n.value(l.offsets));
    for (std::size_t c = static_cast<std::size_t>(r.clip) + 1; c < offsets.size(); ++c) --offsets[c];
    s = graph.set_value(Plug{curve, l.offsets, -1}, std::move(offsets));
  }
  return s;
}

// A new curve keyed once, connected into `dst`.
Status curve_create(Graph& graph, const std::string& name, CurveKind kind, double t, const Value& value,
                    const Plug& dst) {
  const char* type = kind == CurveKind::kScalar ? ops::anim::kAnimCurveType
                     : kind == CurveKind::kVec3 ? ops::anim::kAnimCurveVec3Type
                                                : ops::anim::kAnimCurveQuatType;
  Result<NodeId> curve = graph.create_node(type, name);
  if (!curve) return curve.status();
  const CurveLayout l = layout(kind);
  Status s = graph.set_value(Plug{*curve, l.times, -1}, std::vector<double>{t});
  if (s) {
    if (kind == CurveKind::kScalar) s = graph.set_value(Plug{*curve, l.values, -1}, std::vector<double>{std::get<double>(value)});
    else if (kind == CurveKind::kVec3) s = graph.set_value(Plug{*curve, l.values, -1}, std::vector<Vec3>{std::get<Vec3>(value)});
    else s = graph.set_value(Plug{*curve, l.values, -1}, std::vector<Quat>{std::get<Quat>(value)});
  }
  const AttrIndex out = kind == CurveKind::kScalar ? AttrIndex{curve_attr::kOutput} : AttrIndex{track_attr::kOutput};
  if (s) s = graph.connect(Plug{*curve, out, -1}, dst);
  return s;
}

std::string channel_name(const Graph& graph, NodeId control, AttrIndex attr, int component = -1) {
  return graph.plug_name(Plug{control, attr, -1, static_cast<std::int8_t>(component)});
}

// The curve keying each component of double3 channel `attr` (nullopt where
// the component is free); `any` tells whether one is keyed. Fails naming
// the component when something other than a scalar curve drives it.
Status component_curves(const Graph& graph, const graph::Node& n, NodeId control, AttrIndex attr,
                        std::optional<Plug> (&comp)[3], bool& any) {
  any = false;
  for (int i = 0; i < 3; ++i) {
    comp[i] = source_of(n, Plug{control, attr, -1, static_cast<std::int8_t>(i)});
    if (!comp[i]) continue;
    any = true;
    if (curve_kind(graph, comp[i]->node) != CurveKind::kScalar)
      return error(ErrorCode::kInvalidArgument, channel_name(graph, control, attr, i) + " is driven by " +
                                                    graph.plug_name(*comp[i]) + ", not by a curve; it cannot be keyed");
  }
  return Status::ok();
}

// ---- many keys at once (write_channel_keys) ----------------------------------
// The same edits as curve_write / curve_create once per key in time order,
// computed in one pass over each curve's arrays, which are then set once.

// `array` with `fill` at each position of `at` (increasing, positions in the
// result).
template <typename E>
std::vector<E> with_inserted(const std::vector<E>& array, const std::vector<std::size_t>& at, const E& fill) {
  std::vector<E> out;
  out.reserve(array.size() + at.size());
  std::size_t from = 0, q = 0;
  for (std::size_t p = 0; p < array.size() + at.size(); ++p) {
    if (q < at.size() && at[q] == p) {
      out.push_back(fill);
      ++q;
    } else {
      out.push_back(array[from++]);
    }
  }
  return out;
}

// A quaternion key turned into the hemisphere of `ref` (curve_write's rule);
// other values as they are.
template <typename T>
T continuous(T v, const T* ref) {
  if constexpr (std::is_same_v<T, Quat>) {
    if (ref && v.dot(*ref) < 0) v.coeffs() = -v.coeffs();
  }
  (void)ref;
  return v;
}

// A curve's key times and values after writing keys (ts, vs) into its active
// clip, and where keys were inserted (positions in the result, increasing).
template <typename T>
struct Merged {
  std::vector<double> times;
  std::vector<T> values;
  std::vector<std::size_t> inserted;
};

// Writing the keys one at a time, in time order (`ts` increasing, each more
// than the tolerance after the last): a key matches the first key of the
// clip within the tolerance (only the next unmatched old key or the one the
// last time matched can be it), else it is inserted before the first later
// key; quaternions are turned toward the key before (the key after when
// updating the clip's first key), as the array stood at that moment.
// `old_t` is sorted within `r`.
template <typename T>
Result<Merged<T>> merge_keys(const Graph& graph, const std::vector<double>& old_t, const std::vector<T>& old_v,
                             const KeyRange& r, std::span<const double> ts, std::span<const T> vs, bool insert,
                             const std::string& channel) {
  Merged<T> m;
  m.times.reserve(old_t.size() + ts.size());
  m.values.reserve(old_t.size() + ts.size());
  m.times.assign(old_t.begin(), old_t.begin() + static_cast<std::ptrdiff_t>(r.begin));
  m.values.assign(old_v.begin(), old_v.begin() + static_cast<std::ptrdiff_t>(r.begin));
  std::size_t j = r.begin;  // the next old key not in `m`
  bool matched_last = false;  // m's last key is an old key a time matched
  // Element p of the array as sequential writes would have it now.
  auto current = [&](std::size_t p) -> const T* {
    if (p < m.values.size()) return &m.values[p];
    p = j + (p - m.values.size());
    return p < old_v.size() ? &old_v[p] : nullptr;
  };
  for (std::size_t k = 0; k < ts.size(); ++k) {
    const double t = ts[k];
    if (matched_last && same_time(m.times.back(), t)) {
      const std::size_t i = m.values.size() - 1;
      m.values[i] = continuous(vs[k], i > r.begin ? current(i - 1) : current(i + 1));
      continue;
    }
    matched_last = false;
    while (j < r.end && old_t[j] < t && !same_time(old_t[j], t)) {
      m.times.push_back(old_t[j]);
      m.values.push_back(old_v[j]);
      ++j;
    }
    const std::size_t i = m.values.size();
    if (j < r.end && same_time(old_t[j], t)) {
      const T v = continuous(vs[k], i > r.begin ? current(i - 1) : current(i + 1));
      m.times.push_back(old_t[j]);
      m.values.push_back(v);
      ++j;
      matched_last = true;
      continue;
    }
    if (!insert)
      return error(ErrorCode::kInvalidArgument, channel + " is keyed and " + frame_at(graph, t) +
                                                    " has no key; set a key there or turn auto-key on");
    const T v = continuous(vs[k], i > r.begin ? current(i - 1) : nullptr);
    m.inserted.push_back(i);
    m.times.push_back(t);
    m.values.push_back(v);
  }
  m.times.insert(m.times.end(), old_t.begin() + static_cast<std::ptrdiff_t>(j), old_t.end());
  m.values.insert(m.values.end(), old_v.begin() + static_cast<std::ptrdiff_t>(j), old_v.end());
  return m;
}

// curve_write for many keys: each array of the curve set at most once.
template <typename T>
Status curve_write_many(Graph& graph, NodeId curve, CurveKind kind, std::span<const double> ts, std::span<const T> vs,
                        bool insert, const std::string& channel) {
  const graph::Node& n = *graph.node(curve);
  const CurveLayout l = layout(kind);
  (void)graph.evaluate(Plug{curve, l.clip, -1});  // the active clip, up to date
  const KeyRange r = active_range(n, l);
  if (r.clip == -2)
    return error(ErrorCode::kInvalidArgument,
                 channel + ": the active clip does not animate this channel (curve '" + n.name() + "')");
  const auto& old_t = std::get<std::vector<double>>(n.value(l.times));
  const auto& old_v = std::get<std::vector<T>>(n.value(l.values));
  const std::size_t count = old_t.size();
  if (old_v.size() != count)
    return error(ErrorCode::kInvalidArgument, channel + ": curve '" + n.name() + "' has " +
                                                  std::to_string(old_v.size()) + " key values for " +
                                                  std::to_string(count) + " key times");
  Result<Merged<T>> m = merge_keys(graph, old_t, old_v, r, ts, vs, insert, channel);
  if (!m) return m.status();
  graph::Transaction tx(graph, "key " + channel);
  Status s;
  if (!m->inserted.empty()) {
    s = graph.set_value(Plug{curve, l.times, -1}, std::move(m->times));
    for (AttrIndex a : l.per_key) {
      if (!s) break;
      const Value& arr = n.value(a);
      if (array_size(arr) != count) continue;  // empty: defaults for every key
      Value grown;
      if constexpr (std::is_same_v<T, double>) {
        if (a == curve_attr::kInTangentType || a == curve_attr::kOutTangentType)
          grown = with_inserted(std::get<std::vector<std::int64_t>>(arr), m->inserted, kAutoTangent);
        else
          grown = with_inserted(std::get<std::vector<double>>(arr), m->inserted,
                                a == curve_attr::kInWeight || a == curve_attr::kOutWeight ? 1.0 / 3.0 : 0.0);
      } else if constexpr (std::is_same_v<T, Vec3>) {
        grown = with_inserted(std::get<std::vector<Vec3>>(arr), m->inserted, Vec3(Vec3::Zero()));
      } else {
        grown = with_inserted(std::get<std::vector<Quat>>(arr), m->inserted, Quat(0, 0, 0, 0));  // cubic tangents: flat
      }
      s = graph.set_value(Plug{curve, a, -1}, std::move(grown));
    }
    if (s && r.clip >= 0) {
      auto offsets = std::get<std::vector<std::int64_t>>(n.value(l.offsets));
      for (std::size_t c = static_cast<std::size_t>(r.clip) + 1; c < offsets.size(); ++c)
        offsets[c] += static_cast<std::int64_t>(m->inserted.size());
      s = graph.set_value(Plug{curve, l.offsets, -1}, std::move(offsets));
    }
  }
  if (s) s = graph.set_value(Plug{curve, l.values, -1}, std::move(m->values));
  if (!s) tx.rollback();
  return s;
}

// curve_create for many keys.
template <typename T>
Status curve_create_many(Graph& graph, const std::string& name, CurveKind kind, std::span<const double> ts,
                         std::span<const T> vs, const Plug& dst) {
  const char* type = kind == CurveKind::kScalar ? ops::anim::kAnimCurveType
                     : kind == CurveKind::kVec3 ? ops::anim::kAnimCurveVec3Type
                                                : ops::anim::kAnimCurveQuatType;
  Result<NodeId> curve = graph.create_node(type, name);
  if (!curve) return curve.status();
  const CurveLayout l = layout(kind);
  std::vector<T> values;
  values.reserve(vs.size());
  for (const T& v : vs) values.push_back(continuous(v, values.empty() ? nullptr : &values.back()));
  Status s = graph.set_value(Plug{*curve, l.times, -1}, std::vector<double>(ts.begin(), ts.end()));
  if (s) s = graph.set_value(Plug{*curve, l.values, -1}, std::move(values));
  const AttrIndex out = kind == CurveKind::kScalar ? AttrIndex{curve_attr::kOutput} : AttrIndex{track_attr::kOutput};
  if (s) s = graph.connect(Plug{*curve, out, -1}, dst);
  return s;
}

// write_channel_keys: T is double (scalar channels), Vec3 (double3
// channels) or Quat (rotateQuaternion).
template <typename T>
Status write_keys(Graph& graph, NodeId control, AttrIndex attr, std::span<const double> times, std::span<const T> values,
                  bool insert) {
  constexpr bool kQuat = std::is_same_v<T, Quat>;
  constexpr bool kScalar = std::is_same_v<T, double>;
  const graph::Node* n = graph.node(control);
  if (!n) return error(ErrorCode::kNotFound, "key: no such node (stale handle)");
  if (attr >= n->type().attr_count()) return error(ErrorCode::kNotFound, "key: no such attribute on '" + n->name() + "'");
  const std::string channel = channel_name(graph, control, attr);
  const graph::ValueType expected =
      kScalar ? graph::ValueType::kDouble : kQuat ? graph::ValueType::kQuat : graph::ValueType::kDouble3;
  // (A transform's rotateQuaternion, the one quaternion channel: its type
  // decides, as attribute indices of other node types may equal its index.)
  const bool quaternion_channel = n->type().attr(attr).type == graph::AttrType{graph::ValueType::kQuat, false};
  if (kQuat != quaternion_channel || n->type().attr(attr).type != graph::AttrType{expected, false})
    return error(ErrorCode::kInvalidArgument,
                 "key " + channel + ": " +
                     (kQuat ? "quaternion keys go on rotateQuaternion" : kScalar ? "not a scalar channel" : "not a double3 channel"));
  if (times.size() != values.size())
    return error(ErrorCode::kInvalidArgument, "key " + channel + ": " + std::to_string(times.size()) + " times for " +
                                                  std::to_string(values.size()) + " values");
  for (std::size_t k = 0; k < times.size(); ++k) {
    if (!std::isfinite(times[k]))
      return error(ErrorCode::kInvalidArgument, "key " + channel + ": time " + std::to_string(k) + " is not finite");
    if (k > 0 && !(times[k] > times[k - 1] && !same_time(times[k - 1], times[k])))
      return error(ErrorCode::kInvalidArgument, "key " + channel + ": " + frame_at(graph, times[k]) + " (time " +
                                                    std::to_string(k) + ") is not after " + frame_at(graph, times[k - 1]) +
                                                    " by more than the key tolerance");
  }
  if (times.empty()) return Status::ok();
  const std::string base = n->name() + "_" + n->type().attr(attr).name;
  if (auto src = source_of(*n, Plug{control, attr, -1})) {
    const CurveKind kind = curve_kind(graph, src->node);
    if (kind != (kScalar ? CurveKind::kScalar : kQuat ? CurveKind::kQuat : CurveKind::kVec3))
      return error(ErrorCode::kInvalidArgument,
                   channel + " is driven by " + graph.plug_name(*src) + ", not by a curve; it cannot be keyed");
    return curve_write_many<T>(graph, src->node, kind, times, values, insert, channel);
  }
  if constexpr (kQuat || kScalar) {
    if (!insert) return graph.set_value(Plug{control, attr, -1}, values.back());
    graph::Transaction tx(graph, "key " + channel);
    Status s = curve_create_many<T>(graph, base, kScalar ? CurveKind::kScalar : CurveKind::kQuat, times, values,
                                    Plug{control, attr, -1});
    if (!s) tx.rollback();
    return s;
  } else {
    // Each component free or keyed by its own curve.
    static constexpr const char* kAxis[3] = {"X", "Y", "Z"};
    std::optional<Plug> comp[3];
    bool any = false;
    if (Status s = component_curves(graph, *n, control, attr, comp, any); !s) return s;
    if (!any && !insert) return graph.set_value(Plug{control, attr, -1}, values.back());
    graph::Transaction tx(graph, "key " + channel);
    Status s;
    std::vector<double> component(values.size());
    for (int i = 0; i < 3 && s; ++i) {
      const Plug dst{control, attr, -1, static_cast<std::int8_t>(i)};
      for (std::size_t k = 0; k < values.size(); ++k) component[k] = values[k][i];
      if (comp[i]) s = curve_write_many<double>(graph, comp[i]->node, CurveKind::kScalar, times, component, insert, graph.plug_name(dst));
      else if (insert) s = curve_create_many<double>(graph, base + kAxis[i], CurveKind::kScalar, times, component, dst);
      else s = graph.set_value(dst, component.back());
    }
    if (!s) tx.rollback();
    return s;
  }
}

}  // namespace

CurveKind curve_kind(const Graph& graph, NodeId id) {
  const graph::Node* n = graph.node(id);
  if (!n) return CurveKind::kOther;
  const std::string& t = n->type().name();
  if (t == kAnimCurveType) return CurveKind::kScalar;
  if (t == kAnimCurveVec3Type) return CurveKind::kVec3;
  if (t == kAnimCurveQuatType) return CurveKind::kQuat;
  return CurveKind::kOther;
}

std::vector<double> curve_key_times(const Graph& graph, NodeId curve) {
  const CurveKind kind = curve_kind(graph, curve);
  if (kind == CurveKind::kOther) return {};
  const graph::Node& n = *graph.node(curve);
  const CurveLayout l = layout(kind);
  const KeyRange r = active_range(n, l);
  const auto& times = std::get<std::vector<double>>(n.value(l.times));
  std::vector<double> out;
  for (std::size_t i = r.begin; i < r.end && i < times.size(); ++i) out.push_back(times[i]);
  return out;
}

std::vector<Value> curve_key_values(const Graph& graph, NodeId curve) {
  const CurveKind kind = curve_kind(graph, curve);
  if (kind == CurveKind::kOther) return {};
  const graph::Node& n = *graph.node(curve);
  const CurveLayout l = layout(kind);
  const KeyRange r = active_range(n, l);
  std::vector<Value> out;
  const Value& values = n.value(l.values);
  for (std::size_t i = r.begin; i < r.end && i < array_size(values); ++i) {
    if (kind == CurveKind::kScalar) out.emplace_back(std::get<std::vector<double>>(values)[i]);
    else if (kind == CurveKind::kVec3) out.emplace_back(std::get<std::vector<Vec3>>(values)[i]);
    else out.emplace_back(std::get<std::vector<Quat>>(values)[i]);
  }
  return out;
}

std::pair<std::vector<TangentType>, std::vector<TangentType>> curve_key_tangents(const Graph& graph, NodeId curve) {
  std::pair<std::vector<TangentType>, std::vector<TangentType>> out;
  if (curve_kind(graph, curve) != CurveKind::kScalar) return out;
  const graph::Node& n = *graph.node(curve);
  const CurveLayout l = layout(CurveKind::kScalar);
  const KeyRange r = active_range(n, l);
  const std::size_t count = std::get<std::vector<double>>(n.value(l.times)).size();
  const auto& in = std::get<std::vector<std::int64_t>>(n.value(curve_attr::kInTangentType));
  const auto& tout = std::get<std::vector<std::int64_t>>(n.value(curve_attr::kOutTangentType));
  auto type_at = [&](const std::vector<std::int64_t>& types, std::size_t i) {
    const std::int64_t v = types.size() == count ? types[i] : kAutoTangent;
    return static_cast<TangentType>(std::clamp<std::int64_t>(v, 0, kTangentTypeCount - 1));
  };
  for (std::size_t i = r.begin; i < r.end && i < count; ++i) {
    out.first.push_back(type_at(in, i));
    out.second.push_back(type_at(tout, i));
  }
  return out;
}

std::optional<TangentType> tangent_type_from_name(std::string_view name) {
  const auto names = tangent_type_names();
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<TangentType>(i);
  return std::nullopt;
}

bool curve_has_key_at(const Graph& graph, NodeId curve, double t) {
  const CurveKind kind = curve_kind(graph, curve);
  if (kind == CurveKind::kOther) return false;
  const graph::Node& n = *graph.node(curve);
  const CurveLayout l = layout(kind);
  return key_at(std::get<std::vector<double>>(n.value(l.times)), active_range(n, l), t) >= 0;
}

Status delete_curve_key(Graph& graph, NodeId curve, double t, const Plug& channel, const Value& keep, bool& removed) {
  removed = false;
  if (curve_kind(graph, curve) == CurveKind::kOther)
    return error(ErrorCode::kInvalidArgument, "delete key: '" + (graph.node(curve) ? graph.node(curve)->name() : std::string("?")) +
                                                  "' is not a time curve");
  return delete_key_impl(graph, curve, t, channel, keep, removed);
}

Status write_channel_key(Graph& graph, NodeId control, AttrIndex attr, const Value& value, double t, bool insert) {
  const graph::Node* n = graph.node(control);
  if (!n) return error(ErrorCode::kNotFound, "key: no such node (stale handle)");
  const std::string base = n->name() + "_" + n->type().attr(attr).name;
  // A scalar channel (a switch such as fkIk, a foot roll, a finger's curl):
  // one animCurve.
  const graph::AttrType& type = n->type().attr(attr).type;
  const bool scalar = type.value == graph::ValueType::kDouble && !type.array;
  const bool quaternion = type.value == graph::ValueType::kQuat && !type.array;  // rotateQuaternion
  if (auto src = source_of(*n, Plug{control, attr, -1})) {
    const CurveKind kind = curve_kind(graph, src->node);
    const bool fits = scalar ? kind == CurveKind::kScalar
                             : (kind == CurveKind::kVec3 && !quaternion) || (kind == CurveKind::kQuat && quaternion);
    if (!fits)
      return error(ErrorCode::kInvalidArgument, channel_name(graph, control, attr) + " is driven by " +
                                                    graph.plug_name(*src) + ", not by a curve; it cannot be keyed");
    return curve_write(graph, src->node, kind, t, value, insert, channel_name(graph, control, attr));
  }
  if (scalar) {
    if (!insert) return graph.set_value(Plug{control, attr, -1}, value);
    graph::Transaction tx(graph, "key " + channel_name(graph, control, attr));
    Status s = curve_create(graph, base, CurveKind::kScalar, t, value, Plug{control, attr, -1});
    if (!s) tx.rollback();
    return s;
  }
  if (quaternion) {
    if (!insert) return graph.set_value(Plug{control, attr, -1}, value);
    return curve_create(graph, base, CurveKind::kQuat, t, value, Plug{control, attr, -1});
  }
  // A double3 channel: each component free or keyed by its own curve.
  const Vec3& v = std::get<Vec3>(value);
  static constexpr const char* kAxis[3] = {"X", "Y", "Z"};
  std::optional<Plug> comp[3];
  bool any = false;
  if (Status s = component_curves(graph, *n, control, attr, comp, any); !s) return s;
  if (!any && !insert) return graph.set_value(Plug{control, attr, -1}, value);
  graph::Transaction tx(graph, "key " + channel_name(graph, control, attr));
  Status s;
  for (int i = 0; i < 3 && s; ++i) {
    const Plug dst{control, attr, -1, static_cast<std::int8_t>(i)};
    if (comp[i]) s = curve_write(graph, comp[i]->node, CurveKind::kScalar, t, v[i], insert, graph.plug_name(dst));
    else if (insert) s = curve_create(graph, base + kAxis[i], CurveKind::kScalar, t, v[i], dst);
    else s = graph.set_value(dst, v[i]);
  }
  if (!s) tx.rollback();
  return s;
}

Status write_channel_keys(Graph& graph, NodeId node, AttrIndex attr, std::span<const double> times,
                          std::span<const Vec3> values, bool insert) {
  return write_keys<Vec3>(graph, node, attr, times, values, insert);
}

Status write_channel_keys(Graph& graph, NodeId node, AttrIndex attr, std::span<const double> times,
                          std::span<const Quat> values, bool insert) {
  return write_keys<Quat>(graph, node, attr, times, values, insert);
}

Status write_channel_keys(Graph& graph, NodeId node, AttrIndex attr, std::span<const double> times,
                          std::span<const double> values, bool insert) {
  return write_keys<double>(graph, node, attr, times, values, insert);
}

Status set_key_tangents(Graph& graph, NodeId node, AttrIndex attr, double t, std::optional<TangentType> in,
                        std::optional<TangentType> out) {
  const graph::Node* n = graph.node(node);
  if (!n) return error(ErrorCode::kNotFound, "tangents: no such node (stale handle)");
  if (attr >= n->type().attr_count())
    return error(ErrorCode::kNotFound, "tangents: no such attribute on '" + n->name() + "'");
  const std::string channel = channel_name(graph, node, attr);
  std::vector<NodeId> curves;
  for (const graph::Connection& c : n->inputs()) {
    if (c.dst.attr != attr) continue;
    const CurveKind kind = curve_kind(graph, c.src.node);
    if (kind == CurveKind::kVec3 || kind == CurveKind::kQuat)
      return error(ErrorCode::kInvalidArgument,
                   channel + " is keyed by a track ('" + graph.node(c.src.node)->name() +
                       "', one interpolation for all its keys); tangent types apply to curves");
    if (kind == CurveKind::kScalar) curves.push_back(c.src.node);
  }
  graph::Transaction tx(graph, "tangents " + channel + " (" + frame_at(graph, t) + ")");
  bool any = false;
  for (NodeId curve : curves) {
    const graph::Node& cn = *graph.node(curve);
    (void)graph.evaluate(Plug{curve, anim_curve_attr::kClip, -1});  // the active clip, up to date
    const CurveLayout l = layout(CurveKind::kScalar);
    const auto& times = std::get<std::vector<double>>(cn.value(l.times));
    const long at = key_at(times, active_range(cn, l), t);
    if (at < 0) continue;
    any = true;
    for (auto [a, type] : {std::pair{curve_attr::kInTangentType, in}, std::pair{curve_attr::kOutTangentType, out}}) {
      if (!type) continue;
      auto types = std::get<std::vector<std::int64_t>>(cn.value(a));
      if (types.size() != times.size()) types.assign(times.size(), kAutoTangent);  // empty: auto for every key
      types[static_cast<std::size_t>(at)] = static_cast<std::int64_t>(*type);
      if (Status s = graph.set_value(Plug{curve, a, -1}, std::move(types)); !s) {
        tx.rollback();
        return s.with_context(channel);
      }
    }
  }
  if (!any) {
    tx.rollback();
    return error(ErrorCode::kNotFound, channel + " has no key at " + frame_at(graph, t));
  }
  return Status::ok();
}

}  // namespace rigel::ops::anim
