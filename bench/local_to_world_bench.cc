// The compiled local-to-world kernel (math::LocalToWorldJob) against its
// target of 10 ns per joint on a 1,000-joint chain, a memory floor, a naive
// Eigen loop, and the graph-backed scene::Skeleton::evaluate.
//
//   local_to_world/{chain,bushy}/N   LocalToWorldJob::run() (validate()
//                                    included, as callers pay for it)
//   local_to_world_eigen/chain/N     the same recurrence with Eigen's general
//                                    4x4 product: what the affine kernel saves
//   copy_floor/N                     world[i] = local[i]: 128 bytes read and
//                                    128 written per joint, no arithmetic
//   skeleton_evaluate/chain_clean/1000        Skeleton::evaluate on a clean
//                                    graph: reading cached local matrices
//                                    through Graph::evaluate, then the job
//   skeleton_evaluate/chain_root_moved/1000   after the root's translate was
//                                    set: only the root's local matrix is
//                                    dirty (a parent's move does not change
//                                    its children's locals)
//   skeleton_evaluate/chain_every_rotate/1000 after every joint's rotate was
//                                    set (an animated pose): 1,000 local
//                                    matrices recomputed by the graph
// Only Skeleton::evaluate is timed (manual timing); the sets run untimed.
// ns_per_joint divides by the joint count.

#include <benchmark/benchmark.h>

#include <chrono>
#include <string>
#include <vector>

#include "bench_util.h"
#include "hierarchy_fixture.h"
#include "rigel/math/local_to_world.h"
#include "rigel/scene/skeleton.h"

namespace rigel::bench {
namespace {

// LocalToWorldJob picks an AVX2+FMA kernel at run time where the CPU has
// one; the label says which kind of CPU the figure comes from.
const char* cpu_label() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") ? "cpu: avx2+fma" : "cpu: no avx2+fma";
}

struct Joints {
  std::vector<std::int32_t> parents;
  std::vector<math::Mat4> local;
  std::vector<math::Mat4> world;
};

Joints make_joints(Shape shape, std::size_t count) {
  Joints j;
  j.parents = make_parents(shape, count);
  j.local = make_local_matrices(count);
  j.world.assign(count, math::Mat4::Zero());
  return j;
}

void local_to_world(benchmark::State& state, Shape shape) {
  const auto count = static_cast<std::size_t>(state.range(0));
  Joints j = make_joints(shape, count);
  math::LocalToWorldJob job;
  job.parents = j.parents;
  job.local = j.local;
  job.world = j.world;
  if (!job.run()) {
    state.SkipWithError("LocalToWorldJob refused a valid hierarchy");
    return;
  }
  for (auto _ : state) {
    bool ok = job.run();
    benchmark::DoNotOptimize(ok);
    benchmark::ClobberMemory();
  }
  state.counters["ns_per_joint"] = per_item(static_cast<double>(count));
  state.SetLabel(cpu_label());
}

void local_to_world_eigen(benchmark::State& state) {
  const auto count = static_cast<std::size_t>(state.range(0));
  Joints j = make_joints(Shape::kChain, count);
  for (auto _ : state) {
    for (std::size_t i = 0; i < count; ++i) {
      const std::int32_t p = j.parents[i];
      if (p == math::kNoParent) j.world[i] = j.local[i];
      else j.world[i].noalias() = j.world[static_cast<std::size_t>(p)] * j.local[i];
    }
    benchmark::DoNotOptimize(j.world.data());
    benchmark::ClobberMemory();
  }
  state.counters["ns_per_joint"] = per_item(static_cast<double>(count));
}

void copy_floor(benchmark::State& state) {
  const auto count = static_cast<std::size_t>(state.range(0));
  Joints j = make_joints(Shape::kChain, count);
  for (auto _ : state) {
    for (std::size_t i = 0; i < count; ++i) j.world[i] = j.local[i];
    benchmark::DoNotOptimize(j.world.data());
    benchmark::ClobberMemory();
  }
  state.counters["ns_per_joint"] = per_item(static_cast<double>(count));
}

enum class Change { kNone, kRootTranslate, kEveryRotate };

void skeleton_evaluate(benchmark::State& state, Change change) {
  const auto count = static_cast<std::size_t>(state.range(0));
  std::string error;
  Hierarchy* h = hierarchy_ensure(Shape::kChain, count, &error);
  if (!h) {
    state.SkipWithError(error.c_str());
    return;
  }
  Result<scene::Skeleton> skeleton = scene::Skeleton::compile(*h->scene);
  if (!skeleton) {
    state.SkipWithError(skeleton.status().message().c_str());
    return;
  }
  graph::Graph& g = h->scene->graph();
  std::vector<math::Mat4> local(count), world(count);
  HistoryTrim trim(state, g);
  for (auto _ : state) {
    trim.tick();
    switch (change) {
      case Change::kNone:
        break;
      case Change::kRootTranslate: {
        Status s = g.set_value(graph::Plug{h->nodes.front(), scene::xform::kTranslate, -1}, next_channel_value());
        if (!s) state.SkipWithError(s.message().c_str());  // ends the loop
        break;
      }
      case Change::kEveryRotate: {
        // An animated pose: every local matrix is out of date. The sets are
        // not what is measured here (see hierarchy/set), so they run untimed,
        // and their 1,000 undo steps are dropped each time.
        g.clear_history();
        const math::Vec3 rotate = next_channel_value() * 10.0;
        for (graph::NodeId id : h->nodes) {
          Status s = g.set_value(graph::Plug{id, scene::xform::kRotate, -1}, rotate);
          if (!s) state.SkipWithError(s.message().c_str());  // ends the loop
        }
        break;
      }
    }
    const auto t0 = std::chrono::steady_clock::now();
    Status s = skeleton->evaluate(*h->scene, local, world);
    if (!s) state.SkipWithError(s.message().c_str());  // ends the loop
    benchmark::ClobberMemory();
    state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  state.counters["ns_per_joint"] = per_item(static_cast<double>(count));
}

BENCHMARK_CAPTURE(local_to_world, chain, Shape::kChain)->Arg(100)->Arg(1000)->Arg(10000);
BENCHMARK_CAPTURE(local_to_world, bushy, Shape::kBushy)->Arg(1000)->Arg(10000);
BENCHMARK(local_to_world_eigen)->Name("local_to_world_eigen/chain")->Arg(1000);
BENCHMARK(copy_floor)->Arg(1000)->Arg(10000);
BENCHMARK_CAPTURE(skeleton_evaluate, chain_clean, Change::kNone)->Arg(1000)->UseManualTime()->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(skeleton_evaluate, chain_root_moved, Change::kRootTranslate)
    ->Arg(1000)
    ->UseManualTime()
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(skeleton_evaluate, chain_every_rotate, Change::kEveryRotate)
    ->Arg(1000)
    ->UseManualTime()
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace rigel::bench
