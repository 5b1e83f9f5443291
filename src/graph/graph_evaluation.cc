// Graph: dirty propagation and evaluation, by pull (one plug and what it
// reads) and by the compiled, levelled schedule (everything dirty).
#include "rigel/graph/graph.h"

#include <algorithm>
#include <deque>
#include <unordered_map>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "graph_internal.h"

namespace rigel::graph {
namespace {

// Levels smaller than this run serially: spawning tasks costs more.
constexpr std::size_t kParallelMinLevel = 64;
constexpr std::size_t kParallelGrain = 32;

}  // namespace

// ---- dirty propagation and evaluation ----------------------------------------

void Graph::dirty_downstream(NodeId start, AttrIndex attr) {
  // Worklist rather than recursion: a 100,000-joint chain must not overflow
  // the stack. A plug already dirty stops the walk: everything downstream of
  // a dirty plug is dirty (evaluation cleans upstream first), so the cost is
  // proportional to what becomes dirty, not to the graph.
  // The worklist is kept between calls: interactive edits dirty a few
  // plugs each, thousands of times a second.
  std::vector<std::pair<Node*, AttrIndex>>& work = dirty_work_;
  work.clear();
  auto push_downstream = [&](Node& n, AttrIndex a) {
    for (AttrIndex o : n.type_->affected_outputs(a)) work.emplace_back(&n, o);
    for (const Connection& c : n.outputs_) {
      if (c.src.attr == a) work.emplace_back(slots_[c.dst.node.index].get(), c.dst.attr);
    }
  };
  push_downstream(*node_mut(start), attr);
  while (!work.empty()) {
    auto [n, a] = work.back();
    work.pop_back();
    if (n->dirty_[a]) continue;
    n->dirty_[a] = 1;
    queue(*n);
    push_downstream(*n, a);
  }
}

// A time change: every output of a time-dependent node but its
// time-invariant ones, and everything downstream. The set of those plugs
// depends only on the topology, so it is listed once per topology
// generation and then marked in one pass. Marking plugs already dirty is a
// no-op, and everything downstream of a dirty plug is dirty, so the result
// is the one walking from each output would give.
void Graph::dirty_for_time() {
  if (time_closure_generation_ != topology_generation_) {
    time_closure_.clear();
    std::vector<std::vector<std::uint8_t>> seen(slots_.size());
    std::vector<std::pair<Node*, AttrIndex>>& work = dirty_work_;
    work.clear();
    for (NodeId id : time_dependent_) {
      Node& n = *node_mut(id);
      for (AttrIndex o : n.type_->outputs())
        if (!(n.type_->attr(o).flags & kTimeInvariant)) work.emplace_back(&n, o);
    }
    while (!work.empty()) {
      auto [n, a] = work.back();
      work.pop_back();
      std::vector<std::uint8_t>& marks = seen[n->id_.index];
      if (marks.empty()) marks.assign(n->type_->attr_count(), 0);
      if (marks[a]) continue;
      marks[a] = 1;
      time_closure_.emplace_back(n, a);
      for (AttrIndex o : n->type_->affected_outputs(a)) work.emplace_back(n, o);
      for (const Connection& c : n->outputs_)
        if (c.src.attr == a) work.emplace_back(slots_[c.dst.node.index].get(), c.dst.attr);
    }
    time_closure_generation_ = topology_generation_;
  }
  for (auto [n, a] : time_closure_) {
    if (n->dirty_[a]) continue;
    n->dirty_[a] = 1;
    queue(*n);
  }
}

void Graph::update_node(Node& n) {
  // Refresh connected inputs that are dirty, then compute if an output is.
  for (const Connection& c : n.inputs_) {
    if (!n.dirty_[c.dst.attr]) continue;
    const Node& src = *slots_[c.src.node.index];
    Value& dst = n.values_[c.dst.attr];
    n.versions_[c.dst.attr] = ++n.clock_;
    if (c.dst.element < 0 && c.src.element < 0 && c.dst.component < 0 && c.src.component < 0) {
      dst = src.values_[c.src.attr];
    } else {
      write_part(dst, n.type_->attr(c.dst.attr).type, c.dst, plug_value(c.src));
    }
  }
  for (const Connection& c : n.inputs_) {
    if (!n.dirty_[c.dst.attr]) continue;
    n.dirty_[c.dst.attr] = 0;
    // An int may feed an enum: keep the enum within its names, as set_value does.
    const AttrSpec& spec = n.type_->attr(c.dst.attr);
    if (spec.type.value == ValueType::kEnum) {
      const auto top = static_cast<std::int64_t>(spec.enum_names.size()) - 1;
      Value& v = n.values_[c.dst.attr];
      if (auto* one = std::get_if<std::int64_t>(&v)) *one = std::clamp<std::int64_t>(*one, 0, top);
      else if (auto* many = std::get_if<std::vector<std::int64_t>>(&v))
        for (std::int64_t& e : *many) e = std::clamp<std::int64_t>(e, 0, top);
    }
  }
  // Every attribute is clean after this: connected inputs were refreshed,
  // unconnected inputs are never dirty, and outputs are computed below.
  n.queued_ = false;
  bool compute = false;
  for (AttrIndex o : n.type_->outputs()) compute |= n.dirty_[o] != 0;
  if (!compute) return;
  ComputeContext context(n, time_);
  n.type_->compute()(context);
  for (AttrIndex o : n.type_->outputs()) n.dirty_[o] = 0;
}

void Graph::queue(Node& n) {
  if (n.queued_) return;
  n.queued_ = true;
  dirty_nodes_.push_back(n.id_);
  // Pulls clean nodes without taking them off the list; drop those entries
  // before the list outgrows the graph.
  if (dirty_nodes_.size() > 2 * by_uuid_.size() + 64) {
    std::erase_if(dirty_nodes_, [&](NodeId id) {
      const Node* m = node(id);
      return !m || !m->queued_;
    });
    // A node cleaned and dirtied again appears twice; keep the first.
    const std::uint64_t epoch = ++visit_epoch_;
    std::erase_if(dirty_nodes_, [&](NodeId id) {
      Node* m = slots_[id.index].get();
      if (m->visit_ == epoch) return true;
      m->visit_ = epoch;
      return false;
    });
  }
}

void Graph::pull(NodeId start) {
  // Post-order walk over the dirty part upstream of `start`, then update in
  // that order (sources before the nodes that read them).
  const std::uint64_t epoch = ++visit_epoch_;
  std::vector<Node*> order;
  std::vector<std::pair<Node*, std::size_t>> stack;
  Node* root = node_mut(start);
  root->visit_ = epoch;
  stack.emplace_back(root, 0);
  while (!stack.empty()) {
    auto& [n, next] = stack.back();
    if (next < n->inputs_.size()) {
      const Connection& c = n->inputs_[next++];
      if (!n->dirty_[c.dst.attr]) continue;
      Node* src = slots_[c.src.node.index].get();
      if (src->visit_ == epoch || !src->dirty_[c.src.attr]) continue;
      src->visit_ = epoch;
      stack.emplace_back(src, 0);
      continue;
    }
    order.push_back(n);
    stack.pop_back();
  }
  for (Node* n : order) update_node(*n);
}

const Graph::Schedule& Graph::schedule() {
  if (!schedule_) schedule_ = std::make_unique<Schedule>();
  Schedule& s = *schedule_;
  if (s.generation == topology_generation_) return s;
  // Kahn's algorithm by levels: a node's level is one more than its deepest
  // source, so nodes of one level never read each other and run in parallel.
  std::vector<NodeId> all = nodes();
  std::unordered_map<std::uint32_t, std::size_t> position;
  position.reserve(all.size());
  for (std::size_t i = 0; i < all.size(); ++i) position.emplace(all[i].index, i);
  std::vector<std::uint32_t> pending(all.size(), 0);
  std::vector<std::uint32_t> level(all.size(), 0);
  for (std::size_t i = 0; i < all.size(); ++i) pending[i] = static_cast<std::uint32_t>(node(all[i])->inputs_.size());
  std::deque<std::size_t> ready;
  for (std::size_t i = 0; i < all.size(); ++i)
    if (pending[i] == 0) ready.push_back(i);
  std::uint32_t max_level = 0;
  while (!ready.empty()) {
    std::size_t i = ready.front();
    ready.pop_front();
    max_level = std::max(max_level, level[i]);
    for (const Connection& c : node(all[i])->outputs_) {
      std::size_t j = position[c.dst.node.index];
      level[j] = std::max(level[j], level[i] + 1);
      if (--pending[j] == 0) ready.push_back(j);
    }
  }
  // Counting sort by level, creation order within a level.
  s.level_begin.assign(all.empty() ? 1 : max_level + 2, 0);
  for (std::size_t i = 0; i < all.size(); ++i) ++s.level_begin[level[i] + 1];
  for (std::size_t l = 1; l < s.level_begin.size(); ++l) s.level_begin[l] += s.level_begin[l - 1];
  s.order.assign(all.size(), NodeId{});
  std::vector<std::size_t> fill(s.level_begin.begin(), s.level_begin.end() - 1);
  s.position.assign(slots_.size(), 0);
  s.level.assign(all.size(), 0);
  for (std::size_t i = 0; i < all.size(); ++i) {
    std::size_t at = fill[level[i]]++;
    s.order[at] = all[i];
    s.position[all[i].index] = static_cast<std::uint32_t>(at);
    s.level[at] = level[i];
  }
  s.generation = topology_generation_;
  return s;
}

std::size_t Graph::schedule_level_count() { return schedule().level_begin.size() - 1; }

void Graph::evaluate_all(Execution execution) {
  if (dirty_nodes_.empty()) return;
  const Schedule& s = schedule();
  // Only queued nodes, in schedule order: an edit costs what it dirtied,
  // not the size of the graph.
  std::vector<std::uint32_t> work;
  if (dirty_nodes_.size() * 8 > s.order.size()) {
    for (std::size_t i = 0; i < s.order.size(); ++i) {
      if (slots_[s.order[i].index]->queued_) work.push_back(static_cast<std::uint32_t>(i));
    }
  } else {
    work.reserve(dirty_nodes_.size());
    for (NodeId id : dirty_nodes_) {
      const Node* n = node(id);
      if (n && n->queued_) work.push_back(s.position[id.index]);
    }
    std::sort(work.begin(), work.end());
    work.erase(std::unique(work.begin(), work.end()), work.end());
  }
  dirty_nodes_.clear();
  auto run = [&](std::size_t k) {
    Node& n = *slots_[s.order[work[k]].index];
    if (n.queued_) update_node(n);
  };
  // Queued nodes of one level never read each other: run a large level in parallel.
  for (std::size_t begin = 0; begin < work.size();) {
    std::size_t end = begin + 1;
    while (end < work.size() && s.level[work[end]] == s.level[work[begin]]) ++end;
    if (execution == Execution::kSerial || end - begin < kParallelMinLevel) {
      for (std::size_t k = begin; k < end; ++k) run(k);
    } else {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end, kParallelGrain),
                        [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t k = r.begin(); k != r.end(); ++k) run(k);
                        });
    }
    begin = end;
  }
}

void Graph::topology_changed() { ++topology_generation_; }

}  // namespace rigel::graph
