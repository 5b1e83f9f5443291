// Keys on any keyable channel of any node (keys.h).

#include "rigel/tools/keys.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "rigel/ephemeral/keying.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/ops/anim/key_copy.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"

namespace rigel::tools {
namespace {

using graph::AttrIndex;
using graph::NodeId;
using graph::Plug;
using graph::Value;
using graph::ValueType;
namespace xform = scene::xform;
using ops::anim::CurveKind;

bool is_transform(const graph::Node& n) {
  return n.type().world_output() != graph::kNoAttr && n.type().attr_count() > xform::kCount &&
         n.type().attr(xform::kTranslate).name == "translate";
}

bool is_scalar(const graph::AttrSpec& a) { return a.type.value == ValueType::kDouble && !a.type.array; }


std::string frame_text(const graph::Graph& g, double t) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "frame %g", t * g.fps());
  return buffer;
}
std::string frame_text(const graph::Graph& g) { return frame_text(g, g.time()); }

}  // namespace

bool driven_otherwise(const graph::Graph& g, NodeId node, AttrIndex attr) {
  const graph::Node* n = g.node(node);
  if (!n) return false;
  for (const graph::Connection& c : n->inputs())
    if (c.dst.attr == attr && ops::anim::curve_kind(g, c.src.node) == CurveKind::kOther) return true;
  return false;
}

std::vector<AttrIndex> keyable_attrs(const graph::Node& node) {
  const graph::NodeType& type = node.type();
  std::vector<AttrIndex> out;
  const bool transform = is_transform(node);
  if (transform) out = {AttrIndex{xform::kTranslate}, xform::rotation_channel(node), AttrIndex{xform::kScale}};
  for (AttrIndex i = 0; i < static_cast<AttrIndex>(type.attr_count()); ++i) {
    if (transform && i < xform::kCount) continue;  // the transform's own, above
    const graph::AttrSpec& a = type.attr(i);
    if (!(a.flags & graph::kKeyable) || !(a.flags & graph::kInput) || a.type.array) continue;
    if (a.type.value == ValueType::kDouble || a.type.value == ValueType::kDouble3) out.push_back(i);
  }
  return out;
}

std::vector<NodeId> keying_group(const graph::Graph& graph, const std::vector<NodeId>& nodes) {
  std::vector<NodeId> out;
  auto add = [&](NodeId id) {
    if (std::find(out.begin(), out.end(), id) == out.end()) out.push_back(id);
  };
  for (NodeId id : nodes) {
    if (!graph.node(id)) continue;
    if (ephemeral::control_of(graph, id).is_valid()) {
      for (NodeId c : ephemeral::keying_set(graph, {id})) add(c);
      continue;
    }
    const NodeId root = graph.node(id)->type().name() == scene::kControlType ? rig::rig_of(graph, id) : NodeId{};
    if (!root.is_valid()) {
      add(id);
      continue;
    }
    std::vector<NodeId> metas{root};
    for (NodeId c : rig::rig_components(graph, root)) metas.push_back(c);
    for (NodeId m : metas)
      for (NodeId member : rig::meta_members(graph, m))
        if (graph.node(member)->type().name() == scene::kControlType && !ephemeral::control_of(graph, member).is_valid())
          add(member);
  }
  return out;
}

Result<std::vector<Channel>> channels_of(const graph::Graph& graph, const std::vector<NodeId>& nodes,
                                         const std::vector<std::string>& attrs) {
  std::vector<Channel> out;
  for (NodeId id : nodes) {
    const graph::Node* n = graph.node(id);
    if (!n) return Status(ErrorCode::kNotFound, "no such node (stale handle)").with_field("controls");
    const std::vector<AttrIndex> keyable = keyable_attrs(*n);
    if (attrs.empty()) {
      for (AttrIndex a : keyable)
        if (!driven_otherwise(graph, id, a)) out.push_back(Channel{id, a});
      continue;
    }
    for (const std::string& name : attrs) {
      const AttrIndex a = n->type().attr_find(name);
      if (a == graph::kNoAttr || std::find(keyable.begin(), keyable.end(), a) == keyable.end()) {
        std::string names;
        for (AttrIndex k : keyable) names += (names.empty() ? "" : ", ") + n->type().attr(k).name;
        return Status(ErrorCode::kInvalidArgument, "'" + n->name() + "' has no keyable channel '" + name + "' (" +
                                                       (names.empty() ? "it has none" : "keyable: " + names) + ")")
            .with_field("attrs");
      }
      out.push_back(Channel{id, a});
    }
  }
  if (out.empty()) return Status(ErrorCode::kInvalidArgument, "no keyable channel given").with_field("controls");
  return out;
}

Status set_keys(graph::Graph& graph, const std::vector<Channel>& channels, const std::optional<double>& value,
                const Tangents& tangents) {
  if (value && !std::isfinite(*value))
    return Status(ErrorCode::kInvalidArgument, "the value must be a finite number").with_field("value");
  graph::Transaction tx(graph, "set key (" + frame_text(graph) + ")");
  for (const Channel& c : channels) {
    const graph::Node* n = graph.node(c.node);
    if (!n) {
      tx.rollback();
      return Status(ErrorCode::kNotFound, "set key: no such node (stale handle)").with_field("controls");
    }
    Value v;
    if (value) {
      if (!is_scalar(n->type().attr(c.attr))) {
        tx.rollback();
        return Status(ErrorCode::kInvalidArgument, "set key: a value applies to scalar channels; " +
                                                       graph.plug_name(Plug{c.node, c.attr, -1}) + " is not one")
            .with_field("value");
      }
      v = *value;
    } else {
      Result<Value> current = graph.evaluate(Plug{c.node, c.attr, -1});
      if (!current) {
        tx.rollback();
        return current.status();
      }
      v = std::move(*current);
    }
    if (Status s = ephemeral::write_channel(graph, c.node, c.attr, v, true); !s) {
      tx.rollback();
      return s.with_context("set key");
    }
    if (tangents.any()) {
      if (Status s = ops::anim::set_key_tangents(graph, c.node, c.attr, graph.time(), tangents.in, tangents.out); !s) {
        tx.rollback();
        return Status(s).with_field("tangent");
      }
    }
  }
  return Status::ok();
}

Status delete_keys(graph::Graph& graph, const std::vector<Channel>& channels) {
  std::vector<std::pair<NodeId, AttrIndex>> list;
  for (const Channel& c : channels) list.emplace_back(c.node, c.attr);
  return ephemeral::delete_channel_keys(graph, list);
}

Result<std::size_t> move_keys(graph::Graph& graph, const std::vector<Channel>& channels, double from, double to,
                              bool copy) {
  if (!std::isfinite(from) || !std::isfinite(to))
    return Status(ErrorCode::kInvalidArgument, "move keys: the times must be finite").with_field("moveTo");
  const double tolerance = ephemeral::key_time_tolerance(graph);
  graph::Transaction tx(graph, std::string(copy ? "copy" : "move") + " keys (" + frame_text(graph, from) + " to " +
                                   frame_text(graph, to) + ")");
  std::size_t moved = 0;
  bool any = false;
  for (const Channel& c : channels) {
    const graph::Node* n = graph.node(c.node);
    if (!n) {
      tx.rollback();
      return Status(ErrorCode::kNotFound, "move keys: no such node (stale handle)").with_field("controls");
    }
    std::vector<graph::Connection> curves;
    for (const graph::Connection& conn : n->inputs())
      if (conn.dst.attr == c.attr && ops::anim::curve_kind(graph, conn.src.node) != CurveKind::kOther) curves.push_back(conn);
    for (const graph::Connection& conn : curves) {
      // The key nearest `from` within the tolerance.
      std::optional<double> at;
      for (double t : ops::anim::curve_key_times(graph, conn.src.node))
        if (std::abs(t - from) <= tolerance && (!at || std::abs(t - from) < std::abs(*at - from))) at = t;
      if (!at) continue;
      any = true;
      if (std::abs(*at - to) <= ops::anim::kKeyTimeTolerance) continue;  // already there
      const ops::anim::KeyCopy key_copy{*at, *at, to - *at, tolerance};
      Status s = ops::anim::copy_curve_keys(graph, conn.src.node, key_copy, conn.dst);
      bool removed = false;
      // (The curve keeps at least the moved key, so it is not deleted.)
      if (s && !copy) s = ops::anim::delete_curve_key(graph, conn.src.node, *at, conn.dst, graph::Value(0.0), removed);
      if (!s) {
        tx.rollback();
        return s.with_context("move keys");
      }
      ++moved;
    }
  }
  if (!any) {
    tx.rollback();
    return Status(ErrorCode::kNotFound, "move keys: no channel given has a key at " + frame_text(graph, from))
        .with_field("controls");
  }
  return moved;
}

Status set_values(graph::Graph& graph, const std::vector<Channel>& channels, const std::vector<double>& values,
                  bool auto_key) {
  auto bad = [](const std::string& message) {
    return Status(ErrorCode::kInvalidArgument, "set value: " + message).with_field("value");
  };
  if (values.size() != 1 && values.size() != channels.size())
    return bad("give one value, or one per channel (" + std::to_string(channels.size()) + "); got " +
               std::to_string(values.size()));
  for (double v : values)
    if (!std::isfinite(v)) return bad("the value must be a finite number");
  graph::Transaction tx(graph, "set value (" + frame_text(graph) + ")");
  for (std::size_t i = 0; i < channels.size(); ++i) {
    const Channel& c = channels[i];
    const graph::Node* n = graph.node(c.node);
    if (!n) {
      tx.rollback();
      return Status(ErrorCode::kNotFound, "set value: no such node (stale handle)").with_field("controls");
    }
    const graph::AttrSpec& spec = n->type().attr(c.attr);
    const bool component = spec.type == graph::AttrType{ValueType::kDouble3, false} && c.component >= 0 && c.component < 3;
    if (!is_scalar(spec) && !component) {
      tx.rollback();
      return bad(graph.plug_name(Plug{c.node, c.attr, -1}) +
                 " is not a scalar channel (a value sets switches such as fkIk, a foot's roll, a finger's curl, "
                 "or one component of a vector: translateX)");
    }
    bool keyed = false;
    for (const graph::Connection& conn : n->inputs())
      if (conn.dst.attr == c.attr) keyed = keyed || ops::anim::curve_kind(graph, conn.src.node) == CurveKind::kScalar;
    const double v = values.size() == 1 ? values[0] : values[i];
    Value value(v);
    if (component) {
      math::Vec3 now = std::get<math::Vec3>(graph.evaluate(c.node, c.attr));
      now[c.component] = v;
      value = Value(now);
    }
    if (Status s = ephemeral::write_channel(graph, c.node, c.attr, value, keyed || auto_key); !s) {
      tx.rollback();
      return s.with_context("set value");
    }
  }
  return Status::ok();
}

std::vector<PlugKeys> keys_of(const graph::Graph& graph, const std::vector<Channel>& channels) {
  std::vector<PlugKeys> out;
  for (const Channel& c : channels) {
    const graph::Node* n = graph.node(c.node);
    if (!n) continue;
    std::vector<const graph::Connection*> keyed;
    for (const graph::Connection& conn : n->inputs())
      if (conn.dst.attr == c.attr && ops::anim::curve_kind(graph, conn.src.node) != CurveKind::kOther)
        keyed.push_back(&conn);
    // Components in order (x, y, z), the whole channel first.
    std::sort(keyed.begin(), keyed.end(),
              [](const graph::Connection* a, const graph::Connection* b) { return a->dst.component < b->dst.component; });
    for (const graph::Connection* conn : keyed) {
      PlugKeys k;
      k.plug = conn->dst;
      k.name = graph.plug_name(conn->dst);
      k.times = ops::anim::curve_key_times(graph, conn->src.node);
      k.values = ops::anim::curve_key_values(graph, conn->src.node);
      const auto [in, tout] = ops::anim::curve_key_tangents(graph, conn->src.node);
      const auto names = ops::anim::tangent_type_names();
      for (ops::anim::TangentType t : in) k.in_tangents.emplace_back(names[static_cast<std::size_t>(t)]);
      for (ops::anim::TangentType t : tout) k.out_tangents.emplace_back(names[static_cast<std::size_t>(t)]);
      out.push_back(std::move(k));
    }
  }
  return out;
}

}  // namespace rigel::tools
