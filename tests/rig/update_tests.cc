// Updates of built rigs from their definitions (manager.h, Build::
// rebuild_changed): built on the rest pose whatever the scene's time, keys
// left bit for bit where nothing moved, a component's own version bump (and
// components added or removed) seen without a rig version bump, and the
// definition's path kept relative to the scene file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "../io/io_test_util.h"
#include "rig_test_util.h"
#include "rigel/io/scene_file.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/ops/anim/nodes.h"
#include "rigel/rig/definition_io.h"
#include "rigel/rig/manager.h"

namespace rigel::rig {
namespace {

namespace fs = std::filesystem;
using graph::NodeId;
using math::Mat4;
using math::Vec3;
using testing::metarig;
namespace xform = scene::xform;

constexpr const char* kArmId = "8e81973e-0bec-47b0-b898-d190f9ebdacc";

// global -> hip -> clavicle_L (fkChain) -> arm_L (limb) on the metarig.
std::string arm_rig(const std::string& arm_version = "1.0", const std::string& rig_version = "1.0",
                    const std::string& extra = "") {
  return R"(<?xml version="1.0" encoding="UTF-8"?>
<rig name="hero" version=")" +
         rig_version + R"(">
  <component type="global" name="global" side="C" version="1.0" rigId="6513270e-269e-4d37-b2a7-4de452e6b438">
    <guide name="main"/>
    <component type="hip" name="hip" side="C" version="1.0" rigId="d23f0824-128b-4f33-8c5c-7fd0a6a3a450">
      <guide name="hip" joint="spine"/>
      <component type="fkChain" name="clavicle" side="L" version="1.0" rigId="0cb1e29c-658c-4a14-95e6-0af593bd04cf">
        <guide joint="shoulder.L"/>
        <component type="limb" name="arm" side="L" version=")" +
         arm_version + R"(" rigId="8e81973e-0bec-47b0-b898-d190f9ebdacc">
          <guide name="upper" joint="upper_arm.L"/>
          <guide name="lower" joint="forearm.L"/>
          <guide name="end" joint="hand.L"/>
        </component>
      </component>
)" + extra +
         R"(    </component>
  </component>
</rig>
)";
}

const std::string kExtraChain = R"(      <component type="fkChain" name="clavicle" side="R" version="1.0" rigId="ae97ba94-d0ed-482f-8f6d-05584ef8aa38">
        <guide joint="shoulder.R"/>
      </component>
)";

Definition parse(const std::string& text) {
  ParseResult p = parse_definition(text, Syntax::kXml, "hero.rig.xml");
  EXPECT_TRUE(p.ok()) << (p.ok() ? "" : p.errors.front().str());
  return p.definition;
}

std::unique_ptr<scene::Scene> copy(scene::Scene& s) {
  auto c = io::parse_scene(io::write_scene(s), "copy", default_registry());
  EXPECT_TRUE(c.is_ok()) << c.status().message();
  return c ? std::move(*c) : nullptr;
}

// Every curve's keys by curve name.
std::map<std::string, std::pair<std::vector<double>, std::string>> curves(graph::Graph& g) {
  std::map<std::string, std::pair<std::vector<double>, std::string>> out;
  for (NodeId id : g.nodes()) {
    if (ops::anim::curve_kind(g, id) == ops::anim::CurveKind::kOther) continue;
    const graph::Node& n = *g.node(id);
    out[n.name()] = {ops::anim::curve_key_times(g, id),
                     io::attribute_to_json(n.value(1), n.type().attr(1)).dump()};  // keyValues
  }
  return out;
}

// The biped-like rig built on the metarig, with the global control keyed
// to turn 90 degrees about y from frame 0 to frame 20.
struct Keyed {
  std::unique_ptr<scene::Scene> scene;
  double frame20 = 0;
};
Keyed keyed_rig() {
  Keyed k;
  k.scene = metarig();
  if (!k.scene) return k;
  auto b = Build::open(*k.scene, parse(arm_rig()), builtin_components());
  EXPECT_TRUE(b.is_ok()) << b.status().message();
  if (!b) return k;
  EXPECT_TRUE((*b)->build_all().is_ok());
  graph::Graph& g = k.scene->graph();
  k.frame20 = 20.0 / g.fps();
  const NodeId global = g.find("hero_global_main");
  EXPECT_TRUE(global.is_valid());
  EXPECT_TRUE(ops::anim::write_channel_key(g, global, xform::kRotate, Vec3(0, 0, 0), 0.0, true).is_ok());
  EXPECT_TRUE(ops::anim::write_channel_key(g, global, xform::kRotate, Vec3(0, 90, 0), k.frame20, true).is_ok());
  return k;
}

// Updates the rig of `scene` (at time `t`) to arm_L 1.1; returns the world
// matrices, at time 0, of the arm's pole and switch controls.
std::vector<Mat4> update_at(scene::Scene& scene, double t, Build::KeepKeys keep = Build::KeepKeys::kLocal) {
  graph::Graph& g = scene.graph();
  g.set_time(t);
  auto b = Build::reopen(scene, "hero", builtin_components());
  EXPECT_TRUE(b.is_ok()) << b.status().message();
  if (!b) return {};
  auto rebuilt = (*b)->rebuild_changed(parse(arm_rig("1.1")), Build::Rebuild::kNewerVersion, keep);
  EXPECT_TRUE(rebuilt.is_ok()) << rebuilt.status().message();
  EXPECT_EQ(rebuilt.is_ok() ? *rebuilt : std::vector<std::string>{}, std::vector<std::string>{kArmId});
  g.set_time(0);
  std::vector<Mat4> out;
  for (const char* a : {"hero:arm_L/pole", "hero:arm_L/switch", "hero:arm_L/ik", "hero:arm_L/fk[0]"})
    out.push_back(scene.world_matrix(testing::at(scene, a)));
  return out;
}

TEST(RigUpdate, builds_on_the_rest_pose_whatever_the_scenes_time) {
  Keyed k = keyed_rig();
  ASSERT_TRUE(k.scene);
  std::vector<Mat4> before;
  for (const char* a : {"hero:arm_L/pole", "hero:arm_L/switch", "hero:arm_L/ik", "hero:arm_L/fk[0]"})
    before.push_back(k.scene->world_matrix(testing::at(*k.scene, a)));
  auto at20 = copy(*k.scene);
  auto between = copy(*k.scene);
  ASSERT_TRUE(at20 && between);
  const auto keys_before = curves(k.scene->graph());
  const std::vector<Mat4> at0 = update_at(*k.scene, 0.0);
  const std::vector<Mat4> later = update_at(*at20, k.frame20);
  const std::vector<Mat4> mid = update_at(*between, k.frame20 * 0.37 + 1e-4);
  ASSERT_EQ(at0.size(), 4u);
  ASSERT_EQ(later.size(), 4u);
  ASSERT_EQ(mid.size(), 4u);
  for (std::size_t i = 0; i < at0.size(); ++i) {
    EXPECT_LE((at0[i] - before[i]).cwiseAbs().maxCoeff(), 1e-12) << "control " << i << " at time 0";
    EXPECT_LE((later[i] - at0[i]).cwiseAbs().maxCoeff(), 1e-12) << "control " << i << " updated at frame 20";
    EXPECT_LE((mid[i] - at0[i]).cwiseAbs().maxCoeff(), 1e-12) << "control " << i << " updated between keys";
  }
  // The same rig whatever the time: the files agree but for the time.
  k.scene->graph().set_time(0);
  at20->graph().set_time(0);
  EXPECT_EQ(testing::normalized(*k.scene), testing::normalized(*at20));
  // The global control's keys are untouched, bit for bit.
  EXPECT_EQ(curves(k.scene->graph()), keys_before);
  EXPECT_EQ(curves(at20->graph()), keys_before);
}

TEST(RigUpdate, keep_keys_world_leaves_keys_that_need_no_change_bit_for_bit) {
  Keyed k = keyed_rig();
  ASSERT_TRUE(k.scene);
  graph::Graph& g = k.scene->graph();
  // Keys on the arm's own controls too, a hair off whole frames.
  const NodeId fk1 = testing::at(*k.scene, "hero:arm_L/fk[1]");
  const NodeId ik = testing::at(*k.scene, "hero:arm_L/ik");
  for (double t : {0.0, k.frame20 * 0.5 + 1e-5, k.frame20}) {
    ASSERT_TRUE(ops::anim::write_channel_key(g, fk1, xform::kRotate, Vec3(10 * t, -20 * t, 5), t, true).is_ok());
    ASSERT_TRUE(ops::anim::write_channel_key(g, ik, xform::kTranslate, Vec3(0.01, 0.1 * t, -0.02), t, true).is_ok());
  }
  const auto keys_before = curves(g);
  const std::size_t nodes_before = g.nodes().size();
  std::vector<Mat4> worlds_before;
  for (double t : {0.0, k.frame20 * 0.5 + 1e-5, k.frame20}) {
    g.set_time(t);
    worlds_before.push_back(k.scene->world_matrix(fk1));
    worlds_before.push_back(k.scene->world_matrix(ik));
  }
  (void)update_at(*k.scene, k.frame20, Build::KeepKeys::kWorld);
  EXPECT_EQ(g.nodes().size(), nodes_before) << "no curves added";
  EXPECT_EQ(curves(g), keys_before) << "every key as it was";
  const NodeId new_fk1 = testing::at(*k.scene, "hero:arm_L/fk[1]");
  const NodeId new_ik = testing::at(*k.scene, "hero:arm_L/ik");
  std::size_t i = 0;
  for (double t : {0.0, k.frame20 * 0.5 + 1e-5, k.frame20}) {
    g.set_time(t);
    EXPECT_LE((k.scene->world_matrix(new_fk1) - worlds_before[i++]).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LE((k.scene->world_matrix(new_ik) - worlds_before[i++]).cwiseAbs().maxCoeff(), 1e-12);
  }
}

// ---- versions per component ----------------------------------------------

struct OnDisk {
  io::testing::TempDir dir;
  fs::path def, scene;
  std::unique_ptr<scene::Scene> built;
};

void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

// The rig built from a definition file, saved beside it.
void build_from_file(OnDisk& d, const std::string& text) {
  d.def = d.dir.path() / "defs" / "hero.rig.xml";
  fs::create_directories(d.def.parent_path());
  write(d.def, text);
  d.built = metarig();
  ASSERT_TRUE(d.built);
  auto added = add_rig(*d.built, d.def, builtin_components());
  ASSERT_TRUE(added.is_ok()) << added.status().message();
}

const ComponentState* state_of(const RigState& s, const std::string& name) {
  for (const ComponentState& c : s.components)
    if (c.name == name) return &c;
  return nullptr;
}

TEST(RigUpdate, a_components_version_alone_makes_the_rig_out_of_date_and_is_rebuilt) {
  OnDisk d;
  build_from_file(d, arm_rig());
  graph::Graph& g = d.built->graph();
  Result<RigState> fresh = rig_state(g, "hero");
  ASSERT_TRUE(fresh.is_ok()) << fresh.status().message();
  EXPECT_TRUE(fresh->definition_found);
  EXPECT_FALSE(fresh->out_of_date);
  for (const ComponentState& c : fresh->components) EXPECT_FALSE(c.out_of_date()) << c.name;

  write(d.def, arm_rig("1.1"));  // the rig's version unchanged
  Result<RigState> bumped = rig_state(g, "hero");
  ASSERT_TRUE(bumped.is_ok());
  EXPECT_TRUE(bumped->out_of_date);
  ASSERT_TRUE(state_of(*bumped, "arm_L"));
  EXPECT_EQ(state_of(*bumped, "arm_L")->kind, ComponentState::Kind::kChanged);
  EXPECT_EQ(state_of(*bumped, "arm_L")->definition_version, "1.1");
  EXPECT_EQ(state_of(*bumped, "clavicle_L")->kind, ComponentState::Kind::kCurrent);
  const nlohmann::ordered_json report = rigs_report(g);
  ASSERT_EQ(report.size(), 1u);
  EXPECT_TRUE(report[0]["outOfDate"].get<bool>());
  for (const auto& c : report[0]["components"]) {
    EXPECT_EQ(c["outOfDate"].get<bool>(), c["name"] == "arm_L") << c.dump();
    EXPECT_EQ(c["state"], c["name"] == "arm_L" ? "changed" : "current") << c.dump();
  }

  const NodeId old_pole = testing::at(*d.built, "hero:arm_L/pole");
  Result<UpdateReport> u = update_rig(*d.built, "hero", builtin_components());
  ASSERT_TRUE(u.is_ok()) << u.status().message();
  EXPECT_TRUE(u->updated);
  EXPECT_EQ(u->rebuilt, std::vector<std::string>{"arm_L"});
  EXPECT_FALSE(g.node(old_pole)) << "the arm was built again";
  Result<RigState> after = rig_state(g, "hero");
  ASSERT_TRUE(after.is_ok());
  EXPECT_FALSE(after->out_of_date);
  Result<UpdateReport> again = update_rig(*d.built, "hero", builtin_components());
  ASSERT_TRUE(again.is_ok());
  EXPECT_FALSE(again->updated);
}

TEST(RigUpdate, components_added_or_removed_without_a_version_bump_are_built_or_removed) {
  OnDisk d;
  build_from_file(d, arm_rig());
  graph::Graph& g = d.built->graph();
  write(d.def, arm_rig("1.0", "1.0", kExtraChain));
  Result<RigState> added = rig_state(g, "hero");
  ASSERT_TRUE(added.is_ok());
  EXPECT_TRUE(added->out_of_date);
  ASSERT_TRUE(state_of(*added, "clavicle_R"));
  EXPECT_EQ(state_of(*added, "clavicle_R")->kind, ComponentState::Kind::kAdded);
  EXPECT_EQ(rigs_report(g)[0]["added"].size(), 1u);
  Result<UpdateReport> u = update_rig(*d.built, "hero", builtin_components());
  ASSERT_TRUE(u.is_ok()) << u.status().message();
  EXPECT_EQ(u->rebuilt, std::vector<std::string>{"clavicle_R"});
  EXPECT_TRUE(resolve_address(g, "hero:clavicle_R/fk[0]").is_ok());

  write(d.def, arm_rig());  // and gone again
  Result<RigState> removed = rig_state(g, "hero");
  ASSERT_TRUE(removed.is_ok());
  ASSERT_TRUE(state_of(*removed, "clavicle_R"));
  EXPECT_EQ(state_of(*removed, "clavicle_R")->kind, ComponentState::Kind::kRemoved);
  Result<UpdateReport> r = update_rig(*d.built, "hero", builtin_components());
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  EXPECT_TRUE(r->updated);
  EXPECT_FALSE(resolve_address(g, "hero:clavicle_R/fk[0]").is_ok());
  EXPECT_FALSE(rig_state(g, "hero")->out_of_date);
}

// ---- the definition's path -----------------------------------------------

TEST(RigUpdate, the_definition_path_is_kept_relative_to_the_scene_file) {
  OnDisk d;
  build_from_file(d, arm_rig());
  d.scene = d.dir.path() / "shots" / "hero.rigel";
  fs::create_directories(d.scene.parent_path());
  ASSERT_TRUE(io::save_scene(*d.built, d.scene).is_ok());
  const std::string text = io::testing::read_text(d.scene);
  EXPECT_NE(text.find("\"definitionPath\": \"../defs/hero.rig.xml\""), std::string::npos) << text.substr(0, 400);

  // Loaded from anywhere, it names the same file.
  const fs::path cwd = fs::current_path();
  fs::current_path(d.dir.path() / "defs");
  auto loaded = io::load_scene(fs::path("..") / "shots" / "hero.rigel", default_registry());
  fs::current_path(cwd);
  ASSERT_TRUE(loaded.is_ok()) << loaded.status().message();
  Result<RigState> state = rig_state((*loaded)->graph(), "hero");
  ASSERT_TRUE(state.is_ok());
  EXPECT_TRUE(state->definition_found) << state->problem;
  EXPECT_EQ(fs::path(state->definition), fs::weakly_canonical(d.def));

  // Saved elsewhere, the path is made relative to the new place.
  const fs::path deeper = d.dir.path() / "a" / "b" / "c.rigel";
  fs::create_directories(deeper.parent_path());
  ASSERT_TRUE(io::save_scene(**loaded, deeper).is_ok());
  EXPECT_NE(io::testing::read_text(deeper).find("\"definitionPath\": \"../../defs/hero.rig.xml\""), std::string::npos);
  auto again = io::load_scene(deeper, default_registry());
  ASSERT_TRUE(again.is_ok());
  EXPECT_TRUE(rig_state((*again)->graph(), "hero")->definition_found);

  // A missing definition is said, naming the path.
  fs::remove(d.def);
  Result<RigState> missing = rig_state((*again)->graph(), "hero");
  ASSERT_TRUE(missing.is_ok());
  EXPECT_FALSE(missing->definition_found);
  EXPECT_NE(missing->problem.find("hero.rig.xml: cannot be read"), std::string::npos) << missing->problem;
  const nlohmann::ordered_json report = rigs_report((*again)->graph());
  EXPECT_FALSE(report[0]["definitionFound"].get<bool>());
  EXPECT_TRUE(report[0]["definitionVersion"].is_null());
  Result<UpdateReport> u = update_rig(**again, "hero", builtin_components());
  ASSERT_FALSE(u.is_ok());
  EXPECT_NE(u.status().message().find(fs::weakly_canonical(d.dir.path()).string() + "/defs/hero.rig.xml"),
            std::string::npos)
      << u.status().message();
}

}  // namespace
}  // namespace rigel::rig
