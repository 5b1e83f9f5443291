// The pose library: capturing a pose and applying it (poses.h); the files
// are pose_file.cc's.

#include "rigel/tools/poses.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <string>

#include "mirror_map.h"
#include "roles.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/math/rotation.h"
#include "rigel/math/transform.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"
#include "rigel/tools/keys.h"

namespace rigel::tools {
namespace {

using graph::AttrIndex;
using graph::NodeId;
using graph::Value;
using math::Mat4;
using math::Quat;
using math::Vec3;
namespace xform = scene::xform;

bool is_control(const graph::Graph& g, NodeId id) { return g.node(id)->type().name() == scene::kControlType; }
bool is_transform(const graph::Node& n) { return n.type().world_output() != graph::kNoAttr; }

math::RotateOrder rotate_order(const graph::Graph& g, NodeId id) {
  return static_cast<math::RotateOrder>(std::get<std::int64_t>(g.node(id)->value(xform::kRotateOrder)));
}

// What a pose may hold of a component's members: its built controls (not an
// ephemeral component's, which pose through their session) and the other
// nodes it built with keyable channels.
bool poseable(const graph::Graph& g, NodeId id) {
  const NodeId meta = rig::component_of(g, id);
  if (!meta.is_valid() || g.node(meta)->type().name() != rig::kMetaComponentType) return false;
  if (is_control(g, id)) return !ephemeral::control_of(g, id).is_valid();
  return !keyable_attrs(*g.node(id)).empty();
}

// The whole-component set: what a bind pose resets (controls and the
// nodes with bind values).
void add_component(const graph::Graph& g, NodeId meta, std::set<std::uint32_t>& out) {
  for (NodeId m : rig::meta_members(g, meta))
    if (poseable(g, m) && (is_control(g, m) || g.node(m)->tag_find(rig::kTagBind))) out.insert(m.index);
}

// A node's channels as a pose stores them.
std::vector<PoseChannel> channels_now(graph::Graph& g, NodeId id) {
  std::vector<PoseChannel> out;
  auto free = channels_of(g, {id});
  if (!free) return out;
  const graph::Node& n = *g.node(id);
  for (const Channel& c : *free) {
    Value v = g.node(id)->value(c.attr);
    if (auto e = g.evaluate(graph::Plug{id, c.attr, -1}); e) v = *e;
    const graph::AttrSpec& spec = n.type().attr(c.attr);
    if (is_transform(n) && c.attr == xform::rotation_channel(n)) {
      Quat q = c.attr == xform::kRotateQuaternion
                   ? std::get<Quat>(v).normalized()
                   : math::euler_to_quat(math::to_radians(std::get<Vec3>(v)), rotate_order(g, id));
      out.push_back({"rotation", Value(q)});
    } else if (spec.type.value == graph::ValueType::kDouble || spec.type.value == graph::ValueType::kDouble3) {
      out.push_back({spec.name, v});
    }
  }
  return out;
}

}  // namespace

Result<Pose> capture_pose(graph::Graph& g, const std::vector<NodeId>& nodes, const std::string& name) {
  auto refuse = [](const std::string& m) { return Status(ErrorCode::kInvalidArgument, "pose: " + m).with_field("controls"); };
  if (nodes.empty()) return refuse("nothing given");
  NodeId rig;
  std::set<std::uint32_t> chosen;
  for (NodeId id : nodes) {
    const graph::Node* n = g.node(id);
    if (!n) return Status(ErrorCode::kNotFound, "pose: no such node (stale handle)").with_field("controls");
    const NodeId r = rig::rig_of(g, id);
    if (!r.is_valid()) return refuse("'" + n->name() + "' is not part of a built rig");
    if (rig.is_valid() && r != rig)
      return refuse("'" + n->name() + "' is of rig '" + rig::meta_string(g, r, "rigName") + "', not '" +
                    rig::meta_string(g, rig, "rigName") + "' (a pose is of one rig)");
    rig = r;
    const std::string& type = n->type().name();
    if (type == rig::kMetaRootType) {
      for (NodeId c : rig::rig_components(g, id)) add_component(g, c, chosen);
    } else if (type == rig::kMetaComponentType) {
      add_component(g, id, chosen);
    } else if (poseable(g, id)) {
      chosen.insert(id.index);
    } else {
      return refuse("'" + n->name() + "' is neither a built rig's control (or other keyable node), component nor rig");
    }
  }
  Pose pose;
  pose.name = name;
  pose.rig = rig::meta_string(g, rig, "rigName");
  // Rig order (components parents first, members in creation order), not
  // the order given: the same pose gives the same file.
  for (NodeId meta : rig::rig_components(g, rig)) {
    for (NodeId m : rig::meta_members(g, meta)) {
      if (!chosen.count(m.index)) continue;
      auto role = internal::role_of(g, meta, m);
      if (!role) continue;  // nothing finds it again
      PoseEntry e;
      e.rig_id = rig::meta_string(g, meta, "rigId");
      e.role = role->first;
      e.index = role->second;
      e.component = rig::meta_string(g, meta, "componentName");
      e.side = rig::meta_string(g, meta, "side");
      e.type = rig::meta_string(g, meta, "metaType");
      e.node = g.node(m)->name();
      e.channels = channels_now(g, m);
      if (!e.channels.empty()) pose.entries.push_back(std::move(e));
    }
  }
  if (pose.entries.empty()) return refuse("nothing given has a free or keyed channel");
  return pose;
}

namespace {

// One node's channels to write, the target values then the blend.
struct Write {
  NodeId node;
  std::vector<std::pair<AttrIndex, Value>> values;
};

std::string entry_text(const PoseEntry& e) {
  return e.component + " " + e.role + " " + std::to_string(e.index);
}

Quat rotation_now(const graph::Graph& g, NodeId id) {
  const graph::Node& n = *g.node(id);
  const AttrIndex a = xform::rotation_channel(n);
  const Value& v = n.value(a);
  if (a == xform::kRotateQuaternion) return std::get<Quat>(v).normalized();
  return math::euler_to_quat(math::to_radians(std::get<Vec3>(v)), rotate_order(g, id));
}

// The entry's channel values mirrored onto `target` (the pair of `source`
// on the same rig): a control's matrix through K^-1 C K, others as they are.
Result<std::vector<PoseChannel>> mirrored(const graph::Graph& g, const PoseEntry& e, NodeId source, NodeId target,
                                          const Mat4& reflection) {
  if (!is_control(g, source)) return e.channels;
  Vec3 t = Vec3::Zero(), s = Vec3::Ones();
  Quat q = Quat::Identity();
  std::vector<PoseChannel> out;
  for (const PoseChannel& c : e.channels) {
    if (c.attr == "translate") t = std::get<Vec3>(c.value);
    else if (c.attr == "scale") s = std::get<Vec3>(c.value);
    else if (c.attr == "rotation") q = std::get<Quat>(c.value);
    else out.push_back(c);
  }
  Result<internal::MirrorMap> map = internal::mirror_map(g, source, target, reflection, "apply pose");
  if (!map) return map.status();
  const math::TransformParts parts = math::decompose_to_parts((*map)(math::trs_matrix(t, q, s)), rotate_order(g, target));
  out.insert(out.begin(), {{"translate", Value(parts.translate)},
                           {"rotation", Value(math::euler_to_quat(parts.rotate, rotate_order(g, target)))},
                           {"scale", Value(parts.scale)}});
  if (parts.shear.cwiseAbs().maxCoeff() > 1e-12) out.push_back({"shear", Value(parts.shear)});
  return out;
}

// `target` from the current value by `f` (0: the current value as it is).
Value blend(const graph::Graph& g, NodeId id, AttrIndex a, const Value& target, double f) {
  const graph::Node& n = *g.node(id);
  const Value& now = n.value(a);
  if (f == 0) return now;
  if (const Quat* q = std::get_if<Quat>(&target)) {
    const Quat from = rotation_now(g, id);
    const Quat to = f == 1 ? *q : from.slerp(f, *q).normalized();
    if (a == xform::kRotateQuaternion) return Value(to);
    const math::RotateOrder order = rotate_order(g, id);
    const Vec3 previous = math::to_radians(std::get<Vec3>(now));
    return Value(Vec3(math::to_degrees(math::euler_closest(math::quat_to_euler(to, order), previous, order))));
  }
  if (f == 1) return target;
  if (const double* x = std::get_if<double>(&target)) {
    const double from = std::get<double>(now);
    return Value(from + f * (*x - from));
  }
  const Vec3& from = std::get<Vec3>(now);
  return Value(Vec3(from + f * (std::get<Vec3>(target) - from)));
}

bool keyed(const graph::Graph& g, NodeId node, AttrIndex attr) {
  for (const graph::Connection& c : g.node(node)->inputs())
    if (c.dst.attr == attr && ops::anim::curve_kind(g, c.src.node) != ops::anim::CurveKind::kOther) return true;
  return false;
}

}  // namespace

Result<ApplyPoseReport> apply_pose(graph::Graph& g, const Pose& pose, NodeId rig, const ApplyPoseOptions& o) {
  const graph::Node* root = g.node(rig);
  if (!root || root->type().name() != rig::kMetaRootType)
    return Status(ErrorCode::kInvalidArgument, "apply pose: the target is not a built rig").with_field("rig");
  if (!std::isfinite(o.fraction) || o.fraction < 0 || o.fraction > 1)
    return Status(ErrorCode::kInvalidArgument, "apply pose: the fraction must be within 0..1").with_field("fraction");
  const std::string rig_name = rig::meta_string(g, rig, "rigName");
  auto mismatch = [&](const PoseEntry& e, const std::string& why) {
    return Status(ErrorCode::kInvalidArgument, "pose '" + pose.name + "' (of rig '" + pose.rig + "') does not fit rig '" +
                                                   rig_name + "': " + why + " (entry " + entry_text(e) + ", rigId " +
                                                   e.rig_id + ")")
        .with_field("rig");
  };
  const Mat4 reflection = internal::reflection(o.plane);
  ApplyPoseReport report;
  std::vector<Write> writes;
  std::map<std::uint32_t, std::size_t> by_node;  // target node -> writes index
  for (const PoseEntry& e : pose.entries) {
    const NodeId meta = rig::find_component(g, rig, e.rig_id);
    if (!meta.is_valid() || rig::meta_string(g, meta, "rigId") != e.rig_id)
      return mismatch(e, "no component has rigId " + e.rig_id);
    Result<NodeId> source = rig::get_meta_connection(g, meta, e.role, e.index);
    if (!source) return mismatch(e, "component '" + rig::meta_string(g, meta, "componentName") + "' has no '" + e.role +
                                        "' " + std::to_string(e.index));
    NodeId target = *source;
    std::vector<PoseChannel> channels = e.channels;
    if (o.mirrored) {
      Result<NodeId> pair = rig::mirror_pair(g, *source);
      if (!pair) {
        report.unpaired.push_back(entry_text(e));
        continue;
      }
      target = *pair;
      auto m = mirrored(g, e, *source, target, reflection);
      if (!m) return m.status();
      channels = std::move(*m);
    }
    if (!o.controls.empty() && std::find(o.controls.begin(), o.controls.end(), target) == o.controls.end()) continue;
    const graph::Node& n = *g.node(target);
    Write w{target, {}};
    for (const PoseChannel& c : channels) {
      AttrIndex a = n.type().attr_find(c.attr);
      if (c.attr == "rotation" && is_transform(n)) a = xform::rotation_channel(n);
      if (a == graph::kNoAttr) return mismatch(e, "'" + n.name() + "' has no channel '" + c.attr + "'");
      const Value& now = n.value(a);
      const bool fits = std::holds_alternative<Quat>(c.value) ? a == xform::rotation_channel(n) && is_transform(n)
                                                             : now.index() == c.value.index();
      if (!fits) return mismatch(e, "'" + n.name() + "." + c.attr + "' holds another kind of value");
      if (driven_otherwise(g, target, a)) {
        report.skipped.push_back(g.plug_name(graph::Plug{target, a, -1}));
        continue;
      }
      w.values.emplace_back(a, c.value);
    }
    if (!by_node.emplace(target.index, writes.size()).second) continue;  // two entries for one node: the first
    writes.push_back(std::move(w));
  }
  for (NodeId c : o.controls)
    if (!g.node(c) || !by_node.count(c.index))
      return Status(ErrorCode::kInvalidArgument, "apply pose: pose '" + pose.name + "' sets nothing of '" +
                                                     (g.node(c) ? g.node(c)->name() : std::string("?")) + "'" +
                                                     (o.mirrored ? " (mirrored)" : ""))
          .with_field("controls");
  if (writes.empty())
    return Status(ErrorCode::kInvalidArgument, "apply pose: pose '" + pose.name + "' sets nothing here").with_field("controls");

  // Every value first (they read the current pose), then every write.
  for (Write& w : writes) {
    // Evaluate so that values read are current (a keyed channel's curve).
    for (auto& [a, v] : w.values) {
      (void)g.evaluate(graph::Plug{w.node, a, -1});
      v = blend(g, w.node, a, v, o.fraction);
    }
  }
  if (o.fraction == 0) return report;  // nothing changes (no keys either)
  graph::Transaction tx(g, "apply pose '" + pose.name + "'");
  const double t = g.time();
  for (const Write& w : writes) {
    for (const auto& [a, v] : w.values) {
      const bool insert = o.key || keyed(g, w.node, a);
      if (Status s = ops::anim::write_channel_key(g, w.node, a, v, t, insert); !s) {
        tx.rollback();
        return s.with_context("apply pose");
      }
      ++report.channels;
      if (insert) ++report.keyed;
    }
    report.set.push_back(w.node);
  }
  return report;
}

namespace internal {

// The role a node is found by in its component and its index there, as
// rig::get_meta_connection counts them (so that it gives the node back).
std::optional<std::pair<std::string, int>> role_of(const graph::Graph& g, NodeId meta, NodeId id) {
  const graph::Node& n = *g.node(id);
  const std::string* role = n.tag_find(rig::kTagRole);
  if (!role) role = n.tag_find(rig::kTagStep);
  if (!role) return std::nullopt;
  int tagged = 0;
  if (const std::string* i = n.tag_find(rig::kTagIndex)) tagged = std::atoi(i->c_str());
  if (auto at = rig::get_meta_connection(g, meta, *role, tagged); at && *at == id) return std::pair{*role, tagged};
  for (int i = 0;; ++i) {
    Result<NodeId> at = rig::get_meta_connection(g, meta, *role, i);
    if (!at) return std::nullopt;
    if (*at == id) return std::pair{*role, i};
  }
}

}  // namespace internal

}  // namespace rigel::tools
