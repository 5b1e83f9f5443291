#pragma once
// Small helpers shared by the benchmark files.

#include <benchmark/benchmark.h>

#include <cstdint>

#include "rigel/graph/graph.h"

namespace rigel::bench {

// A counter of seconds per item, where `items` is the work of one iteration:
// Google Benchmark computes 1 / (items * iterations / seconds), with
// `seconds` the benchmark's own measure (real, manual or CPU time, as chosen
// by UseRealTime()/UseManualTime()). The console prints inverted rates with
// an SI prefix and an "s", so 7.0e-9 shows as "7.0ns"; JSON output holds the
// plain number of seconds.
inline benchmark::Counter per_item(double items) {
  return benchmark::Counter(items, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// Every Graph::set_value outside a transaction records one undo step, and
// the history has no cap. Left alone, a benchmark doing 500,000 sets grows it
// by hundreds of MB, and the time goes to page faults on fresh heap rather
// than to the edit. Clearing it every kEvery iterations, with the timer
// paused, keeps the steady state of a session with a bounded history: each
// set still pays for allocating its undo record, but from recycled memory.
class HistoryTrim {
 public:
  static constexpr std::uint32_t kEvery = 256;
  HistoryTrim(benchmark::State& state, graph::Graph& graph) : state_(state), graph_(graph) { graph_.clear_history(); }
  ~HistoryTrim() { graph_.clear_history(); }
  HistoryTrim(const HistoryTrim&) = delete;
  HistoryTrim& operator=(const HistoryTrim&) = delete;

  // Call once per iteration, outside any manually timed region.
  void tick() {
    if (++count_ % kEvery != 0) return;
    state_.PauseTiming();
    graph_.clear_history();
    state_.ResumeTiming();
  }

 private:
  benchmark::State& state_;
  graph::Graph& graph_;
  std::uint32_t count_ = 0;
};

}  // namespace rigel::bench
