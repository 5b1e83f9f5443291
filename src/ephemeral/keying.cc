#include "rigel/ephemeral/keying.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "rigel/graph/graph.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/scene/transform_types.h"

namespace rigel::ephemeral {
namespace {

using graph::AttrIndex;
using graph::Plug;
using graph::Value;
using math::Quat;
using math::Vec3;
namespace xform = scene::xform;
using ops::anim::CurveKind;
using ops::anim::curve_kind;

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
  return xform::rotation_channel(control);
}


// The key time of `curve` nearest `t` within key_time_tolerance(), if any.
std::optional<double> curve_key_near(const Graph& graph, NodeId curve, double t) {
  const double tolerance = key_time_tolerance(graph);
  std::optional<double> best;
  for (double k : ops::anim::curve_key_times(graph, curve))
    if (std::abs(k - t) <= tolerance && (!best || std::abs(k - t) < std::abs(*best - t))) best = k;
  return best;
}

// The time to edit channel `attr` of `control` at for time `t`: the key time
// its curves hold within the tolerance of `t` (the same for every component
// curve), else `t` itself.
Result<double> channel_key_time(const Graph& graph, NodeId control, AttrIndex attr, double t) {
  std::optional<double> found;
  const graph::Node& n = *graph.node(control);
  for (const graph::Connection& conn : n.inputs()) {
    if (conn.dst.attr != attr) continue;
    const std::optional<double> k = curve_key_near(graph, conn.src.node, t);
    if (!k) continue;
    if (found && std::abs(*found - *k) > ops::anim::kKeyTimeTolerance) {
      return error(ErrorCode::kInvalidArgument,
                   n.name() + "." + n.type().attr(attr).name + ": its component curves have keys near " +
                       frame_text(graph) + " at different times (" + std::to_string(*found * graph.fps()) + " and " +
                       std::to_string(*k * graph.fps()) + "); key the components at one time");
    }
    if (!found) found = k;
  }
  return found ? *found : t;
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

double key_time_tolerance(const Graph& graph) {
  const double fps = graph.fps();
  const double frame = fps > 0 && std::isfinite(fps) ? kKeyFrameTolerance / fps : 0.0;
  return std::max(frame, ops::anim::kKeyTimeTolerance);
}

Status write_channel(Graph& graph, NodeId control, AttrIndex attr, const Value& value, bool insert) {
  if (!graph.node(control)) return error(ErrorCode::kNotFound, "key: no such node (stale handle)");
  Result<double> t = channel_key_time(graph, control, attr, graph.time());
  if (!t) return t.status();
  return ops::anim::write_channel_key(graph, control, attr, value, *t, insert);
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

Status delete_channel_key(Graph& graph, NodeId node, AttrIndex attr, bool& removed) {
  removed = false;
  const graph::Node* n = graph.node(node);
  if (!n) return error(ErrorCode::kNotFound, "delete key: no such node (stale handle)");
  Result<Value> current = graph.evaluate(Plug{node, attr, -1});
  if (!current) return current.status();
  const double t = graph.time();
  // Gather the curves first: deleting one changes the node's inputs.
  std::vector<std::pair<Plug, Plug>> curves;  // (curve output, channel plug)
  for (const graph::Connection& conn : n->inputs())
    if (conn.dst.attr == attr && curve_kind(graph, conn.src.node) != CurveKind::kOther) curves.emplace_back(conn.src, conn.dst);
  for (const auto& [src, dst] : curves) {
    const std::optional<double> at = curve_key_near(graph, src.node, t);
    if (!at) continue;
    const Value keep = dst.component >= 0 ? Value(std::get<Vec3>(*current)[dst.component]) : *current;
    bool gone = false;
    if (Status s = ops::anim::delete_curve_key(graph, src.node, *at, dst, keep, gone); !s) return s;
    removed = removed || gone;
  }
  return Status::ok();
}

Status delete_channel_keys(Graph& graph, const std::vector<std::pair<NodeId, AttrIndex>>& channels) {
  bool any = false;
  graph::Transaction tx(graph, "delete key (" + frame_text(graph) + ")");
  for (const auto& [node, attr] : channels) {
    bool removed = false;
    if (Status s = delete_channel_key(graph, node, attr, removed); !s) {
      tx.rollback();
      return s.with_context("delete key");
    }
    any = any || removed;
  }
  if (!any) {
    tx.rollback();
    return error(ErrorCode::kNotFound, "delete key: no key at " + frame_text(graph));
  }
  return Status::ok();
}

Status delete_key(Graph& graph, const std::vector<NodeId>& controls) {
  std::vector<NodeId> set = keying_set(graph, controls);
  if (set.empty()) return error(ErrorCode::kInvalidArgument, "delete key: no control of an ephemeral rig given");
  std::vector<std::pair<NodeId, AttrIndex>> channels;
  for (NodeId c : set)
    for (AttrIndex attr : {AttrIndex{xform::kTranslate}, rotation_attr(*graph.node(c))}) channels.emplace_back(c, attr);
  return delete_channel_keys(graph, channels);
}

std::vector<double> key_times(const Graph& graph, const std::vector<NodeId>& controls) {
  std::vector<double> out;
  for (NodeId c : keying_set(graph, controls)) {
    for (const graph::Connection& conn : graph.node(c)->inputs()) {
      if (conn.dst.attr != xform::kTranslate && conn.dst.attr != xform::kRotate && conn.dst.attr != xform::kRotateQuaternion)
        continue;
      for (double t : ops::anim::curve_key_times(graph, conn.src.node)) out.push_back(t);
    }
  }
  std::sort(out.begin(), out.end());
  std::vector<double> unique;
  const double tolerance = key_time_tolerance(graph);
  for (double t : out)
    if (unique.empty() || t - unique.back() > tolerance) unique.push_back(t);
  return unique;
}

bool has_key_now(const Graph& graph, NodeId control) {
  const double t = graph.time();
  const NodeId c = control_of(graph, control);
  if (!c.is_valid()) return false;
  for (const graph::Connection& conn : graph.node(c)->inputs()) {
    if (curve_key_near(graph, conn.src.node, t)) return true;
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
