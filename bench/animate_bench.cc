// The animator tools over long shots (issue "Animate a shot"): FK/IK bake
// of one limb over 1,000 frames (tools::match), the deform-only game
// export of 1,000 frames (io::export_gltf, deform_only) and the mirror of a
// whole character's 200-frame range (tools::mirror, all), each per frame
// and against its anchor in the same run: playing the same frames of the
// same scene (set the frame, Graph::evaluate_all). Target: at most 3x the
// anchor per frame.
//
// The scene: the bundled biped (examples/biped.rig.xml) on Rigify's human
// metarig, its left arm in IK with the ik control keyed at frames 0, 500
// and 999, re-read from its text before each timed run (untimed).
#include <benchmark/benchmark.h>

#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <unistd.h>

#include "rigel/ephemeral/component.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/io/gltf_export.h"
#include "rigel/io/gltf_import.h"
#include "rigel/io/scene_file.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/ops/util/blend.h"
#include "rigel/rig/manager.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"
#include "rigel/tools/match.h"
#include "rigel/tools/mirror.h"

namespace rigel::bench {
namespace {

namespace fs = std::filesystem;
using graph::Plug;
using graph::Value;
using math::Vec3;

constexpr int kFrames = 1000;
constexpr int kMirrorFrames = 200;

graph::NodeId at(const graph::Graph& g, const std::string& address) {
  auto id = rig::resolve_address(g, address);
  if (!id) throw std::runtime_error(id.status().message());
  return *id;
}

const std::string& shot_text() {
  static const std::string text = [] {
    io::GltfImportOptions options;
    options.registry = ephemeral::default_registry();
    auto s = io::import_gltf(fs::path(RIGEL_SOURCE_DIR) / "tests/data/gltf/rigify_human_metarig.glb", options);
    if (!s) throw std::runtime_error(s.status().message());
    auto added = rig::add_rig(**s, fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml", ephemeral::components());
    if (!added) throw std::runtime_error(added.status().message());
    graph::Graph& g = (*s)->graph();
    const graph::NodeId ik = at(g, "hero:arm_L/ik");
    for (auto [frame, v] : {std::pair{0, Vec3(0, 0, 0)}, {500, Vec3(-0.15, 0.1, 0.2)}, {kFrames - 1, Vec3(0.05, -0.2, 0.1)}})
      if (!ops::anim::write_channel_key(g, ik, scene::xform::kTranslate, Value(v), frame / g.fps(), true))
        throw std::runtime_error("key");
    if (!g.set_value(Plug{at(g, "hero:arm_L/fkIkSwitch"), ops::util::fk_ik_attr::kFkIk, -1}, Value(1.0)))
      throw std::runtime_error("fkIk");
    return io::write_scene(**s);
  }();
  return text;
}

std::unique_ptr<scene::Scene> fresh_shot() {
  auto s = io::parse_scene(shot_text(), "shot", ephemeral::default_registry());
  if (!s) throw std::runtime_error(s.status().message());
  (*s)->graph().clear_history();
  return std::move(*s);
}

void per_frame(benchmark::State& state, int frames = kFrames) {
  state.counters["per_frame"] =
      benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// The anchor: playing the frames.
void BM_animate_play_1000_frames(benchmark::State& state) {
  std::unique_ptr<scene::Scene> s = fresh_shot();
  for (auto _ : state) {
    for (int f = 0; f < kFrames; ++f) {
      s->set_frame(f);
      s->graph().evaluate_all();
    }
  }
  per_frame(state);
}
BENCHMARK(BM_animate_play_1000_frames)->Unit(benchmark::kMillisecond);

void BM_animate_match_fk_1000_frames(benchmark::State& state) {
  for (auto _ : state) {
    state.PauseTiming();
    std::unique_ptr<scene::Scene> s = fresh_shot();
    const graph::NodeId limb = rig::find_component(s->graph(), rig::find_rig(s->graph(), "hero"), "arm_L");
    tools::MatchOptions o;
    o.to = rig::components::MatchSide::kFk;
    o.first = 0;
    o.last = kFrames - 1;
    state.ResumeTiming();
    auto report = tools::match(*s, limb, o);
    if (!report) {
      state.SkipWithError(report.status().message().c_str());
      break;
    }
    benchmark::DoNotOptimize(report->keys);
    state.PauseTiming();
    s.reset();
    state.ResumeTiming();
  }
  per_frame(state);
}
BENCHMARK(BM_animate_match_fk_1000_frames)->Unit(benchmark::kMillisecond);

void BM_animate_deform_only_export_1000_frames(benchmark::State& state) {
  std::unique_ptr<scene::Scene> s = fresh_shot();
  const fs::path out = fs::temp_directory_path() / ("rigel_bench_deform_" + std::to_string(::getpid()) + ".glb");
  io::GltfExportOptions o;
  o.deform_only = true;
  o.frames = std::pair{0.0, double(kFrames - 1)};
  for (auto _ : state) {
    const Status st = io::export_gltf(*s, out, o);
    if (!st) {
      state.SkipWithError(st.message().c_str());
      break;
    }
  }
  std::error_code ec;
  fs::remove(out, ec);
  per_frame(state);
}
BENCHMARK(BM_animate_deform_only_export_1000_frames)->Unit(benchmark::kMillisecond);

// The mirror's anchor: playing its 200 frames.
void BM_animate_play_200_frames(benchmark::State& state) {
  std::unique_ptr<scene::Scene> s = fresh_shot();
  for (auto _ : state) {
    for (int f = 0; f < kMirrorFrames; ++f) {
      s->set_frame(f);
      s->graph().evaluate_all();
    }
  }
  per_frame(state, kMirrorFrames);
}
BENCHMARK(BM_animate_play_200_frames)->Unit(benchmark::kMillisecond);

// Mirror of the whole character (every control and switch, left onto
// right) keyed at each of 200 frames.
void BM_animate_mirror_all_200_frames(benchmark::State& state) {
  for (auto _ : state) {
    state.PauseTiming();
    std::unique_ptr<scene::Scene> s = fresh_shot();
    tools::MirrorOptions o;
    o.all = true;
    o.first = 0;
    o.last = kMirrorFrames - 1;
    state.ResumeTiming();
    auto report = tools::mirror(*s, o);
    if (!report) {
      state.SkipWithError(report.status().message().c_str());
      break;
    }
    benchmark::DoNotOptimize(report->keys);
    state.PauseTiming();
    s.reset();
    state.ResumeTiming();
  }
  per_frame(state, kMirrorFrames);
}
BENCHMARK(BM_animate_mirror_all_200_frames)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace rigel::bench
