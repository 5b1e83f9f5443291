// The component library's newer types (issue 21): control (mGear's
// control_01), meta (groups, no controls) and mouth (jaw and lips), built on
// Rigify's human metarig: the rest pose is kept, the build is removed byte
// for byte, stepping equals the straight build, and each does its own job.
//
// Tolerances as in body_tests.cc: rest at 1e-9, posed at 1e-6 (the
// metarig's float32 quaternions).
#include <gtest/gtest.h>

#include <numbers>

#include "rig_test_util.h"
#include "rigel/io/scene_file.h"
#include "rigel/math/rotation.h"
#include "rigel/math/transform.h"
#include "rigel/ops/util/eyelid.h"
#include "rigel/rig/build.h"
#include "rigel/rig/component.h"
#include "rigel/scene/transform_types.h"

namespace rigel::rig {
namespace {

using testing::at;
using testing::at_joint;
using testing::built_rig;
using testing::BuiltRig;
using testing::first_difference;
using testing::pose_error;
using graph::Plug;
using graph::Value;
using math::Mat3;
using math::Mat4;
using math::Vec3;
namespace xform = scene::xform;

Component component(std::string type, std::string name, std::vector<Guide> guides, std::vector<Param> params = {}) {
  return testing::make_component(std::move(type), std::move(name), std::move(guides), std::move(params));
}

Param param(std::string name, ParamValue value) { return testing::make_param(std::move(name), std::move(value)); }

Guide at_values(Vec3 translate, Vec3 rotate = Vec3::Zero()) {
  Guide g;
  g.translate = translate;
  g.rotate = rotate;
  return g;
}

// global -> hip (spine joint) -> the given components.
Definition rig_with(std::vector<Component> under_hip) {
  Definition d;
  d.name = "lib";
  Component global = component("global", "global", {Guide{}});
  Component hip = component("hip", "hip", {at_joint("spine")});
  hip.children = std::move(under_hip);
  global.children = {hip};
  d.components = {global};
  return d;
}

Component mouth(bool corners) {
  std::vector<Guide> guides = {at_joint("jaw"), at_joint("lip.T.L"), at_joint("lip.B.L")};
  if (corners) {
    guides.push_back(at_joint("lip.T.L.001"));
    guides.push_back(at_joint("lip.T.R.001"));
  }
  Component m = component("mouth", "mouth", guides, {param("upperLipFollow", 0.1), param("cornerFollow", 0.5)});
  return m;
}

// control at a joint (driving it) with an fkChain hanging from it; a control
// at values (no joint); a meta whose groups hold a chain.
Definition everything() {
  Component arm = component("control", "shoulderCtl", {at_joint("shoulder.L")});
  Component chain = component("fkChain", "arm", {at_joint("upper_arm.L"), at_joint("forearm.L")});
  arm.children = {chain};
  Component floating = component("control", "ui", {at_values(Vec3(0.5, 1.8, 0), Vec3(0, 0, 90))});
  Component meta = component("meta", "palm", {at_joint("palm.01.R"), at_values(Vec3(-0.7, 1.0, 0.05))});
  Component finger = component("fkChain", "finger", {at_joint("f_index.01.R"), at_joint("f_index.02.R")});
  finger.attach = "1";
  meta.children = {finger};
  Component piston = component("piston", "piston", {at_joint("thigh.L"), at_joint("shin.L")});
  Component squash = component("squash", "squash", {at_joint("upper_arm.R"), at_joint("forearm.R")});
  Component wheel = component("wheel", "wheel", {at_joint("foot.R")}, {param("radius", 0.25)});
  Component lids = component("eyelid", "lids", {at_joint("eye.L"), at_joint("lid.T.L"), at_joint("lid.B.L")},
                             {param("blinkHeight", 0.25)});
  Component brows = component("brows", "brows", {at_joint("brow.T.L"), at_joint("brow.T.L.001"),
                                                  at_joint("brow.T.L.002"), at_joint("brow.T.L.003")});
  return rig_with({arm, floating, meta, mouth(true), piston, squash, wheel, lids, brows});
}

Vec3 position(scene::Scene& s, NodeId id) { return s.world_matrix(id).topRightCorner<3, 1>(); }
Vec3 position(scene::Scene& s, const char* joint) { return position(s, s.graph().find(joint)); }

void set(scene::Scene& s, NodeId node, graph::AttrIndex attr, const Vec3& v) {
  ASSERT_TRUE(s.graph().set_value(Plug{node, attr, -1}, Value(v)).is_ok());
}

TEST(RigLibrary, every_type_keeps_the_rest_pose_and_is_removed_byte_for_byte) {
  for (const Definition& d : {everything(), rig_with({mouth(false)})}) {
    BuiltRig b = built_rig(d);
    ASSERT_TRUE(b.build);
    std::string worst;
    EXPECT_LT(pose_error(*b.scene, b.rest, &worst), 1e-9) << "at rest nothing moves (worst: " << worst << ")";
    ASSERT_TRUE(b.build->remove().is_ok());
    const std::string after = io::write_scene(*b.scene);
    EXPECT_TRUE(after == b.before) << first_difference(after, b.before);
  }
}

TEST(RigLibrary, stepping_back_and_forward_from_every_index_gives_the_straight_build) {
  BuiltRig b = built_rig(everything());
  ASSERT_TRUE(b.build);
  testing::expect_stepping_gives_the_straight_build(*b.build, *b.scene);
}

TEST(RigLibrary, a_control_drives_its_joint_and_carries_its_children) {
  BuiltRig b = built_rig(everything());
  ASSERT_TRUE(b.build);
  scene::Scene& s = *b.scene;
  const NodeId ctl = at(s, "lib:shoulderCtl/main");
  const Vec3 forearm = position(s, "forearm.L");
  set(s, ctl, xform::kRotate, Vec3(0, 0, 30));
  const Mat4 turn = s.world_matrix(s.graph().find("shoulder.L")) * math::affine_inverse(b.rest.at("shoulder.L"));
  EXPECT_GT((turn - Mat4(Mat4::Identity())).norm(), 0.1) << "the control turns its joint";
  // The chain hangs from the control's hook: the forearm turns with it.
  const Vec3 expected = (turn * forearm.homogeneous()).head<3>();
  EXPECT_LT((position(s, "forearm.L") - expected).norm(), 1e-6);
  // A control at values drives nothing and sits where its guide says.
  const NodeId ui = at(s, "lib:ui/main");
  EXPECT_LT((position(s, ui) - Vec3(0.5, 1.8, 0)).norm(), 1e-12);
  const Mat4 w = s.world_matrix(ui);
  EXPECT_LT((w.block<3, 1>(0, 0) - Vec3(0, 1, 0)).norm(), 1e-12) << "turned 90 degrees about z";
}

TEST(RigLibrary, a_meta_holds_groups_that_follow_its_attach_point_and_carry_children) {
  BuiltRig b = built_rig(everything());
  ASSERT_TRUE(b.build);
  scene::Scene& s = *b.scene;
  const NodeId g0 = at(s, "lib:palm/group[0]"), g1 = at(s, "lib:palm/group[1]");
  EXPECT_LT((position(s, g0) - position(s, "palm.01.R")).norm(), 1e-12);
  EXPECT_LT((position(s, g1) - Vec3(-0.7, 1.0, 0.05)).norm(), 1e-12);
  const Vec3 finger_ctl = position(s, at(s, "lib:finger/fk[0]"));
  // Moving the hip (the meta's attach point) moves the groups and the chain on them.
  const NodeId hip = at(s, "lib:hip/main");
  const Vec3 hip_before = position(s, hip);
  set(s, hip, xform::kTranslate, Vec3(0, 0.2, 0));
  const Vec3 moved = position(s, hip) - hip_before;
  EXPECT_NEAR(moved.norm(), 0.2, 1e-6);
  EXPECT_LT((position(s, g1) - (Vec3(-0.7, 1.0, 0.05) + moved)).norm(), 1e-9);
  EXPECT_LT((position(s, at(s, "lib:finger/fk[0]")) - (finger_ctl + moved)).norm(), 1e-9);
  // Turning a group's parent (here: the hip) keeps the chain's offset from group 1.
  const Mat4 before = math::affine_inverse(s.world_matrix(g1)) * s.world_matrix(at(s, "lib:finger/fk[0]"));
  set(s, at(s, "lib:hip/main"), xform::kRotate, Vec3(10, 20, 30));
  const Mat4 after = math::affine_inverse(s.world_matrix(g1)) * s.world_matrix(at(s, "lib:finger/fk[0]"));
  EXPECT_LT((after - before).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(RigLibrary, the_jaw_turns_the_jaw_and_the_lips_follow_by_their_fractions) {
  BuiltRig b = built_rig(rig_with({mouth(true)}));
  ASSERT_TRUE(b.build);
  scene::Scene& s = *b.scene;
  const NodeId jaw = at(s, "lib:mouth/jaw");
  const Vec3 upper = position(s, "lip.T.L"), lower = position(s, "lip.B.L"), corner = position(s, "lip.T.L.001");
  set(s, jaw, xform::kRotate, Vec3(20, 0, 0));
  const Mat4 turn = s.world_matrix(s.graph().find("jaw")) * math::affine_inverse(b.rest.at("jaw"));
  EXPECT_GT((turn - Mat4(Mat4::Identity())).norm(), 0.1) << "the jaw joint turns";
  auto carried = [&](const Vec3& p) { return Vec3((turn * p.homogeneous()).head<3>()); };
  // Lower lip: all of the jaw's motion; upper 0.1; corners 0.5 (positions blend linearly).
  EXPECT_LT((position(s, "lip.B.L") - carried(lower)).norm(), 1e-6);
  EXPECT_LT((position(s, "lip.T.L") - (upper + 0.1 * (carried(upper) - upper))).norm(), 1e-6);
  EXPECT_LT((position(s, "lip.T.L.001") - (corner + 0.5 * (carried(corner) - corner))).norm(), 1e-6);
  EXPECT_GT((position(s, "lip.T.L") - upper).norm(), 1e-4) << "the upper lip moves a little";
  // A lip control moves its lip on top of the follow.
  const Vec3 lower_now = position(s, "lip.B.L");
  const NodeId lip = at(s, "lib:mouth/lip[1]");
  const Mat4 parent = s.world_matrix(s.graph().parent(lip)) * std::get<Mat4>(s.graph().node(lip)->value(xform::kOffsetParentMatrix));
  set(s, lip, xform::kTranslate, Vec3(0.01, 0, 0));
  const Vec3 moved = parent.block<3, 3>(0, 0) * Vec3(0.01, 0, 0);
  EXPECT_LT((position(s, "lip.B.L") - (lower_now + moved)).norm(), 1e-6);
}

Mat3 rotation(const Mat4& m) { return math::decompose(m).rotation.toRotationMatrix(); }

TEST(RigLibrary, a_pistons_ends_follow_their_controls_and_keep_aiming_at_each_other) {
  BuiltRig b = built_rig(everything());
  ASSERT_TRUE(b.build);
  scene::Scene& s = *b.scene;
  const Mat4 rest0 = b.rest.at("thigh.L"), rest1 = b.rest.at("shin.L");
  const Vec3 p0 = rest0.topRightCorner<3, 1>(), p1 = rest1.topRightCorner<3, 1>();
  const Vec3 aim0 = rotation(rest0).transpose() * (p1 - p0).normalized();
  const Vec3 aim1 = rotation(rest1).transpose() * (p0 - p1).normalized();
  const NodeId start = at(s, "lib:piston/start"), end = at(s, "lib:piston/end");
  set(s, end, xform::kTranslate, Vec3(0.1, -0.05, 0.08));
  set(s, start, xform::kTranslate, Vec3(0, 0.03, 0));
  const Mat4 w0 = s.world_matrix(s.graph().find("thigh.L")), w1 = s.world_matrix(s.graph().find("shin.L"));
  const Vec3 q0 = w0.topRightCorner<3, 1>(), q1 = w1.topRightCorner<3, 1>();
  EXPECT_LT((q1 - position(s, end)).norm(), 1e-6) << "the end joint follows its control";
  EXPECT_LT((q0 - position(s, start)).norm(), 1e-6) << "the start joint follows its control";
  EXPECT_GT((q1 - p1).norm(), 0.05);
  EXPECT_LT((rotation(w0) * aim0 - (q1 - q0).normalized()).norm(), 1e-6) << "the start aims at the end";
  EXPECT_LT((rotation(w1) * aim1 - (q0 - q1).normalized()).norm(), 1e-6) << "the end aims at the start";
  // Turning the end control about the piston's axis rolls the end joint with it.
  const Mat4 before = s.world_matrix(s.graph().find("shin.L"));
  set(s, end, xform::kRotate, Vec3(0, 25, 0));
  EXPECT_GT((s.world_matrix(s.graph().find("shin.L")) - before).norm(), 1e-3);
  EXPECT_LT((rotation(s.world_matrix(s.graph().find("shin.L"))) * aim1 - (q0 - q1).normalized()).norm(), 1e-6);
}

TEST(RigLibrary, a_squash_stretches_to_its_end_control_keeping_its_volume) {
  BuiltRig b = built_rig(everything());
  ASSERT_TRUE(b.build);
  scene::Scene& s = *b.scene;
  const Mat4 rest = b.rest.at("upper_arm.R");
  const Vec3 p0 = rest.topRightCorner<3, 1>(), p1 = b.rest.at("forearm.R").topRightCorner<3, 1>();
  const Vec3 aim = rotation(rest).transpose() * (p1 - p0).normalized();
  const NodeId end = at(s, "lib:squash/end");
  // The end control moved half the bone's length further along it (in its parent's frame, the start control's).
  const Mat4 end_parent = s.world_matrix(s.graph().parent(end)) *
                          std::get<Mat4>(s.graph().node(end)->value(xform::kOffsetParentMatrix));
  const Vec3 along = end_parent.block<3, 3>(0, 0).inverse() * (0.5 * (p1 - p0));
  set(s, end, xform::kTranslate, along);
  const Mat4 w = s.world_matrix(s.graph().find("upper_arm.R"));
  EXPECT_LT((w.topRightCorner<3, 1>() - p0).norm(), 1e-9) << "the start stays";
  for (int k = 0; k < 3; ++k) {
    const double ratio = w.block<3, 1>(0, k).norm() / rest.block<3, 1>(0, k).norm();
    EXPECT_NEAR(ratio, k == 1 ? 1.5 : 1.0 / std::sqrt(1.5), 1e-6) << "axis " << k;
  }
  EXPECT_LT((rotation(w) * aim - (p1 - p0).normalized()).norm(), 1e-6) << "it still aims along the bone";
  // Moved across the bone, it turns to aim at the control.
  set(s, end, xform::kTranslate, Vec3(0.1, 0.1, 0));
  const Mat4 w2 = s.world_matrix(s.graph().find("upper_arm.R"));
  const Vec3 target = position(s, end);
  EXPECT_LT((rotation(w2) * aim - (target - p0).normalized()).norm(), 1e-6);
  // volume 0: only the bone axis scales.
  Component flat = component("squash", "squash", {at_joint("upper_arm.R"), at_joint("forearm.R")}, {param("volume", 0.0)});
  BuiltRig c = built_rig(rig_with({flat}));
  ASSERT_TRUE(c.build);
  set(*c.scene, at(*c.scene, "lib:squash/end"), xform::kTranslate, along);
  const Mat4 w3 = c.scene->world_matrix(c.scene->graph().find("upper_arm.R"));
  const double x_ratio = w3.block<3, 1>(0, 0).norm() / rest.block<3, 1>(0, 0).norm();
  const double y_ratio = w3.block<3, 1>(0, 1).norm() / rest.block<3, 1>(0, 1).norm();
  EXPECT_NEAR(x_ratio, 1.0, 1e-6);
  EXPECT_NEAR(y_ratio, 1.5, 1e-6);
}

TEST(RigLibrary, a_wheel_rolls_by_the_distance_it_travels_forward) {
  BuiltRig b = built_rig(everything());
  ASSERT_TRUE(b.build);
  scene::Scene& s = *b.scene;
  const Mat4 rest = b.rest.at("foot.R");
  const NodeId main = at(s, "lib:wheel/main");
  // The main control stands in the joint's frame: its z is the wheel's forward, x its axle.
  // foot.R's rest matrix is ~2e-6 off orthonormal (float32 quaternions), so
  // its turns compare with ideal rotations to 1e-5.
  constexpr double kTurn = 1e-5;
  const double d = 0.3;
  set(s, main, xform::kTranslate, Vec3(0, 0, d));
  const Mat4 w = s.world_matrix(s.graph().find("foot.R"));
  const Vec3 forward = rotation(rest) * Vec3::UnitZ(), axle = rotation(rest) * Vec3::UnitX();
  EXPECT_LT((w.topRightCorner<3, 1>() - (rest.topRightCorner<3, 1>() + d * forward)).norm(), 1e-6);
  const Mat3 turn = rotation(w) * rotation(rest).transpose();
  const Mat3 expected = Eigen::AngleAxisd(d / 0.25, axle).toRotationMatrix();
  EXPECT_LT((turn - expected).cwiseAbs().maxCoeff(), kTurn) << "turned d / r radians about the axle";
  // Sideways motion does not roll it; the spin control turns it on top.
  set(s, main, xform::kTranslate, Vec3(0.2, 0, 0));
  EXPECT_LT((rotation(s.world_matrix(s.graph().find("foot.R"))) - rotation(rest)).cwiseAbs().maxCoeff(), kTurn);
  set(s, at(s, "lib:wheel/spin"), xform::kRotate, Vec3(30, 0, 0));
  const Mat3 spun = rotation(s.world_matrix(s.graph().find("foot.R"))) * rotation(rest).transpose();
  EXPECT_LT((spun - Mat3(Eigen::AngleAxisd(30.0 * std::numbers::pi / 180.0, axle))).cwiseAbs().maxCoeff(), kTurn);
  // What carries it counts as travel: the hip moves the wheel, which rolls by
  // the distance it went along its forward axis.
  set(s, at(s, "lib:wheel/spin"), xform::kRotate, Vec3(0, 0, 0));
  set(s, main, xform::kTranslate, Vec3(0, 0, 0));
  const NodeId hip = at(s, "lib:hip/main");
  const Vec3 before = position(s, main);
  set(s, hip, xform::kTranslate, Vec3(0.1, 0.2, 0.3));
  const double travel = (position(s, main) - before).dot(forward);
  EXPECT_GT(std::abs(travel), 0.01);
  const Mat3 carried = rotation(s.world_matrix(s.graph().find("foot.R"))) * rotation(rest).transpose();
  EXPECT_LT((carried - Mat3(Eigen::AngleAxisd(travel / 0.25, axle))).cwiseAbs().maxCoeff(), kTurn);
}

// The lids turn about the eye in its parent's frame: a blink closes them
// by the gap, meeting at blinkHeight; they follow the eye's pitch by their
// fractions.
TEST(RigLibrary, eyelids_blink_and_follow_the_eye) {
  BuiltRig b = built_rig(everything());
  ASSERT_TRUE(b.build);
  scene::Scene& s = *b.scene;
  graph::Graph& g = s.graph();
  const NodeId node = at(s, "lib:lids/eyelid");
  const Vec3 eye = position(s, "eye.L");
  const Mat3 head = math::rigid_part(s.world_matrix(g.parent(g.find("eye.L")))).topLeftCorner<3, 3>();
  const Vec3 axis = head * Vec3::UnitX();
  const Vec3 upper = position(s, "lid.T.L"), lower = position(s, "lid.B.L");
  auto turned = [&](const Vec3& p, double degrees) {
    return Vec3(eye + Eigen::AngleAxisd(degrees * std::numbers::pi / 180.0, axis) * (p - eye));
  };
  namespace el = ops::util::eyelid_attr;
  ASSERT_TRUE(g.set_value(Plug{node, el::kBlink, -1}, Value(1.0)).is_ok());
  EXPECT_LT((position(s, "lid.T.L") - turned(upper, 30.0 * 0.75)).norm(), 1e-6) << "the upper lid comes down";
  EXPECT_LT((position(s, "lid.B.L") - turned(lower, -30.0 * 0.25)).norm(), 1e-6) << "the lower lid comes up";
  ASSERT_TRUE(g.set_value(Plug{node, el::kBlink, -1}, Value(0.0)).is_ok());
  EXPECT_LT((position(s, "lid.T.L") - upper).norm(), 1e-9);
  const NodeId eye_joint = g.find("eye.L");
  if (xform::is_quaternion_mode(*g.node(eye_joint))) {
    const math::Quat q = std::get<math::Quat>(g.evaluate(eye_joint, xform::kRotateQuaternion));
    ASSERT_TRUE(g.set_value(Plug{eye_joint, xform::kRotateQuaternion, -1},
                            Value(math::Quat(q * math::Quat(Eigen::AngleAxisd(0.2, Vec3::UnitX())))))
                    .is_ok());
  } else {
    set(s, eye_joint, xform::kRotate, Vec3(12, 0, 0));
  }
  const double pitch = std::get<double>(g.evaluate(node, el::kPitch));
  EXPECT_GT(std::abs(pitch), 1.0) << "the eye's turn about the lids' hinge";
  EXPECT_LT((position(s, "lid.T.L") - turned(upper, 0.4 * pitch)).norm(), 1e-6);
  EXPECT_LT((position(s, "lid.B.L") - turned(lower, 0.2 * pitch)).norm(), 1e-6);
}

// The main brow control moves each brow by its share: 1 at the inner brow,
// 0.5 at the outer, linearly between; a brow control moves its own joint.
TEST(RigLibrary, brows_follow_the_main_control_by_their_falloff) {
  BuiltRig b = built_rig(everything());
  ASSERT_TRUE(b.build);
  scene::Scene& s = *b.scene;
  const char* joints[] = {"brow.T.L", "brow.T.L.001", "brow.T.L.002", "brow.T.L.003"};
  std::vector<Vec3> rest;
  for (const char* j : joints) rest.push_back(position(s, j));
  const NodeId main = at(s, "lib:brows/main");
  const Vec3 delta(0, 0.012, 0.003);
  const Mat4 place = s.world_matrix(main);
  const Mat3 to_local = math::affine_inverse(place).topLeftCorner<3, 3>();
  set(s, main, xform::kTranslate, Vec3(to_local * delta));
  for (int g = 0; g < 4; ++g) {
    const double share = 1.0 - 0.5 * g / 3.0;
    EXPECT_LT((position(s, joints[g]) - (rest[static_cast<std::size_t>(g)] + delta * share)).norm(), 1e-6)
        << joints[g] << " moves by " << share;
  }
  set(s, main, xform::kTranslate, Vec3(0, 0, 0));
  const NodeId brow = at(s, "lib:brows/brow[2]");
  set(s, brow, xform::kTranslate, Vec3(Vec3(0.004, 0, 0)));
  EXPECT_GT((position(s, joints[2]) - rest[2]).norm(), 1e-3) << "a brow control moves its joint";
  EXPECT_LT((position(s, joints[0]) - rest[0]).norm(), 1e-9) << "and no other";
}

TEST(RigLibrary, a_mouth_without_joints_fails_naming_the_component) {
  Component m = component("mouth", "mouth", {at_joint("jaw"), at_values(Vec3(0, 1, 0)), at_joint("lip.B.L")});
  scene::Scene* scene = nullptr;
  auto s = testing::metarig();
  ASSERT_TRUE(s);
  scene = s.get();
  auto opened = Build::open(*scene, rig_with({m}), builtin_components());
  ASSERT_TRUE(opened.is_ok()) << opened.status().message();
  const Status built = (*opened)->build_all();
  EXPECT_FALSE(built.is_ok());
  EXPECT_NE(built.message().find("mouth"), std::string::npos) << built.message();
  EXPECT_NE(built.message().find("guide 1"), std::string::npos) << built.message();
}

}  // namespace
}  // namespace rigel::rig
