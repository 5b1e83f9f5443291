// The compiled evaluation against the interpreted reference (issue 19,
// "Evaluation at kernel speed"), as OpenSubdiv checks its backends: every
// scene in tests/data (each glTF character, the BVH motion, the scene
// files) and the example rigs built and keyed on the bundled body,
// evaluated at 20 times both ways (off-frame times included), every value
// of every node equal bit for bit (the two run the same computes in the
// same order; the bound is 1e-12 relative); and random edit
// sequences (drags, keys, constraints added and removed, time changes,
// undo and redo) applied to both keep them equal.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "rigel/app/scene_files.h"
#include "rigel/ephemeral/component.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/graph/graph.h"
#include "rigel/io/scene_file.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/ops/constraints/nodes.h"
#include "rigel/rig/manager.h"
#include "rigel/scene/scene.h"
#include "rigel/scene/transform_types.h"

namespace rigel {
namespace {

namespace fs = std::filesystem;
using graph::AttrIndex;
using graph::Evaluation;
using graph::Graph;
using graph::NodeId;
using graph::Plug;
using graph::Value;
using math::Vec3;

fs::path source(const std::string& relative) { return fs::path(RIGEL_SOURCE_DIR) / relative; }

// Two copies of one scene: the reference and the compiled.
struct Pair {
  std::unique_ptr<scene::Scene> reference, compiled;
};

Pair pair_of(const std::string& text, const std::string& name) {
  Pair p;
  for (auto* slot : {&p.reference, &p.compiled}) {
    auto s = io::parse_scene(text, name, ephemeral::default_registry());
    EXPECT_TRUE(s.is_ok()) << name << ": " << s.status().message();
    if (s) *slot = std::move(*s);
  }
  if (p.reference) p.reference->graph().set_evaluation(Evaluation::kInterpreted);
  if (p.compiled) p.compiled->graph().set_evaluation(Evaluation::kCompiled);
  return p;
}

// Every value of every node, brought up to date by evaluate_all (parallel
// in the compiled scene, serial in the reference), then read: equal bit for
// bit; the first difference named with the time.
::testing::AssertionResult same_values(Graph& a, Graph& b) {
  a.evaluate_all(graph::Execution::kSerial);
  b.evaluate_all(graph::Execution::kParallel);
  const std::vector<NodeId> na = a.nodes(), nb = b.nodes();
  if (na.size() != nb.size()) return ::testing::AssertionFailure() << "node counts differ";
  for (std::size_t i = 0; i < na.size(); ++i) {
    const graph::Node& x = *a.node(na[i]);
    const graph::Node& y = *b.node(nb[i]);
    if (x.name() != y.name()) return ::testing::AssertionFailure() << "nodes differ: " << x.name() << ", " << y.name();
    for (AttrIndex at = 0; at < x.type().attr_count(); ++at) {
      if (x.is_dirty(at) || y.is_dirty(at))
        return ::testing::AssertionFailure() << x.name() << "." << x.type().attr(at).name << " still dirty";
      if (!graph::values_identical(x.value(at), y.value(at))) {
        return ::testing::AssertionFailure() << "at t=" << a.time() << " s, " << x.name() << "." << x.type().attr(at).name
                                             << ": " << graph::value_to_text(x.value(at)) << " (interpreted) vs "
                                             << graph::value_to_text(y.value(at)) << " (compiled)";
      }
    }
  }
  return ::testing::AssertionSuccess();
}

// 20 times over the first 100 frames, most of them between frames.
void expect_equal_at_20_times(Pair& p, const std::string& name) {
  ASSERT_TRUE(p.reference && p.compiled) << name;
  for (int i = 0; i < 20; ++i) {
    const double frame = i * 5.3;
    p.reference->set_frame(frame);
    p.compiled->set_frame(frame);
    ASSERT_TRUE(same_values(p.reference->graph(), p.compiled->graph())) << name << ", frame " << frame;
  }
}

std::string scene_text(const fs::path& path) {
  auto s = app::open_scene(path);
  EXPECT_TRUE(s.is_ok()) << path << ": " << s.status().message();
  return s ? io::write_scene(**s) : std::string();
}

TEST(CompiledEvaluation, every_test_scene_equals_the_interpreted_at_20_times) {
  std::vector<fs::path> files;
  for (const char* folder : {"tests/data/gltf", "tests/data/bvh", "tests/data/scenes"}) {
    for (const auto& entry : fs::directory_iterator(source(folder))) {
      const fs::path& f = entry.path();
      const std::string ext = f.extension().string();
      if (ext != ".glb" && ext != ".gltf" && ext != ".bvh" && ext != ".rigel") continue;
      if (f.filename().string().rfind("malformed_", 0) == 0) continue;  // refused at load, by design
      files.push_back(f);
    }
  }
  files.push_back(source("examples/cmu_131_skeleton.rigel"));
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 14u) << "the glTF characters, the BVH and the scene files";
  for (const fs::path& f : files) {
    SCOPED_TRACE(f.filename().string());
    Pair p = pair_of(scene_text(f), f.filename().string());
    expect_equal_at_20_times(p, f.filename().string());
  }
}

// `character` with an example rig built and every control's rotate keyed at
// four frames (angles from a fixed sequence), as text.
std::string keyed_rig_on(const std::string& definition, const std::string& character) {
  auto s = app::open_scene(source(character));
  EXPECT_TRUE(s.is_ok()) << s.status().message();
  if (!s) return {};
  auto added = rig::add_rig(**s, source(definition), ephemeral::components());
  EXPECT_TRUE(added.is_ok()) << definition << ": " << added.status().message();
  Graph& g = (*s)->graph();
  std::uint32_t seed = 4321;
  auto angle = [&] {
    seed = seed * 1664525u + 1013904223u;
    return static_cast<double>(seed >> 8) / static_cast<double>(1u << 24) * 40.0 - 20.0;
  };
  int keyed = 0;
  for (NodeId id : g.nodes()) {
    if (g.node(id)->type().name() != scene::kControlType) continue;
    for (double frame : {0.0, 31.5, 64.0, 99.0}) {
      const Vec3 r(angle(), angle(), angle());
      if (ops::anim::write_channel_key(g, id, scene::xform::kRotate, Value(r), frame / g.fps(), true)) ++keyed;
    }
  }
  EXPECT_GT(keyed, 40) << definition << ": controls keyed";
  return io::write_scene(**s);
}

// The bundled skinned body (10,037 vertices) under a rig.
std::string keyed_rig_on_body(const std::string& definition) {
  return keyed_rig_on(definition, "tests/data/gltf/rigify_human_body.glb");
}

TEST(CompiledEvaluation, example_rigs_built_and_keyed_on_the_body_equal_the_interpreted_at_20_times) {
  const std::pair<const char*, const char*> examples[] = {
      {"examples/biped.rig.xml", "tests/data/gltf/rigify_human_body.glb"},
      {"examples/puppet.rig.xml", "tests/data/gltf/rigify_human_body.glb"},
      {"examples/quadruped.rig.xml", "examples/quadruped.rigel"}};
  for (const auto& [definition, character] : examples) {
    SCOPED_TRACE(definition);
    Pair p = pair_of(keyed_rig_on(definition, character), definition);
    expect_equal_at_20_times(p, definition);
  }
}

// "c1", "c2", ... (built by insert: GCC 12 warns falsely on "c" + to_string).
std::string constraint_name(int k) {
  std::string name = std::to_string(k);
  name.insert(name.begin(), 'c');
  return name;
}

std::vector<std::string> names_of_type(Graph& g, const std::string& type) {
  std::vector<std::string> out;
  for (NodeId id : g.nodes())
    if (g.node(id)->type().name() == type) out.push_back(g.node(id)->name());
  return out;
}

TEST(CompiledEvaluation, random_edit_sequences_keep_the_compiled_equal_to_the_interpreted) {
  Pair p = pair_of(keyed_rig_on_body("examples/biped.rig.xml"), "biped");
  ASSERT_TRUE(p.reference && p.compiled);
  for (auto* s : {&p.reference, &p.compiled}) {
    (*s)->graph().clear_history();
    ASSERT_TRUE((*s)->graph().create_node(scene::kLocatorType, "driven").is_ok());
  }
  const std::vector<std::string> controls = names_of_type(p.reference->graph(), scene::kControlType);
  ASSERT_GT(controls.size(), 20u);
  // The same edit, by names, in both scenes.
  const auto both = [&](auto&& fn) {
    fn(*p.reference);
    fn(*p.compiled);
  };
  std::mt19937 rng(2026);
  auto pick = [&](std::size_t n) { return std::uniform_int_distribution<std::size_t>(0, n - 1)(rng); };
  auto uniform = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
  int constraints = 0;
  for (int step = 0; step < 60; ++step) {
    const int kind = static_cast<int>(pick(7));
    const std::string control = controls[pick(controls.size())];
    const Vec3 v(uniform(-20, 20), uniform(-20, 20), uniform(-20, 20));
    const double frame = uniform(0, 100);
    std::string what;
    switch (kind) {
      case 0:  // a drag: translate and rotate set (one undo step each)
        what = "drag " + control;
        both([&](scene::Scene& s) {
          Graph& g = s.graph();
          const NodeId id = g.find(control);
          (void)g.set_value(Plug{id, scene::xform::kTranslate, -1}, Value(Vec3(v * 0.01)));
          (void)g.set_value(Plug{id, scene::xform::kRotate, -1}, Value(v));
        });
        break;
      case 1:  // a key a hair off a frame
        what = "key " + control;
        both([&](scene::Scene& s) {
          Graph& g = s.graph();
          (void)ops::anim::write_channel_key(g, g.find(control), scene::xform::kRotate, Value(v), frame / g.fps(), true);
        });
        break;
      case 2:  // a constraint added: the control drives the locator
        what = "constraint added from " + control;
        ++constraints;
        both([&](scene::Scene& s) {
          Graph& g = s.graph();
          graph::Transaction t(g, "add constraint");
          auto made = g.create_node(ops::constraints::kParentConstraintType, constraint_name(constraints));
          ASSERT_TRUE(made.is_ok());
          const NodeId driven = g.find("driven");
          (void)g.disconnect_input(Plug{driven, scene::xform::kTranslate, -1});
          ASSERT_TRUE(g.connect(Plug{g.find(control), scene::xform::kWorldMatrix, -1}, *g.plug_find(*made, "targetWorldMatrix", 0)).is_ok());
          ASSERT_TRUE(g.connect(*g.plug_find(*made, "translate"), Plug{driven, scene::xform::kTranslate, -1}).is_ok());
        });
        break;
      case 3:  // the last constraint removed
        what = "constraint removed";
        both([&](scene::Scene& s) {
          Graph& g = s.graph();
          for (int c = constraints; c > 0; --c) {
            const NodeId id = g.find(constraint_name(c));
            if (id.is_valid()) {
              ASSERT_TRUE(g.delete_node(id).is_ok());
              break;
            }
          }
        });
        break;
      case 4:
        what = "undo";
        both([&](scene::Scene& s) { (void)s.graph().undo(); });
        break;
      case 5:
        what = "redo";
        both([&](scene::Scene& s) { (void)s.graph().redo(); });
        break;
      default:
        what = "time";
        both([&](scene::Scene& s) { s.set_frame(frame); });
        break;
    }
    ASSERT_TRUE(same_values(p.reference->graph(), p.compiled->graph())) << "step " << step << ": " << what;
  }
  EXPECT_GT(constraints, 3) << "the sequence added constraints";
}

}  // namespace
}  // namespace rigel
