// Graph: connections between plugs (with the cycle check) and the
// transform hierarchy, which is made of connections.
#include "rigel/graph/graph.h"

#include <algorithm>
#include <tuple>
#include <unordered_map>

#include "graph_internal.h"

namespace rigel::graph {
namespace {

bool types_compatible(AttrType a, AttrType b) {
  auto norm = [](AttrType t) {
    if (t.value == ValueType::kEnum) t.value = ValueType::kInt;
    return t;
  };
  return norm(a) == norm(b);
}

}  // namespace

// ---- connections -----------------------------------------------------------

Status Graph::check_connection(const Plug& src, const Plug& dst) const {
  const Node* s = node(src.node);
  const Node* d = node(dst.node);
  if (!s || !d) return error(ErrorCode::kNotFound, "connect: no such node (stale handle)");
  if (src.attr >= s->type_->attr_count() || dst.attr >= d->type_->attr_count())
    return error(ErrorCode::kNotFound, "connect: no such attribute");
  for (const Plug* p : {&src, &dst}) {
    const Node* n = node(p->node);
    if (p->element >= 0 && !n->type_->attr(p->attr).type.array)
      return error(ErrorCode::kInvalidArgument, plug_name(*p) + ": not an array");
    if (p->element >= kMaxElement) return error(ErrorCode::kInvalidArgument, plug_name(*p) + ": index too large");
    if (p->component >= 3 || (p->component >= 0 && (p->element >= 0 || n->type_->attr(p->attr).type != AttrType{ValueType::kDouble3, false})))
      return error(ErrorCode::kInvalidArgument, plug_name(*p) + ": components exist only on double3 attributes");
  }
  const std::string what = "cannot connect " + plug_name(src) + " -> " + plug_name(dst);
  if (!(d->type_->attr(dst.attr).flags & kInput))
    return error(ErrorCode::kInvalidArgument, what + ": the destination is an output");
  AttrType st = plug_type(src), dt = plug_type(dst);
  if (!types_compatible(st, dt))
    return error(ErrorCode::kInvalidArgument, what + ": types differ (" + type_name(st) + " -> " + type_name(dt) + ")");
  for (const Connection& c : d->inputs_) {
    if (overlaps(c.dst, dst))
      return error(ErrorCode::kAlreadyExists, what + ": " + plug_name(c.dst) + " is already connected from " + plug_name(c.src));
  }
  // Cycle: is the source node downstream of the destination node?
  if (src.node == dst.node) return error(ErrorCode::kCycle, what + ": it would create a cycle: " + s->name_ + " -> " + s->name_);
  std::unordered_map<std::uint32_t, std::uint32_t> came_from;  // node index -> predecessor index
  std::vector<std::uint32_t> frontier{dst.node.index};
  came_from.emplace(dst.node.index, dst.node.index);
  bool found = false;
  while (!frontier.empty() && !found) {
    std::uint32_t i = frontier.back();
    frontier.pop_back();
    for (const Connection& c : slots_[i]->outputs_) {
      std::uint32_t j = c.dst.node.index;
      if (!came_from.emplace(j, i).second) continue;
      if (j == src.node.index) {
        found = true;
        break;
      }
      frontier.push_back(j);
    }
  }
  if (found) {
    std::vector<std::string> path;
    for (std::uint32_t i = src.node.index;; i = came_from[i]) {
      path.push_back(slots_[i]->name_);
      if (i == dst.node.index) break;
    }
    std::reverse(path.begin(), path.end());
    std::string cycle;
    for (const std::string& name : path) cycle += name + " -> ";
    cycle += d->name_;
    return error(ErrorCode::kCycle, what + ": it would create a cycle: " + cycle);
  }
  return Status::ok();
}

Status Graph::connect(const Plug& src, const Plug& dst) {
  if (Status s = check_connection(src, dst); !s) return s;
  Edit edit;
  edit.kind = Edit::Kind::kConnect;
  edit.src = PlugRef{node(src.node)->uuid_, src.attr, src.element, src.component};
  edit.dst = PlugRef{node(dst.node)->uuid_, dst.attr, dst.element, dst.component};
  edit.before = node(dst.node)->values_[dst.attr];
  if (Status s = connect_impl(src, dst); !s) return s;
  record(std::move(edit));
  notify([&](Observer& o) { o.connection_made(*this, Connection{src, dst}); });
  return Status::ok();
}

Status Graph::connect_impl(const Plug& src, const Plug& dst) {
  Node& s = *node_mut(src.node);
  Node& d = *node_mut(dst.node);
  s.outputs_.push_back(Connection{src, dst});
  d.inputs_.push_back(Connection{src, dst});
  topology_changed();
  if (!d.dirty_[dst.attr]) {
    d.dirty_[dst.attr] = 1;
    queue(d);
    dirty_downstream(dst.node, dst.attr);
  }
  return Status::ok();
}

Status Graph::disconnect(const Plug& src, const Plug& dst) {
  const Node* d = node(dst.node);
  if (!d || !node(src.node)) return error(ErrorCode::kNotFound, "disconnect: no such node (stale handle)");
  auto it = std::find_if(d->inputs_.begin(), d->inputs_.end(),
                         [&](const Connection& c) { return c.src == src && c.dst == dst; });
  if (it == d->inputs_.end())
    return error(ErrorCode::kNotFound, plug_name(src) + " is not connected to " + plug_name(dst));
  // The destination keeps the value it last received, as in Maya; pull it
  // first so that value does not depend on when evaluation last ran.
  evaluate(dst.node, dst.attr);
  Edit edit;
  edit.kind = Edit::Kind::kDisconnect;
  edit.src = PlugRef{node(src.node)->uuid_, src.attr, src.element, src.component};
  edit.dst = PlugRef{d->uuid_, dst.attr, dst.element, dst.component};
  disconnect_impl(src, dst);
  edit.after = node(dst.node)->values_[dst.attr];
  record(std::move(edit));
  notify([&](Observer& o) { o.connection_broken(*this, Connection{src, dst}); });
  return Status::ok();
}

void Graph::disconnect_impl(const Plug& src, const Plug& dst) {
  Node& s = *node_mut(src.node);
  Node& d = *node_mut(dst.node);
  auto same = [&](const Connection& c) { return c.src == src && c.dst == dst; };
  s.outputs_.erase(std::find_if(s.outputs_.begin(), s.outputs_.end(), same));
  d.inputs_.erase(std::find_if(d.inputs_.begin(), d.inputs_.end(), same));
  d.dirty_[dst.attr] = 0;
  dirty_downstream(dst.node, dst.attr);
  topology_changed();
}

Status Graph::disconnect_input(const Plug& dst) {
  std::optional<Plug> src = source(dst);
  if (!src) return Status::ok();
  return disconnect(*src, dst);
}

std::optional<Plug> Graph::source(const Plug& dst) const {
  const Node* d = node(dst.node);
  if (!d) return std::nullopt;
  for (const Connection& c : d->inputs_) {
    if (c.dst == dst) return c.src;
  }
  return std::nullopt;
}

std::vector<Connection> Graph::connections() const {
  std::vector<Connection> all;
  for (const auto& slot : slots_) {
    if (slot) all.insert(all.end(), slot->inputs_.begin(), slot->inputs_.end());
  }
  auto key = [&](const Connection& c) {
    return std::make_tuple(node(c.dst.node)->order_, c.dst.attr, c.dst.element, c.dst.component);
  };
  std::sort(all.begin(), all.end(), [&](const Connection& a, const Connection& b) { return key(a) < key(b); });
  return all;
}

// ---- hierarchy -------------------------------------------------------------

NodeId Graph::parent(NodeId child) const {
  const Node* n = node(child);
  if (!n || n->type_->parent_input() == kNoAttr) return NodeId{};
  for (const Connection& c : n->inputs_) {
    if (c.dst.attr == n->type_->parent_input() && c.src.attr == node(c.src.node)->type_->world_output())
      return c.src.node;
  }
  return NodeId{};
}

std::vector<NodeId> Graph::children(NodeId parent_id) const {
  std::vector<NodeId> result;
  const Node* n = node(parent_id);
  if (!n || n->type_->world_output() == kNoAttr) return result;
  for (const Connection& c : n->outputs_) {
    const Node* d = node(c.dst.node);
    if (c.src.attr == n->type_->world_output() && c.dst.attr == d->type_->parent_input()) result.push_back(c.dst.node);
  }
  std::sort(result.begin(), result.end(), [&](NodeId a, NodeId b) { return node(a)->order_ < node(b)->order_; });
  return result;
}

Status Graph::set_parent(NodeId child, NodeId new_parent) {
  const Node* c = node(child);
  if (!c) return error(ErrorCode::kNotFound, "parent: no such child node (stale handle)");
  if (c->type_->parent_input() == kNoAttr)
    return error(ErrorCode::kInvalidArgument, "'" + c->name_ + "' (" + c->type_->name() + ") cannot have a parent");
  const Node* p = nullptr;
  if (new_parent.is_valid()) {
    p = node(new_parent);
    if (!p) return error(ErrorCode::kNotFound, "parent: no such parent node (stale handle)");
    if (p->type_->world_output() == kNoAttr)
      return error(ErrorCode::kInvalidArgument, "'" + p->name_ + "' (" + p->type_->name() + ") cannot be a parent");
  }
  Plug dst{child, c->type_->parent_input(), -1};
  std::optional<Plug> current = source(dst);
  if (p && current && *current == Plug{new_parent, p->type_->world_output(), -1}) return Status::ok();
  if (!p && !current) return Status::ok();
  Transaction transaction(*this, p ? "parent " + c->name_ + " under " + p->name_ : "unparent " + c->name_);
  if (current) {
    if (Status s = disconnect(*current, dst); !s) return s;
    if (Status s = set_value(dst, Mat4(Mat4::Identity())); !s) return s;
  }
  if (p) {
    if (Status s = connect(Plug{new_parent, p->type_->world_output(), -1}, dst); !s) {
      transaction.rollback();
      return s;
    }
  }
  return Status::ok();
}

}  // namespace rigel::graph
