// Playing a keyed character (issue "Evaluation at kernel speed"): the
// bundled biped (examples/biped.rig.xml) built on the skinned Rigify body
// (tests/data/gltf/rigify_human_body.glb, 10,037 vertices), every control's
// rotate keyed at four frames, played over 1,000 frames (set the frame,
// Graph::evaluate_all), per frame; and the same scene with its deformers
// deleted (the rig alone). Issue 19's targets: at most 60 us a frame with
// the mesh, 15 us without. Counters: nodes in the scene, keyed channels,
// deformed vertices.
//
//   eval/biped_body/play_1000            the whole scene
//   eval/biped_body/play_1000/no_mesh    skinCluster and blendShape deleted
//
// Results, 2026-12-05: Release (GCC 12.2, no -march), 2 vCPUs (Zen 5),
// another engineer's test run on the other core, --benchmark_min_time=0.3,
// best of 3: see bench/README.md "Playing a keyed character".
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "rigel/ephemeral/component.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/graph/graph.h"
#include "rigel/io/gltf_import.h"
#include "rigel/io/scene_file.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/ops/deform/nodes.h"
#include "rigel/rig/manager.h"
#include "rigel/scene/scene.h"
#include "rigel/scene/transform_types.h"

namespace rigel::bench {
namespace {

namespace fs = std::filesystem;
using graph::NodeId;
using graph::Value;
using math::Vec3;

constexpr int kFrames = 1000;

struct Shot {
  std::string text;
  int keyed_channels = 0;
  std::size_t vertices = 0;
};

// The keyed scene as text, made once: parsing it again gives each timed run
// a scene with no history and no cached results.
const Shot& shot() {
  static const Shot made = [] {
    io::GltfImportOptions options;
    options.registry = ephemeral::default_registry();
    auto s = io::import_gltf(fs::path(RIGEL_SOURCE_DIR) / "tests/data/gltf/rigify_human_body.glb", options);
    if (!s) throw std::runtime_error(s.status().message());
    auto added = rig::add_rig(**s, fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml", ephemeral::components());
    if (!added) throw std::runtime_error(added.status().message());
    graph::Graph& g = (*s)->graph();
    std::vector<std::pair<std::string, NodeId>> controls;
    for (NodeId id : g.nodes())
      if (g.node(id)->type().name() == scene::kControlType) controls.emplace_back(g.node(id)->name(), id);
    std::sort(controls.begin(), controls.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    Shot out;
    std::uint32_t seed = 12345;
    auto angle = [&] {  // a fixed sequence in [-15, 15) degrees
      seed = seed * 1664525u + 1013904223u;
      return static_cast<double>(seed >> 8) / static_cast<double>(1u << 24) * 30.0 - 15.0;
    };
    for (const auto& [name, id] : controls) {
      bool keyed = true;
      for (int frame : {0, 333, 666, kFrames - 1}) {
        const Vec3 r(angle(), angle(), angle());
        keyed = keyed && ops::anim::write_channel_key(g, id, scene::xform::kRotate, Value(r), frame / g.fps(), true);
      }
      if (keyed) out.keyed_channels += 3;
    }
    for (NodeId id : g.nodes()) {
      if (g.node(id)->type().name() != ops::kSkinClusterType) continue;
      out.vertices += std::get<std::vector<Vec3>>(g.node(id)->value(ops::skin_cluster_attr::kBindPoints)).size();
    }
    out.text = io::write_scene(**s);
    return out;
  }();
  return made;
}

std::unique_ptr<scene::Scene> fresh_shot(bool mesh) {
  auto s = io::parse_scene(shot().text, "shot", ephemeral::default_registry());
  if (!s) throw std::runtime_error(s.status().message());
  graph::Graph& g = (*s)->graph();
  if (!mesh) {
    for (NodeId id : g.nodes()) {
      const std::string& type = g.node(id)->type().name();
      if (type == ops::kSkinClusterType || type == ops::kBlendShapeType) {
        if (!g.delete_node(id)) throw std::runtime_error("deleting a deformer failed");
      }
    }
  }
  g.clear_history();
  return std::move(*s);
}

void play(benchmark::State& state, bool mesh, graph::Execution execution) {
  std::unique_ptr<scene::Scene> s;
  try {
    s = fresh_shot(mesh);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  for (auto _ : state) {
    for (int f = 0; f < kFrames; ++f) {
      s->set_frame(f);
      s->graph().evaluate_all(execution);
    }
  }
  state.counters["per_frame"] = benchmark::Counter(
      kFrames, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["nodes"] = static_cast<double>(s->graph().node_count());
  state.counters["keyed_channels"] = shot().keyed_channels;
  state.counters["vertices"] = mesh ? static_cast<double>(shot().vertices) : 0.0;
}

BENCHMARK_CAPTURE(play, biped_body_play_1000, true, graph::Execution::kParallel)
    ->Name("eval/biped_body/play_1000")
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(play, biped_body_play_1000_serial, true, graph::Execution::kSerial)
    ->Name("eval/biped_body/play_1000/serial")
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(play, biped_body_play_1000_no_mesh, false, graph::Execution::kParallel)
    ->Name("eval/biped_body/play_1000/no_mesh")
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(play, biped_body_play_1000_no_mesh_serial, false, graph::Execution::kSerial)
    ->Name("eval/biped_body/play_1000/no_mesh/serial")
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace rigel::bench
