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


// The arrays of a curve node that hold one entry per key, and its clips.
struct CurveLayout {
  AttrIndex times, values;
  std::vector<AttrIndex> per_key;  // besides times and values (empty or one per key)
  AttrIndex offsets, clip;
};
CurveLayout layout(CurveKind kind) {
  if (kind == CurveKind::kScalar)
    return {curve_attr::kKeyTimes,
            curve_attr::kKeyValues,
            {curve_attr::kInTangentType, curve_attr::kOutTangentType, curve_attr::kInSlope, curve_attr::kOutSlope,
             curve_attr::kInWeight, curve_attr::kOutWeight},
            anim_curve_attr::kClipOffsets,
            anim_curve_attr::kClip};
  return {track_attr::kKeyTimes,
          track_attr::kKeyValues,
          {track_attr::kInTangents, track_attr::kOutTangents},
          track_attr::kClipOffsets,
          track_attr::kClip};
}

// Keys [begin, end) of the active clip (all keys when the curve has no clips).
struct KeyRange {
  std::size_t begin = 0, end = 0;
  int clip = -1;  // -1: no clips
};
KeyRange active_range(const graph::Node& curve, const CurveLayout& l) {
  const auto& times = std::get<std::vector<double>>(curve.value(l.times));
  const auto& offsets = std::get<std::vector<std::int64_t>>(curve.value(l.offsets));
  KeyRange r{0, times.size(), -1};
  if (offsets.size() < 2) return r;
  const std::int64_t c = std::get<std::int64_t>(curve.value(l.clip));
  if (c < 0 || c + 1 >= static_cast<std::int64_t>(offsets.size())) return KeyRange{0, 0, -2};  // rest value
  r.begin = static_cast<std::size_t>(std::clamp<std::int64_t>(offsets[c], 0, static_cast<std::int64_t>(times.size())));
  r.end = static_cast<std::size_t>(std::clamp<std::int64_t>(offsets[c + 1], 0, static_cast<std::int64_t>(times.size())));
  r.clip = static_cast<int>(c);
  return r;
}

// Index of the key at `t` in the range, or -1.
long key_at(const std::vector<double>& times, const KeyRange& r, double t) {
  for (std::size_t i = r.begin; i < r.end && i < times.size(); ++i)
    if (std::abs(times[i] - t) <= kKeyTimeTolerance) return static_cast<long>(i);
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
  if (auto src = source_of(*n, Plug{control, attr, -1})) {
    const CurveKind kind = curve_kind(graph, src->node);
    const bool fits = (kind == CurveKind::kVec3 && attr != xform::kRotateQuaternion) ||
                      (kind == CurveKind::kQuat && attr == xform::kRotateQuaternion);
    if (!fits)
      return error(ErrorCode::kInvalidArgument, channel_name(graph, control, attr) + " is driven by " +
                                                    graph.plug_name(*src) + ", not by a curve; it cannot be keyed");
    return curve_write(graph, src->node, kind, t, value, insert, channel_name(graph, control, attr));
  }
  if (attr == xform::kRotateQuaternion) {
    if (!insert) return graph.set_value(Plug{control, attr, -1}, value);
    return curve_create(graph, base, CurveKind::kQuat, t, value, Plug{control, attr, -1});
  }
  // A double3 channel: each component free or keyed by its own curve.
  const Vec3& v = std::get<Vec3>(value);
  static constexpr const char* kAxis[3] = {"X", "Y", "Z"};
  std::optional<Plug> comp[3];
  bool any = false;
  for (int i = 0; i < 3; ++i) {
    comp[i] = source_of(*n, Plug{control, attr, -1, static_cast<std::int8_t>(i)});
    if (!comp[i]) continue;
    any = true;
    if (curve_kind(graph, comp[i]->node) != CurveKind::kScalar)
      return error(ErrorCode::kInvalidArgument, channel_name(graph, control, attr, i) + " is driven by " +
                                                    graph.plug_name(*comp[i]) + ", not by a curve; it cannot be keyed");
  }
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

}  // namespace rigel::ops::anim
