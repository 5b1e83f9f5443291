#include "rigel/ephemeral/keying.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <type_traits>

#include "rigel/graph/graph.h"
#include "rigel/ops/anim/nodes.h"
#include "rigel/scene/transform_types.h"

namespace rigel::ephemeral {
namespace {

using graph::AttrIndex;
using graph::Plug;
using graph::Value;
using math::Quat;
using math::Vec3;
namespace xform = scene::xform;
namespace curve_attr = ops::anim::curve_attr;
namespace anim_curve_attr = ops::anim::anim_curve_attr;
namespace track_attr = ops::anim::track_attr;

// Keys closer than this (seconds) are the same key: float32 glTF times of
// frame f differ from f / fps by ~1e-9.
constexpr double kTimeTolerance = 1e-6;
// curve_attr tangent type "auto" (fixed linear flat step stepNext spline clamped plateau auto).
constexpr std::int64_t kAutoTangent = 8;

bool is_rig(const Graph& graph, NodeId id) {
  const graph::Node* n = graph.node(id);
  return n && n->type().name() == kRigType;
}

const std::string& rig_string(const Graph& graph, NodeId rig, AttrIndex attr) {
  return std::get<std::string>(graph.node(rig)->value(attr));
}

std::string frame_text(const Graph& graph) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "frame %g", graph.time() * graph.fps());
  return buffer;
}

// The rotation channel a control uses.
AttrIndex rotation_attr(const graph::Node& control) {
  return std::get<std::int64_t>(control.value(xform::kRotateMode)) == 1 ? xform::kRotateQuaternion : xform::kRotate;
}

std::optional<Plug> source_of(const graph::Node& node, const Plug& dst) {
  for (const graph::Connection& c : node.inputs())
    if (c.dst == dst) return c.src;
  return std::nullopt;
}

enum class CurveKind { kNone, kScalar, kVec3, kQuat, kOther };
CurveKind curve_kind(const Graph& graph, NodeId id) {
  const std::string& t = graph.node(id)->type().name();
  if (t == ops::anim::kAnimCurveType) return CurveKind::kScalar;
  if (t == ops::anim::kAnimCurveVec3Type) return CurveKind::kVec3;
  if (t == ops::anim::kAnimCurveQuatType) return CurveKind::kQuat;
  return CurveKind::kOther;
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
    if (std::abs(times[i] - t) <= kTimeTolerance) return static_cast<long>(i);
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
    return error(ErrorCode::kInvalidArgument, channel + " is keyed and " + frame_text(graph) +
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
Status curve_delete_key(Graph& graph, NodeId curve, CurveKind kind, double t, const Plug& channel, const Value& keep,
                        bool& removed) {
  const graph::Node& n = *graph.node(curve);
  const CurveLayout l = layout(kind);
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

// Controls of a rig that no other control of it parents.
std::vector<NodeId> root_controls(const Graph& graph, NodeId rig) {
  std::vector<NodeId> controls = rig_controls(graph, rig), out;
  for (NodeId c : controls) {
    NodeId p = graph.parent(c);
    if (std::find(controls.begin(), controls.end(), p) == controls.end()) out.push_back(c);
  }
  return out;
}

}  // namespace

const char* key_scope_name(KeyScope scope) { return scope == KeyScope::kControls ? "controls" : "character"; }

std::optional<KeyScope> key_scope_from_name(std::string_view name) {
  if (name == "character") return KeyScope::kCharacter;
  if (name == "controls") return KeyScope::kControls;
  return std::nullopt;
}

KeyScope key_scope(const Graph& graph, NodeId rig) {
  if (!is_rig(graph, rig)) return KeyScope::kCharacter;
  return static_cast<KeyScope>(std::get<std::int64_t>(graph.node(rig)->value(rig_attr::kKeyScope)));
}

Status set_key_scope(Graph& graph, NodeId rig, KeyScope scope) {
  if (!is_rig(graph, rig)) return error(ErrorCode::kInvalidArgument, "key scope: not an ephemeralRig node");
  return graph.set_value(Plug{rig, rig_attr::kKeyScope, -1}, static_cast<std::int64_t>(scope));
}

// ---- merging -------------------------------------------------------------------

std::vector<NodeId> merged_rigs(const Graph& graph, NodeId rig) {
  if (!is_rig(graph, rig)) return {};
  const std::string& group = rig_string(graph, rig, rig_attr::kMergeGroup);
  if (group.empty()) return {rig};
  std::vector<NodeId> out;
  for (NodeId r : rigs_find(graph))
    if (rig_string(graph, r, rig_attr::kMergeGroup) == group) out.push_back(r);
  return out;
}

Status merge_characters(Graph& graph, const std::vector<NodeId>& rigs) {
  if (rigs.size() < 2) return error(ErrorCode::kInvalidArgument, "merge: name two characters or more");
  for (NodeId r : rigs)
    if (!is_rig(graph, r)) return error(ErrorCode::kInvalidArgument, "merge: not an ephemeralRig node");
  // Join every group involved under one name.
  std::string group;
  for (NodeId r : rigs)
    if (!rig_string(graph, r, rig_attr::kMergeGroup).empty()) group = rig_string(graph, r, rig_attr::kMergeGroup);
  if (group.empty()) group = graph.node(rigs.front())->uuid().str();
  std::vector<NodeId> members;
  for (NodeId r : rigs)
    for (NodeId m : merged_rigs(graph, r))
      if (std::find(members.begin(), members.end(), m) == members.end()) members.push_back(m);
  graph::Transaction tx(graph, "merge characters");
  for (NodeId m : members) {
    if (Status s = graph.set_value(Plug{m, rig_attr::kMergeGroup, -1}, group); !s) {
      tx.rollback();
      return s;
    }
  }
  return Status::ok();
}

Status unmerge_character(Graph& graph, NodeId rig) {
  if (!is_rig(graph, rig)) return error(ErrorCode::kInvalidArgument, "unmerge: not an ephemeralRig node");
  std::vector<NodeId> group = merged_rigs(graph, rig);
  std::vector<std::string> own;
  for (NodeId c : rig_controls(graph, rig)) own.push_back(graph.node(c)->uuid().str());
  graph::Transaction tx(graph, "unmerge character");
  Status s = graph.set_value(Plug{rig, rig_attr::kMergeGroup, -1}, std::string());
  if (s) s = graph.set_value(Plug{rig, rig_attr::kCarrier, -1}, std::string());
  for (NodeId m : group) {
    if (!s || m == rig) continue;
    const std::string& carrier = rig_string(graph, m, rig_attr::kCarrier);
    if (std::find(own.begin(), own.end(), carrier) != own.end())
      s = graph.set_value(Plug{m, rig_attr::kCarrier, -1}, std::string());
  }
  // A group of one is no group.
  std::vector<NodeId> rest;
  for (NodeId m : group)
    if (m != rig) rest.push_back(m);
  if (s && rest.size() == 1) {
    s = graph.set_value(Plug{rest[0], rig_attr::kMergeGroup, -1}, std::string());
    if (s) s = graph.set_value(Plug{rest[0], rig_attr::kCarrier, -1}, std::string());
  }
  if (!s) tx.rollback();
  return s;
}

Status set_carrier(Graph& graph, NodeId rig, NodeId carrier) {
  if (!is_rig(graph, rig)) return error(ErrorCode::kInvalidArgument, "carrier: not an ephemeralRig node");
  if (!carrier.is_valid()) return graph.set_value(Plug{rig, rig_attr::kCarrier, -1}, std::string());
  const graph::Node* c = graph.node(carrier);
  if (!c) return error(ErrorCode::kNotFound, "carrier: no such control (stale handle)");
  const NodeId owner = rig_of(graph, carrier);
  if (!owner.is_valid()) return error(ErrorCode::kInvalidArgument, "carrier: '" + c->name() + "' is not a control of an ephemeral rig");
  if (owner == rig) return error(ErrorCode::kInvalidArgument, "carrier: '" + c->name() + "' belongs to the carried character itself");
  std::vector<NodeId> group = merged_rigs(graph, rig);
  if (std::find(group.begin(), group.end(), owner) == group.end())
    return error(ErrorCode::kInvalidArgument, "carrier: '" + c->name() + "' belongs to a character not merged with '" +
                                                  graph.node(rig)->name() + "'; merge them first");
  // No loops: the carrier's character must not be carried (directly or not) by this one.
  for (NodeId r = owner; r.is_valid();) {
    const NodeId next = rig_of(graph, carrier_of(graph, r));
    if (next == rig) return error(ErrorCode::kCycle, "carrier: '" + graph.node(owner)->name() + "' is carried by '" +
                                                       graph.node(rig)->name() + "'; a character cannot carry its carrier");
    if (next == r) break;
    r = next;
  }
  return graph.set_value(Plug{rig, rig_attr::kCarrier, -1}, c->uuid().str());
}

NodeId carrier_of(const Graph& graph, NodeId rig) {
  if (!is_rig(graph, rig)) return {};
  const std::string& text = rig_string(graph, rig, rig_attr::kCarrier);
  if (text.empty()) return {};
  auto uuid = graph::Uuid::parse(text);
  if (!uuid) return {};
  const NodeId c = graph.find(*uuid);
  const NodeId owner = rig_of(graph, c);
  if (!owner.is_valid() || owner == rig) return {};
  std::vector<NodeId> group = merged_rigs(graph, rig);
  if (std::find(group.begin(), group.end(), owner) == group.end()) return {};
  return c;
}

std::vector<Relation> carrier_relations(const Graph& graph) {
  std::vector<Relation> out;
  for (NodeId rig : rigs_find(graph)) {
    const NodeId carrier = carrier_of(graph, rig);
    if (!carrier.is_valid()) continue;
    for (NodeId root : root_controls(graph, rig)) {
      out.push_back(Relation{RelationKind::kForward, carrier, root});
      out.push_back(Relation{RelationKind::kInverse, root, carrier});
    }
  }
  return out;
}

// ---- keys ----------------------------------------------------------------------

std::vector<NodeId> keying_set(const Graph& graph, const std::vector<NodeId>& controls) {
  std::vector<NodeId> out;
  auto add = [&](NodeId c) {
    if (std::find(out.begin(), out.end(), c) == out.end()) out.push_back(c);
  };
  for (NodeId id : controls) {
    const NodeId c = control_of(graph, id);
    if (!c.is_valid()) continue;
    const NodeId rig = rig_of(graph, c);
    if (key_scope(graph, rig) == KeyScope::kControls) {
      add(c);
      continue;
    }
    for (NodeId r : merged_rigs(graph, rig))
      for (NodeId m : rig_controls(graph, r)) add(m);
  }
  return out;
}

Status write_channel(Graph& graph, NodeId control, AttrIndex attr, const Value& value, bool insert) {
  const graph::Node* n = graph.node(control);
  if (!n) return error(ErrorCode::kNotFound, "key: no such control (stale handle)");
  const double t = graph.time();
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

Status set_key(Graph& graph, const std::vector<NodeId>& controls) {
  std::vector<NodeId> set = keying_set(graph, controls);
  if (set.empty()) return error(ErrorCode::kInvalidArgument, "set key: no control of an ephemeral rig given");
  graph::Transaction tx(graph, "set key (" + frame_text(graph) + ")");
  for (NodeId c : set) {
    const graph::Node& n = *graph.node(c);
    for (AttrIndex attr : {AttrIndex{xform::kTranslate}, rotation_attr(n)}) {
      Result<Value> v = graph.evaluate(Plug{c, attr, -1});
      Status s = v ? write_channel(graph, c, attr, *v, true) : v.status();
      if (!s) {
        tx.rollback();
        return s.with_context("set key");
      }
    }
  }
  return Status::ok();
}

Status delete_key(Graph& graph, const std::vector<NodeId>& controls) {
  std::vector<NodeId> set = keying_set(graph, controls);
  if (set.empty()) return error(ErrorCode::kInvalidArgument, "delete key: no control of an ephemeral rig given");
  const double t = graph.time();
  bool any = false;
  graph::Transaction tx(graph, "delete key (" + frame_text(graph) + ")");
  for (NodeId c : set) {
    for (AttrIndex attr : {AttrIndex{xform::kTranslate}, rotation_attr(*graph.node(c))}) {
      Result<Value> current = graph.evaluate(Plug{c, attr, -1});
      if (!current) {
        tx.rollback();
        return current.status();
      }
      // Gather the curves first: deleting one changes the node's inputs.
      std::vector<std::pair<Plug, Plug>> curves;  // (curve output, channel plug)
      for (const graph::Connection& conn : graph.node(c)->inputs())
        if (conn.dst.attr == attr && curve_kind(graph, conn.src.node) != CurveKind::kOther) curves.emplace_back(conn.src, conn.dst);
      for (const auto& [src, dst] : curves) {
        bool removed = false;
        const Value keep = dst.component >= 0 ? Value(std::get<Vec3>(*current)[dst.component]) : *current;
        Status s = curve_delete_key(graph, src.node, curve_kind(graph, src.node), t, dst, keep, removed);
        if (!s) {
          tx.rollback();
          return s.with_context("delete key");
        }
        any = any || removed;
      }
    }
  }
  if (!any) {
    tx.rollback();
    return error(ErrorCode::kNotFound, "delete key: no key at " + frame_text(graph));
  }
  return Status::ok();
}

std::vector<double> key_times(const Graph& graph, const std::vector<NodeId>& controls) {
  std::vector<double> out;
  for (NodeId c : keying_set(graph, controls)) {
    for (const graph::Connection& conn : graph.node(c)->inputs()) {
      if (conn.dst.attr != xform::kTranslate && conn.dst.attr != xform::kRotate && conn.dst.attr != xform::kRotateQuaternion)
        continue;
      const CurveKind kind = curve_kind(graph, conn.src.node);
      if (kind == CurveKind::kOther) continue;
      const graph::Node& curve = *graph.node(conn.src.node);
      const CurveLayout l = layout(kind);
      const KeyRange r = active_range(curve, l);
      const auto& times = std::get<std::vector<double>>(curve.value(l.times));
      for (std::size_t i = r.begin; i < r.end && i < times.size(); ++i) out.push_back(times[i]);
    }
  }
  std::sort(out.begin(), out.end());
  std::vector<double> unique;
  for (double t : out)
    if (unique.empty() || t - unique.back() > kTimeTolerance) unique.push_back(t);
  return unique;
}

bool has_key_now(const Graph& graph, NodeId control) {
  const double t = graph.time();
  const NodeId c = control_of(graph, control);
  if (!c.is_valid()) return false;
  for (const graph::Connection& conn : graph.node(c)->inputs()) {
    const CurveKind kind = curve_kind(graph, conn.src.node);
    if (kind == CurveKind::kOther) continue;
    const graph::Node& curve = *graph.node(conn.src.node);
    const CurveLayout l = layout(kind);
    if (key_at(std::get<std::vector<double>>(curve.value(l.times)), active_range(curve, l), t) >= 0) return true;
  }
  return false;
}

bool is_keyed(const Graph& graph, NodeId control) {
  const NodeId c = control_of(graph, control);
  if (!c.is_valid()) return false;
  for (const graph::Connection& conn : graph.node(c)->inputs())
    if (curve_kind(graph, conn.src.node) != CurveKind::kOther) return true;
  return false;
}

}  // namespace rigel::ephemeral
