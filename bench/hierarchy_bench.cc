// Whole-hierarchy evaluation through the dependency graph: every iteration
// sets the root joint's translate (which dirties every node below it) and
// evaluates the graph with Graph::evaluate_all, serially and in parallel.
//
// Three measures per (shape, size, execution):
//   hierarchy/set+evaluate_all  the edit and the evaluation, timed together
//   hierarchy/evaluate_all      only evaluate_all (the set runs untimed;
//                               manual timing, so no PauseTiming overhead)
//   hierarchy/set               only the set (dirty propagation + undo
//                               record); the evaluation that cleans the graph
//                               again runs untimed; .../compiled in the
//                               compiled evaluation, whose program lets the
//                               walk prefetch nodes in schedule order
// The ns_per_node counter divides by the number of nodes. set+evaluate_all
// also runs with the compiled evaluation (".../compiled").

#include <benchmark/benchmark.h>

#include <chrono>
#include <string>

#include "bench_util.h"
#include "hierarchy_fixture.h"

namespace rigel::bench {
namespace {

using Clock = std::chrono::steady_clock;

enum class Measure { kSetAndEvaluate, kEvaluate, kSet };

graph::Plug root_translate(const Hierarchy& h) { return graph::Plug{h.nodes.front(), scene::xform::kTranslate, -1}; }

void run_hierarchy(benchmark::State& state, Shape shape, std::size_t count, graph::Execution execution,
                   Measure measure, graph::Evaluation evaluation) {
  std::string error;
  Hierarchy* h = hierarchy_ensure(shape, count, &error);
  if (!h) {
    state.SkipWithError(error.c_str());
    return;
  }
  graph::Graph& g = h->scene->graph();
  g.set_evaluation(evaluation);  // the scene is shared between benchmarks: each sets its own
  const graph::Plug plug = root_translate(*h);
  HistoryTrim trim(state, g);
  for (auto _ : state) {
    trim.tick();
    switch (measure) {
      case Measure::kSetAndEvaluate: {
        Status s = g.set_value(plug, next_channel_value());
        if (!s) state.SkipWithError(s.message().c_str());  // ends the loop
        g.evaluate_all(execution);
        break;
      }
      case Measure::kEvaluate: {
        Status s = g.set_value(plug, next_channel_value());
        if (!s) state.SkipWithError(s.message().c_str());  // ends the loop
        const auto t0 = Clock::now();
        g.evaluate_all(execution);
        state.SetIterationTime(std::chrono::duration<double>(Clock::now() - t0).count());
        break;
      }
      case Measure::kSet: {
        const auto t0 = Clock::now();
        Status s = g.set_value(plug, next_channel_value());
        if (!s) state.SkipWithError(s.message().c_str());  // ends the loop
        state.SetIterationTime(std::chrono::duration<double>(Clock::now() - t0).count());
        g.evaluate_all(graph::Execution::kSerial);
        break;
      }
    }
  }
  state.counters["ns_per_node"] = per_item(static_cast<double>(count));
  state.counters["levels"] = static_cast<double>(g.schedule_level_count());
}

bool register_hierarchy_benchmarks() {
  // Registered size-major so that each cached scene serves all its
  // benchmarks before the next one is built.
  for (std::size_t count : {100u, 1000u, 10000u, 100000u}) {
    for (Shape shape : {Shape::kChain, Shape::kBushy}) {
      const std::string suffix = std::string("/") + shape_name(shape) + "/" + std::to_string(count);
      for (graph::Execution execution : {graph::Execution::kSerial, graph::Execution::kParallel}) {
        const std::string exec = execution == graph::Execution::kSerial ? "/serial" : "/parallel";
        benchmark::RegisterBenchmark(("hierarchy/set+evaluate_all" + suffix + exec).c_str(), run_hierarchy, shape,
                                     count, execution, Measure::kSetAndEvaluate, graph::Evaluation::kInterpreted)
            ->UseRealTime()
            ->Unit(benchmark::kMicrosecond);
        benchmark::RegisterBenchmark(("hierarchy/set+evaluate_all" + suffix + exec + "/compiled").c_str(), run_hierarchy,
                                     shape, count, execution, Measure::kSetAndEvaluate, graph::Evaluation::kCompiled)
            ->UseRealTime()
            ->Unit(benchmark::kMicrosecond);
        benchmark::RegisterBenchmark(("hierarchy/evaluate_all" + suffix + exec).c_str(), run_hierarchy, shape, count,
                                     execution, Measure::kEvaluate, graph::Evaluation::kInterpreted)
            ->UseManualTime()
            ->Unit(benchmark::kMicrosecond);
      }
      benchmark::RegisterBenchmark(("hierarchy/set" + suffix).c_str(), run_hierarchy, shape, count,
                                   graph::Execution::kSerial, Measure::kSet, graph::Evaluation::kInterpreted)
          ->UseManualTime()
          ->Unit(benchmark::kMicrosecond);
      benchmark::RegisterBenchmark(("hierarchy/set" + suffix + "/compiled").c_str(), run_hierarchy, shape, count,
                                   graph::Execution::kSerial, Measure::kSet, graph::Evaluation::kCompiled)
          ->UseManualTime()
          ->Unit(benchmark::kMicrosecond);
    }
  }
  return true;
}

[[maybe_unused]] const bool registered = register_hierarchy_benchmarks();

}  // namespace
}  // namespace rigel::bench
