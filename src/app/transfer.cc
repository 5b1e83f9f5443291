// The workspace's transfer keys, move keys and channel values (workspace.h).

#include <algorithm>
#include <cmath>
#include <string>

#include "internal.h"
#include "rigel/app/workspace.h"
#include "rigel/ephemeral/keying.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/tools/keys.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"

namespace rigel::app {
namespace {

using internal::conflict;

// "RIG:COMPONENT" or "RIG:" as its meta node (errors name `field`).
Result<NodeId> meta_of(const graph::Graph& g, const std::string& ref, const std::string& field) {
  const std::size_t colon = ref.find(':');
  if (colon == std::string::npos)
    return Status(ErrorCode::kInvalidArgument, field + ": expected RIG:COMPONENT or RIG:, got '" + ref + "'")
        .with_field(field);
  const std::string rig_name = ref.substr(0, colon), component = ref.substr(colon + 1);
  const NodeId rig = rig::find_rig(g, rig_name);
  if (!rig.is_valid())
    return Status(ErrorCode::kNotFound, field + ": no built rig '" + rig_name + "' in the scene").with_field(field);
  if (component.empty()) return rig;
  const NodeId meta = rig::find_component(g, rig, component);
  if (!meta.is_valid())
    return Status(ErrorCode::kNotFound, field + ": rig '" + rig_name + "' has no component '" + component + "'")
        .with_field(field);
  return meta;
}

bool is_built_control(const graph::Graph& g, NodeId id) {
  return g.node(id)->type().name() == scene::kControlType && rig::component_of(g, id).is_valid() &&
         !ephemeral::control_of(g, id).is_valid();
}

// "translateX" of a node whose double3 channel is "translate": {"translate",
// 0}; anything else {attr, -1}.
std::pair<std::string, int> component_attr(const graph::Graph& g, NodeId node, const std::string& attr) {
  if (attr.size() < 2) return {attr, -1};
  const char last = attr.back();
  const int k = last == 'X' ? 0 : last == 'Y' ? 1 : last == 'Z' ? 2 : -1;
  if (k < 0 || g.node(node)->type().attr_find(attr) != graph::kNoAttr) return {attr, -1};
  const std::string base = attr.substr(0, attr.size() - 1);
  const graph::AttrIndex a = g.node(node)->type().attr_find(base);
  if (a == graph::kNoAttr || g.node(node)->type().attr(a).type != graph::AttrType{graph::ValueType::kDouble3, false})
    return {attr, -1};
  return {base, k};
}

// The node that holds keyable channel `attr` for `node`: itself, or for a
// built rig's control without it, the one node of its component that has it.
NodeId holder_of(const graph::Graph& g, NodeId node, const std::string& attr) {
  auto has = [&](NodeId id, const std::string& name = {}) {
    const graph::Node& n = *g.node(id);
    const graph::AttrIndex a = n.type().attr_find(name.empty() ? attr : name);
    const std::vector<graph::AttrIndex> keyable = tools::keyable_attrs(n);
    return a != graph::kNoAttr && std::find(keyable.begin(), keyable.end(), a) != keyable.end();
  };
  if (has(node) || has(node, component_attr(g, node, attr).first) || !is_built_control(g, node)) return node;
  for (NodeId m : rig::meta_members(g, rig::component_of(g, node)))
    if (!is_built_control(g, m) && has(m)) return m;
  return node;
}

}  // namespace

Result<tools::TransferReport> Workspace::transfer_keys(const std::string& from, const std::string& to,
                                                       const std::optional<std::array<double, 2>>& frames,
                                                       double offset) {
  tools::TransferOptions options;
  Result<NodeId> a = meta_of(graph(), from, "from");
  if (!a) return a.status();
  Result<NodeId> b = meta_of(graph(), to, "to");
  if (!b) return b.status();
  options.from = *a;
  options.to = *b;
  if (frames) {
    options.first = (*frames)[0];
    options.last = (*frames)[1];
  }
  options.offset = offset;
  auto bad = [](const char* field, const std::string& message) {
    return Status(ErrorCode::kInvalidArgument, std::string(field) + ": " + message).with_field(field);
  };
  if (frames && (std::abs((*frames)[0]) > kMaxFrame || std::abs((*frames)[1]) > kMaxFrame))
    return bad("frames", "out of range (at most 1e6)");
  if (std::isfinite(offset) && std::abs(offset) > 2 * kMaxFrame) return bad("offset", "out of range (at most 2e6 frames)");
  Result<tools::TransferReport> report = tools::transfer_keys(graph(), options);
  if (!report) return report.status().field().empty() ? conflict(report.status()) : report.status();
  if (report->channels > 0) bump_revision();
  return report;
}

Result<std::vector<tools::PlugKeys>> Workspace::move_channel_keys(const std::vector<NodeId>& controls,
                                                                  const std::vector<std::string>& attrs, double to_frame,
                                                                  bool copy, std::optional<double> from_frame) {
  if (!std::isfinite(to_frame) || std::abs(to_frame) > kMaxFrame)
    return Status(ErrorCode::kInvalidArgument, "moveTo: not a frame within 1e6 of 0").with_field("moveTo");
  if (from_frame && (!std::isfinite(*from_frame) || std::abs(*from_frame) > kMaxFrame))
    return Status(ErrorCode::kInvalidArgument, "from: not a frame within 1e6 of 0").with_field("from");
  auto channels = key_channels(controls, attrs);
  if (!channels) return channels.status();
  const double from = from_frame ? *from_frame / graph().fps() : graph().time();
  Result<std::size_t> moved = tools::move_keys(graph(), *channels, from, to_frame / graph().fps(), copy);
  if (!moved) return moved.status().field().empty() ? conflict(moved.status()) : moved.status();
  bump_revision();
  return tools::keys_of(graph(), *channels);
}

Result<Workspace::ChannelValues> Workspace::set_channel_values(const std::vector<NodeId>& controls,
                                                               const std::vector<std::string>& attrs,
                                                               const std::vector<double>& values) {
  const graph::Graph& g = graph();
  ChannelValues out;
  for (NodeId id : controls) {
    if (!g.node(id)) return Status(ErrorCode::kNotFound, "controls: no such node (stale handle)").with_field("controls");
    std::vector<NodeId> holders;
    std::vector<std::string> names;
    if (attrs.empty()) {
      holders.push_back(id);
    } else {
      for (const std::string& attr : attrs) {
        holders.push_back(holder_of(g, id, attr));
        names.push_back(attr);
      }
    }
    for (std::size_t i = 0; i < holders.size(); ++i) {
      // "translateX": one component of a vector channel.
      int component = -1;
      std::string name = names.empty() ? std::string() : names[i];
      if (const auto [base, k] = component_attr(g, holders[i], name); k >= 0) {
        name = base;
        component = k;
      }
      auto channels = tools::channels_of(g, {holders[i]}, name.empty() ? std::vector<std::string>{} : std::vector{name});
      if (!channels) return channels.status();
      for (tools::Channel c : *channels)
        if (component >= 0) {
          c.component = component;
          out.channels.push_back(c);
        } else if (g.node(c.node)->type().attr(c.attr).type == graph::AttrType{graph::ValueType::kDouble, false})
          out.channels.push_back(c);
        else if (!attrs.empty())
          return Status(ErrorCode::kInvalidArgument, "attrs: " + g.plug_name(graph::Plug{c.node, c.attr, -1}) +
                                                         " is not a scalar channel (values set switches such as fkIk, "
                                                         "a foot's roll, a finger's curl)")
              .with_field("attrs");
    }
  }
  if (out.channels.empty())
    return Status(ErrorCode::kInvalidArgument, "controls: no scalar channel given").with_field("controls");
  if (Status s = tools::set_values(graph(), out.channels, values, session_->options().auto_key); !s)
    return s.field().empty() ? conflict(s) : s;
  bump_revision();
  out.keys = tools::keys_of(graph(), out.channels);
  return out;
}

namespace {

// Where `channel`'s component `k` (-1: a scalar) has keys: at the graph's
// time, elsewhere, or nowhere.
Workspace::KeyState key_state(const graph::Graph& g, const tools::Channel& channel, int k) {
  Workspace::KeyState state = Workspace::KeyState::kNone;
  for (const tools::PlugKeys& keys : tools::keys_of(g, {channel})) {
    if (k >= 0 && keys.plug.component >= 0 && keys.plug.component != k) continue;
    for (double t : keys.times) {
      if (std::abs(t - g.time()) <= ephemeral::key_time_tolerance(g)) return Workspace::KeyState::kHere;
      state = Workspace::KeyState::kElsewhere;
    }
  }
  return state;
}

}  // namespace

std::vector<NodeId> internal::channel_holders(const graph::Graph& g, NodeId id) {
  std::vector<NodeId> holders{id};
  if (is_built_control(g, id))
    for (NodeId m : rig::meta_members(g, rig::component_of(g, id)))
      if (g.node(m)->type().world_output() == graph::kNoAttr && !tools::keyable_attrs(*g.node(m)).empty())
        holders.push_back(m);
  return holders;
}

Result<std::vector<Workspace::ChannelBox>> Workspace::channel_box(const std::vector<NodeId>& controls) {
  graph::Graph& g = graph();
  std::vector<ChannelBox> out;
  for (NodeId id : controls) {
    if (!g.node(id)) return Status(ErrorCode::kNotFound, "controls: no such node (stale handle)").with_field("controls");
    ChannelBox box{id, {}};
    for (NodeId holder : internal::channel_holders(g, id)) {
      Result<std::vector<tools::Channel>> channels = tools::channels_of(g, {holder});
      if (!channels) continue;  // nothing keyable on it
      for (const tools::Channel& c : *channels) {
        const graph::AttrSpec& spec = g.node(holder)->type().attr(c.attr);
        const graph::Value value = g.evaluate(holder, c.attr);
        auto row = [&](const std::string& attr, int k, double v) {
          box.rows.push_back(ChannelRow{holder, attr, spec.name, g.node(holder)->name() + "." + attr, v,
                                        key_state(g, c, k)});
        };
        if (const auto* d = std::get_if<double>(&value)) {
          row(spec.name, -1, *d);
        } else if (const auto* v = std::get_if<math::Vec3>(&value)) {
          for (int k = 0; k < 3; ++k) row(spec.name + "XYZ"[k], k, (*v)[k]);
        }
        // A quaternion rotation has no channels an animator types; it is posed.
      }
    }
    out.push_back(std::move(box));
  }
  return out;
}

}  // namespace rigel::app
