// The foot component (a reverse foot) on Rigify's human metarig, under a
// leg (limb) and on its own: the rest pose kept, roll on the heel, the ball
// and the toe tip, bank on either edge, twist, toe tap, the IK takeover of
// the leg (the leg's ik control still moves everything; FK ignores the
// roll), exact removal and stepping, and errors for bad guides. Expected
// poses are worked out here from the guides' positions and the rotations
// foot.h specifies (turns about lines through the pivots), not read back
// from the reverseFoot node.
#include <gtest/gtest.h>

#include <limits>
#include <map>

#include "rig_test_util.h"
#include "rigel/io/scene_file.h"
#include "rigel/math/rotation.h"
#include "rigel/math/transform.h"
#include "rigel/ops/util/blend.h"
#include "rigel/ops/util/foot.h"
#include "rigel/rig/build.h"
#include "rigel/rig/component.h"
#include "rigel/rig/components/limbs.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"

namespace rigel::rig {
namespace {

using testing::at_joint;
using testing::first_difference;
using testing::metarig;
using testing::joint_worlds;
using testing::normalized;

using graph::Plug;
using graph::Value;
using math::Mat4;
using math::Quat;
using math::Vec3;
namespace xform = scene::xform;
namespace rf = ops::util::reverse_foot_attr;

// The sole's pivots without joints in the metarig (Rigify has none for the
// toe tip and the edges): on the ground (y = 0), the toe tip ahead of toe.L,
// the edges either side of the ball.
const Vec3 kToeTip(0.098, 0.0, 0.17);
const Vec3 kInner(0.05, 0.0, 0.05);
const Vec3 kOuter(0.145, 0.0, 0.05);

Guide at(const Vec3& p) {
  Guide g;
  g.translate = p;
  return g;
}

Component component(std::string type, std::string name, Side side, std::vector<Guide> guides,
                    std::vector<Param> params = {}) {
  Component c;
  c.type = std::move(type);
  c.name = std::move(name);
  c.side = side;
  c.rig_id = new_rig_id();
  c.guides = std::move(guides);
  c.params = std::move(params);
  return c;
}

Component foot_component() {
  Component foot =
      component("foot", "foot", Side::kLeft,
                {at_joint("foot.L"), at_joint("toe.L"), at(kToeTip), at_joint("heel.02.L"), at(kInner), at(kOuter)});
  foot.attach = "end";
  return foot;
}

// global -> hip (spine) -> leg_L (limb, leg, IK) -> foot_L; or, `with_leg`
// false, the foot straight under the hip.
Definition legs(bool with_leg = true) {
  Definition d;
  d.name = "hero";
  Component global = component("global", "global", Side::kCenter, {Guide{}});
  Component hip = component("hip", "hip", Side::kCenter, {at_joint("spine")});
  Component foot = foot_component();
  if (with_leg) {
    Component leg = component("limb", "leg", Side::kLeft, {at_joint("thigh.L"), at_joint("shin.L"), at_joint("foot.L")},
                              {Param{"kind", std::string("leg"), {}}, Param{"defaultMode", std::string("ik"), {}}});
    leg.children = {foot};
    hip.children = {leg};
  } else {
    foot.attach.clear();
    hip.children = {foot};
  }
  global.children = {hip};
  d.components = {global};
  return d;
}

// The two-bone kernel reaches its target within ~1e-7 on the metarig's
// single-precision joints (limbs_tests.cc): IK results to 1e-6, exact paths
// (rest pose, FK, the foot on its own) to 1e-9.
constexpr double kIkTol = 1e-6;

Vec3 pos(const Mat4& m) { return m.topRightCorner<3, 1>(); }
Quat rot(const Mat4& m) { return math::decompose(m).rotation; }

// `x` turned by `degrees` about the line through `pivot` along `axis`.
Vec3 turned(const Vec3& x, const Vec3& pivot, const Vec3& axis, double degrees) {
  return pivot + Eigen::AngleAxisd(math::to_radians(degrees), axis) * (x - pivot);
}
Quat turn(const Vec3& axis, double degrees) { return Quat(Eigen::AngleAxisd(math::to_radians(degrees), axis)); }

struct Rig : testing::BuiltRig {
  NodeId at(const std::string& address) {
    Result<NodeId> id = resolve_address(g(), "hero:" + address);
    EXPECT_TRUE(id.is_ok()) << address << ": " << id.status().message();
    return id.is_ok() ? *id : NodeId{};
  }
  NodeId joint(const char* name) { return g().find(name); }
  Mat4 world(NodeId id) { return scene->world_matrix(id); }
  Mat4 world(const char* joint_name) { return world(joint(joint_name)); }
  void set(NodeId id, graph::AttrIndex attr, Value v) {
    Status s = g().set_value(Plug{id, attr, -1}, std::move(v));
    ASSERT_TRUE(s.is_ok()) << s.message();
  }
  void foot(graph::AttrIndex attr, double degrees) { set(at("foot_L/reverseFoot"), attr, Value(degrees)); }
  void fk_ik(double value) { set(at("leg_L/fkIkSwitch"), ops::util::fk_ik_attr::kFkIk, Value(value)); }
  // Moves a control at rest by `d` in the world (its translate is in its rest frame).
  void shift(NodeId control, const Vec3& d) {
    const NodeId parent = g().parent(control);
    const Mat4 space = (parent.is_valid() ? world(parent) : Mat4(Mat4::Identity())) *
                       std::get<Mat4>(g().evaluate(control, xform::kOffsetParentMatrix));
    set(control, xform::kTranslate, Value(Vec3(space.topLeftCorner<3, 3>().inverse() * d)));
  }
  // Where a point that moves with `joint_name` is now, given where it was at rest.
  Vec3 carried(const char* joint_name, const Vec3& rest_point) {
    const Mat4 m = world(joint_name) * math::affine_inverse(rest.at(joint_name));
    return m.topLeftCorner<3, 3>() * rest_point + m.topRightCorner<3, 1>();
  }
};

Rig built(Definition d = legs()) {
  Rig r;
  testing::build_on_metarig(r, std::move(d));
  return r;
}

// The foot's frame as foot.h defines it, from the guides' rest positions.
struct Frame {
  Vec3 ankle, ball, heel, up, forward, roll, outward, bank, twist;
};

Frame frame(Rig& r) {
  Frame f;
  f.ankle = pos(r.rest.at("foot.L"));
  f.ball = pos(r.rest.at("toe.L"));
  f.heel = pos(r.rest.at("heel.02.L"));
  f.up = (kToeTip - f.heel).cross(kOuter - kInner).normalized();
  if (f.up.dot(f.ankle - f.heel) < 0) f.up = -f.up;
  f.forward = kToeTip - f.ankle;
  f.forward = (f.forward - f.up * f.up.dot(f.forward)).normalized();
  f.roll = f.up.cross(f.forward);
  f.outward = (kOuter - kInner).dot(f.roll) > 0 ? f.roll : Vec3(-f.roll);
  f.bank = f.up.cross(f.outward);
  f.twist = f.forward.cross(f.outward);
  return f;
}

void expect_near(const Vec3& got, const Vec3& want, double tol, const std::string& what) {
  EXPECT_LT((got - want).norm(), tol) << what << ": got " << got.transpose() << ", want " << want.transpose();
}

void expect_turned(Rig& r, const char* joint_name, const Quat& by, double tol, const std::string& what) {
  const Quat want = by * rot(r.rest.at(joint_name));
  EXPECT_LT(rot(r.world(joint_name)).angularDistance(want), tol) << what << ": " << joint_name;
}

TEST(RigFoot, the_frame_of_the_metarig_foot_is_the_world_axes) {
  // The metarig's sole lies in y = 0 and its toes point along +z, so the
  // spec's frame is the world's (left foot: outward +x). heel.02.L is 2e-7
  // above the ground (single precision).
  Rig r = built();
  ASSERT_TRUE(r.build);
  const Frame f = frame(r);
  expect_near(f.up, Vec3::UnitY(), 1e-5, "up");
  expect_near(f.forward, Vec3::UnitZ(), 1e-5, "forward");
  expect_near(f.roll, Vec3::UnitX(), 1e-5, "roll axis");
  expect_near(f.outward, Vec3::UnitX(), 1e-5, "outward");
  // The control sits on the ground below the ankle with those axes.
  const Mat4 control = r.world(r.at("foot_L/foot"));
  expect_near(pos(control), Vec3(f.ankle.x(), f.heel.y(), f.ankle.z()), 1e-6, "foot control");
  EXPECT_LT(rot(control).angularDistance(Quat::Identity()), 1e-5);
  EXPECT_EQ(r.g().parent(r.at("foot_L/foot")), r.at("leg_L/ik")) << "the foot control hangs from the leg's ik control";
}

TEST(RigFoot, at_rest_no_joint_moves) {
  Rig r = built();
  ASSERT_TRUE(r.build);
  for (const auto& [name, m] : r.rest)
    EXPECT_LT((r.world(name.c_str()) - m).cwiseAbs().maxCoeff(), 1e-9) << "IK: " << name;
  r.fk_ik(0.0);
  for (const auto& [name, m] : r.rest)
    EXPECT_LT((r.world(name.c_str()) - m).cwiseAbs().maxCoeff(), 1e-9) << "FK: " << name;
  Rig alone = built(legs(false));
  ASSERT_TRUE(alone.build);
  for (const auto& [name, m] : alone.rest)
    EXPECT_LT((alone.world(name.c_str()) - m).cwiseAbs().maxCoeff(), 1e-9) << "on its own: " << name;
}

TEST(RigFoot, negative_roll_turns_the_foot_about_the_heel) {
  Rig r = built();
  ASSERT_TRUE(r.build);
  const Frame f = frame(r);
  r.foot(rf::kRoll, -20.0);
  const Vec3 ankle = turned(f.ankle, f.heel, f.roll, -20.0);
  EXPECT_GT((ankle - f.ankle).norm(), 0.01) << "the ankle moves";
  expect_near(pos(r.world("foot.L")), ankle, kIkTol, "ankle");
  expect_turned(r, "foot.L", turn(f.roll, -20.0), kIkTol, "roll -20");
  expect_near(pos(r.world("heel.02.L")), f.heel, kIkTol, "the heel stays");
  // The toes go with the foot (no ball roll): the tip lifts.
  expect_near(pos(r.world("toe.L")), turned(f.ball, f.heel, f.roll, -20.0), kIkTol, "ball");
  expect_turned(r, "toe.L", turn(f.roll, -20.0), kIkTol, "roll -20");
  EXPECT_GT(r.carried("toe.L", kToeTip).y(), 0.05);
  // The leg bends to follow: the hip end stays, the bones keep their lengths.
  expect_near(pos(r.world("thigh.L")), pos(r.rest.at("thigh.L")), 1e-12, "hip");
  EXPECT_NEAR((pos(r.world("foot.L")) - pos(r.world("shin.L"))).norm(),
              (pos(r.rest.at("foot.L")) - pos(r.rest.at("shin.L"))).norm(), kIkTol);
}

TEST(RigFoot, roll_up_to_the_break_turns_about_the_ball_and_keeps_the_toes_down) {
  Rig r = built();
  ASSERT_TRUE(r.build);
  const Frame f = frame(r);
  r.foot(rf::kRoll, 20.0);
  const Vec3 ankle = turned(f.ankle, f.ball, f.roll, 20.0);
  EXPECT_GT(ankle.y() - f.ankle.y(), 0.02) << "the ankle lifts";
  expect_near(pos(r.world("foot.L")), ankle, kIkTol, "ankle");
  expect_turned(r, "foot.L", turn(f.roll, 20.0), kIkTol, "roll 20");
  expect_near(pos(r.world("toe.L")), f.ball, kIkTol, "the ball stays");
  expect_turned(r, "toe.L", Quat::Identity(), kIkTol, "the toes stay down");
  EXPECT_GT(r.carried("heel.02.L", f.heel).y(), 0.04) << "the heel lifts";
  // At the break exactly, still the ball.
  r.foot(rf::kRoll, 30.0);
  expect_near(pos(r.world("toe.L")), f.ball, kIkTol, "the ball stays at the break");
  expect_near(pos(r.world("foot.L")), turned(f.ankle, f.ball, f.roll, 30.0), kIkTol, "ankle at the break");
}

TEST(RigFoot, roll_past_the_break_turns_about_the_toe_tip) {
  Definition d = legs();
  d.components[0].children[0].children[0].children[0].params.push_back(Param{"rollBreak", 25.0, {}});
  Rig r = built(d);
  ASSERT_TRUE(r.build);
  const Frame f = frame(r);
  r.foot(rf::kRoll, 40.0);  // 25 on the ball, then 15 on the toe tip
  const Vec3 ankle = turned(turned(f.ankle, f.ball, f.roll, 25.0), kToeTip, f.roll, 15.0);
  expect_near(pos(r.world("foot.L")), ankle, kIkTol, "ankle");
  expect_turned(r, "foot.L", turn(f.roll, 40.0), kIkTol, "roll 40");
  expect_near(pos(r.world("toe.L")), turned(f.ball, kToeTip, f.roll, 15.0), kIkTol, "the ball lifts");
  expect_turned(r, "toe.L", turn(f.roll, 15.0), kIkTol, "the toes turn on the tip");
  expect_near(r.carried("toe.L", kToeTip), kToeTip, kIkTol, "the toe tip stays");
  // The toe hook rides on the toes' tip.
  expect_near(pos(r.world(r.at("foot_L/hook[2]"))), kToeTip, kIkTol, "toe hook");
}

TEST(RigFoot, bank_rolls_onto_the_outer_edge_when_positive_and_the_inner_when_negative) {
  Rig r = built();
  ASSERT_TRUE(r.build);
  const Frame f = frame(r);
  r.foot(rf::kBank, 15.0);
  expect_near(pos(r.world("foot.L")), turned(f.ankle, kOuter, f.bank, 15.0), kIkTol, "bank 15: ankle");
  expect_turned(r, "foot.L", turn(f.bank, 15.0), kIkTol, "bank 15");
  expect_near(r.carried("foot.L", kOuter), kOuter, kIkTol, "bank 15: the outer edge stays");
  expect_near(r.carried("toe.L", kOuter), kOuter, kIkTol, "bank 15: the outer edge stays (toes)");
  EXPECT_GT(r.carried("foot.L", kInner).y(), 0.01) << "bank 15: the inner edge lifts";
  r.foot(rf::kBank, -15.0);
  expect_near(pos(r.world("foot.L")), turned(f.ankle, kInner, f.bank, -15.0), kIkTol, "bank -15: ankle");
  expect_near(r.carried("foot.L", kInner), kInner, kIkTol, "bank -15: the inner edge stays");
  EXPECT_GT(r.carried("foot.L", kOuter).y(), 0.01) << "bank -15: the outer edge lifts";
}

TEST(RigFoot, twists_turn_about_the_up_axis_through_their_pivot_toes_outward) {
  Rig r = built();
  ASSERT_TRUE(r.build);
  const Frame f = frame(r);
  expect_near(f.twist, Vec3::UnitY(), 1e-5, "left foot: toes outward = about +y");
  r.foot(rf::kHeelTwist, 20.0);
  expect_near(pos(r.world("foot.L")), turned(f.ankle, f.heel, f.twist, 20.0), kIkTol, "heelTwist: ankle");
  EXPECT_GT(r.carried("toe.L", kToeTip).x(), kToeTip.x() + 0.03) << "the toes swing outward";
  r.foot(rf::kHeelTwist, 0.0);
  r.foot(rf::kBallTwist, 20.0);
  expect_near(pos(r.world("foot.L")), turned(f.ankle, f.ball, f.twist, 20.0), kIkTol, "ballTwist: ankle");
  expect_near(pos(r.world("toe.L")), f.ball, kIkTol, "ballTwist: the ball stays");
  expect_turned(r, "toe.L", Quat::Identity(), kIkTol, "ballTwist: the toes stay");
  r.foot(rf::kBallTwist, 0.0);
  r.foot(rf::kToeTwist, 20.0);
  expect_near(r.carried("toe.L", kToeTip), kToeTip, kIkTol, "toeTwist: the tip stays");
  expect_near(pos(r.world("foot.L")), turned(f.ankle, kToeTip, f.twist, 20.0), kIkTol, "toeTwist: ankle");
}

TEST(RigFoot, toe_tap_turns_only_the_ball_joint) {
  Rig r = built();
  ASSERT_TRUE(r.build);
  const Frame f = frame(r);
  r.foot(rf::kToeTap, 25.0);
  for (const auto& [name, m] : r.rest) {
    if (name == "toe.L") continue;
    EXPECT_LT((r.world(name.c_str()) - m).cwiseAbs().maxCoeff(), 1e-9) << name;
  }
  expect_near(pos(r.world("toe.L")), f.ball, 1e-9, "the ball joint stays in place");
  expect_turned(r, "toe.L", turn(f.roll, -25.0), 1e-9, "toe tap 25: the toes lift");
  EXPECT_GT(r.carried("toe.L", kToeTip).y(), 0.02);
}

TEST(RigFoot, the_legs_ik_control_still_moves_everything_and_fk_ignores_the_roll) {
  Rig r = built();
  ASSERT_TRUE(r.build);
  const Frame f = frame(r);
  // Moving the leg's ik control carries the foot control and the rolled foot.
  r.foot(rf::kRoll, 20.0);
  const Vec3 d(0.02, 0.1, 0.05);
  r.shift(r.at("leg_L/ik"), d);
  expect_near(pos(r.world("foot.L")), turned(f.ankle, f.ball, f.roll, 20.0) + d, kIkTol, "ankle");
  expect_near(pos(r.world("toe.L")), f.ball + d, kIkTol, "ball");
  // FK: the leg and toes follow their FK controls; the roll does nothing.
  r.fk_ik(0.0);
  for (const auto& [name, m] : r.rest)
    EXPECT_LT((r.world(name.c_str()) - m).cwiseAbs().maxCoeff(), 1e-9) << "FK: " << name;
  const NodeId toe_fk = r.at("foot_L/toeFk");
  EXPECT_EQ(r.g().parent(toe_fk), r.at("leg_L/fk[2]"));
  r.set(toe_fk, xform::kRotate, Value(Vec3(30, 0, 0)));
  // toeFk stands at the rigid part of the ball joint's frame; its
  // toeFkJoint group, at the joint's own frame, is what the toes follow.
  const NodeId toe_joint = r.at("foot_L/toeFkJoint");
  EXPECT_EQ(r.g().parent(toe_joint), toe_fk);
  EXPECT_LT((r.world("toe.L") - r.world(toe_joint)).cwiseAbs().maxCoeff(), 1e-9) << "the toes follow toeFk";
  EXPECT_TRUE(math::is_rigid(r.world(toe_fk))) << "a rigid control";
  // Halfway: the toes' local rotation is halfway between the two sides'.
  r.set(toe_fk, xform::kRotate, Value(Vec3(0, 0, 0)));
  r.set(r.at("leg_L/ik"), xform::kTranslate, Value(Vec3(0, 0, 0)));
  r.foot(rf::kRoll, 0.0);
  r.foot(rf::kToeTap, 40.0);
  r.fk_ik(0.5);
  // Not exact: the metarig's joints carry single-precision, slightly
  // non-uniform scales (1 +- 3e-6), so the local rotations the switch
  // blends differ from the world turn by ~1e-7.
  expect_turned(r, "toe.L", turn(f.roll, -20.0), kIkTol, "fkIk 0.5, toe tap 40");
}

TEST(RigFoot, matching_fk_to_a_rolled_ik_leg_keeps_the_leg) {
  Rig r = built();
  ASSERT_TRUE(r.build);
  r.foot(rf::kRoll, 20.0);
  r.foot(rf::kBank, -10.0);
  const std::map<std::string, Mat4> ik = joint_worlds(*r.scene);
  const NodeId leg = find_component(r.g(), find_rig(r.g(), "hero"), "leg_L");
  ASSERT_TRUE(components::match_fk_to_ik(*r.scene, leg).is_ok());
  r.fk_ik(0.0);
  for (const char* name : {"thigh.L", "shin.L", "foot.L"}) {
    EXPECT_LT((pos(r.world(name)) - pos(ik.at(name))).norm(), kIkTol) << name;
    EXPECT_LT(rot(r.world(name)).angularDistance(rot(ik.at(name))), kIkTol) << name;
  }
}

TEST(RigFoot, under_a_two_bone_ik_chain_the_foot_takes_over_its_target) {
  Definition d = legs();
  Component& leg = d.components[0].children[0].children[0];
  leg.type = "ikChain";
  leg.params.clear();
  leg.children[0].attach = "END";  // an ikChain's hooks are named after its joints
  Rig r = built(d);
  ASSERT_TRUE(r.build);
  const Frame f = frame(r);
  EXPECT_EQ(r.g().parent(r.at("foot_L/foot")), r.at("leg_L/ik"));
  EXPECT_EQ(resolve_address(r.g(), "hero:foot_L/toeFk").status().code(), ErrorCode::kNotFound) << "no FK side";
  r.foot(rf::kRoll, 20.0);
  expect_near(pos(r.world("foot.L")), turned(f.ankle, f.ball, f.roll, 20.0), kIkTol, "ankle");
  expect_turned(r, "foot.L", turn(f.roll, 20.0), kIkTol, "roll 20");
  expect_near(pos(r.world("toe.L")), f.ball, kIkTol, "the ball stays");
}

TEST(RigFoot, on_its_own_the_foot_control_drives_the_ankle) {
  Rig r = built(legs(false));
  ASSERT_TRUE(r.build);
  const Frame f = frame(r);
  EXPECT_EQ(resolve_address(r.g(), "hero:foot_L/toeFk").status().code(), ErrorCode::kNotFound) << "no FK toe";
  r.foot(rf::kRoll, 20.0);
  expect_near(pos(r.world("foot.L")), turned(f.ankle, f.ball, f.roll, 20.0), 1e-9, "roll 20: ankle");
  expect_turned(r, "foot.L", turn(f.roll, 20.0), 1e-9, "roll 20");
  expect_near(pos(r.world("toe.L")), f.ball, 1e-9, "roll 20: the ball stays");
  expect_turned(r, "toe.L", Quat::Identity(), 1e-9, "roll 20: the toes stay");
  r.foot(rf::kRoll, -10.0);
  // The heel joint hangs 0.1 m from the ankle, whose parentConstraint writes
  // no shear: the metarig's single-precision matrices (shear ~3e-7) leave it
  // ~4e-8 off.
  expect_near(pos(r.world("heel.02.L")), f.heel, kIkTol, "roll -10: the heel stays");
  // The foot control's own channels move the whole foot.
  r.foot(rf::kRoll, 0.0);
  r.shift(r.at("foot_L/foot"), Vec3(0, 0.1, 0));
  expect_near(pos(r.world("foot.L")), f.ankle + Vec3(0, 0.1, 0), 1e-9, "moved: ankle");
  expect_near(pos(r.world("toe.L")), f.ball + Vec3(0, 0.1, 0), 1e-9, "moved: ball");
  // The hip carries it.
  r.set(r.at("foot_L/foot"), xform::kTranslate, Value(Vec3(0, 0, 0)));
  r.set(r.at("hip/main"), xform::kTranslate, Value(Vec3(0.1, 0, 0)));
  expect_near(pos(r.world("foot.L")), f.ankle + Vec3(0.1, 0, 0), 1e-9, "hip moved: ankle");
}

TEST(RigFoot, construct_all_then_remove_gives_back_the_file_byte_for_byte) {
  for (bool with_leg : {true, false}) {
    auto scene = metarig();
    ASSERT_TRUE(scene);
    const std::string before = io::write_scene(*scene);
    auto b = Build::open(*scene, legs(with_leg), builtin_components());
    ASSERT_TRUE(b.is_ok());
    ASSERT_TRUE((*b)->build_all().is_ok());
    ASSERT_TRUE((*b)->remove().is_ok());
    const std::string after = io::write_scene(*scene);
    EXPECT_TRUE(after == before) << (with_leg ? "with a leg: " : "alone: ") << first_difference(after, before);
  }
}

TEST(RigFoot, stepping_back_and_forward_from_every_index_gives_the_straight_build) {
  auto scene = metarig();
  ASSERT_TRUE(scene);
  auto b = Build::open(*scene, legs(), builtin_components());
  ASSERT_TRUE(b.is_ok());
  Build& build = **b;
  ASSERT_TRUE(build.build_all().is_ok());
  testing::expect_stepping_gives_the_straight_build(build, *scene);
}

// Builds `d` and expects an error naming foot_L and saying `what`.
void expect_error(Definition d, const std::string& what) {
  auto scene = metarig();
  ASSERT_TRUE(scene);
  const std::string before = io::write_scene(*scene);
  auto b = Build::open(*scene, std::move(d), builtin_components());
  ASSERT_TRUE(b.is_ok()) << b.status().message();
  Status s = (*b)->build_all();
  ASSERT_FALSE(s.is_ok()) << what;
  EXPECT_NE(s.message().find("foot_L"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find(what), std::string::npos) << s.message();
}

TEST(RigFoot, bad_guides_give_errors_naming_the_component) {
  auto with_guide = [](int i, Guide g) {
    Definition d = legs();
    d.components[0].children[0].children[0].children[0].guides[i] = std::move(g);
    return d;
  };
  expect_error(with_guide(1, at_joint("shin.L")), "'shin.L' is not a child of the ankle joint 'foot.L'");
  expect_error(with_guide(0, at(Vec3(0.1, 0.08, 0))), "guide 0 (ankle) must name a joint");
  // The other leg's foot: the limb does not end there.
  Definition other = with_guide(0, at_joint("foot.R"));
  other.components[0].children[0].children[0].children[0].guides[1] = at_joint("toe.R");
  expect_error(other, "the ankle joint 'foot.R' is not the end joint of limb 'leg_L'");
  // The knee and the ankle: the limb drives them, but the knee is not its last joint.
  Definition knee = with_guide(0, at_joint("shin.L"));
  knee.components[0].children[0].children[0].children[0].guides[1] = at_joint("foot.L");
  expect_error(knee, "the ankle joint 'shin.L' is not the last joint of limb 'leg_L'");
  expect_error(with_guide(3, at(kToeTip)), "the heel and toe guides coincide");
  // Inner and outer one behind the other along the foot.
  Definition along = with_guide(4, at(Vec3(0.145, 0, 0.0)));
  expect_error(along, "not on either side of the foot");
  Definition behind = with_guide(2, at(Vec3(0.098, 0, 0.0)));
  behind.components[0].children[0].children[0].children[0].guides[3] = at(Vec3(0.098, 0, 0.1));
  expect_error(behind, "the toe guide is behind the heel guide");
  expect_error(with_guide(2, at(Vec3(0.098, 0, -0.0162))), "the toe guide is straight below the ankle");
  // The sole raised to the ankle's height (0.0852).
  Definition raised = legs();
  std::vector<Guide>& guides = raised.components[0].children[0].children[0].children[0].guides;
  guides[2] = at(Vec3(0.098, 0.0852, 0.17));
  guides[3] = at(Vec3(0.098, 0.0852, -0.05));
  guides[4] = at(Vec3(0.05, 0.0852, 0.05));
  guides[5] = at(Vec3(0.145, 0.0852, 0.05));
  expect_error(raised, "the ankle lies on the sole's plane");
}

TEST(RigFoot, the_reverse_foot_node_falls_back_to_the_rest_pose_on_bad_values) {
  Rig r = built();
  ASSERT_TRUE(r.build);
  const NodeId node = r.at("foot_L/reverseFoot");
  r.set(node, rf::kRollAxis, Value(Vec3(0, 0, 0)));
  r.foot(rf::kRoll, 20.0);
  EXPECT_NE(std::get<std::string>(r.g().evaluate(node, rf::kError)).find("rollAxis"), std::string::npos);
  for (const auto& [name, m] : r.rest) EXPECT_LT((pos(r.world(name.c_str())) - pos(m)).norm(), kIkTol) << name;
  r.set(node, rf::kRollAxis, Value(Vec3(2, 0, 0)));  // normalized
  EXPECT_EQ(std::get<std::string>(r.g().evaluate(node, rf::kError)), "");
  r.foot(rf::kBank, std::numeric_limits<double>::quiet_NaN());
  EXPECT_NE(std::get<std::string>(r.g().evaluate(node, rf::kError)).find("bank"), std::string::npos);
}

}  // namespace
}  // namespace rigel::rig
