// Graph: the undo record, transactions (nested, merged by gesture, rolled
// back) and undo/redo.
#include "rigel/graph/graph.h"

#include <algorithm>
#include <atomic>

#include "graph_internal.h"

namespace rigel::graph {

// ---- undo ------------------------------------------------------------------

void Graph::record(Edit edit) {
  if (replaying_) return;
  redo_stack_.clear();
  if (open_.empty()) {
    auto step = std::make_unique<Step>();
    switch (edit.kind) {
      case Edit::Kind::kCreate: step->label = "create " + edit.x().snapshot.name; break;
      case Edit::Kind::kDelete: step->label = "delete " + edit.x().snapshot.name; break;
      case Edit::Kind::kConnect: step->label = "connect"; break;
      case Edit::Kind::kDisconnect: step->label = "disconnect"; break;
      case Edit::Kind::kSet: step->label = "set"; break;
      case Edit::Kind::kRename: step->label = "rename " + *edit.x().text_before + " to " + *edit.x().text_after; break;
      case Edit::Kind::kTag: step->label = "tag " + edit.x().key; break;
    }
    step->edits.push_back(std::move(edit));
    push_undo(std::move(step));
    return;
  }
  pending_->edits.push_back(std::move(edit));
}

void Graph::apply(const Edit& e, bool forward) {
  auto id_of = [&](const Uuid& u) { return find(u); };
  auto plug_of = [&](const PlugRef& r) { return Plug{id_of(r.node), r.attr, r.element, r.component}; };
  auto restore = [&](const NodeSnapshot& s) {
    Result<NodeId> id = create_node_impl(*s.type, s.name, s.uuid, s.order);
    assert(id.is_ok());
    Node& n = *node_mut(*id);
    n.values_ = s.values;
    for (std::uint64_t& v : n.versions_) v = ++n.clock_;
    for (AttrIndex o : n.type_->outputs()) n.dirty_[o] = 1;
    n.tags_ = s.tags;
    notify([&](Observer& o) { o.node_added(*this, *id); });
  };
  auto remove = [&](const Uuid& u) {
    NodeId id = id_of(u);
    // As delete_node(): the selection drops the node (and says so) before
    // node_removed.
    if (std::erase(selection_, id) != 0) notify([&](Observer& o) { o.selection_changed(*this); });
    notify([&](Observer& o) { o.node_removed(*this, id); });
    (void)delete_node_impl(id);
  };
  auto set_whole = [&](const PlugRef& r, const Value& v) {
    Plug p = plug_of(r);
    Node& n = *node_mut(p.node);
    n.values_[p.attr] = v;
    n.versions_[p.attr] = ++n.clock_;
    // `v` was recorded when the edit was made, when elements of this array
    // fed by other connections may have been stale (dirty, not yet pulled).
    // Mark the attribute dirty so that those elements are pulled again
    // rather than served stale from the restored copy.
    if (std::any_of(n.inputs_.begin(), n.inputs_.end(), [&](const Connection& c) { return c.dst.attr == p.attr; })) {
      n.dirty_[p.attr] = 1;
      queue(n);
    }
    dirty_downstream(p.node, p.attr);
    notify([&](Observer& o) { o.attribute_changed(*this, Plug{p.node, p.attr, -1}); });
  };
  auto link = [&](bool make) {
    Plug src = plug_of(e.src), dst = plug_of(e.dst);
    if (make) {
      (void)connect_impl(src, dst);
      notify([&](Observer& o) { o.connection_made(*this, Connection{src, dst}); });
    } else {
      disconnect_impl(src, dst);
      notify([&](Observer& o) { o.connection_broken(*this, Connection{src, dst}); });
    }
  };
  switch (e.kind) {
    case Edit::Kind::kCreate:
      forward ? restore(e.x().snapshot) : remove(e.x().snapshot.uuid);
      break;
    case Edit::Kind::kDelete:
      forward ? remove(e.x().snapshot.uuid) : restore(e.x().snapshot);
      break;
    case Edit::Kind::kConnect:
      if (forward) {
        link(true);
      } else {
        link(false);
        set_whole(PlugRef{e.dst.node, e.dst.attr, -1}, e.before);
      }
      break;
    case Edit::Kind::kDisconnect:
      if (forward) {
        link(false);
        set_whole(PlugRef{e.dst.node, e.dst.attr, -1}, e.after);
      } else {
        link(true);
      }
      break;
    case Edit::Kind::kSet:
      set_whole(e.dst, forward ? e.after : e.before);
      break;
    case Edit::Kind::kRename: {
      NodeId id = id_of(e.dst.node);
      Node& n = *node_mut(id);
      std::string old = n.name_;
      by_name_.erase(old);
      n.name_ = forward ? *e.x().text_after : *e.x().text_before;
      by_name_.emplace(n.name_, id);
      notify([&](Observer& o) { o.node_renamed(*this, id, old); });
      break;
    }
    case Edit::Kind::kTag: {
      NodeId id = id_of(e.dst.node);
      Node& n = *node_mut(id);
      const std::optional<std::string>& v = forward ? e.x().text_after : e.x().text_before;
      if (v) n.tags_[e.x().key] = *v;
      else n.tags_.erase(e.x().key);
      notify([&](Observer& o) { o.tag_changed(*this, id, e.x().key); });
      break;
    }
  }
}

std::uint64_t Graph::new_merge_key() {
  static std::atomic<std::uint64_t> next{1};
  return next.fetch_add(1, std::memory_order_relaxed);
}

void Graph::begin_transaction(std::string label, std::uint64_t merge_key) {
  if (open_.empty()) {
    pending_ = spare_ ? std::move(spare_) : std::make_unique<Step>();
    // Interactive edits repeat: size the step like the last one.
    pending_->edits.reserve(std::min<std::size_t>(last_step_edits_, 1 << 16));
    pending_->label = std::move(label);
    pending_->merge_key = merge_key;
  }
  open_.push_back(pending_->edits.size());
}

void Graph::commit_transaction() {
  assert(!open_.empty() && "commit_transaction without begin_transaction");
  if (open_.empty()) return;
  open_.pop_back();
  if (!open_.empty()) return;
  std::unique_ptr<Step> step = std::move(pending_);
  if (step->edits.empty()) return;
  last_step_edits_ = step->edits.size();
  Step* top = undo_stack_.empty() ? nullptr : undo_stack_.back().get();
  // A step with other edits (a key that created a curve) may be merged
  // into, but is never merged itself.
  if (step->merge_key == 0 || !top || top->merge_key != step->merge_key || !step->only_sets()) {
    push_undo(std::move(step));
    return;
  }
  // Same gesture: fold into the step on top.
  if (!top->indexed) {
    std::size_t first = top->edits.size();
    while (first > 0 && top->edits[first - 1].kind == Edit::Kind::kSet) --first;
    for (std::size_t i = first; i < top->edits.size(); ++i)
      top->set_at[Step::PlugKey{top->edits[i].dst.node, top->edits[i].dst.attr}] = i;
    top->indexed = true;
  }
  for (Edit& e : step->edits) {
    auto [it, added] = top->set_at.try_emplace(Step::PlugKey{e.dst.node, e.dst.attr}, top->edits.size());
    if (added) top->edits.push_back(std::move(e));
    else top->edits[it->second].after = std::move(e.after);
  }
  step->edits.clear();
  step->set_at.clear();
  step->indexed = false;
  spare_ = std::move(step);
}

void Graph::rollback_transaction() {
  assert(!open_.empty() && "rollback_transaction without begin_transaction");
  if (open_.empty()) return;
  std::size_t first = open_.back();
  replaying_ = true;
  for (std::size_t i = pending_->edits.size(); i > first; --i) apply(pending_->edits[i - 1], false);
  replaying_ = false;
  pending_->edits.resize(first);
  commit_transaction();
}

std::string Graph::undo_label() const { return undo_stack_.empty() ? "" : undo_stack_.back()->label; }
std::string Graph::redo_label() const { return redo_stack_.empty() ? "" : redo_stack_.back()->label; }

bool Graph::undo() {
  if (undo_stack_.empty() || !open_.empty()) return false;
  std::unique_ptr<Step> step = std::move(undo_stack_.back());
  undo_stack_.pop_back();
  replaying_ = true;
  for (auto it = step->edits.rbegin(); it != step->edits.rend(); ++it) apply(*it, false);
  replaying_ = false;
  redo_stack_.push_back(std::move(step));
  return true;
}

bool Graph::redo() {
  if (redo_stack_.empty() || !open_.empty()) return false;
  std::unique_ptr<Step> step = std::move(redo_stack_.back());
  redo_stack_.pop_back();
  replaying_ = true;
  for (const Edit& e : step->edits) apply(e, true);
  replaying_ = false;
  undo_stack_.push_back(std::move(step));
  return true;
}

void Graph::push_undo(std::unique_ptr<Step> step) {
  undo_stack_.push_back(std::move(step));
  if (undo_stack_.size() > undo_limit_) {
    // Drop the oldest quarter at once so trimming is amortised O(1).
    std::size_t drop = std::max<std::size_t>(1, undo_stack_.size() - undo_limit_ * 3 / 4);
    undo_stack_.erase(undo_stack_.begin(), undo_stack_.begin() + static_cast<std::ptrdiff_t>(drop));
  }
}

void Graph::set_undo_limit(std::size_t steps) {
  undo_limit_ = std::max<std::size_t>(1, steps);
  if (undo_stack_.size() > undo_limit_)
    undo_stack_.erase(undo_stack_.begin(), undo_stack_.end() - static_cast<std::ptrdiff_t>(undo_limit_));
}

void Graph::clear_history() {
  undo_stack_.clear();
  redo_stack_.clear();
}

}  // namespace rigel::graph
