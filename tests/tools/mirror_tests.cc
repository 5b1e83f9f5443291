// Mirror and flip (tools/mirror.h), and bind pose resets
// (tools/bind_pose.h), on the biped of examples/biped.rig.xml
// built on the metarig: mirrored twice gives the pose back, a symmetric pose
// flips onto itself, the mirrored side's joints are the reflection of the
// posed side's, pairs are found without names, ranges are keyed on their
// frames only, and bad input is refused changing nothing.

#include "rigel/tools/mirror.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "rigel/ephemeral/component.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/io/gltf_import.h"
#include "rigel/math/rotation.h"
#include "rigel/math/transform.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/ops/util/blend.h"
#include "rigel/ops/util/foot.h"
#include "rigel/rig/manager.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"
#include "rigel/tools/bind_pose.h"
#include "../io/io_test_util.h"
#include "tools_test_util.h"

namespace rigel::tools {
namespace {

namespace fs = std::filesystem;
using graph::NodeId;
using graph::Plug;
using graph::Value;
using math::Mat4;
using math::Vec3;
namespace xform = scene::xform;


using testing::at;

std::unique_ptr<scene::Scene> built(const fs::path& definition = testing::source("examples/biped.rig.xml")) {
  return testing::built_rig(definition);
}

const std::vector<std::string> kLeft = {"hero:arm_L/fk[0]", "hero:arm_L/fk[1]", "hero:arm_L/fk[2]", "hero:arm_L/ik",
                                        "hero:arm_L/pole",  "hero:leg_L/fk[0]", "hero:leg_L/ik",    "hero:foot_L/foot"};
std::string right_of(const std::string& address) {
  std::string r = address;
  r.replace(r.find("_L/"), 3, "_R/");
  return r;
}

// An asymmetric pose on the left: each control turned, moved and (fk0)
// scaled differently.
void pose_left(scene::Scene& s) {
  graph::Graph& g = s.graph();
  int i = 0;
  for (const std::string& a : kLeft) {
    const NodeId c = at(g, a);
    ++i;
    ASSERT_TRUE(g.set_value(Plug{c, xform::kRotate, -1}, Value(Vec3(7.0 * i, -11.0 + 3 * i, 5.0 - 2 * i))).is_ok()) << a;
    ASSERT_TRUE(g.set_value(Plug{c, xform::kTranslate, -1}, Value(Vec3(0.01 * i, -0.02, 0.015 * i))).is_ok()) << a;
  }
}

std::map<std::string, Mat4> channels(scene::Scene& s, const std::vector<std::string>& addresses) {
  std::map<std::string, Mat4> out;
  for (const std::string& a : addresses) out[a] = std::get<Mat4>(s.graph().evaluate(at(s.graph(), a), xform::kMatrix));
  return out;
}

double worst(const std::map<std::string, Mat4>& a, const std::map<std::string, Mat4>& b) {
  double w = 0;
  for (const auto& [k, m] : a) w = std::max(w, (m - b.at(k)).cwiseAbs().maxCoeff());
  return w;
}

std::vector<NodeId> ids(const graph::Graph& g, const std::vector<std::string>& addresses) {
  std::vector<NodeId> out;
  for (const std::string& a : addresses) out.push_back(at(g, a));
  return out;
}

std::vector<std::string> rights() {
  std::vector<std::string> out;
  for (const std::string& a : kLeft) out.push_back(right_of(a));
  return out;
}

TEST(Mirror, the_right_side_becomes_the_reflection_and_mirroring_back_gives_the_pose) {
  auto s = built();
  graph::Graph& g = s->graph();
  pose_left(*s);
  const auto left = channels(*s, kLeft);
  MirrorOptions o;
  o.controls = ids(g, kLeft);
  auto r = mirror(*s, o);
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  EXPECT_EQ(r->set.size(), kLeft.size());
  // The joints the arm and leg drive: the right ones at the reflection of the left ones.
  auto reflect = [](const Vec3& p) { return Vec3(-p.x(), p.y(), p.z()); };
  for (auto [l, rj] : {std::pair{"upper_arm.L", "upper_arm.R"}, {"forearm.L", "forearm.R"}, {"hand.L", "hand.R"},
                       {"thigh.L", "thigh.R"}, {"shin.L", "shin.R"}, {"foot.L", "foot.R"}}) {
    const Vec3 pl = s->world_matrix(g.find(l)).topRightCorner<3, 1>(), pr = s->world_matrix(g.find(rj)).topRightCorner<3, 1>();
    EXPECT_LT((reflect(pl) - pr).norm(), 1e-5) << l << " / " << rj << " (the metarig is symmetric to float precision)";
  }
  // Back: the right side onto the left gives the left pose again.
  for (const std::string& a : kLeft) ASSERT_TRUE(g.set_value(Plug{at(g, a), xform::kRotate, -1}, Value(Vec3(1, 2, 3))).is_ok());
  o.controls = ids(g, rights());
  ASSERT_TRUE(mirror(*s, o).is_ok());
  EXPECT_LT(worst(channels(*s, kLeft), left), 1e-9);
  // One undo step each.
  EXPECT_EQ(g.undo_label(), "mirror pose");
}

TEST(Mirror, a_symmetric_pose_flips_onto_itself_and_an_asymmetric_one_swaps) {
  auto s = built();
  graph::Graph& g = s->graph();
  pose_left(*s);
  MirrorOptions o;
  o.controls = ids(g, kLeft);
  o.key = false;  // set, not keyed: the channels stay free to pose
  ASSERT_TRUE(mirror(*s, o).is_ok());  // now symmetric
  std::vector<std::string> both = kLeft;
  for (const std::string& a : rights()) both.push_back(a);
  const auto symmetric = channels(*s, both);
  MirrorOptions flip;
  flip.all = true;
  flip.flip = true;
  flip.key = false;
  auto r = mirror(*s, flip);
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  EXPECT_LT(worst(channels(*s, both), symmetric), 1e-9) << "a symmetric pose flips onto itself";
  // Asymmetric: flip swaps; flipping twice gives it back.
  ASSERT_TRUE(g.set_value(Plug{at(g, "hero:arm_L/fk[0]"), xform::kRotate, -1}, Value(Vec3(40, 10, -20))).is_ok());
  const auto before = channels(*s, both);
  ASSERT_TRUE(mirror(*s, flip).is_ok());
  EXPECT_GT(worst(channels(*s, both), before), 1e-3);
  ASSERT_TRUE(mirror(*s, flip).is_ok());
  EXPECT_LT(worst(channels(*s, both), before), 1e-9) << "flip twice";
}

TEST(Mirror, pairs_are_found_without_names) {
  auto s = built();
  graph::Graph& g = s->graph();
  const NodeId fk0 = at(g, "hero:arm_L/fk[0]"), right = at(g, "hero:arm_R/fk[0]");
  ASSERT_TRUE(g.rename(fk0, "banana").is_ok());
  ASSERT_TRUE(g.rename(right, "apple").is_ok());
  EXPECT_EQ(*rig::mirror_pair(g, fk0), right);
  ASSERT_TRUE(g.set_value(Plug{fk0, xform::kRotate, -1}, Value(Vec3(30, 0, 0))).is_ok());
  MirrorOptions o;
  o.controls = {fk0};
  auto r = mirror(*s, o);
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  ASSERT_EQ(r->set, std::vector<NodeId>{right});
  EXPECT_GT((std::get<Mat4>(g.evaluate(right, xform::kMatrix)) - Mat4::Identity()).norm(), 0.1) << "the renamed pair moved";
  EXPECT_EQ(*rig::mirror_pair(g, at(g, "hero:spine/fk[0]")), at(g, "hero:spine/fk[0]")) << "centre: its own pair";
}

TEST(Mirror, a_range_is_keyed_on_its_frames_only) {
  auto s = built();
  graph::Graph& g = s->graph();
  const NodeId fk1 = at(g, "hero:arm_L/fk[1]");
  ASSERT_TRUE(ops::anim::write_channel_key(g, fk1, xform::kRotate, Value(Vec3(0, 0, 0)), 0.0, true).is_ok());
  ASSERT_TRUE(ops::anim::write_channel_key(g, fk1, xform::kRotate, Value(Vec3(0, 0, 50)), 20 / g.fps(), true).is_ok());
  MirrorOptions o;
  o.all = true;
  o.first = 5;
  o.last = 15;
  auto r = mirror(*s, o);
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  EXPECT_EQ(r->frames, 11u);
  const NodeId right = at(g, "hero:arm_R/fk[1]");
  std::size_t curves = 0;
  for (const graph::Connection& c : g.node(right)->inputs()) {
    const std::vector<double> t = ops::anim::curve_key_times(g, c.src.node);
    if (t.empty()) continue;
    ++curves;
    EXPECT_EQ(t.size(), 11u);
    EXPECT_NEAR(t.front() * g.fps(), 5.0, 1e-9);
    EXPECT_NEAR(t.back() * g.fps(), 15.0, 1e-9);
  }
  EXPECT_GE(curves, 9u) << "translate, rotate and scale keyed";
  s->set_frame(10);
  const Mat4 l = std::get<Mat4>(g.evaluate(fk1, xform::kMatrix)), rm = std::get<Mat4>(g.evaluate(right, xform::kMatrix));
  EXPECT_NEAR(math::decompose(l).rotation.angularDistance(Eigen::Quaterniond::Identity()),
              math::decompose(rm).rotation.angularDistance(Eigen::Quaterniond::Identity()), 1e-9)
      << "the same turn, mirrored";
}

TEST(Mirror, bad_input_is_refused_naming_the_control_and_changing_nothing) {
  io::testing::TempDir dir;
  const fs::path def = dir.path() / "one_arm.rig.xml";
  std::ofstream(def) << R"(<rig name="hero" version="1.0">
  <component type="global" name="global" side="C" version="1.0" rigId="6513270e-269e-4d37-b2a7-4de452e6b438">
    <guide name="main"/>
    <component type="limb" name="arm" side="L" version="1.0" rigId="8e81973e-0bec-47b0-b898-d190f9ebdacc">
      <guide name="upper" joint="upper_arm.L"/>
      <guide name="lower" joint="forearm.L"/>
      <guide name="end" joint="hand.L"/>
    </component>
  </component>
</rig>)";
  auto s = built(def);
  graph::Graph& g = s->graph();
  const std::size_t nodes = g.nodes().size();
  MirrorOptions o;
  o.controls = {at(g, "hero:arm_L/fk[0]")};
  auto none = mirror(*s, o);
  ASSERT_FALSE(none.is_ok());
  EXPECT_EQ(none.status().field(), "controls");
  EXPECT_NE(none.status().message().find("has no pair"), std::string::npos) << none.status().message();
  EXPECT_NE(none.status().message().find("hero_arm_L_fk0"), std::string::npos) << none.status().message();
  o.controls = {g.find("hand.L")};
  EXPECT_FALSE(mirror(*s, o).is_ok()) << "a joint is not a built rig's control";
  o.controls = {at(g, "hero:global/main")};
  auto centre = mirror(*s, o);
  ASSERT_FALSE(centre.is_ok());
  EXPECT_NE(centre.status().message().find("nothing to mirror"), std::string::npos) << centre.status().message();
  o.controls.clear();
  EXPECT_FALSE(mirror(*s, o).is_ok()) << "nothing given";
  EXPECT_EQ(g.nodes().size(), nodes);
  EXPECT_FALSE(g.can_undo());
}

}  // namespace
}  // namespace rigel::tools

namespace rigel::tools {
namespace {

// Bind pose: a component's controls back to their rest and its switch and
// foot values to theirs as built, the rest of the character untouched; the
// whole rig by its root; keyed when asked.
TEST(BindPose, a_component_and_then_the_whole_rig_go_back_to_their_pose_as_built) {
  auto s = built();
  graph::Graph& g = s->graph();
  const NodeId sw = at(g, "hero:leg_L/fkIkSwitch"), foot = at(g, "hero:foot_L/reverseFoot");
  const double fk_ik = std::get<double>(g.evaluate(sw, ops::util::fk_ik_attr::kFkIk));
  const double roll_break = std::get<double>(g.evaluate(foot, ops::util::reverse_foot_attr::kRollBreak));
  std::map<std::string, Mat4> joints;
  for (NodeId id : s->hierarchy())
    if (g.node(id)->type().name() == scene::kJointType) joints[g.node(id)->name()] = s->world_matrix(id);
  pose_left(*s);
  ASSERT_TRUE(g.set_value(Plug{sw, ops::util::fk_ik_attr::kFkIk, -1}, Value(1.0 - fk_ik)).is_ok());
  ASSERT_TRUE(g.set_value(Plug{foot, ops::util::reverse_foot_attr::kRoll, -1}, Value(25.0)).is_ok());
  ASSERT_TRUE(g.set_value(Plug{foot, ops::util::reverse_foot_attr::kRollBreak, -1}, Value(50.0)).is_ok());

  auto arm = reset_bind_pose(g, {at(g, "hero:arm_L")}, false);
  ASSERT_TRUE(arm.is_ok()) << arm.status().message();
  for (const char* a : {"hero:arm_L/fk[0]", "hero:arm_L/ik", "hero:arm_L/pole"})
    EXPECT_EQ(std::get<Mat4>(g.evaluate(at(g, a), xform::kMatrix)), Mat4::Identity()) << a;
  EXPECT_NE(std::get<Mat4>(g.evaluate(at(g, "hero:leg_L/fk[0]"), xform::kMatrix)), Mat4::Identity()) << "the leg stays";

  auto all = reset_bind_pose(g, {at(g, "hero:")}, false);
  ASSERT_TRUE(all.is_ok()) << all.status().message();
  EXPECT_EQ(std::get<double>(g.evaluate(sw, ops::util::fk_ik_attr::kFkIk)), fk_ik) << "the switch as built";
  EXPECT_EQ(std::get<double>(g.evaluate(foot, ops::util::reverse_foot_attr::kRoll)), 0.0);
  EXPECT_EQ(std::get<double>(g.evaluate(foot, ops::util::reverse_foot_attr::kRollBreak)), roll_break);
  double worst = 0;
  for (const auto& [name, m] : joints) worst = std::max(worst, (s->world_matrix(g.find(name)) - m).cwiseAbs().maxCoeff());
  EXPECT_LT(worst, 1e-9) << "every joint where the build left it";

  // Keyed: a key at the current frame on each reset channel.
  s->set_frame(12);
  auto keyed = reset_bind_pose(g, {at(g, "hero:arm_L/fk[1]")}, true);
  ASSERT_TRUE(keyed.is_ok()) << keyed.status().message();
  EXPECT_EQ(keyed->channels, 3u);
  std::size_t curves = 0;
  for (const graph::Connection& c : g.node(at(g, "hero:arm_L/fk[1]"))->inputs())
    curves += ops::anim::curve_key_times(g, c.src.node).size();
  EXPECT_EQ(curves, 9u) << "translate, rotate and scale, each component keyed once";

  auto bad = reset_bind_pose(g, {g.find("hand.L")}, false);
  ASSERT_FALSE(bad.is_ok());
  EXPECT_EQ(bad.status().field(), "controls");
  EXPECT_FALSE(reset_bind_pose(g, {}, false).is_ok());
}

}  // namespace
}  // namespace rigel::tools
