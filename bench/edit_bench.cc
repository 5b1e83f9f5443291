// One attribute change deep in a hierarchy: set one joint's rotate, then
// bring the graph up to date, in hierarchies of growing size. The work that
// the edit implies is the edited joint and everything below it (the
// "dirtied" counter); a graph whose cost follows that, and not the graph's
// size, shows a flat time across sizes for the same edit.
//
//   edit/bushy_leaf/N     the parent of the last (deepest) joint of a 4-ary
//                         tree, at depth 4, 6 and 8 for N = 1,000, 10,000,
//                         100,000: it and its 3 leaf children are dirtied
//   edit/chain_tail/N     the joint 10 from the end of a chain (10 dirtied)
//   edit/chain_mid/10000  the middle of a 10,000 chain (5,000 dirtied)
//
// and two ways to update:
//   /pull           Graph::evaluate(leaf, worldMatrix) for every leaf below
//                   the edited joint: a pull evaluates exactly the dirty
//                   nodes upstream of what it asks for
//   /evaluate_all   Graph::evaluate_all(kSerial): visits the whole compiled
//                   schedule and updates the dirty nodes
// Both time the set_value too (it is the edit's cost: dirty propagation and
// undo record).

#include <benchmark/benchmark.h>

#include <string>

#include "bench_util.h"
#include "hierarchy_fixture.h"

namespace rigel::bench {
namespace {

enum class Update { kPull, kEvaluateAll };

void run_edit(benchmark::State& state, Shape shape, std::size_t count, std::int32_t edited, Update update) {
  std::string error;
  Hierarchy* h = hierarchy_ensure(shape, count, &error);
  if (!h) {
    state.SkipWithError(error.c_str());
    return;
  }
  graph::Graph& g = h->scene->graph();
  const std::vector<std::int32_t> dirtied = subtree(h->parents, edited);
  std::vector<graph::NodeId> leaves;
  for (std::int32_t i : subtree_leaves(h->parents, dirtied)) leaves.push_back(h->nodes[static_cast<std::size_t>(i)]);
  const graph::Plug plug{h->nodes[static_cast<std::size_t>(edited)], scene::xform::kRotate, -1};
  g.evaluate_all(graph::Execution::kSerial);  // start clean, whatever ran before
  HistoryTrim trim(state, g);
  for (auto _ : state) {
    trim.tick();
    Status s = g.set_value(plug, next_channel_value());
    if (!s) state.SkipWithError(s.message().c_str());  // ends the loop
    if (update == Update::kPull) {
      for (graph::NodeId leaf : leaves) benchmark::DoNotOptimize(&g.evaluate(leaf, scene::xform::kWorldMatrix));
    } else {
      g.evaluate_all(graph::Execution::kSerial);
    }
  }
  state.counters["dirtied"] = static_cast<double>(dirtied.size());
  state.counters["ns_per_dirtied"] = per_item(static_cast<double>(dirtied.size()));
}

void register_edit(const std::string& name, Shape shape, std::size_t count, std::int32_t edited) {
  for (Update update : {Update::kPull, Update::kEvaluateAll}) {
    const std::string full = name + "/" + std::to_string(count) + (update == Update::kPull ? "/pull" : "/evaluate_all");
    benchmark::RegisterBenchmark(full.c_str(), run_edit, shape, count, edited, update)
        ->UseRealTime()
        ->Unit(benchmark::kMicrosecond);
  }
}

bool register_edit_benchmarks() {
  for (std::size_t count : {1000u, 10000u, 100000u}) {
    const auto n = static_cast<std::int32_t>(count);
    register_edit("edit/bushy_leaf", Shape::kBushy, count, (n - 2) / kBushyFanout);
    register_edit("edit/chain_tail", Shape::kChain, count, n - 10);
    if (count == 10000u) register_edit("edit/chain_mid", Shape::kChain, count, n / 2);
  }
  return true;
}

[[maybe_unused]] const bool registered = register_edit_benchmarks();

}  // namespace
}  // namespace rigel::bench
