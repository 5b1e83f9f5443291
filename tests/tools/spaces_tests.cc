// Spaces (rig/spaces.h) and space switches and bakes (tools/spaces.h) on
// the biped of examples/biped.rig.xml built on the metarig: the limbs'
// IK controls come with their default spaces and stand where they were
// built; a switch at a frame keeps the control's world matrix there and
// every earlier frame as it was, with no key on the control; a bake keeps
// the world motion over its range, keyed on its frames only; custom spaces
// follow any transform; bad input is refused changing nothing.

#include "rigel/tools/spaces.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "rigel/math/transform.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/rig/meta.h"
#include "rigel/rig/spaces.h"
#include "rigel/scene/transform_types.h"
#include "rigel/tools/keys.h"
#include "tools_test_util.h"

namespace rigel::tools {
namespace {

using graph::NodeId;
using graph::Value;
using math::Mat4;
using math::Vec3;
namespace xform = scene::xform;
namespace anim = ops::anim;
using testing::at;

double difference(const Mat4& a, const Mat4& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1.0, b.cwiseAbs().maxCoeff());
}

void key(scene::Scene& s, NodeId node, graph::AttrIndex attr, double frame, const Vec3& v) {
  ASSERT_TRUE(anim::write_channel_key(s.graph(), node, attr, Value(v), frame / s.graph().fps(), true).is_ok());
}

std::vector<std::string> names(const rig::ControlSpaces& s) {
  std::vector<std::string> out;
  for (const rig::Space& space : s.spaces) out.push_back(space.name);
  return out;
}

// The biped with its global, chest and left arm animated over 0..30: the
// spaces move differently from each other and the IK control moves in its own.
std::unique_ptr<scene::Scene> animated() {
  auto s = testing::built_rig();
  if (!s) return nullptr;
  const graph::Graph& g = s->graph();
  const NodeId global = at(g, "hero:global/main"), chest = at(g, "hero:chest/main"), ik = at(g, "hero:arm_L/ik");
  key(*s, global, xform::kTranslate, 0, Vec3(0, 0, 0));
  key(*s, global, xform::kTranslate, 30, Vec3(0.4, 0, 0.9));
  key(*s, chest, xform::kRotate, 0, Vec3(0, 0, 0));
  key(*s, chest, xform::kRotate, 30, Vec3(10, 35, -20));
  key(*s, ik, xform::kTranslate, 0, Vec3(0, 0, 0));
  key(*s, ik, xform::kTranslate, 12, Vec3(0.1, 0.2, -0.05));
  key(*s, ik, xform::kTranslate, 30, Vec3(-0.1, 0.3, 0.1));
  key(*s, ik, xform::kRotate, 0, Vec3(0, 0, 0));
  key(*s, ik, xform::kRotate, 30, Vec3(30, -20, 45));
  s->graph().clear_history();
  return s;
}

std::vector<Mat4> worlds(scene::Scene& s, NodeId node, int first, int last) {
  std::vector<Mat4> out;
  for (int f = first; f <= last; ++f) {
    s.set_frame(f);
    out.push_back(s.world_matrix(node));
  }
  return out;
}

std::vector<double> key_times(const graph::Graph& g, NodeId node) {
  std::vector<double> out;
  for (const PlugKeys& k : keys_of(g, *channels_of(g, {node}, {"translate", "rotate"})))
    for (double t : k.times) out.push_back(std::round(t * g.fps() * 1e6) / 1e6);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

TEST(Spaces, LimbsComeWithTheirDefaultSpacesAndStayWhereTheyWereBuilt) {
  auto s = testing::built_rig();
  ASSERT_TRUE(s);
  graph::Graph& g = s->graph();
  const rig::ControlSpaces arm = rig::spaces_of(*s, at(g, "hero:arm_L/ik"));
  EXPECT_EQ(names(arm), (std::vector<std::string>{"parent", "world", "global", "chest", "head"}));
  EXPECT_EQ(arm.current, 0);
  EXPECT_EQ(arm.spaces[2].target, at(g, "hero:global/main"));
  EXPECT_EQ(arm.spaces[4].target, at(g, "hero:neck/head"));
  EXPECT_FALSE(arm.spaces[1].target.is_valid());
  EXPECT_EQ(names(rig::spaces_of(*s, at(g, "hero:leg_R/ik"))), (std::vector<std::string>{"parent", "world", "global", "hip"}));
  // Nameless: the switch is the component's, by role.
  EXPECT_EQ(at(g, "hero:arm_L/ikSpaceSwitch"), arm.node);
  for (const char* c : {"hero:arm_L/ik", "hero:arm_R/ik", "hero:leg_L/ik", "hero:leg_R/ik"}) {
    const NodeId ik = at(g, c);
    EXPECT_LT(difference(s->world_matrix(ik), *rig::rest_world(g, ik)), 1e-12) << c;
  }
  // FK controls have none.
  EXPECT_FALSE(rig::spaces_of(*s, at(g, "hero:arm_L/fk[0]")).node.is_valid());
}

TEST(Spaces, SwitchKeepsTheWorldMatrixThereAndEveryEarlierFrame) {
  auto s = animated();
  ASSERT_TRUE(s);
  graph::Graph& g = s->graph();
  const NodeId ik = at(g, "hero:arm_L/ik");
  const std::vector<Mat4> before = worlds(*s, ik, 0, 30);
  const std::vector<double> keys_before = key_times(g, ik);
  s->set_frame(3);
  SpaceSwitchOptions o;
  o.space = "world";
  o.frame = 10;
  auto r = switch_space(*s, ik, o);
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  EXPECT_EQ(r->from, "parent");
  EXPECT_EQ(r->to, "world");
  EXPECT_LT(r->max_error, 1e-9);
  EXPECT_DOUBLE_EQ(s->frame(), 3);  // time put back
  const std::vector<Mat4> after = worlds(*s, ik, 0, 30);
  for (int f = 0; f < 10; ++f) EXPECT_LT(difference(after[f], before[f]), 1e-12) << "frame " << f;
  EXPECT_LT(difference(after[10], before[10]), 1e-9);
  // No key on the control: its own curves are as they were.
  EXPECT_EQ(key_times(g, ik), keys_before);
  // From 10 on it follows the world: its channels act under a fixed matrix.
  s->set_frame(10);
  const Mat4 fixed = after[10] * math::affine_inverse(s->local_matrix(ik));
  for (int f = 11; f <= 30; ++f) {
    s->set_frame(f);
    EXPECT_LT(difference(after[f], fixed * s->local_matrix(ik)), 1e-9) << "frame " << f;
  }
  s->set_frame(20);
  EXPECT_EQ(rig::spaces_of(*s, ik).current, 1);
  // One undo step gives everything back.
  ASSERT_TRUE(g.undo());
  const std::vector<Mat4> undone = worlds(*s, ik, 0, 30);
  for (int f = 0; f <= 30; ++f) EXPECT_LT(difference(undone[f], before[f]), 1e-12) << "frame " << f;
}

TEST(Spaces, SwitchesInARowEachKeepTheirFrame) {
  auto s = animated();
  ASSERT_TRUE(s);
  const NodeId ik = at(s->graph(), "hero:arm_L/ik");
  for (auto [space, frame] : {std::pair{"chest", 8.0}, {"global", 16.0}, {"head", 16.4}, {"parent", 24.0}}) {
    s->set_frame(frame);
    const Mat4 there = s->world_matrix(ik);
    SpaceSwitchOptions o;
    o.space = space;
    auto r = switch_space(*s, ik, o);
    ASSERT_TRUE(r.is_ok()) << r.status().message();
    s->set_frame(frame);
    EXPECT_LT(difference(s->world_matrix(ik), there), 1e-9) << space;
  }
}

TEST(Spaces, BakeKeepsTheWorldMotionOverTheRangeKeyedOnItsFramesOnly) {
  auto s = animated();
  ASSERT_TRUE(s);
  graph::Graph& g = s->graph();
  const NodeId ik = at(g, "hero:arm_L/ik");
  const std::vector<Mat4> before = worlds(*s, ik, 0, 30);
  SpaceSwitchOptions o;
  o.space = "chest";
  o.first = 5;
  o.last = 25;
  auto r = switch_space(*s, ik, o);
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  EXPECT_EQ(r->frames, 21u);
  EXPECT_LT(r->max_error, 1e-6);
  const std::vector<Mat4> after = worlds(*s, ik, 0, 30);
  for (int f = 5; f <= 25; ++f) EXPECT_LT(difference(after[f], before[f]), 1e-6) << "frame " << f;
  for (double t : key_times(g, ik)) EXPECT_TRUE((t >= 5 && t <= 25) || t == 0 || t == 30) << "a key at frame " << t;
  EXPECT_EQ(key_times(g, ik).size(), 21u + 2u);
}

TEST(Spaces, CustomSpaceFollowsAnyTransformWithoutMovingTheControl) {
  auto s = animated();
  ASSERT_TRUE(s);
  graph::Graph& g = s->graph();
  const NodeId pole = at(g, "hero:arm_L/pole");
  const NodeId prop = g.find("hand.R");
  ASSERT_TRUE(prop.is_valid());
  s->set_frame(6);
  const std::vector<Mat4> before = worlds(*s, pole, 0, 30);
  s->set_frame(6);
  auto added = rig::add_space(*s, pole, "prop", prop);
  ASSERT_TRUE(added.is_ok()) << added.status().message();
  EXPECT_EQ(*added, 1);
  EXPECT_EQ(names(rig::spaces_of(*s, pole)), (std::vector<std::string>{"parent", "prop"}));
  const std::vector<Mat4> same = worlds(*s, pole, 0, 30);
  for (int f = 0; f <= 30; ++f) EXPECT_LT(difference(same[f], before[f]), 1e-12) << "frame " << f;
  // Followed from frame 6: the pole keeps its offset to the right hand.
  SpaceSwitchOptions o;
  o.space = "prop";
  o.frame = 6;
  ASSERT_TRUE(switch_space(*s, pole, o).is_ok());
  s->set_frame(6);
  const Mat4 offset = math::affine_inverse(s->world_matrix(prop)) * s->world_matrix(pole);
  EXPECT_LT(difference(s->world_matrix(pole), before[6]), 1e-9);
  for (int f = 7; f <= 30; f += 5) {
    s->set_frame(f);
    EXPECT_LT(difference(math::affine_inverse(s->world_matrix(prop)) * s->world_matrix(pole), offset), 1e-9) << f;
  }
}

TEST(Spaces, BadInputIsRefusedChangingNothing) {
  auto s = animated();
  ASSERT_TRUE(s);
  graph::Graph& g = s->graph();
  const NodeId ik = at(g, "hero:arm_L/ik");
  const std::size_t nodes = g.nodes().size();
  // A target that follows the control (its own hand joint) would be a cycle.
  auto cycle = rig::add_space(*s, ik, "hand", g.find("hand.L"));
  ASSERT_FALSE(cycle.is_ok());
  EXPECT_EQ(cycle.status().field(), "target");
  EXPECT_EQ(rig::add_space(*s, ik, "self", ik).status().field(), "target");
  EXPECT_EQ(rig::add_space(*s, ik, "world", {}).status().field(), "space");        // taken
  EXPECT_EQ(rig::add_space(*s, ik, "no good", {}).status().field(), "space");      // not an identifier
  EXPECT_EQ(g.nodes().size(), nodes);
  EXPECT_EQ(names(rig::spaces_of(*s, ik)).size(), 5u);
  SpaceSwitchOptions o;
  o.space = "moon";
  auto unknown = switch_space(*s, ik, o);
  ASSERT_FALSE(unknown.is_ok());
  EXPECT_EQ(unknown.status().field(), "space");
  EXPECT_NE(unknown.status().message().find("chest"), std::string::npos) << unknown.status().message();
  o.space = "world";
  auto none = switch_space(*s, at(g, "hero:arm_L/fk[0]"), o);
  ASSERT_FALSE(none.is_ok());
  EXPECT_EQ(none.status().field(), "control");
  o.first = 20;
  o.last = 10;
  EXPECT_EQ(switch_space(*s, ik, o).status().field(), "frames");
  EXPECT_FALSE(g.can_undo());
}

}  // namespace
}  // namespace rigel::tools
