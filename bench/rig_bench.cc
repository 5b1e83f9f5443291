// Rig definitions and builds (issue 5's targets): building the bundled biped
// (examples/biped.rig.xml) on Rigify's human metarig from its definition
// (target at most 30 ms; Blender's Rigify generates its human rig in
// 3.2-3.7 s on this machine), an update after one component changed (target
// at most 5 ms), and validating a 1,000-component definition (what
// `rigel validate` does: parse with positions, then every check).
//
// Build graphs (issue 20): the biped built from the text of its converted
// graph (read, compiled, built) against the same from the definition's
// text (read, validated, built): target at most 1.5x; and one graph node's
// live rebuild (its input changed, the graph compiled again, what changed
// rebuilt): target at most 5 ms.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <memory>
#include <optional>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <string>

#include "rigel/app/graphs.h"
#include "rigel/ephemeral/component.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/io/gltf_import.h"
#include "rigel/io/scene_file.h"
#include "rigel/rig/build.h"
#include "rigel/rig/build_graph.h"
#include "rigel/rig/definition_io.h"

namespace rigel::bench {
namespace {

namespace fs = std::filesystem;

// The metarig as scene text (parsed afresh for each build, untimed).
const std::string& metarig_text() {
  static const std::string text = [] {
    auto imported = io::import_gltf(fs::path(RIGEL_SOURCE_DIR) / "tests/data/gltf/rigify_human_metarig.glb");
    if (!imported) throw std::runtime_error(imported.status().message());
    return io::write_scene(**imported);
  }();
  return text;
}

std::unique_ptr<scene::Scene> fresh_scene() {
  auto s = io::parse_scene(metarig_text(), "metarig", ephemeral::default_registry());
  if (!s) throw std::runtime_error(s.status().message());
  (*s)->graph().clear_history();
  return std::move(*s);
}

const rig::Definition& biped() {
  static const rig::Definition d = [] {
    rig::ParseResult p = rig::load_definition(fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml");
    if (!p.ok()) throw std::runtime_error(p.errors.front().str());
    return p.definition;
  }();
  return d;
}

// Each iteration rebuilds what changed in `definition(k)`, k alternating
// 0, 1, 0, ... (so every one changes something); the undo history is
// cleared untimed.
template <typename Definitions>
void rebuild_alternately(benchmark::State& state, rig::Build& build, scene::Scene& scene, Definitions definition,
                         rig::Build::Rebuild when = rig::Build::Rebuild::kChanged) {
  std::size_t rebuilt = 0;
  int k = 0;
  for (auto _ : state) {
    auto r = build.rebuild_changed(definition(k), when);
    if (!r) {
      state.SkipWithError(r.status().message().c_str());
      break;
    }
    rebuilt = r->size();
    k = 1 - k;
    state.PauseTiming();
    scene.graph().clear_history();
    state.ResumeTiming();
  }
  state.counters["rebuilt"] = static_cast<double>(rebuilt);
}

// Each iteration builds the definition `definition()` gives (timed with
// the build; nullopt: skipped with `why`) on a fresh metarig (untimed).
template <typename MakeDefinition>
void build_each(benchmark::State& state, MakeDefinition definition, const char* why) {
  for (auto _ : state) {
    state.PauseTiming();
    std::unique_ptr<scene::Scene> scene = fresh_scene();
    state.ResumeTiming();
    std::optional<rig::Definition> d = definition();
    if (!d) {
      state.SkipWithError(why);
      break;
    }
    auto b = rig::Build::open(*scene, std::move(*d), ephemeral::components());
    if (!b || !(*b)->build_all()) {
      state.SkipWithError("build failed");
      break;
    }
    benchmark::DoNotOptimize((*b)->position());
    state.PauseTiming();
    scene.reset();
    state.ResumeTiming();
  }
}

void BM_rig_build_biped(benchmark::State& state) {
  build_each(state, [] { return std::optional<rig::Definition>(biped()); }, "");
  const auto components = static_cast<double>(biped().all_components().size());
  state.counters["components"] = components;
  // Seconds per component (issue 21's target: at most 0.5 ms).
  state.counters["perComponent"] = benchmark::Counter(components * static_cast<double>(state.iterations()),
                                                      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_rig_build_biped)->Unit(benchmark::kMillisecond);

// One component (the left arm's limb) changes version and a parameter on each
// update, alternating between two definitions so every update rebuilds it.
void BM_rig_update_one_component(benchmark::State& state) {
  std::unique_ptr<scene::Scene> scene = fresh_scene();
  auto b = rig::Build::open(*scene, biped(), ephemeral::components());
  if (!b || !(*b)->build_all()) {
    state.SkipWithError("build failed");
    return;
  }
  rig::Definition next[2] = {biped(), biped()};
  std::string changed;
  for (int k = 0; k < 2; ++k) {
    rig::Component* arm = nullptr;
    auto find = [&](auto&& self, std::vector<rig::Component>& list) -> void {
      for (rig::Component& c : list) {
        if (c.type == "limb" && c.side == rig::Side::kLeft && c.name == "arm") arm = &c;
        self(self, c.children);
      }
    };
    find(find, next[k].components);
    if (!arm) {
      state.SkipWithError("the biped has no left arm limb");
      return;
    }
    arm->version = k == 0 ? "1.1" : "1.2";
    arm->params.push_back(rig::Param{"poleDistance", k == 0 ? 0.6 : 0.5, {}});
    changed = arm->rig_id;
  }
  rebuild_alternately(state, **b, *scene, [&](int k) { return next[k]; }, rig::Build::Rebuild::kNewerVersion);
}
BENCHMARK(BM_rig_update_one_component)->Unit(benchmark::kMillisecond);

// A definition of `n` components: a global root, then fkChain components of
// three value guides each, ten levels deep in a 10-ary-ish tree.
std::string large_definition(int n) {
  std::ostringstream out;
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<rig name=\"crowd\" version=\"1.0\">\n";
  out << "  <component type=\"global\" name=\"global\" side=\"C\" version=\"1.0\" "
         "rigId=\"00000000-0000-4000-8000-000000000000\">\n    <guide name=\"main\"/>\n";
  for (int i = 1; i < n; ++i) {
    char id[40];
    std::snprintf(id, sizeof id, "%08x-0000-4000-8000-%012x", i, i);
    out << "    <component type=\"fkChain\" name=\"chain" << i << "\" side=\"C\" version=\"1.0\" rigId=\"" << id
        << "\">\n";
    for (int gidx = 0; gidx < 3; ++gidx)
      out << "      <guide translate=\"" << i * 0.01 << " " << gidx * 0.1 << " 0\"/>\n";
    out << "      <control role=\"fk\" shape=\"circle\" color=\"yellow\" size=\"0.1\"/>\n    </component>\n";
  }
  out << "  </component>\n</rig>\n";
  return out.str();
}

void BM_rig_validate_1000_components(benchmark::State& state) {
  const std::string text = large_definition(1000);
  std::size_t problems = 0;
  for (auto _ : state) {
    rig::ParseResult parsed = rig::parse_definition(text, rig::Syntax::kXml, "crowd.rig.xml");
    std::vector<rig::Diagnostic> found = parsed.ok() ? rig::validate(parsed.definition) : parsed.errors;
    problems = found.size();
    benchmark::DoNotOptimize(found.data());
  }
  state.counters["problems"] = static_cast<double>(problems);
  state.counters["bytes"] = static_cast<double>(text.size());
}
BENCHMARK(BM_rig_validate_1000_components)->Unit(benchmark::kMillisecond);

// The biped's definition and its converted graph, as text.
const std::string& biped_text() {
  static const std::string text = rig::write_definition(biped(), rig::Syntax::kXml);
  return text;
}
const std::string& biped_graph_text() {
  static const std::string text = rig::write_build_graph(rig::convert_definition(biped()));
  return text;
}

// From text to a built rig: the definition read and validated, or the
// graph read and compiled.
void BM_rig_build_biped_from_definition_text(benchmark::State& state) {
  build_each(state, []() -> std::optional<rig::Definition> {
    rig::ParseResult parsed = rig::parse_definition(biped_text(), rig::Syntax::kXml, "biped.rig.xml");
    if (!parsed.ok() || !rig::validate(parsed.definition).empty()) return std::nullopt;
    return std::move(parsed.definition);
  }, "the definition is not valid");
}
BENCHMARK(BM_rig_build_biped_from_definition_text)->Unit(benchmark::kMillisecond);
void BM_graph_build_biped_from_graph_text(benchmark::State& state) {
  build_each(state, []() -> std::optional<rig::Definition> {
    rig::BuildGraphParse parsed = rig::parse_build_graph(biped_graph_text(), "biped.build.json");
    rig::BuildGraphCompile compiled = rig::compile_build_graph(parsed.graph);
    if (!parsed.ok() || !compiled.ok()) return std::nullopt;
    return std::move(compiled.definition);
  }, "the graph does not compile");
}
BENCHMARK(BM_graph_build_biped_from_graph_text)->Unit(benchmark::kMillisecond);

// The editor's live rebuild: the left arm's node gets another pole distance
// (alternating, so each time it changes), the graph is compiled again and
// what changed is rebuilt.
void BM_graph_live_rebuild_one_node(benchmark::State& state) {
  std::unique_ptr<scene::Scene> scene = fresh_scene();
  rig::BuildGraph graph = rig::convert_definition(biped());
  auto b = rig::Build::open(*scene, rig::compile_build_graph(graph).definition, ephemeral::components());
  if (!b || !(*b)->build_all()) {
    state.SkipWithError("build failed");
    return;
  }
  rig::GraphNode* arm = nullptr;
  for (rig::GraphNode& n : graph.nodes)
    if (n.id == "arm_L") arm = &n;
  if (!arm) {
    state.SkipWithError("the graph has no arm_L node");
    return;
  }
  arm->component.params.push_back(rig::Param{"poleDistance", 0.5, {}});
  rebuild_alternately(state, **b, *scene, [&](int k) {
    arm->component.params.back().value = k == 0 ? 0.6 : 0.5;
    return rig::compile_build_graph(graph).definition;
  });
}
BENCHMARK(BM_graph_live_rebuild_one_node)->Unit(benchmark::kMillisecond);

// Compiling a for-each that makes one component per item (a one-joint FK
// chain named by the item), with the definition's validation: the cost per
// item should stay flat from 100 to 10,000 items (the compile limit).
void BM_graph_compile_for_each(benchmark::State& state) {
  const auto items = static_cast<int>(state.range(0));
  rig::BuildGraph g;
  g.rig.name = "many";
  rig::GraphNode start, names, each, chain;
  start.id = start.kind = "start";
  names.id = "names";
  names.kind = "constant:list:string";
  for (int i = 0; i < items; ++i) names.lists["value"].push_back("c" + std::to_string(i));
  each.id = "each";
  each.kind = "forEach:string";
  chain.id = "chain";
  chain.kind = "component:fkChain";
  chain.component.type = "fkChain";
  chain.component.guides = {rig::Guide{"", "spine", math::Vec3::Zero(), math::Vec3::Zero(), math::Vec3::Ones(), {}}};
  g.nodes = {start, names, each, chain};
  const auto link = [](std::string a, std::string as, std::string b, std::string bs) {
    return rig::GraphLink{{std::move(a), std::move(as)}, {std::move(b), std::move(bs)}, {}};
  };
  g.links = {link("start", "then", "each", "exec"), link("names", "value", "each", "list"),
             link("each", "body", "chain", "exec"), link("each", "element", "chain", "name")};
  for (auto _ : state) {
    rig::BuildGraphCompile c = rig::compile_build_graph(g);
    if (!c.ok()) {
      state.SkipWithError(c.errors.front().str().c_str());
      return;
    }
    benchmark::DoNotOptimize(c.definition.components.size());
  }
  state.SetItemsProcessed(state.iterations() * items);
}
BENCHMARK(BM_graph_compile_for_each)->Arg(100)->Arg(1000)->Arg(9999)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace rigel::bench
