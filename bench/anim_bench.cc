// Animation curve sampling (src/ops/anim): SampleCurvesJob over 500
// channels in sequential playback at 30 fps (the target: at most 20 ns per
// channel per frame; ozz-animation's sampling job is about 22 ns per joint),
// random access for comparison, weighted curves, glTF rotation tracks
// (slerp), and the same curves as animCurve graph nodes.
//
// Run: rigel_bench --benchmark_min_time=0.2 --benchmark_filter='anim/'
//
// Results, 2026-11-23, Release, GCC 12.2, the 2-vCPU AMD EPYC VM of
// bench/README.md under load average 5-7 (other builds running), best of
// five runs; ns per channel (per track) per frame, CPU time (wall in
// parentheses: up to 2x higher while the machine is shared):
//   sample/sequential/500            4.7 (5.9)   target 20: 0.24x; ozz 22: 0.22x
//   sample/sequential_weighted/500  34   (34)    Newton solve of time per sample
//   sample/random/500               22   (34)    binary search over ~33 keys
//   quat_slerp/sequential/500       66  (106)    acos + 2 sin per sample
//   nodes/set_time+evaluate_all     277 (421)    validation + search + graph overhead
// Caveat: ozz's 22 ns is per joint (translation, rotation and scale, SoA);
// a joint here is up to nine scalar channels (~43 ns at 4.7 ns each).

#include <benchmark/benchmark.h>

#include <memory>
#include <random>
#include <string>
#include <vector>

#include "bench_util.h"
#include "rigel/graph/graph.h"
#include "rigel/ops/anim/curve.h"
#include "rigel/ops/anim/nodes.h"
#include "rigel/ops/anim/track.h"
#include "rigel/scene/transform_types.h"

namespace {

using rigel::ops::anim::AnimCurve;
using rigel::ops::anim::CurveSettings;
using rigel::ops::anim::Cursor;
using rigel::ops::anim::Interpolation;
using rigel::ops::anim::Key;
using rigel::ops::anim::QuatTrack;
using rigel::ops::anim::SampleCurvesJob;
using rigel::ops::anim::SampleQuatTracksJob;
using rigel::ops::anim::TangentType;
using rigel::math::Quat;

constexpr int kChannels = 500;
constexpr double kFps = 30.0;
constexpr double kSeconds = 10.0;  // keyed range; playback loops over it
constexpr int kFrames = static_cast<int>(kSeconds * kFps);

// Hand-keyed-looking curves: a key every 0.1-0.5 s (about 33 keys over
// 10 s), mostly auto tangents with some spline, linear, clamped, flat and
// step keys.
std::vector<Key> random_keys(std::mt19937& engine) {
  std::uniform_real_distribution<double> gap(0.1, 0.5), value(-90.0, 90.0), unit(0.0, 1.0);
  const TangentType kinds[] = {TangentType::kAuto,    TangentType::kAuto,   TangentType::kAuto,
                               TangentType::kSpline,  TangentType::kLinear, TangentType::kClamped,
                               TangentType::kFlat,    TangentType::kStep,   TangentType::kAuto};
  std::vector<Key> keys;
  for (double t = 0.0; t <= kSeconds + 0.5; t += gap(engine)) {
    Key k;
    k.time = t;
    k.value = value(engine);
    k.in_type = k.out_type = kinds[static_cast<int>(unit(engine) * 9) % 9];
    k.in_weight = 0.2 + 0.3 * unit(engine);
    k.out_weight = 0.2 + 0.3 * unit(engine);
    keys.push_back(k);
  }
  return keys;
}

std::vector<AnimCurve> make_curves(bool weighted) {
  std::mt19937 engine(weighted ? 2 : 1);
  std::vector<AnimCurve> curves;
  CurveSettings settings;
  settings.weighted = weighted;
  for (int i = 0; i < kChannels; ++i) curves.push_back(std::move(AnimCurve::build(random_keys(engine), settings)).value());
  return curves;
}

void sample_sequential(benchmark::State& state, bool weighted) {
  const std::vector<AnimCurve> curves = make_curves(weighted);
  std::vector<Cursor> cursors(curves.size());
  std::vector<double> output(curves.size());
  SampleCurvesJob job;
  job.curves = curves;
  job.cursors = cursors;
  job.output = output;
  int frame = 0;
  for (auto _ : state) {
    job.time = frame / kFps;
    if (!job.run()) state.SkipWithError("job did not validate");
    benchmark::DoNotOptimize(output.data());
    benchmark::ClobberMemory();
    if (++frame == kFrames) frame = 0;  // loop playback: one jump back per 300 frames
  }
  state.counters["ns_per_channel"] = rigel::bench::per_item(kChannels);
  state.SetLabel(weighted ? "weighted Bezier" : "Hermite");
}

// Sequential playback at 30 fps: the target.
void BM_anim_sample_sequential(benchmark::State& state) { sample_sequential(state, false); }
BENCHMARK(BM_anim_sample_sequential)->Name("anim/sample/sequential/500");

// The same with weighted tangents: each value solves a cubic in time
// (Newton with a bisection fallback).
void BM_anim_sample_sequential_weighted(benchmark::State& state) { sample_sequential(state, true); }
BENCHMARK(BM_anim_sample_sequential_weighted)->Name("anim/sample/sequential_weighted/500");

// Random times: every curve's cursor misses, so each sample is a binary
// search over ~33 keys plus the cubic.
void BM_anim_sample_random(benchmark::State& state) {
  const std::vector<AnimCurve> curves = make_curves(false);
  std::vector<Cursor> cursors(curves.size());
  std::vector<double> output(curves.size());
  std::mt19937 engine(3);
  std::uniform_real_distribution<double> when(0.0, kSeconds);
  std::vector<double> times(4096);
  for (double& t : times) t = when(engine);
  SampleCurvesJob job;
  job.curves = curves;
  job.cursors = cursors;
  job.output = output;
  std::size_t next = 0;
  for (auto _ : state) {
    job.time = times[next];
    next = (next + 1) & (times.size() - 1);
    if (!job.run()) state.SkipWithError("job did not validate");
    benchmark::DoNotOptimize(output.data());
    benchmark::ClobberMemory();
  }
  state.counters["ns_per_channel"] = rigel::bench::per_item(kChannels);
}
BENCHMARK(BM_anim_sample_random)->Name("anim/sample/random/500");

// glTF rotation tracks, linear (slerp), sequential at 30 fps. Keys every
// 0.05-0.3 s.
void BM_anim_quat_slerp_sequential(benchmark::State& state) {
  std::mt19937 engine(4);
  std::uniform_real_distribution<double> gap(0.05, 0.3), component(-1.0, 1.0);
  std::vector<QuatTrack> tracks;
  for (int i = 0; i < kChannels; ++i) {
    std::vector<double> times;
    std::vector<Quat> values;
    for (double t = 0.0; t <= kSeconds + 0.3; t += gap(engine)) {
      times.push_back(t);
      values.push_back(Quat(component(engine), component(engine), component(engine), component(engine)).normalized());
    }
    tracks.push_back(std::move(QuatTrack::build(std::move(times), std::move(values), Interpolation::kLinear)).value());
  }
  std::vector<Cursor> cursors(tracks.size());
  std::vector<Quat> output(tracks.size());
  SampleQuatTracksJob job;
  job.tracks = tracks;
  job.cursors = cursors;
  job.output = output;
  int frame = 0;
  for (auto _ : state) {
    job.time = frame / kFps;
    if (!job.run()) state.SkipWithError("job did not validate");
    benchmark::DoNotOptimize(output.data());
    benchmark::ClobberMemory();
    if (++frame == kFrames) frame = 0;
  }
  state.counters["ns_per_track"] = rigel::bench::per_item(kChannels);
}
BENCHMARK(BM_anim_quat_slerp_sequential)->Name("anim/quat_slerp/sequential/500");

// The same 500 curves as animCurve nodes in a graph: set_time, then
// evaluate_all. Each compute validates its key arrays and binary-searches
// (no per-node cursor; see nodes.h), plus the graph's per-node overhead.
void BM_anim_curve_nodes(benchmark::State& state) {
  auto registry = std::make_shared<rigel::graph::Registry>();
  if (!rigel::scene::register_scene_types(*registry) || !rigel::ops::anim::register_anim_types(*registry)) {
    state.SkipWithError("registration failed");
    return;
  }
  rigel::graph::Graph graph(registry);
  std::mt19937 engine(1);
  for (int i = 0; i < kChannels; ++i) {
    const std::vector<Key> keys = random_keys(engine);
    std::vector<double> times, values;
    std::vector<std::int64_t> types;
    for (const Key& k : keys) {
      times.push_back(k.time);
      values.push_back(k.value);
      types.push_back(static_cast<std::int64_t>(k.in_type));
    }
    std::string name = "c";  // not "c" + to_string(i): GCC 12 warns falsely (-Wrestrict) on that
    name += std::to_string(i);
    const rigel::graph::NodeId node = *graph.create_node(rigel::ops::anim::kAnimCurveType, name);
    namespace a = rigel::ops::anim::curve_attr;
    (void)graph.set_value({node, a::kKeyTimes, -1}, times);
    (void)graph.set_value({node, a::kKeyValues, -1}, values);
    (void)graph.set_value({node, a::kInTangentType, -1}, types);
    (void)graph.set_value({node, a::kOutTangentType, -1}, types);
  }
  graph.clear_history();
  int frame = 0;
  for (auto _ : state) {
    graph.set_time(frame / kFps);
    graph.evaluate_all(rigel::graph::Execution::kSerial);
    if (++frame == kFrames) frame = 0;
  }
  state.counters["ns_per_channel"] = rigel::bench::per_item(kChannels);
}
BENCHMARK(BM_anim_curve_nodes)->Name("anim/nodes/set_time+evaluate_all/500")->UseRealTime();

}  // namespace
