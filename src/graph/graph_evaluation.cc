// Graph: dirty propagation and evaluation, by pull (one plug and what it
// reads) and by the compiled, levelled schedule (everything dirty).
#include "rigel/graph/graph.h"

#include <algorithm>
#include <span>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "graph_internal.h"

namespace rigel::graph {
namespace {

// Levels (and whole evaluations) smaller than this run serially: spawning
// tasks costs more.
constexpr std::size_t kParallelMinLevel = 256;
constexpr std::size_t kParallelGrain = 32;
// How many steps (or time marks) ahead the compiled evaluation prefetches a
// node's storage.
constexpr std::size_t kPrefetchAhead = 8;

}  // namespace

// ---- dirty propagation and evaluation ----------------------------------------

void Graph::dirty_downstream(NodeId start, AttrIndex attr) {
  // Worklist rather than recursion: a 100,000-joint chain must not overflow
  // the stack. A plug already dirty stops the walk: everything downstream of
  // a dirty plug is dirty (evaluation cleans upstream first), so the cost is
  // proportional to what becomes dirty, not to the graph.
  // The worklist is kept between calls: interactive edits dirty a few
  // plugs each, thousands of times a second. It holds connected plugs only
  // (the outputs an input affects are marked with it, so a node is visited
  // once per input reached) and is a queue (breadth first): the order plugs
  // are marked in does not change what ends up dirty, and breadth first
  // visits nodes about in schedule order (by level), so with the compiled
  // program current the nodes a few schedule positions ahead are
  // prefetched: on a large graph each node is a handful of cache misses
  // (its object, flags and connections), which otherwise come one after
  // another.
  std::vector<std::pair<Node*, AttrIndex>>& work = dirty_work_;
  work.clear();
  const auto push_connections = [&](Node& n, AttrIndex a) {
    for (const Connection& c : n.outputs_) {
      if (c.src.attr == a) work.emplace_back(slots_[c.dst.node.index].get(), c.dst.attr);
    }
  };
  // Marks what plug (n, a) affects, and queues what its plugs feed.
  const auto push_downstream = [&](Node& n, AttrIndex a) {
    for (AttrIndex o : n.type_->affected_outputs(a)) {
      if (n.dirty_[o]) continue;
      n.dirty_[o] = 1;
      queue(n);
      push_connections(n, o);
    }
    push_connections(n, a);
  };
  const Program* p =
      evaluation_ == Evaluation::kCompiled && program_ && program_->generation == topology_generation_ ? program_.get()
                                                                                                        : nullptr;
  std::size_t prefetched = 0;  // schedule positions below this are prefetched
  const auto prefetch_after = [&](const Node& n) {
    const std::size_t k = schedule_->position[n.id_.index];
    const std::size_t last = std::min(k + kPrefetchAhead, p->steps.size() - 1);
    for (prefetched = std::max(prefetched, k + 1); prefetched <= last; ++prefetched) p->prefetch_flags(prefetched);
  };
  push_downstream(*node_mut(start), attr);
  for (std::size_t head = 0; head < work.size(); ++head) {
    auto [n, a] = work[head];
    if (n->dirty_[a]) continue;
    n->dirty_[a] = 1;
    queue(*n);
    if (p) prefetch_after(*n);
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
  if (evaluation_ == Evaluation::kCompiled) {
    // The same plugs marked in schedule order (the order the evaluation
    // then runs them), prefetching ahead: the closure's own order is a
    // graph walk's, and on a large graph its marks are cache misses.
    program();
    Program& p = *program_;
    if (!p.time_marks_made) {
      const Schedule& s = *schedule_;
      std::vector<std::pair<std::uint32_t, std::uint32_t>> by_position;  // position, index in the closure
      by_position.reserve(time_closure_.size());
      for (std::size_t i = 0; i < time_closure_.size(); ++i)
        by_position.emplace_back(s.position[time_closure_[i].first->id_.index], static_cast<std::uint32_t>(i));
      std::sort(by_position.begin(), by_position.end());
      p.time_marks.clear();
      p.time_marks.reserve(by_position.size());
      for (const auto& entry : by_position) {
        const auto [n, a] = time_closure_[entry.second];
        p.time_marks.push_back(Program::TimeMark{n, n->dirty_.data(), a});
      }
      p.time_marks_made = true;
    }
    const std::size_t count = p.time_marks.size();
    for (std::size_t i = 0; i < count; ++i) {
      if (i + kPrefetchAhead < count) {
        __builtin_prefetch(p.time_marks[i + kPrefetchAhead].node);
        __builtin_prefetch(p.time_marks[i + kPrefetchAhead].dirty);
      }
      const Program::TimeMark& m = p.time_marks[i];
      if (m.dirty[m.attr]) continue;
      m.dirty[m.attr] = 1;
      queue(*m.node);
    }
    return;
  }
  for (auto [n, a] : time_closure_) {
    if (n->dirty_[a]) continue;
    n->dirty_[a] = 1;
    queue(*n);
  }
}

void Graph::update_node(Node& n) {
  // Refresh connected inputs that are dirty, then compute if an output is.
  // The schedule's flattened inputs when it is current; else the node's
  // connections resolved here (a pull after a topology edit).
  std::span<const ScheduledInput> inputs;
  thread_local std::vector<ScheduledInput> resolved;
  if (schedule_ && schedule_->generation == topology_generation_) {
    const auto [first, last] = schedule_->input_range[n.id_.index];
    inputs = std::span<const ScheduledInput>(schedule_->inputs).subspan(first, last - first);
  } else {
    resolved.clear();
    for (const Connection& c : n.inputs_) resolved.push_back(resolve_input(n, *slots_[c.src.node.index], c));
    inputs = resolved;
  }
  // Two passes: several connections may write parts of one attribute, so
  // dirty flags are cleared (and enums clamped) after every refresh.
  for (const ScheduledInput& in : inputs) {
    if (!n.dirty_[in.dst_attr]) continue;
    n.versions_[in.dst_attr] = ++n.clock_;
    if (in.whole) n.values_[in.dst_attr] = in.src->values_[in.src_attr];
    else write_part(n.values_[in.dst_attr], n.type_->attr(in.dst_attr).type, in.connection->dst, plug_value(in.connection->src));
  }
  for (const ScheduledInput& in : inputs) {
    if (!n.dirty_[in.dst_attr]) continue;
    n.dirty_[in.dst_attr] = 0;
    if (in.enum_dst) clamp_enum(n.values_[in.dst_attr], n.type_->attr(in.dst_attr));
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
  // Compiled: on the program when it is current. A pull never makes it: a
  // script that creates a node and reads a matrix, a thousand times, would
  // rebuild the schedule and the program (O(graph)) each time, and inside
  // a transaction (a delete breaking its connections, a build step
  // connecting a rig) on every connection edit. It takes the interpreted
  // refresh (the same values) until evaluate_all() makes the program.
  if (evaluation_ == Evaluation::kCompiled && program_ && program_->generation == topology_generation_) {
    const Program& p = program();
    for (Node* n : order) run_step(p, schedule_->position[n->id_.index]);
    return;
  }
  for (Node* n : order) update_node(*n);
}

const Graph::Schedule& Graph::schedule() {
  if (!schedule_) schedule_ = std::make_unique<Schedule>();
  Schedule& s = *schedule_;
  if (s.generation == topology_generation_) return s;
  // Rebuilt on every topology edit (a constraint added is one), so it is
  // linear and sort-free: nodes in slot order (dense indices), Kahn's
  // algorithm by levels (a node's level is one more than its deepest
  // source), union-find for the components, two counting sorts.
  std::vector<Node*> all;
  all.reserve(by_uuid_.size());
  std::vector<std::uint32_t> dense(slots_.size(), 0);  // slot index -> index in all
  for (const auto& slot : slots_) {
    if (!slot) continue;
    dense[slot->id_.index] = static_cast<std::uint32_t>(all.size());
    all.push_back(slot.get());
  }
  const std::size_t count = all.size();
  std::vector<std::uint32_t> pending(count, 0);
  std::vector<std::uint32_t> level(count, 0);
  std::vector<std::uint32_t> ready;
  ready.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    pending[i] = static_cast<std::uint32_t>(all[i]->inputs_.size());
    if (pending[i] == 0) ready.push_back(static_cast<std::uint32_t>(i));
  }
  std::vector<std::uint32_t> root(count);
  for (std::size_t i = 0; i < count; ++i) root[i] = static_cast<std::uint32_t>(i);
  const auto find = [&](std::uint32_t i) {
    while (root[i] != i) i = root[i] = root[root[i]];
    return i;
  };
  std::uint32_t max_level = 0;
  for (std::size_t head = 0; head < ready.size(); ++head) {
    const std::uint32_t i = ready[head];
    max_level = std::max(max_level, level[i]);
    for (const Connection& c : all[i]->outputs_) {
      const std::uint32_t j = dense[c.dst.node.index];
      level[j] = std::max(level[j], level[i] + 1);
      if (--pending[j] == 0) ready.push_back(j);
      const std::uint32_t ri = find(i), rj = find(j);
      if (ri != rj) root[std::max(ri, rj)] = std::min(ri, rj);
    }
  }
  // Components numbered by their first node.
  std::vector<std::uint32_t> component(count, 0);
  std::vector<std::uint32_t> number(count, ~std::uint32_t{0});
  std::uint32_t components = 0;
  for (std::size_t i = 0; i < count; ++i) {
    std::uint32_t& n = number[find(static_cast<std::uint32_t>(i))];
    if (n == ~std::uint32_t{0}) n = components++;
    component[i] = n;
  }
  // Stable counting sorts: by level, then by component.
  const auto counting_sort = [count](const std::vector<std::uint32_t>& in, const std::vector<std::uint32_t>& key,
                                     std::size_t keys) {
    std::vector<std::uint32_t> begin(keys + 1, 0);
    for (std::uint32_t i : in) ++begin[key[i] + 1];
    for (std::size_t k = 1; k <= keys; ++k) begin[k] += begin[k - 1];
    std::vector<std::uint32_t> out(count);
    for (std::uint32_t i : in) out[begin[key[i]]++] = i;
    return out;
  };
  std::vector<std::uint32_t> sorted(count);
  for (std::size_t i = 0; i < count; ++i) sorted[i] = static_cast<std::uint32_t>(i);
  sorted = counting_sort(sorted, level, count == 0 ? 0 : max_level + 1);
  sorted = counting_sort(sorted, component, components);
  s.level_count = count == 0 ? 0 : max_level + 1;
  s.order.resize(count);
  s.position.assign(slots_.size(), 0);
  s.level.resize(count);
  s.component.resize(count);
  for (std::size_t at = 0; at < count; ++at) {
    const std::uint32_t i = sorted[at];
    s.order[at] = all[i]->id_;
    s.position[all[i]->id_.index] = static_cast<std::uint32_t>(at);
    s.level[at] = level[i];
    s.component[at] = component[i];
  }
  s.inputs.clear();
  s.input_range.assign(slots_.size(), {0, 0});
  for (NodeId id : s.order) {
    const Node& n = *slots_[id.index];
    const auto first = static_cast<std::uint32_t>(s.inputs.size());
    for (const Connection& c : n.inputs_) s.inputs.push_back(resolve_input(n, *slots_[c.src.node.index], c));
    s.input_range[id.index] = {first, static_cast<std::uint32_t>(s.inputs.size())};
  }
  s.generation = topology_generation_;
  return s;
}

std::size_t Graph::schedule_level_count() { return schedule().level_count; }

void Graph::evaluate_all(Execution execution) {
  if (dirty_nodes_.empty()) return;
  const Schedule& s = schedule();
  const Program* compiled = evaluation_ == Evaluation::kCompiled ? &program() : nullptr;
  // Only queued nodes, in schedule order: an edit costs what it dirtied,
  // not the size of the graph.
  std::vector<std::uint32_t> work;
  if (compiled) {
    // Marks by schedule position, then one pass in order: no sort, and no
    // node touched before it runs (a stale id is dropped by its generation;
    // a node pulled clean since it was queued is skipped when it runs).
    std::vector<std::uint8_t>& marks = program_->marks;
    marks.assign(s.order.size(), 0);
    for (NodeId id : dirty_nodes_)
      if (node(id)) marks[s.position[id.index]] = 1;
    work.reserve(dirty_nodes_.size());
    for (std::size_t i = 0; i < marks.size(); ++i)
      if (marks[i]) work.push_back(static_cast<std::uint32_t>(i));
  } else if (dirty_nodes_.size() * 8 > s.order.size()) {
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
  const bool parallel = execution == Execution::kParallel;
  const auto run = [&](std::size_t k) {
    if (compiled) {
      if (k + kPrefetchAhead < work.size()) compiled->prefetch(work[k + kPrefetchAhead]);
      if (compiled->steps[work[k]].node->queued_) run_step(*compiled, work[k]);
      return;
    }
    Node& n = *slots_[s.order[work[k]].index];
    if (n.queued_) update_node(n);
  };
  // One component's work [begin, end), level by level: queued nodes of one
  // level never read each other, so a wide level runs in parallel.
  const auto run_component = [&](std::size_t begin, std::size_t end) {
    while (begin < end) {
      std::size_t level_end = begin + 1;
      while (level_end < end && s.level[work[level_end]] == s.level[work[begin]]) ++level_end;
      if (!parallel || level_end - begin < kParallelMinLevel) {
        for (std::size_t k = begin; k < level_end; ++k) run(k);
      } else {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, level_end, kParallelGrain),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                            for (std::size_t k = r.begin(); k != r.end(); ++k) run(k);
                          });
      }
      begin = level_end;
    }
  };
  // Where each component's work starts, plus a final end.
  std::vector<std::size_t> starts;
  for (std::size_t k = 0; k < work.size(); ++k)
    if (k == 0 || s.component[work[k]] != s.component[work[k - 1]]) starts.push_back(k);
  starts.push_back(work.size());
  const std::size_t count = starts.size() - 1;
  if (!parallel || count < 2 || work.size() < kParallelMinLevel) {
    for (std::size_t c = 0; c < count; ++c) run_component(starts[c], starts[c + 1]);
    return;
  }
  // Independent components (characters) as parallel tasks.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t c = r.begin(); c != r.end(); ++c) run_component(starts[c], starts[c + 1]);
  });
}

void Graph::topology_changed() { ++topology_generation_; }

}  // namespace rigel::graph
