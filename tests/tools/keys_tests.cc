// Keys on any keyable channel (tools/keys.h): a built rig's controls and
// its fkIk switch on the bundled character with examples/biped.rig.xml.

#include "rigel/tools/keys.h"
#include "rigel/tools/tween.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "rigel/ephemeral/component.h"
#include "rigel/ephemeral/keying.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/io/gltf_import.h"
#include "rigel/io/scene_file.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/ops/util/blend.h"
#include "rigel/rig/manager.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"
#include "../io/io_test_util.h"
#include "tools_test_util.h"

namespace rigel::tools {
namespace {

namespace fs = std::filesystem;
using graph::NodeId;
using graph::Plug;
using graph::Value;
namespace xform = scene::xform;


using testing::at;

std::unique_ptr<scene::Scene> biped() { return testing::built_rig(); }

std::vector<std::string> names(const graph::Node& n, const std::vector<graph::AttrIndex>& attrs) {
  std::vector<std::string> out;
  for (graph::AttrIndex a : attrs) out.push_back(n.type().attr(a).name);
  return out;
}

double scalar(graph::Graph& g, const Plug& p) {
  auto v = g.evaluate(p);
  EXPECT_TRUE(v.is_ok()) << v.status().message();
  return v ? std::get<double>(*v) : std::nan("");
}

TEST(Keys, the_keyable_channels_of_a_control_and_of_a_switch) {
  auto s = biped();
  const graph::Graph& g = s->graph();
  const NodeId fk = g.find("hero_arm_L_fk1");
  ASSERT_TRUE(fk.is_valid());
  EXPECT_EQ(names(*g.node(fk), keyable_attrs(*g.node(fk))), (std::vector<std::string>{"translate", "rotate", "scale"}));
  const NodeId sw = at(g, "hero:arm_L/fkIkSwitch");
  ASSERT_TRUE(sw.is_valid());
  EXPECT_EQ(names(*g.node(sw), keyable_attrs(*g.node(sw))), (std::vector<std::string>{"fkIk"}));
}

TEST(Keys, a_built_rigs_control_is_keyed_at_two_frames_and_interpolates_between) {
  auto s = biped();
  graph::Graph& g = s->graph();
  const NodeId fk = g.find("hero_arm_L_fk1");
  auto channels = channels_of(g, {fk});
  ASSERT_TRUE(channels.is_ok()) << channels.status().message();
  ASSERT_EQ(channels->size(), 3u);
  s->set_frame(0);
  ASSERT_TRUE(set_keys(g, *channels).is_ok());
  EXPECT_TRUE(g.can_undo());
  s->set_frame(10);
  // A drag at frame 10 writes the rotation (a key there), then the key
  // takes every channel's current value.
  ASSERT_TRUE(ephemeral::write_channel(g, fk, xform::kRotate, Value(math::Vec3(0, 0, 40)), true).is_ok());
  ASSERT_TRUE(set_keys(g, *channels).is_ok());
  s->set_frame(5);
  const auto r = std::get<math::Vec3>(*g.evaluate(Plug{fk, xform::kRotate, -1}));
  EXPECT_GT(r.z(), 1.0);
  EXPECT_LT(r.z(), 39.0);
  const std::vector<PlugKeys> keys = keys_of(g, *channels);
  ASSERT_EQ(keys.size(), 9u) << "translate, rotate and scale, a curve per component";
  for (const PlugKeys& k : keys) {
    ASSERT_EQ(k.times.size(), 2u) << k.name;
    EXPECT_NEAR(k.times[1] * g.fps(), 10.0, 1e-9) << k.name;
    ASSERT_EQ(k.values.size(), 2u) << k.name;
  }
  EXPECT_EQ(keys[5].name, "hero_arm_L_fk1.rotateZ");
  EXPECT_DOUBLE_EQ(std::get<double>(keys[5].values[1]), 40.0);

  // Saved and read back, the keys are there.
  io::testing::TempDir dir;
  ASSERT_TRUE(io::save_scene(*s, dir.path() / "keyed.rigel").is_ok());
  auto loaded = io::load_scene(dir.path() / "keyed.rigel", ephemeral::default_registry());
  ASSERT_TRUE(loaded.is_ok()) << loaded.status().message();
  graph::Graph& lg = (*loaded)->graph();
  auto again = channels_of(lg, {lg.find("hero_arm_L_fk1")});
  ASSERT_TRUE(again.is_ok());
  EXPECT_EQ(keys_of(lg, *again).size(), 9u);
}

TEST(Keys, the_fk_ik_switch_takes_keyed_values_and_a_key_a_hair_off_a_frame_is_that_frames) {
  auto s = biped();
  graph::Graph& g = s->graph();
  const NodeId sw = at(g, "hero:arm_L/fkIkSwitch");
  auto channels = channels_of(g, {sw}, {"fkIk"});
  ASSERT_TRUE(channels.is_ok()) << channels.status().message();
  const Plug fk_ik{sw, ops::util::fk_ik_attr::kFkIk, -1};
  s->set_frame(0);
  ASSERT_TRUE(set_keys(g, *channels, 0.0).is_ok());
  s->set_frame(20);
  ASSERT_TRUE(set_keys(g, *channels, 1.0).is_ok());
  s->set_frame(10);
  const double mid = scalar(g, fk_ik);
  EXPECT_GT(mid, 0.0);
  EXPECT_LT(mid, 1.0);
  // Frame 20 and a hair: the key at 20 takes the value, no new key.
  g.set_time((20.0 + 1e-5) / g.fps());
  ASSERT_TRUE(set_keys(g, *channels, 0.5).is_ok());
  const std::vector<PlugKeys> keys = keys_of(g, *channels);
  ASSERT_EQ(keys.size(), 1u);
  ASSERT_EQ(keys[0].times.size(), 2u);
  EXPECT_DOUBLE_EQ(std::get<double>(keys[0].values[1]), 0.5);
  EXPECT_EQ(keys[0].name, g.plug_name(fk_ik));
}

TEST(Keys, deleting_keys_and_one_undo_step_per_edit) {
  auto s = biped();
  graph::Graph& g = s->graph();
  const NodeId sw = at(g, "hero:arm_L/fkIkSwitch");
  auto channels = channels_of(g, {sw}, {"fkIk"});
  ASSERT_TRUE(channels.is_ok());
  const Plug fk_ik{sw, ops::util::fk_ik_attr::kFkIk, -1};
  s->set_frame(0);
  ASSERT_TRUE(set_keys(g, *channels, 1.0).is_ok());
  s->set_frame(8);
  ASSERT_TRUE(set_keys(g, *channels, 0.0).is_ok());
  s->set_frame(4);
  const Status none = delete_keys(g, *channels);
  EXPECT_EQ(none.code(), ErrorCode::kNotFound) << none.message();
  s->set_frame(8);
  ASSERT_TRUE(delete_keys(g, *channels).is_ok());
  ASSERT_EQ(keys_of(g, *channels).at(0).times.size(), 1u);
  s->set_frame(0);
  ASSERT_TRUE(delete_keys(g, *channels).is_ok());
  EXPECT_TRUE(keys_of(g, *channels).empty()) << "the last key takes its curve with it";
  EXPECT_DOUBLE_EQ(scalar(g, fk_ik), 1.0) << "and the channel keeps its value";
  ASSERT_TRUE(g.undo());
  EXPECT_EQ(keys_of(g, *channels).at(0).times.size(), 1u) << "one undo step gives the key back";
}

TEST(Keys, a_built_rigs_character_is_one_keying_group_and_a_key_is_a_pose) {
  auto s = biped();
  graph::Graph& g = s->graph();
  const NodeId fk = g.find("hero_arm_L_fk1");
  const std::vector<NodeId> group = keying_group(g, {fk});
  ASSERT_GT(group.size(), 10u);
  auto has = [&](const std::string& name) { return std::find(group.begin(), group.end(), g.find(name)) != group.end(); };
  EXPECT_TRUE(has("hero_arm_L_fk1"));
  EXPECT_TRUE(has("hero_global_main"));
  EXPECT_TRUE(has("hero_arm_L_pole"));
  for (NodeId c : group) EXPECT_EQ(g.node(c)->type().name(), scene::kControlType) << g.node(c)->name();
  EXPECT_EQ(keying_group(g, {fk, g.find("hero_global_main")}), group) << "one group for the character";
  const NodeId sw = at(g, "hero:arm_L/fkIkSwitch");
  EXPECT_EQ(keying_group(g, {sw}), std::vector<NodeId>{sw}) << "a node that is no control stands for itself";

  auto channels = channels_of(g, group);
  ASSERT_TRUE(channels.is_ok()) << channels.status().message();
  s->set_frame(12);
  ASSERT_TRUE(set_keys(g, *channels).is_ok());
  const std::vector<PlugKeys> keys = keys_of(g, *channels);
  EXPECT_EQ(keys.size(), 3 * channels->size()) << "every channel of every control, a curve per component";
  for (const PlugKeys& k : keys) {
    ASSERT_EQ(k.times.size(), 1u) << k.name;
    EXPECT_NEAR(k.times[0] * g.fps(), 12.0, 1e-9) << k.name;
  }
  ASSERT_TRUE(g.undo());
  EXPECT_TRUE(keys_of(g, *channels).empty()) << "the whole pose was one undo step";
}

TEST(Keys, bad_channels_and_values_name_the_input) {
  auto s = biped();
  graph::Graph& g = s->graph();
  const NodeId fk = g.find("hero_arm_L_fk1");
  auto bad = channels_of(g, {fk}, {"fkIk"});
  ASSERT_FALSE(bad.is_ok());
  EXPECT_EQ(bad.status().field(), "attrs");
  EXPECT_NE(bad.status().message().find("keyable: translate, rotate, scale"), std::string::npos) << bad.status().message();
  auto hidden = channels_of(g, {fk}, {"worldMatrix"});
  EXPECT_FALSE(hidden.is_ok());
  auto channels = channels_of(g, {fk}, {"rotate"});
  ASSERT_TRUE(channels.is_ok());
  const Status vec_value = set_keys(g, *channels, 3.0);
  EXPECT_EQ(vec_value.field(), "value") << vec_value.message();
  auto sw = channels_of(g, {at(g, "hero:arm_L/fkIkSwitch")}, {"fkIk"});
  ASSERT_TRUE(sw.is_ok());
  EXPECT_EQ(set_keys(g, *sw, std::numeric_limits<double>::quiet_NaN()).field(), "value");
  EXPECT_FALSE(g.can_undo()) << "nothing changed";
  auto nothing = channels_of(g, {});
  EXPECT_EQ(nothing.status().field(), "controls");
}

}  // namespace
}  // namespace rigel::tools


namespace rigel::tools {
namespace {

// Tween: at 0 and 1 the neighbouring keys, at 0.5 the halfway blend
// (translate linear, rotation by slerp), beyond 1 an overshoot; channels
// without keys on both sides are left; bad fractions refused.
TEST(Tween, blends_between_the_previous_and_the_next_key) {
  auto s = biped();
  graph::Graph& g = s->graph();
  const NodeId fk = g.find("hero_arm_L_fk1");
  auto key = [&](double frame, const math::Vec3& t, const math::Vec3& r) {
    g.set_time(frame / g.fps());
    ASSERT_TRUE(ops::anim::write_channel_key(g, fk, xform::kTranslate, Value(t), g.time(), true).is_ok());
    ASSERT_TRUE(ops::anim::write_channel_key(g, fk, xform::kRotate, Value(r), g.time(), true).is_ok());
  };
  key(0, math::Vec3(0, 0, 0), math::Vec3(0, 0, 0));
  key(20, math::Vec3(0.2, 0, 0), math::Vec3(0, 90, 0));
  auto channels = channels_of(g, {fk}, {"translate", "rotate"});
  ASSERT_TRUE(channels.is_ok());
  auto at = [&](double f) {
    g.set_time(10 / g.fps());
    EXPECT_TRUE(tween(g, *channels, f, true).is_ok());
    return std::pair{std::get<math::Vec3>(*g.evaluate(Plug{fk, xform::kTranslate, -1})),
                     std::get<math::Vec3>(*g.evaluate(Plug{fk, xform::kRotate, -1}))};
  };
  auto [t0, r0] = at(0.0);
  EXPECT_LT((t0 - math::Vec3(0, 0, 0)).norm(), 1e-12);
  EXPECT_LT(r0.norm(), 1e-9);
  auto [t1, r1] = at(1.0);
  EXPECT_LT((t1 - math::Vec3(0.2, 0, 0)).norm(), 1e-12);
  EXPECT_LT((r1 - math::Vec3(0, 90, 0)).norm(), 1e-9);
  auto [th, rh] = at(0.5);
  EXPECT_LT((th - math::Vec3(0.1, 0, 0)).norm(), 1e-12);
  EXPECT_LT((rh - math::Vec3(0, 45, 0)).norm(), 1e-9) << "slerp halfway about the one axis";
  auto [to, ro] = at(1.5);
  EXPECT_LT((to - math::Vec3(0.3, 0, 0)).norm(), 1e-12) << "overshoot";
  EXPECT_LT((ro - math::Vec3(0, 135, 0)).norm(), 1e-9);
  // One undo step per tween; keyed at frame 10.
  EXPECT_EQ(g.undo_label(), "tween");
  for (const PlugKeys& k : keys_of(g, *channels)) EXPECT_EQ(k.times.size(), 3u) << k.name;
  // Outside the keys: nothing on both sides, nothing blended.
  g.set_time(30 / g.fps());
  auto none = tween(g, *channels, 0.5, true);
  ASSERT_TRUE(none.is_ok());
  EXPECT_EQ(*none, 0u);
  EXPECT_EQ(tween(g, *channels, std::nan(""), true).status().field(), "fraction");
  EXPECT_FALSE(tween(g, *channels, 50, true).is_ok());
}

}  // namespace
}  // namespace rigel::tools
