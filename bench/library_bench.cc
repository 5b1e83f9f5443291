// The component library (issue 21): building the biggest shipped rig per
// component (target at most 0.5 ms per component: the `perComponent`
// counter, seconds), and mGear's biped guide template (38 components)
// imported (read, mapped, its skeleton made) and then built on that
// skeleton, per component likewise; the quadruped example likewise.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "rigel/ephemeral/component.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/io/scene_file.h"
#include "rigel/rig/build.h"
#include "rigel/rig/definition_io.h"
#include "rigel/tools/mgear_guides.h"

namespace rigel::bench {
namespace {

namespace fs = std::filesystem;

const std::string& biped_template() {
  static const std::string text = [] {
    std::ifstream in(fs::path(RIGEL_SOURCE_DIR) / "tests/data/mgear/biped.sgt", std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    if (s.str().empty()) throw std::runtime_error("tests/data/mgear/biped.sgt: cannot be read");
    return s.str();
  }();
  return text;
}

void per_component(benchmark::State& state, std::size_t components) {
  state.counters["components"] = static_cast<double>(components);
  state.counters["perComponent"] = benchmark::Counter(static_cast<double>(components * state.iterations()),
                                                      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_mgear_import_biped_template(benchmark::State& state) {
  std::size_t components = 0;
  for (auto _ : state) {
    auto imported = tools::import_mgear_guides(biped_template(), "biped.sgt");
    if (!imported) {
      state.SkipWithError(imported.status().message().c_str());
      break;
    }
    auto skeleton = tools::guide_skeleton_scene(*imported, ephemeral::default_registry());
    if (!skeleton) {
      state.SkipWithError(skeleton.status().message().c_str());
      break;
    }
    components = imported->components.size();
    benchmark::DoNotOptimize((*skeleton)->graph().nodes().size());
  }
  per_component(state, components);
}
BENCHMARK(BM_mgear_import_biped_template)->Unit(benchmark::kMillisecond);

// The imported biped built on its skeleton (the skeleton made afresh, untimed).
void BM_mgear_build_biped_on_its_skeleton(benchmark::State& state) {
  auto imported = tools::import_mgear_guides(biped_template(), "biped.sgt");
  if (!imported) {
    state.SkipWithError(imported.status().message().c_str());
    return;
  }
  for (auto _ : state) {
    state.PauseTiming();
    auto skeleton = tools::guide_skeleton_scene(*imported, ephemeral::default_registry());
    if (!skeleton) {
      state.SkipWithError(skeleton.status().message().c_str());
      break;
    }
    (*skeleton)->graph().clear_history();
    state.ResumeTiming();
    auto b = rig::Build::open(**skeleton, imported->definition, ephemeral::components());
    if (!b || !(*b)->build_all()) {
      state.SkipWithError("build failed");
      break;
    }
    benchmark::DoNotOptimize((*b)->position());
    state.PauseTiming();
    skeleton->reset();
    state.ResumeTiming();
  }
  per_component(state, imported->definition.all_components().size());
}
BENCHMARK(BM_mgear_build_biped_on_its_skeleton)->Unit(benchmark::kMillisecond);

// The quadruped example (examples/quadruped.rig.xml: quadLegs, springChain
// tail, face, cart mechanics, correctives, sliders) built on its skeleton,
// per component (the scene loaded afresh, untimed).
void BM_rig_build_quadruped(benchmark::State& state) {
  const fs::path examples = fs::path(RIGEL_SOURCE_DIR) / "examples";
  rig::ParseResult parsed = rig::load_definition(examples / "quadruped.rig.xml");
  if (!parsed.ok()) {
    state.SkipWithError(parsed.errors.front().str().c_str());
    return;
  }
  for (auto _ : state) {
    state.PauseTiming();
    auto scene = io::load_scene(examples / "quadruped.rigel", ephemeral::default_registry());
    if (!scene) {
      state.SkipWithError(scene.status().message().c_str());
      break;
    }
    state.ResumeTiming();
    auto b = rig::Build::open(**scene, parsed.definition, ephemeral::components());
    if (!b || !(*b)->build_all()) {
      state.SkipWithError("build failed");
      break;
    }
    benchmark::DoNotOptimize((*b)->position());
    state.PauseTiming();
    scene->reset();
    state.ResumeTiming();
  }
  per_component(state, parsed.definition.all_components().size());
}
BENCHMARK(BM_rig_build_quadruped)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace rigel::bench
