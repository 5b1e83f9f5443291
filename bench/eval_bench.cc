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
//   eval/biped_body/ik_move              one IK control moved + evaluate_all
//                                        (target: at most 30 us)
//   eval/biped_body/constraint_add_remove a parentConstraint added (created,
//                                        connected) + evaluate_all, then
//                                        deleted + evaluate_all, per edit
//                                        (target: at most 100 us)
//   .../compiled                         each of these with the compiled
//                                        evaluation (Graph::set_evaluation)
//   eval/bipeds_64/play_50/threads:N     64 copies of the keyed rig (no mesh)
//                                        in one scene, 50 frames, on at most
//                                        N threads (target: 2 threads at
//                                        least 1.7x faster than 1)
//
// Results: bench/README.md, "Evaluation at kernel speed (issue 19)".
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <tbb/global_control.h>
#include <stdexcept>
#include <string>
#include <vector>

#include "rigel/ephemeral/component.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/graph/graph.h"
#include "rigel/io/gltf_import.h"
#include "rigel/io/scene_file.h"
#include "bench_util.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/ops/constraints/nodes.h"
#include "rigel/ops/ik/nodes.h"
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

std::unique_ptr<scene::Scene> fresh_shot(bool mesh, graph::Evaluation evaluation = graph::Evaluation::kInterpreted) {
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
  g.set_evaluation(evaluation);
  return std::move(*s);
}

void play(benchmark::State& state, bool mesh, graph::Execution execution, graph::Evaluation evaluation) {
  std::unique_ptr<scene::Scene> s;
  try {
    s = fresh_shot(mesh, evaluation);
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

BENCHMARK_CAPTURE(play, biped, true, graph::Execution::kParallel, graph::Evaluation::kInterpreted)
    ->Name("eval/biped_body/play_1000")
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(play, biped_compiled, true, graph::Execution::kParallel, graph::Evaluation::kCompiled)
    ->Name("eval/biped_body/play_1000/compiled")
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(play, biped_serial, true, graph::Execution::kSerial, graph::Evaluation::kInterpreted)
    ->Name("eval/biped_body/play_1000/serial")
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(play, biped_serial_compiled, true, graph::Execution::kSerial, graph::Evaluation::kCompiled)
    ->Name("eval/biped_body/play_1000/serial/compiled")
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(play, biped_no_mesh, false, graph::Execution::kParallel, graph::Evaluation::kInterpreted)
    ->Name("eval/biped_body/play_1000/no_mesh")
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(play, biped_no_mesh_compiled, false, graph::Execution::kParallel, graph::Evaluation::kCompiled)
    ->Name("eval/biped_body/play_1000/no_mesh/compiled")
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(play, biped_no_mesh_serial, false, graph::Execution::kSerial, graph::Evaluation::kInterpreted)
    ->Name("eval/biped_body/play_1000/no_mesh/serial")
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(play, biped_no_mesh_serial_compiled, false, graph::Execution::kSerial, graph::Evaluation::kCompiled)
    ->Name("eval/biped_body/play_1000/no_mesh/serial/compiled")
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// The first (by name) control feeding a two-bone IK node: an arm's or leg's IK control.
NodeId ik_control(const graph::Graph& g) {
  std::vector<std::pair<std::string, NodeId>> found;
  for (NodeId id : g.nodes()) {
    if (g.node(id)->type().name() != ops::ik::kIkTwoBoneType) continue;
    for (const graph::Connection& c : g.node(id)->inputs()) {
      const graph::Node* src = g.node(c.src.node);
      if (src->type().name() == scene::kControlType) found.emplace_back(src->name(), c.src.node);
    }
  }
  if (found.empty()) throw std::runtime_error("no control feeds a two-bone IK");
  return std::min_element(found.begin(), found.end(), [](const auto& x, const auto& y) { return x.first < y.first; })->second;
}

// The keyed shot with its mesh and its IK control; no scene (and the
// benchmark skipped with the reason) when either cannot be made.
std::pair<std::unique_ptr<scene::Scene>, NodeId> ik_shot(benchmark::State& state, graph::Evaluation evaluation) {
  try {
    std::unique_ptr<scene::Scene> s = fresh_shot(true, evaluation);
    const NodeId control = ik_control(s->graph());
    return {std::move(s), control};
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return {nullptr, NodeId{}};
  }
}

// An animator drags an IK control: its translate set, the scene evaluated
// (the limb, and the mesh it skins).
void ik_move(benchmark::State& state, graph::Evaluation evaluation) {
  auto [s, control] = ik_shot(state, evaluation);
  if (!s) return;
  graph::Graph& g = s->graph();
  g.evaluate_all();
  const Vec3 rest = std::get<Vec3>(g.node(control)->value(scene::xform::kTranslate));
  HistoryTrim trim(state, g);
  int step = 0;
  for (auto _ : state) {
    const double offset = 0.001 * (step++ % 20);
    if (!g.set_value(graph::Plug{control, scene::xform::kTranslate, -1}, Value(Vec3(rest + Vec3(offset, offset, 0))))) {
      state.SkipWithError("setting the IK control failed");
      return;
    }
    g.evaluate_all();
    trim.tick();
  }
  state.counters["per_edit"] = per_item(1);
}

// A rigger or animator adds a constraint and takes it away: a
// parentConstraint created and connected from a control to a locator, the
// scene evaluated; then deleted, the scene evaluated. Two topology edits.
void constraint_add_remove(benchmark::State& state, graph::Evaluation evaluation) {
  auto [s, control] = ik_shot(state, evaluation);
  if (!s) return;
  graph::Graph& g = s->graph();
  auto locator = g.create_node(scene::kLocatorType, "bench_driven");
  if (!locator) {
    state.SkipWithError(locator.status().message().c_str());
    return;
  }
  g.evaluate_all();
  HistoryTrim trim(state, g);
  for (auto _ : state) {
    auto made = g.create_node(ops::constraints::kParentConstraintType, "bench_constraint");
    bool ok = made.is_ok();
    if (ok) {
      auto target = g.plug_find(*made, "targetWorldMatrix", 0);
      auto out = g.plug_find(*made, "translate");
      ok = target && out && g.connect(graph::Plug{control, scene::xform::kWorldMatrix, -1}, *target) &&
           g.connect(*out, graph::Plug{*locator, scene::xform::kTranslate, -1});
      g.evaluate_all();
      ok = ok && g.delete_node(*made);
      g.evaluate_all();
    }
    if (!ok) {
      state.SkipWithError("adding or removing the constraint failed");
      return;
    }
    trim.tick();
  }
  state.counters["per_edit"] = per_item(2);
  state.counters["nodes"] = static_cast<double>(g.node_count());
}

BENCHMARK_CAPTURE(ik_move, interpreted, graph::Evaluation::kInterpreted)
    ->Name("eval/biped_body/ik_move")
    ->UseRealTime()
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(ik_move, compiled, graph::Evaluation::kCompiled)
    ->Name("eval/biped_body/ik_move/compiled")
    ->UseRealTime()
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(constraint_add_remove, interpreted, graph::Evaluation::kInterpreted)
    ->Name("eval/biped_body/constraint_add_remove")
    ->UseRealTime()
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(constraint_add_remove, compiled, graph::Evaluation::kCompiled)
    ->Name("eval/biped_body/constraint_add_remove/compiled")
    ->UseRealTime()
    ->Unit(benchmark::kMicrosecond);

// 64 copies of the keyed rig without its mesh, as one scene's text: each
// copy's nodes prefixed "cK_" (names, parents, connections), uuids dropped
// (new ones are made). Independent characters: evaluation can run them on
// separate cores.
constexpr int kCopies = 64;
const std::string& crowd_text() {
  static const std::string made = [] {
    const std::string one = io::write_scene(*fresh_shot(false));
    const nlohmann::ordered_json single = nlohmann::ordered_json::parse(one);
    nlohmann::ordered_json crowd = single;
    crowd["nodes"] = nlohmann::ordered_json::array();
    crowd["connections"] = nlohmann::ordered_json::array();
    for (int k = 0; k < kCopies; ++k) {
      const auto prefixed = [k](const nlohmann::ordered_json& name) {
        std::string out = std::to_string(k);
        out.insert(out.begin(), 'c');
        out.push_back('_');
        return out.append(name.get<std::string>());
      };
      for (nlohmann::ordered_json n : single["nodes"]) {
        n["name"] = prefixed(n["name"]);
        if (n.contains("parent")) n["parent"] = prefixed(n["parent"]);
        n.erase("uuid");
        crowd["nodes"].push_back(std::move(n));
      }
      for (nlohmann::ordered_json c : single["connections"]) {
        c["src"] = prefixed(c["src"]);
        c["dst"] = prefixed(c["dst"]);
        crowd["connections"].push_back(std::move(c));
      }
    }
    return crowd.dump();
  }();
  return made;
}

constexpr int kCrowdFrames = 50;

void play_crowd(benchmark::State& state, graph::Evaluation evaluation) {
  const auto threads = static_cast<std::size_t>(state.range(0));
  std::unique_ptr<scene::Scene> s;
  try {
    auto parsed = io::parse_scene(crowd_text(), "crowd", ephemeral::default_registry());
    if (!parsed) throw std::runtime_error(parsed.status().message());
    s = std::move(*parsed);
    s->graph().set_evaluation(evaluation);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  // Playback, not the first evaluation: everything computed once (the
  // schedule, every node's caches) before the timed frames.
  s->set_frame(kCrowdFrames);
  s->graph().evaluate_all(graph::Execution::kParallel);
  for (auto _ : state) {
    for (int f = 0; f < kCrowdFrames; ++f) {
      s->set_frame(f);
      s->graph().evaluate_all(graph::Execution::kParallel);
    }
  }
  state.counters["per_frame"] = benchmark::Counter(
      kCrowdFrames, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["nodes"] = static_cast<double>(s->graph().node_count());
  state.counters["levels"] = static_cast<double>(s->graph().schedule_level_count());
}

BENCHMARK_CAPTURE(play_crowd, interpreted, graph::Evaluation::kInterpreted)
    ->Name("eval/bipeds_64/play_50")
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(2)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(play_crowd, compiled, graph::Evaluation::kCompiled)
    ->Name("eval/bipeds_64/play_50/compiled")
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(2)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace rigel::bench
