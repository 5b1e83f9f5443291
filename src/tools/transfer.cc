// Transfer keys between components and characters (transfer.h).

#include "rigel/tools/transfer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <tuple>

#include "rigel/ops/anim/channel_keys.h"
#include "rigel/ops/anim/key_copy.h"
#include "rigel/rig/meta.h"
#include "rigel/tools/keys.h"

namespace rigel::tools {
namespace {

using graph::AttrIndex;
using graph::NodeId;
using graph::Plug;

Status bad(const std::string& field, const std::string& message) {
  return Status(ErrorCode::kInvalidArgument, "transfer: " + message).with_field(field);
}

std::string name_of(const graph::Graph& g, NodeId id) { return g.node(id) ? g.node(id)->name() : std::string("?"); }

// What pairs a node with its counterpart: role (or step), index, and its
// rank among the component's nodes with that role and index.
using MemberKey = std::tuple<std::string, std::string, int>;

std::map<MemberKey, NodeId> member_keys(const graph::Graph& g, NodeId meta) {
  std::map<MemberKey, NodeId> out;
  std::map<std::pair<std::string, std::string>, int> seen;
  for (NodeId m : rig::meta_members(g, meta)) {
    const graph::Node& n = *g.node(m);
    const std::string* role = n.tag_find(rig::kTagRole);
    if (!role) role = n.tag_find(rig::kTagStep);
    const std::string* index = n.tag_find(rig::kTagIndex);
    std::pair<std::string, std::string> k{role ? *role : "", index ? *index : ""};
    out[{k.first, k.second, seen[k]++}] = m;
  }
  return out;
}

// One curve's keys and the channel plug they go onto.
struct Job {
  NodeId curve;
  Plug target;
};

// The keyed channels of `meta`'s nodes and where they go on `target`.
Status plan_component(const graph::Graph& g, NodeId meta, NodeId target, std::vector<Job>& jobs,
                      std::vector<NodeId>& set) {
  const std::map<MemberKey, NodeId> theirs = member_keys(g, target);
  for (const auto& [key, m] : member_keys(g, meta)) {
    const graph::Node& n = *g.node(m);
    std::vector<Job> mine;
    for (AttrIndex a : keyable_attrs(n))
      for (const graph::Connection& c : n.inputs())
        if (c.dst.attr == a && ops::anim::curve_kind(g, c.src.node) != ops::anim::CurveKind::kOther)
          mine.push_back(Job{c.src.node, c.dst});
    if (mine.empty()) continue;
    auto it = theirs.find(key);
    if (it == theirs.end())
      return bad("to", "'" + n.name() + "' (" + (std::get<0>(key).empty() ? "no role" : std::get<0>(key)) + " " +
                           (std::get<1>(key).empty() ? "0" : std::get<1>(key)) + " of " + name_of(g, meta) +
                           ") has no match in " + name_of(g, target));
    const graph::Node& t = *g.node(it->second);
    if (t.type().name() != n.type().name())
      return bad("to", "'" + n.name() + "' is a " + n.type().name() + ", its match '" + t.name() + "' a " + t.type().name());
    const std::vector<AttrIndex> keyable = keyable_attrs(t);
    for (Job& j : mine) {
      const std::string& attr = n.type().attr(j.target.attr).name;
      const AttrIndex ta = t.type().attr_find(attr);
      if (ta == graph::kNoAttr || std::find(keyable.begin(), keyable.end(), ta) == keyable.end())
        return bad("to", "'" + t.name() + "' has no keyable channel '" + attr + "' for the keys of '" + n.name() + "'");
      j.target = Plug{it->second, ta, -1, j.target.component};
      jobs.push_back(j);
    }
    set.push_back(it->second);
  }
  return Status::ok();
}

bool has_keys(const graph::Graph& g, NodeId meta) {
  std::vector<Job> jobs;
  std::vector<NodeId> set;
  (void)plan_component(g, meta, meta, jobs, set);
  return !jobs.empty();
}

// The component of `rig` that pairs with `component`: the same rigId, else
// the same name and side; invalid when none.
NodeId counterpart(const graph::Graph& g, NodeId component, NodeId rig) {
  const std::string id = rig::meta_string(g, component, "rigId");
  const std::vector<NodeId> candidates = rig::rig_components(g, rig);
  if (!id.empty())
    for (NodeId c : candidates)
      if (rig::meta_string(g, c, "rigId") == id) return c;
  for (NodeId c : candidates)
    if (rig::meta_string(g, c, "componentName") == rig::meta_string(g, component, "componentName") &&
        rig::meta_string(g, c, "side") == rig::meta_string(g, component, "side"))
      return c;
  return {};
}

Status same_type(const graph::Graph& g, NodeId a, NodeId b) {
  const std::string ta = rig::meta_string(g, a, "metaType"), tb = rig::meta_string(g, b, "metaType");
  if (ta != tb)
    return bad("to", name_of(g, a) + " is a " + ta + " component and " + name_of(g, b) + " a " + tb +
                         ": keys transfer between components of the same type");
  return Status::ok();
}

Status plan(const graph::Graph& g, const TransferOptions& o, std::vector<Job>& jobs, TransferReport& report) {
  auto kind = [&](NodeId id) -> std::string {
    const graph::Node* n = g.node(id);
    return n ? n->type().name() : std::string();
  };
  const std::string from = kind(o.from), to = kind(o.to);
  // (append, not "'" + name: GCC 12 warns falsely on the latter.)
  auto not_meta = [&](NodeId id) { return std::string("'").append(name_of(g, id)).append("' is not a built rig's component or rig"); };
  if (from != rig::kMetaComponentType && from != rig::kMetaRootType) return bad("from", not_meta(o.from));
  if (to != rig::kMetaComponentType && to != rig::kMetaRootType) return bad("to", not_meta(o.to));
  if (from != to)
    return bad("to", "give a component for a component (RIG:COMPONENT) or a rig for a rig (RIG:), not one of each");
  std::vector<std::pair<NodeId, NodeId>> pairs;
  if (from == rig::kMetaComponentType) {
    if (Status s = same_type(g, o.from, o.to); !s) return s;
    pairs.emplace_back(o.from, o.to);
  } else {
    pairs.emplace_back(o.from, o.to);  // the rigs' own nodes
    for (NodeId c : rig::rig_components(g, o.from)) {
      const NodeId t = counterpart(g, c, o.to);
      if (!t.is_valid()) {
        if (!has_keys(g, c)) continue;
        return bad("to", "rig '" + name_of(g, o.to) + "' has no component matching " + name_of(g, c) + " (rigId " +
                             rig::meta_string(g, c, "rigId") + ", or name and side)");
      }
      if (Status s = same_type(g, c, t); !s) return s;
      pairs.emplace_back(c, t);
    }
  }
  for (const auto& [a, b] : pairs) {
    const std::size_t before = jobs.size();
    if (Status s = plan_component(g, a, b, jobs, report.set); !s) return s;
    if (jobs.size() > before) report.components.emplace_back(a, b);
  }
  return Status::ok();
}

}  // namespace

Result<TransferReport> transfer_keys(graph::Graph& g, const TransferOptions& o) {
  if (o.first.has_value() != o.last.has_value()) return bad("frames", "give both ends of the range, or neither");
  if (o.first && (!std::isfinite(*o.first) || !std::isfinite(*o.last) || *o.first > *o.last))
    return bad("frames", "frames must be finite, first <= last");
  if (!std::isfinite(o.offset)) return bad("offset", "the offset must be a finite number of frames");
  TransferReport report;
  std::vector<Job> jobs;
  if (Status s = plan(g, o, jobs, report); !s) return s;
  const double fps = g.fps();
  ops::anim::KeyCopy copy;
  copy.offset = o.offset / fps;
  if (o.first) {
    copy.first = *o.first / fps;
    copy.last = *o.last / fps;
  } else {
    // Every key: the span of all the channels transferred, so that every
    // channel's destination range is the same.
    copy.first = std::numeric_limits<double>::infinity();
    copy.last = -copy.first;
    for (const Job& j : jobs) {
      const std::vector<double> times = ops::anim::curve_key_times(g, j.curve);
      if (times.empty()) continue;
      copy.first = std::min(copy.first, times.front());
      copy.last = std::max(copy.last, times.back());
    }
    if (copy.first > copy.last) copy.first = copy.last = 0;
  }
  graph::Transaction tx(g, "transfer keys");
  std::vector<NodeId> set;
  for (const Job& j : jobs) {
    std::size_t copied = 0;
    if (Status s = ops::anim::copy_curve_keys(g, j.curve, copy, j.target, &copied); !s) {
      tx.rollback();
      return Status(s).with_field("to");
    }
    if (copied == 0) continue;
    ++report.channels;
    report.keys += copied;
    if (std::find(set.begin(), set.end(), j.target.node) == set.end()) set.push_back(j.target.node);
  }
  report.set = std::move(set);
  if (report.channels > 0) {
    report.first = copy.first * fps;
    report.last = copy.last * fps;
  }
  return report;
}

}  // namespace rigel::tools
