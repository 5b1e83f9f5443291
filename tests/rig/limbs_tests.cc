// ikChain, limb and twist on Rigify's human metarig: the rest pose kept,
// IK reach and bone lengths, the pole's bend plane, FK/IK blending and
// matching both ways, stretch with its limit, twist shares, exact removal and
// stepping.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>

#include "rig_test_util.h"
#include "rigel/io/gltf_import.h"
#include "rigel/io/scene_file.h"
#include "rigel/math/rotation.h"
#include "rigel/math/transform.h"
#include "rigel/ops/ik/nodes.h"
#include "rigel/ops/util/blend.h"
#include "rigel/rig/build.h"
#include "rigel/rig/component.h"
#include "rigel/rig/components/limbs.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"

namespace rigel::rig {
namespace {

using testing::first_difference;
using testing::normalized;
using testing::at_joint;
using testing::metarig;
using testing::joint_worlds;

namespace fs = std::filesystem;
using graph::Plug;
using graph::Value;
using math::Mat4;
using math::Quat;
using math::Vec3;
namespace xform = scene::xform;

Component component(std::string type, std::string name, Side side, std::vector<std::string> joints,
                    std::vector<Param> params = {}) {
  Component c;
  c.type = std::move(type);
  c.name = std::move(name);
  c.side = side;
  c.rig_id = new_rig_id();
  for (std::string& j : joints) c.guides.push_back(at_joint(std::move(j)));
  c.params = std::move(params);
  return c;
}

// global -> hip (spine) -> arm_L (limb), leg_L (limb, leg), armIk_R
// (ikChain, two-bone), legIk_R (ikChain, 4 joints: FABRIK), and
// forearmTwist_L (twist, forearm.L -> hand.L) under the arm.
Definition limbs() {
  Definition d;
  d.name = "hero";
  Component global = component("global", "global", Side::kCenter, {""});
  global.guides[0] = Guide{};
  Component hip = component("hip", "hip", Side::kCenter, {"spine"});
  Component arm = component("limb", "arm", Side::kLeft, {"upper_arm.L", "forearm.L", "hand.L"});
  Component leg = component("limb", "leg", Side::kLeft, {"thigh.L", "shin.L", "foot.L"},
                            {Param{"kind", std::string("leg"), {}}});
  Component arm_ik = component("ikChain", "armIk", Side::kRight, {"upper_arm.R", "forearm.R", "hand.R"});
  Component leg_ik = component("ikChain", "legIk", Side::kRight, {"thigh.R", "shin.R", "foot.R", "toe.R"});
  Component twist = component("twist", "forearmTwist", Side::kLeft, {"forearm.L", "hand.L"});
  twist.attach = "lower";
  arm.children = {twist};
  hip.children = {arm, leg, arm_ik, leg_ik};
  global.children = {hip};
  d.components = {global};
  return d;
}

// The glTF metarig's joint matrices are single precision (scales 1 within
// ~1e-7), and the two-bone kernel reaches its target within ~1e-7 on them:
// IK results are checked to 1e-6 m / 1e-6 rad, exact paths (rest pose,
// blending endpoints, twist) to 1e-9.
constexpr double kIkTol = 1e-6;

Vec3 pos(const Mat4& m) { return m.topRightCorner<3, 1>(); }
Quat rot(const Mat4& m) { return math::decompose(m).rotation; }

// A built rig with shorthands.
struct Rig : testing::BuiltRig {
  NodeId at(const std::string& address) {
    Result<NodeId> id = resolve_address(g(), "hero:" + address);
    EXPECT_TRUE(id.is_ok()) << address << ": " << id.status().message();
    return id.is_ok() ? *id : NodeId{};
  }
  NodeId joint(const char* name) { return g().find(name); }
  Mat4 world(NodeId id) { return scene->world_matrix(id); }
  Vec3 p(const char* joint_name) { return pos(world(joint(joint_name))); }
  void set(NodeId id, graph::AttrIndex attr, Value v) {
    Status s = g().set_value(Plug{id, attr, -1}, std::move(v));
    ASSERT_TRUE(s.is_ok()) << s.message();
  }
  void fk_ik(const std::string& component, double value) {
    set(at(component + "/fkIkSwitch"), ops::util::fk_ik_attr::kFkIk, value);
  }
  // Moves a control (rotation channels kept) so its world position is `world`.
  void move_to(NodeId control, const Vec3& world_position) {
    const NodeId parent = g().parent(control);
    const Mat4 offset = std::get<Mat4>(g().evaluate(control, xform::kOffsetParentMatrix));
    const Mat4 space = (parent.is_valid() ? world(parent) : Mat4(Mat4::Identity())) * offset;
    set(control, xform::kTranslate, Value(Vec3(math::affine_inverse(space).topLeftCorner<3, 3>() * world_position +
                                               math::affine_inverse(space).topRightCorner<3, 1>())));
  }
  // Turns a control by `q` about its own rest frame (its rotate channels).
  void turn(NodeId control, const Quat& q) {
    set(control, xform::kRotate, Value(Vec3(math::to_degrees(math::quat_to_euler(q, math::RotateOrder::kXYZ)))));
  }
};

Rig built(Definition d = limbs()) {
  Rig r;
  testing::build_on_metarig(r, std::move(d));
  return r;
}

void expect_same_pose(Rig& r, const std::map<std::string, Mat4>& before, const char* what, double tol_m = 1e-6,
                      double tol_rad = 1e-6) {
  for (const auto& [name, m] : before) {
    const Mat4 now = r.world(r.joint(name.c_str()));
    EXPECT_LT((pos(now) - pos(m)).norm(), tol_m) << what << ": " << name << " moved";
    EXPECT_LT(rot(now).angularDistance(rot(m)), tol_rad) << what << ": " << name << " turned";
  }
}

TEST(RigLimbs, at_rest_no_joint_moves) {
  auto scene = metarig();
  ASSERT_TRUE(scene);
  const std::map<std::string, Mat4> before = joint_worlds(*scene);
  auto b = Build::open(*scene, limbs(), builtin_components());
  ASSERT_TRUE(b.is_ok()) << b.status().message();
  ASSERT_TRUE((*b)->build_all().is_ok());
  for (const auto& [name, m] : before)
    EXPECT_LT((scene->world_matrix(scene->graph().find(name)) - m).cwiseAbs().maxCoeff(), 1e-9) << name;
  // In IK mode too: the IK controls sit on the rest pose.
  Rig r;
  r.scene = std::move(scene);
  r.build = std::move(*b);
  r.fk_ik("arm_L", 1.0);
  r.fk_ik("leg_L", 1.0);
  for (const auto& [name, m] : before)
    EXPECT_LT((r.world(r.joint(name.c_str())) - m).cwiseAbs().maxCoeff(), 1e-9) << "IK mode: " << name;
}

TEST(RigLimbs, the_ik_control_moves_the_end_joint_keeping_bone_lengths_and_the_pole_turns_the_plane) {
  Rig r = built();
  ASSERT_TRUE(r.build);
  r.fk_ik("arm_L", 1.0);
  const Vec3 s = r.p("upper_arm.L"), m = r.p("forearm.L"), e = r.p("hand.L");
  const double upper = (m - s).norm(), lower = (e - m).norm();
  // A reachable target: toward the shoulder and down.
  const Vec3 target = s + (e - s) * 0.7 + Vec3(0, -0.1, 0.05);
  r.move_to(r.at("arm_L/ik"), target);
  EXPECT_LT((r.p("hand.L") - target).norm(), kIkTol) << "the hand reaches the IK control";
  EXPECT_NEAR((r.p("forearm.L") - r.p("upper_arm.L")).norm(), upper, kIkTol);
  EXPECT_NEAR((r.p("hand.L") - r.p("forearm.L")).norm(), lower, kIkTol);
  EXPECT_LT((r.p("upper_arm.L") - s).norm(), 1e-12) << "the root stays";
  // The pole: the elbow turns into the plane of shoulder, hand and pole.
  const NodeId pole = r.at("arm_L/pole");
  const Vec3 elbow_before = r.p("forearm.L");
  const Vec3 pole_at = r.p("forearm.L") + Vec3(0, 0.6, 0);
  r.move_to(pole, pole_at);
  const Vec3 normal = (r.p("forearm.L") - r.p("upper_arm.L")).cross(r.p("hand.L") - r.p("upper_arm.L")).normalized();
  EXPECT_LT(std::abs(normal.dot(pole_at - r.p("upper_arm.L"))), kIkTol) << "the pole lies in the bend plane";
  EXPECT_GT((r.p("forearm.L") - elbow_before).norm(), 0.01) << "the elbow turned";
  EXPECT_LT((r.p("hand.L") - target).norm(), kIkTol);
  // The hand takes the IK control's orientation.
  r.turn(r.at("arm_L/ik"), Quat(Eigen::AngleAxisd(0.5, Vec3(1, 0, 0))));
  EXPECT_LT(rot(r.world(r.joint("hand.L"))).angularDistance(rot(r.world(r.at("arm_L/ik")))), kIkTol);
}

TEST(RigLimbs, fk_ik_blends_the_local_rotations) {
  Rig r = built();
  ASSERT_TRUE(r.build);
  r.turn(r.at("arm_L/fk[0]"), Quat(Eigen::AngleAxisd(0.6, Vec3(0, 0, 1))));
  r.move_to(r.at("arm_L/ik"), r.p("upper_arm.L") + (r.p("hand.L") - r.p("upper_arm.L")) * 0.8);
  const NodeId upper = r.joint("upper_arm.L");
  // The FK controls stand at the rigid part of their joints' frames (the
  // joint under each by an fkJoint group, at its own frame).
  EXPECT_LT((r.world(upper) - r.world(r.at("arm_L/fkJoint[0]"))).norm(), 1e-9) << "fkIk 0: the FK pose";
  EXPECT_TRUE(math::is_rigid(r.world(r.at("arm_L/fk[0]")))) << "a rigid control";
  const Quat q0 = rot(r.world(upper));
  r.fk_ik("arm_L", 1.0);
  const Quat q1 = rot(r.world(upper));
  EXPECT_GT(q0.angularDistance(q1), 0.1);
  r.fk_ik("arm_L", 0.5);
  // The parent (shoulder.L) does not move, so a slerp in its space is a slerp in the world.
  EXPECT_LT(rot(r.world(upper)).angularDistance(q0.slerp(0.5, q1)), kIkTol);
}

TEST(RigLimbs, matching_both_ways_leaves_the_joints_where_they_are) {
  Rig r = built();
  ASSERT_TRUE(r.build);
  graph::Graph& g = r.g();
  NodeId meta = find_component(g, find_rig(g, "hero"), "arm_L");
  ASSERT_TRUE(meta.is_valid());
  // IK pose -> FK.
  r.fk_ik("arm_L", 1.0);
  r.move_to(r.at("arm_L/ik"), r.p("upper_arm.L") + (r.p("hand.L") - r.p("upper_arm.L")) * 0.75 + Vec3(0, 0, 0.1));
  r.move_to(r.at("arm_L/pole"), r.p("forearm.L") + Vec3(0, -0.3, -0.4));
  r.turn(r.at("arm_L/ik"), Quat(Eigen::AngleAxisd(0.4, Vec3(0, 1, 1).normalized())));
  auto ik_pose = joint_worlds(*r.scene);
  ASSERT_TRUE(components::match_fk_to_ik(*r.scene, meta).is_ok());
  r.fk_ik("arm_L", 0.0);
  expect_same_pose(r, ik_pose, "FK matched to IK, switched to FK");
  // One undo step.
  const Vec3 fk0 = std::get<Vec3>(g.node(r.at("arm_L/fk[0]"))->value(xform::kRotate));
  ASSERT_TRUE(g.undo());  // the fkIk edit
  ASSERT_TRUE(g.undo());  // the match
  EXPECT_NE(std::get<Vec3>(g.node(r.at("arm_L/fk[0]"))->value(xform::kRotate)), fk0);
  EXPECT_EQ(std::get<Vec3>(g.node(r.at("arm_L/fk[0]"))->value(xform::kRotate)), Vec3(0, 0, 0));
  ASSERT_TRUE(g.redo());
  ASSERT_TRUE(g.redo());

  // FK pose -> IK: the elbow bent about its rest hinge only.
  const Vec3 s = r.p("upper_arm.L"), m = r.p("forearm.L"), e = r.p("hand.L");
  // The hinge in fk1's rest frame (the frame its rotate channels turn in).
  const Vec3 hinge_world = (m - s).cross(e - m).normalized();
  const Quat fk1_rest = rot(r.world(r.at("arm_L/fk[1]"))) *
                        math::euler_to_quat(math::to_radians(std::get<Vec3>(
                                                g.node(r.at("arm_L/fk[1]"))->value(xform::kRotate))),
                                            math::RotateOrder::kXYZ)
                            .conjugate();
  const Vec3 hinge = fk1_rest.conjugate() * hinge_world;
  r.turn(r.at("arm_L/fk[0]"), Quat(Eigen::AngleAxisd(0.5, Vec3(1, 2, 3).normalized())));
  r.turn(r.at("arm_L/fk[1]"), Quat(Eigen::AngleAxisd(0.7, hinge)));
  r.turn(r.at("arm_L/fk[2]"), Quat(Eigen::AngleAxisd(0.3, Vec3(0, 0, 1))));
  auto fk_pose = joint_worlds(*r.scene);
  ASSERT_TRUE(components::match_ik_to_fk(*r.scene, meta).is_ok());
  r.fk_ik("arm_L", 1.0);
  expect_same_pose(r, fk_pose, "IK matched to FK, switched to IK");
  EXPECT_FALSE(components::match_ik_to_fk(*r.scene, find_component(g, find_rig(g, "hero"), "armIk_R")).is_ok())
      << "an ikChain is not a limb";
}

TEST(RigLimbs, the_leg_stretches_past_full_extension_up_to_max_stretch) {
  Rig r = built();
  ASSERT_TRUE(r.build);
  r.fk_ik("leg_L", 1.0);
  const Vec3 s = r.p("thigh.L"), m = r.p("shin.L"), e = r.p("foot.L");
  const double upper = (m - s).norm(), lower = (e - m).norm(), reach = upper + lower;
  const Vec3 down = (e - s).normalized();
  r.move_to(r.at("leg_L/ik"), s + down * reach * 1.3);
  EXPECT_LT((r.p("foot.L") - (s + down * reach * 1.3)).norm(), kIkTol) << "1.3 times the reach: stretched to it";
  EXPECT_NEAR((r.p("shin.L") - r.p("thigh.L")).norm(), upper * 1.3, kIkTol);
  EXPECT_NEAR((r.p("foot.L") - r.p("shin.L")).norm(), lower * 1.3, kIkTol);
  r.move_to(r.at("leg_L/ik"), s + down * reach * 2.0);
  EXPECT_NEAR((r.p("foot.L") - r.p("thigh.L")).norm(), reach * 1.5, kIkTol) << "maxStretch 1.5";
  EXPECT_NEAR((r.p("shin.L") - r.p("thigh.L")).norm(), upper * 1.5, kIkTol);
  // Matching FK to a stretched IK pose carries the stretch to the FK controls.
  auto pose = joint_worlds(*r.scene);
  NodeId meta = find_component(r.g(), find_rig(r.g(), "hero"), "leg_L");
  ASSERT_TRUE(components::match_fk_to_ik(*r.scene, meta).is_ok());
  r.fk_ik("leg_L", 0.0);
  expect_same_pose(r, pose, "stretched IK matched to FK");
}

TEST(RigLimbs, ik_chains_reach_and_follow_their_attach_point) {
  Rig r = built();
  ASSERT_TRUE(r.build);
  // Two-bone (3 joints, auto).
  EXPECT_EQ(r.g().node(r.at("armIk_R/ikSolver"))->type().name(), "ikTwoBone");
  const Vec3 s = r.p("upper_arm.R"), e = r.p("hand.R");
  const double upper = (r.p("forearm.R") - s).norm();
  const Vec3 target = s + (e - s) * 0.6 + Vec3(0, 0.1, 0);
  r.move_to(r.at("armIk_R/ik"), target);
  EXPECT_LT((r.p("hand.R") - target).norm(), kIkTol);
  EXPECT_NEAR((r.p("forearm.R") - r.p("upper_arm.R")).norm(), upper, kIkTol);
  // FABRIK (4 joints, auto).
  EXPECT_EQ(r.g().node(r.at("legIk_R/ikSolver"))->type().name(), "ikFabrik");
  const Vec3 toe_target = r.p("toe.R") + Vec3(0.05, 0.15, 0.1);
  const double shin = (r.p("foot.R") - r.p("shin.R")).norm();
  r.move_to(r.at("legIk_R/ik"), toe_target);
  EXPECT_LT((r.p("toe.R") - toe_target).norm(), 1e-5);
  EXPECT_NEAR((r.p("foot.R") - r.p("shin.R")).norm(), shin, kIkTol);
  // The whole chain follows the hip (its attach point) rigidly.
  auto before = joint_worlds(*r.scene);
  const NodeId hip = r.at("hip/main");
  const Mat4 hip_before = r.world(hip);
  r.set(hip, xform::kRotate, Value(Vec3(0, 30, 0)));
  r.set(hip, xform::kTranslate, Value(Vec3(0.1, 0.2, 0)));
  const Mat4 delta = r.world(hip) * math::affine_inverse(hip_before);
  for (const char* name : {"upper_arm.R", "forearm.R", "hand.R", "thigh.R", "shin.R", "foot.R", "toe.R",
                           "upper_arm.L", "hand.L", "thigh.L", "foot.L"}) {
    const Mat4 expected = delta * before.at(name);
    EXPECT_LT((pos(r.world(r.joint(name))) - pos(expected)).norm(), 1e-5) << name;
  }
  EXPECT_LT((r.p("hand.R") - pos(r.world(r.at("armIk_R/ik")))).norm(), kIkTol);
}

TEST(RigLimbs, an_ik_chain_with_stretch_reaches_past_full_extension) {
  Definition d = limbs();
  d.components[0].children[0].children[2].params.push_back(Param{"stretch", true, {}});
  Rig r = built(d);
  ASSERT_TRUE(r.build);
  const Vec3 s = r.p("upper_arm.R"), e = r.p("hand.R");
  const double reach = (r.p("forearm.R") - s).norm() + (e - r.p("forearm.R")).norm();
  const Vec3 target = s + (e - s).normalized() * reach * 1.8;
  r.move_to(r.at("armIk_R/ik"), target);
  EXPECT_LT((r.p("hand.R") - target).norm(), kIkTol) << "no limit on an ikChain's stretch";
  // Without the stretch feature the same parameter does nothing.
  d.features.push_back(Feature{"stretch", false, {}, {}});
  Rig off = built(d);
  ASSERT_TRUE(off.build);
  off.move_to(off.at("armIk_R/ik"), target);
  EXPECT_NEAR((off.p("hand.R") - s).norm(), reach, kIkTol) << "full extension, not beyond";
}

TEST(RigLimbs, two_bone_needs_three_joints_and_the_error_names_the_component) {
  Definition d = limbs();
  Component& leg_ik = d.components[0].children[0].children[3];
  leg_ik.params.push_back(Param{"solver", std::string("twoBone"), {}});
  auto scene = metarig();
  ASSERT_TRUE(scene);
  auto b = Build::open(*scene, d, builtin_components());
  ASSERT_TRUE(b.is_ok());
  Status s = (*b)->build_all();
  ASSERT_FALSE(s.is_ok());
  EXPECT_NE(s.message().find("legIk_R"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("3 joints"), std::string::npos) << s.message();
}

TEST(RigLimbs, twist_joints_take_their_share_of_the_end_joints_twist) {
  Rig r = built();
  ASSERT_TRUE(r.build);
  std::vector<NodeId> twists;
  for (int i = 0; i < 3; ++i) twists.push_back(r.at("forearmTwist_L/twistJoint[" + std::to_string(i) + "]"));
  const NodeId forearm = r.joint("forearm.L"), hand = r.joint("hand.L");
  for (NodeId t : twists) EXPECT_EQ(r.g().parent(t), forearm);
  const Quat rest_relative = rot(r.world(forearm)).conjugate() * rot(r.world(hand));
  // Twist the hand 60 degrees about the forearm's y axis (FK), keeping it in place.
  const NodeId fk2 = r.at("arm_L/fk[2]");
  const Quat hand_target = rot(r.world(forearm)) * Quat(Eigen::AngleAxisd(math::to_radians(60.0), Vec3::UnitY())) *
                           rest_relative;
  r.turn(fk2, rot(r.world(fk2)).conjugate() * hand_target);
  ASSERT_LT(rot(r.world(hand)).angularDistance(hand_target), kIkTol);
  // The twist the hand has now, by hand: D = R_forearm^-1 R_hand rest^-1, its angle about y.
  Quat d = rot(r.world(forearm)).conjugate() * rot(r.world(hand)) * rest_relative.conjugate();
  if (d.w() < 0) d.coeffs() = -d.coeffs();
  const double theta = 2.0 * std::atan2(d.y(), d.w());
  EXPECT_NEAR(theta, math::to_radians(60.0), kIkTol);
  const Vec3 a = r.p("forearm.L"), e = r.p("hand.L");
  for (int i = 0; i < 3; ++i) {
    const double f = (i + 1) / 4.0;
    // world = forearm world * T(f * hand in forearm space) * R_y(theta * f)
    const Vec3 along = pos(math::affine_inverse(r.world(forearm)) * r.world(hand)) * f;
    const Mat4 expected = r.world(forearm) * math::trs_matrix(along, Quat(Eigen::AngleAxisd(theta * f, Vec3::UnitY())),
                                                              Vec3::Ones());
    EXPECT_LT((r.world(twists[i]) - expected).cwiseAbs().maxCoeff(), 1e-9) << "twist joint " << i;
    EXPECT_LT((pos(r.world(twists[i])) - (a + (e - a) * f)).norm(), 1e-9) << "evenly spaced " << i;
  }
  // A pure swing of the hand (about the forearm's x) adds no twist.
  r.turn(fk2, Quat::Identity());
  const Quat swung = rot(r.world(forearm)) * Quat(Eigen::AngleAxisd(0.4, Vec3::UnitX())) * rest_relative;
  r.turn(fk2, rot(r.world(fk2)).conjugate() * swung);
  for (int i = 0; i < 3; ++i) EXPECT_LT(rot(r.world(twists[i])).angularDistance(rot(r.world(forearm))), kIkTol) << i;
}

TEST(RigLimbs, construct_all_then_remove_gives_back_the_file_byte_for_byte) {
  auto scene = metarig();
  ASSERT_TRUE(scene);
  const std::string before = io::write_scene(*scene);
  auto b = Build::open(*scene, limbs(), builtin_components());
  ASSERT_TRUE(b.is_ok());
  ASSERT_TRUE((*b)->build_all().is_ok());
  ASSERT_TRUE((*b)->remove().is_ok());
  const std::string after = io::write_scene(*scene);
  EXPECT_TRUE(after == before) << first_difference(after, before);
}

TEST(RigLimbs, stepping_back_and_forward_from_every_index_gives_the_straight_build) {
  auto scene = metarig();
  ASSERT_TRUE(scene);
  auto b = Build::open(*scene, limbs(), builtin_components());
  ASSERT_TRUE(b.is_ok());
  Build& build = **b;
  ASSERT_TRUE(build.build_all().is_ok());
  testing::expect_stepping_gives_the_straight_build(build, *scene);
}

TEST(RigLimbs, features_off_build_fk_only_limbs) {
  Definition d = limbs();
  d.features.push_back(Feature{"ik", false, {}, {}});
  d.features.push_back(Feature{"stretch", false, {}, {}});
  Rig r = built(d);
  ASSERT_TRUE(r.build);
  EXPECT_EQ(resolve_address(r.g(), "hero:arm_L/ik").status().code(), ErrorCode::kNotFound);
  r.fk_ik("arm_L", 1.0);  // no IK side: FK either way
  const Vec3 hand = r.p("hand.L");
  r.turn(r.at("arm_L/fk[0]"), Quat(Eigen::AngleAxisd(0.3, Vec3::UnitX())));
  EXPECT_GT((r.p("hand.L") - hand).norm(), 0.01);
  EXPECT_EQ(r.g().node(r.at("armIk_R/ikSolver"))->value(ops::ik::two_bone_attr::kStretch), Value(false));
}

}  // namespace
}  // namespace rigel::rig
