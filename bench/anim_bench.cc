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

#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <type_traits>
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

// Scene and anim node types, registered once; null if registration failed.
std::shared_ptr<const rigel::graph::Registry> anim_registry() {
  static const std::shared_ptr<const rigel::graph::Registry> made = [] {
    auto registry = std::make_shared<rigel::graph::Registry>();
    const bool ok = rigel::scene::register_scene_types(*registry) && rigel::ops::anim::register_anim_types(*registry);
    return ok ? std::shared_ptr<const rigel::graph::Registry>(std::move(registry)) : nullptr;
  }();
  return made;
}

// The same 500 curves as animCurve nodes in a graph: set_time, then
// evaluate_all. Each compute evaluates its compiled curve from its cursor
// (see nodes.h), plus the graph's per-node overhead.
void BM_anim_curve_nodes(benchmark::State& state) {
  const auto registry = anim_registry();
  if (!registry) {
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

// ---- a joint's translate, rotate and scale (glTF tracks) ---------------------
//
// 500 joints of a baked clip (a key every 1/30 s over 10 s, as glTF and BVH
// exports write them): each a linear Vec3Track translate, QuatTrack rotate
// (slerp) and Vec3Track scale, sampled at 60 fps (every other sample between
// two keys). Per joint per frame:
//   anim/sample/joint_trs/sequential/500   Track::evaluate with cursors
//   anim/sample/joint_trs/random/500       the same at random times (scrubbing)
//   anim/sample/joint_trs/arrays/500       evaluate_arrays: a binary search and
//                                          the keys normalised as read, no
//                                          prepared slerp (what animCurveVec3 /
//                                          animCurveQuat nodes did before they
//                                          kept a Track; the in-run anchor)
//   anim/nodes/joint_trs/set_time+evaluate_all/500
//                                          the same tracks as 1,500 nodes
struct JointTracks {
  std::vector<rigel::ops::anim::Vec3Track> translate, scale;
  std::vector<QuatTrack> rotate;
};

const JointTracks& joint_tracks() {
  static const JointTracks made = [] {
    std::mt19937 engine(5);
    std::uniform_real_distribution<double> step(-0.02, 0.02), angle(-0.05, 0.05);
    JointTracks out;
    for (int j = 0; j < kChannels; ++j) {
      std::vector<double> times;
      std::vector<rigel::math::Vec3> t_values, s_values;
      std::vector<Quat> r_values;
      rigel::math::Vec3 t(0.0, 0.1 * j, 0.0), sc(1.0, 1.0, 1.0);
      Quat r = Quat::Identity();
      for (int k = 0; k <= kFrames; ++k) {  // a random walk, as captured motion
        times.push_back(k / kFps);
        t += rigel::math::Vec3(step(engine), step(engine), step(engine));
        sc += 0.1 * rigel::math::Vec3(step(engine), step(engine), step(engine));
        r = (r * Quat(Eigen::AngleAxisd(angle(engine), rigel::math::Vec3(step(engine), 0.01, step(engine)).normalized())))
                .normalized();
        t_values.push_back(t);
        s_values.push_back(sc);
        r_values.push_back(r);
      }
      out.translate.push_back(
          std::move(rigel::ops::anim::Vec3Track::build(times, std::move(t_values), Interpolation::kLinear)).value());
      out.scale.push_back(
          std::move(rigel::ops::anim::Vec3Track::build(times, std::move(s_values), Interpolation::kLinear)).value());
      out.rotate.push_back(std::move(QuatTrack::build(times, std::move(r_values), Interpolation::kLinear)).value());
    }
    return out;
  }();
  return made;
}

struct JointPose {
  rigel::math::Vec3 translate, scale;
  Quat rotate;
};

void sample_joints(benchmark::State& state, bool random, bool arrays) {
  const JointTracks& tracks = joint_tracks();
  std::vector<Cursor> cursors(3 * kChannels);
  std::vector<JointPose> pose(kChannels);
  std::mt19937 engine(6);
  std::uniform_real_distribution<double> when(0.0, kSeconds);
  std::vector<double> times(4096);
  for (std::size_t i = 0; i < times.size(); ++i) times[i] = random ? when(engine) : std::fmod(i / 60.0, kSeconds);
  std::size_t next = 0;
  for (auto _ : state) {
    const double t = times[next];
    next = (next + 1) & (times.size() - 1);
    for (int j = 0; j < kChannels; ++j) {
      JointPose& p = pose[j];
      if (arrays) {
        p.translate = rigel::ops::anim::evaluate_arrays(tracks.translate[j].arrays(), t);
        p.rotate = rigel::ops::anim::evaluate_arrays(tracks.rotate[j].arrays(), t);
        p.scale = rigel::ops::anim::evaluate_arrays(tracks.scale[j].arrays(), t);
      } else {
        p.translate = tracks.translate[j].evaluate(t, cursors[3 * j]);
        p.rotate = tracks.rotate[j].evaluate(t, cursors[3 * j + 1]);
        p.scale = tracks.scale[j].evaluate(t, cursors[3 * j + 2]);
      }
    }
    benchmark::DoNotOptimize(pose.data());
    benchmark::ClobberMemory();
  }
  state.counters["ns_per_joint"] = rigel::bench::per_item(kChannels);
}
BENCHMARK_CAPTURE(sample_joints, sequential, false, false)->Name("anim/sample/joint_trs/sequential/500");
BENCHMARK_CAPTURE(sample_joints, random, true, false)->Name("anim/sample/joint_trs/random/500");
BENCHMARK_CAPTURE(sample_joints, arrays, false, true)->Name("anim/sample/joint_trs/arrays/500");

// The joints' tracks as animCurveVec3 / animCurveQuat nodes, played at 60 fps.
void BM_anim_joint_track_nodes(benchmark::State& state) {
  const auto registry = anim_registry();
  if (!registry) {
    state.SkipWithError("registration failed");
    return;
  }
  rigel::graph::Graph graph(registry);
  namespace a = rigel::ops::anim::track_attr;
  const JointTracks& tracks = joint_tracks();
  auto add = [&](const char* type, const std::string& name, const auto& track) {
    using T = typename std::decay_t<decltype(track.arrays().values)>::element_type;
    const auto arrays = track.arrays();
    const rigel::graph::NodeId node = *graph.create_node(type, name);
    (void)graph.set_value({node, a::kKeyTimes, -1}, std::vector<double>(arrays.times.begin(), arrays.times.end()));
    (void)graph.set_value({node, a::kKeyValues, -1},
                          std::vector<std::remove_const_t<T>>(arrays.values.begin(), arrays.values.end()));
  };
  for (int j = 0; j < kChannels; ++j) {
    std::string name = "j";  // not "j" + to_string(j): GCC 12 warns falsely (-Wrestrict) on that
    name += std::to_string(j);
    add(rigel::ops::anim::kAnimCurveVec3Type, name + "_t", tracks.translate[j]);
    add(rigel::ops::anim::kAnimCurveQuatType, name + "_r", tracks.rotate[j]);
    add(rigel::ops::anim::kAnimCurveVec3Type, name + "_s", tracks.scale[j]);
  }
  graph.clear_history();
  int frame = 0;
  for (auto _ : state) {
    graph.set_time(frame / 60.0);
    graph.evaluate_all(rigel::graph::Execution::kSerial);
    if (++frame == 2 * kFrames) frame = 0;
  }
  state.counters["ns_per_joint"] = rigel::bench::per_item(kChannels);
}
BENCHMARK(BM_anim_joint_track_nodes)->Name("anim/nodes/joint_trs/set_time+evaluate_all/500")->UseRealTime();

}  // namespace
