// The hand component built on Rigify's human metarig: the rest pose is kept
// exactly, curl and spread turn the fingers as components/hand.h says (the
// expected poses are computed here from the rest pose by that rule), the FK
// finger controls work on top, a limb keeps its wrist, and builds are undone
// byte for byte.
//
// Tolerances: the rest pose is compared at 1e-9. Posed comparisons use 1e-6:
// the metarig's rotations are float32 quaternions up to ~5e-8 off unit
// length (its matrices are rotations times |q|^2), so a turned joint matches
// a turned rest matrix only to that order.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "rig_test_util.h"
#include "rigel/io/scene_file.h"
#include "rigel/math/transform.h"
#include "rigel/ops/util/blend.h"
#include "rigel/ops/util/finger.h"
#include "rigel/rig/build.h"
#include "rigel/rig/component.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"

namespace rigel::rig {
namespace {

using testing::at_joint;
using testing::first_difference;
using testing::metarig;
using testing::at;
using testing::built_rig;
using testing::BuiltRig;
using testing::joint_worlds;
using testing::pose_error;
using testing::normalized;

using graph::Plug;
using graph::Value;
using math::Mat3;
using math::Mat4;
using math::Vec3;
namespace xform = scene::xform;
namespace fa = ops::util::finger_attr;

constexpr double kPi = math::kPi;

// The metarig's left hand: finger name and its three joints.
const std::vector<std::pair<std::string, std::vector<std::string>>>& fingers() {
  static const std::vector<std::pair<std::string, std::vector<std::string>>> kFingers = {
      {"thumb", {"thumb.01.L", "thumb.02.L", "thumb.03.L"}},
      {"index", {"f_index.01.L", "f_index.02.L", "f_index.03.L"}},
      {"middle", {"f_middle.01.L", "f_middle.02.L", "f_middle.03.L"}},
      {"ring", {"f_ring.01.L", "f_ring.02.L", "f_ring.03.L"}},
      {"pinky", {"f_pinky.01.L", "f_pinky.02.L", "f_pinky.03.L"}}};
  return kFingers;
}

Guide named(std::string name, std::string joint) {
  Guide g = at_joint(std::move(joint));
  g.name = std::move(name);
  return g;
}

Param param(std::string name, ParamValue value) {
  Param p;
  p.name = std::move(name);
  p.value = std::move(value);
  return p;
}

Component component(std::string type, std::string name, Side side, std::vector<Guide> guides) {
  Component c;
  c.type = std::move(type);
  c.name = std::move(name);
  c.side = side;
  c.rig_id = new_rig_id();
  c.guides = std::move(guides);
  return c;
}

// The metarig's joint on `side`: "f_index.01.L" -> "f_index.01.R".
std::string on_side(const std::string& joint, Side side) {
  return side == Side::kRight ? joint.substr(0, joint.size() - 1) + "R" : joint;
}

// hand.L (or .R) and every finger joint, named FINGER.N.
Component hand(std::vector<Param> params = {}, Side side = Side::kLeft) {
  std::vector<Guide> guides = {named("hand", on_side("hand.L", side))};
  for (const auto& [finger, joints] : fingers())
    for (std::size_t j = 0; j < joints.size(); ++j)
      guides.push_back(named(finger + "." + std::to_string(j), on_side(joints[j], side)));
  Component c = component("hand", "hand", side, std::move(guides));
  c.params = std::move(params);
  c.attach = "END";
  return c;
}

enum class Parent { kFkArm, kLimb, kNone };

// global -> hip (spine) -> fkChain torso (spine.001 .. spine.003) -> at END
//   kFkArm: fkChain arm (shoulder.L, upper_arm.L, forearm.L) -> hand at END;
//   kLimb:  fkChain shoulder (shoulder.L) -> limb arm (upper_arm.L, forearm.L,
//           hand.L) -> hand at END (the limb drives hand.L);
// kNone: the hand hangs straight from the global control.
Definition rig(Parent parent, Component h = hand()) {
  Definition d;
  d.name = "hero";
  d.version = "1.0";
  Component global = component("global", "global", Side::kCenter, {Guide{}});
  if (parent == Parent::kNone) {
    h.attach.clear();
    global.children = {h};
    d.components = {global};
    return d;
  }
  Component hip = component("hip", "hip", Side::kCenter, {at_joint("spine")});
  Component torso = component("fkChain", "torso", Side::kCenter,
                              {at_joint("spine.001"), at_joint("spine.002"), at_joint("spine.003")});
  if (parent == Parent::kFkArm) {
    Component arm = component("fkChain", "arm", Side::kLeft,
                              {at_joint("shoulder.L"), at_joint("upper_arm.L"), at_joint("forearm.L")});
    arm.attach = "END";
    arm.children = {h};
    torso.children = {arm};
  } else {
    Component shoulder = component("fkChain", "shoulder", Side::kLeft, {at_joint("shoulder.L")});
    shoulder.attach = "END";
    Component arm = component("limb", "arm", Side::kLeft,
                              {named("upper", "upper_arm.L"), named("lower", "forearm.L"), named("end", "hand.L")});
    arm.attach = "END";
    arm.children = {h};
    shoulder.children = {arm};
    torso.children = {shoulder};
  }
  hip.children = {torso};
  global.children = {hip};
  d.components = {global};
  return d;
}

Vec3 position_of(const Mat4& m) { return m.topRightCorner<3, 1>(); }
Mat3 rotation_of(const Mat4& m) { return math::decompose(m).rotation.toRotationMatrix(); }

void set(scene::Scene& s, const Plug& p, Value v) { ASSERT_TRUE(s.graph().set_value(p, std::move(v)).is_ok()); }

Mat4 world(scene::Scene& s, const std::string& joint) { return s.world_matrix(s.graph().find(joint)); }

// A turn by `angle` (radians) about the unit world `axis` through `pivot`.
Mat4 turn_about(const Vec3& axis, double angle, const Vec3& pivot) {
  Mat4 m = Mat4::Identity();
  const Mat3 r = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
  m.topLeftCorner<3, 3>() = r;
  m.topRightCorner<3, 1>() = pivot - r * pivot;
  return m;
}

// A finger's bend axis by hand.h's rule: the normal of its three joints'
// plane, signed to agree with joint 0's x axis (bendAxis x).
Vec3 bend_axis(const std::map<std::string, Mat4>& rest, const std::vector<std::string>& joints) {
  const Vec3 p0 = position_of(rest.at(joints[0])), p1 = position_of(rest.at(joints[1])),
             p2 = position_of(rest.at(joints[2]));
  Vec3 b = (p1 - p0).cross(p2 - p1).normalized();
  if (b.dot(rotation_of(rest.at(joints[0])).col(0)) < 0) b = -b;
  return b;
}

// The rest pose of a finger curled by `angle` (radians) at every joint about
// `axis`: joint j turns about its own (already moved) position, carrying
// the joints after it.
std::vector<Mat4> curled(const std::map<std::string, Mat4>& rest, const std::vector<std::string>& joints,
                         const Vec3& axis, double angle) {
  Mat4 carry = Mat4::Identity();
  std::vector<Mat4> out;
  for (const std::string& j : joints) {
    const Vec3 pivot = (carry * rest.at(j)).topRightCorner<3, 1>();
    carry = turn_about(axis, angle, pivot) * carry;
    out.push_back(carry * rest.at(j));
  }
  return out;
}

double difference(const Mat4& a, const Mat4& b) { return (a - b).cwiseAbs().maxCoeff(); }

std::set<std::string> finger_joints() {
  std::set<std::string> out;
  for (const auto& f : fingers()) out.insert(f.second.begin(), f.second.end());
  return out;
}

// ---- rest, remove, stepping ------------------------------------------------

TEST(RigHand, at_rest_nothing_moves_and_remove_gives_back_the_file_byte_for_byte) {
  const std::pair<const char*, Definition> cases[] = {
      {"under an fkChain arm", rig(Parent::kFkArm)},
      {"under a limb", rig(Parent::kLimb)},
      {"standalone", rig(Parent::kNone)},
      {"curlAttributes false", rig(Parent::kFkArm, hand({param("curlAttributes", false)}))}};
  for (const auto& [what, d] : cases) {
    BuiltRig b = built_rig(d);
    ASSERT_TRUE(b.build) << what;
    std::string worst;
    EXPECT_LT(pose_error(*b.scene, b.rest, &worst), 1e-9) << what << ": at rest nothing moves (worst: " << worst << ")";
    const bool curl_node = resolve_address(b.scene->graph(), "hero:hand_L/fingerCurl").is_ok();
    EXPECT_EQ(curl_node, std::string(what) != "curlAttributes false") << what << ": the fingerCurl node";
    ASSERT_TRUE(b.build->remove().is_ok()) << what;
    const std::string after = io::write_scene(*b.scene);
    EXPECT_TRUE(after == b.before) << what << ": " << first_difference(after, b.before);
  }
}

TEST(RigHand, stepping_back_and_forward_from_every_index_gives_the_straight_build) {
  BuiltRig b = built_rig(rig(Parent::kLimb));
  ASSERT_TRUE(b.build);
  Build& build = *b.build;
  testing::expect_stepping_gives_the_straight_build(build, *b.scene);
}

TEST(RigHand, controls_sit_at_their_joints_one_per_finger_joint) {
  BuiltRig b = built_rig(rig(Parent::kFkArm));
  ASSERT_TRUE(b.build);
  scene::Scene& s = *b.scene;
  EXPECT_LT(difference(s.world_matrix(at(s, "hero:hand_L/hand")), b.rest.at("hand.L")), 1e-9);
  int running = 0;
  for (const auto& [finger, joints] : fingers()) {
    for (std::size_t j = 0; j < joints.size(); ++j, ++running) {
      const NodeId c = at(s, "hero:hand_L/finger[" + std::to_string(running) + "]");
      EXPECT_LT(difference(s.world_matrix(c), b.rest.at(joints[j])), 1e-9) << finger << "." << j;
      EXPECT_EQ(at(s, "hero:hand_L/joint[" + std::to_string(running + 1) + "]/finger"), c)
          << "finger control " << running << " belongs to guide " << running + 1;
      const NodeId parent = s.graph().parent(c);
      EXPECT_EQ(parent, j == 0 ? at(s, "hero:hand_L/hand")
                               : at(s, "hero:hand_L/finger[" + std::to_string(running - 1) + "]"))
          << "each finger is a chain hanging from the hand control";
    }
  }
  EXPECT_EQ(running, 15);
}

// ---- curl ----------------------------------------------------------------------

TEST(RigHand, curl_turns_every_finger_joint_about_its_bend_axis) {
  BuiltRig b = built_rig(rig(Parent::kFkArm));
  ASSERT_TRUE(b.build);
  scene::Scene& s = *b.scene;
  const NodeId curl = at(s, "hero:hand_L/fingerCurl");
  set(s, Plug{curl, fa::kCurl, -1}, Value(30.0));
  const double angle = 30.0 * kPi / 180.0;
  for (const auto& [finger, joints] : fingers()) {
    const Vec3 axis = bend_axis(b.rest, joints);
    const std::vector<Mat4> expected = curled(b.rest, joints, axis, angle);
    for (std::size_t j = 0; j < joints.size(); ++j)
      EXPECT_LT(difference(world(s, joints[j]), expected[j]), 1e-6) << finger << " joint " << j;
    // The first joint's turn since rest: the curl, about the bend axis.
    const Mat3 since_rest = rotation_of(world(s, joints[0])) * rotation_of(b.rest.at(joints[0])).transpose();
    const Eigen::AngleAxisd turn(since_rest);
    EXPECT_NEAR(turn.angle(), angle, 1e-6) << finger << ": the first joint turns by the curl";
    EXPECT_GT(turn.axis().dot(axis), 1 - 1e-6) << finger << ": about the bend axis";
  }
  std::string worst;
  EXPECT_LT(pose_error(s, b.rest, &worst, finger_joints()), 1e-9) << "nothing outside the fingers moves: " << worst;
  // Positive curl closes the fist: the index's last joint comes nearer the wrist.
  const double tip_before = (position_of(b.rest.at("f_index.03.L")) - position_of(b.rest.at("hand.L"))).norm();
  EXPECT_LT((position_of(world(s, "f_index.03.L")) - position_of(world(s, "hand.L"))).norm(), tip_before - 0.01);
  set(s, Plug{curl, fa::kCurl, -1}, Value(0.0));
  EXPECT_LT(pose_error(s, b.rest, &worst), 1e-9) << "curl back at 0: the rest pose (" << worst << ")";
}

TEST(RigHand, per_finger_curl_moves_only_that_finger) {
  BuiltRig b = built_rig(rig(Parent::kFkArm));
  ASSERT_TRUE(b.build);
  scene::Scene& s = *b.scene;
  const NodeId curl = at(s, "hero:hand_L/fingerCurl");
  EXPECT_EQ(std::get<std::vector<std::string>>(s.graph().node(curl)->value(fa::kFingerNames)),
            (std::vector<std::string>{"thumb", "index", "middle", "ring", "pinky"}));
  set(s, Plug{curl, fa::kFingerCurl, -1}, Value(std::vector<double>{0, 0, 0, 45, 0}));
  const auto& ring = fingers()[3].second;
  const std::vector<Mat4> expected = curled(b.rest, ring, bend_axis(b.rest, ring), 45.0 * kPi / 180.0);
  for (std::size_t j = 0; j < ring.size(); ++j) EXPECT_LT(difference(world(s, ring[j]), expected[j]), 1e-6) << ring[j];
  std::string worst;
  EXPECT_LT(pose_error(s, b.rest, &worst, std::set<std::string>(ring.begin(), ring.end())), 1e-9)
      << "only the ring moves: " << worst;
  // The overall curl adds to a finger's own.
  set(s, Plug{curl, fa::kCurl, -1}, Value(-10.0));
  const std::vector<Mat4> sum = curled(b.rest, ring, bend_axis(b.rest, ring), 35.0 * kPi / 180.0);
  for (std::size_t j = 0; j < ring.size(); ++j) EXPECT_LT(difference(world(s, ring[j]), sum[j]), 1e-6) << ring[j];
  const auto& index = fingers()[1].second;
  const std::vector<Mat4> opened = curled(b.rest, index, bend_axis(b.rest, index), -10.0 * kPi / 180.0);
  for (std::size_t j = 0; j < index.size(); ++j)
    EXPECT_LT(difference(world(s, index[j]), opened[j]), 1e-6) << index[j] << ": negative curl opens";
}

TEST(RigHand, positive_curl_closes_both_hands) {
  for (Side side : {Side::kLeft, Side::kRight}) {
    const std::string rig_side = side == Side::kLeft ? "L" : "R";
    BuiltRig b = built_rig(rig(Parent::kNone, hand({}, side)));
    ASSERT_TRUE(b.build) << rig_side;
    scene::Scene& s = *b.scene;
    std::string worst;
    EXPECT_LT(pose_error(s, b.rest, &worst), 1e-9) << rig_side << ": at rest nothing moves (" << worst << ")";
    set(s, Plug{at(s, "hero:hand_" + rig_side + "/fingerCurl"), fa::kCurl, -1}, Value(40.0));
    const Vec3 wrist = position_of(b.rest.at(on_side("hand.L", side)));
    for (std::size_t k = 1; k < fingers().size(); ++k) {
      const std::string tip = on_side(fingers()[k].second.back(), side);
      const double before = (position_of(b.rest.at(tip)) - wrist).norm();
      EXPECT_LT((position_of(world(s, tip)) - wrist).norm(), before - 0.01) << tip << " comes nearer the wrist";
      const Vec3 axis = bend_axis(b.rest, {on_side(fingers()[k].second[0], side), on_side(fingers()[k].second[1], side),
                                           on_side(fingers()[k].second[2], side)});
      EXPECT_GT(axis.dot(rotation_of(b.rest.at(on_side(fingers()[k].second[0], side))).col(0)), 0.9)
          << tip << ": the plane normal is near the joints' own x (Rigify's bend axis)";
    }
  }
}

// ---- spread --------------------------------------------------------------------

TEST(RigHand, spread_turns_the_first_joints_away_from_the_middle_finger) {
  BuiltRig b = built_rig(rig(Parent::kFkArm));
  ASSERT_TRUE(b.build);
  scene::Scene& s = *b.scene;
  // The hand's normal by hand.h's rule: (mean of the first joints - hand) x
  // (sum of the bend axes of the fingers other than the thumb).
  Vec3 mean = Vec3::Zero(), across = Vec3::Zero();
  for (const auto& [finger, joints] : fingers()) {
    mean += position_of(b.rest.at(joints[0])) / 5.0;
    if (finger != "thumb") across += bend_axis(b.rest, joints);
  }
  const Vec3 normal = (mean - position_of(b.rest.at("hand.L"))).cross(across).normalized();
  set(s, Plug{at(s, "hero:hand_L/fingerCurl"), fa::kSpread, -1}, Value(8.0));
  const Vec3 middle_base = position_of(b.rest.at("f_middle.01.L"));
  std::map<std::string, double> signed_turn;
  for (std::size_t k = 0; k < fingers().size(); ++k) {
    const auto& [finger, joints] = fingers()[k];
    const Mat3 turn = rotation_of(world(s, joints[0])) * rotation_of(b.rest.at(joints[0])).transpose();
    const Eigen::AngleAxisd aa(turn);
    const double expected = 8.0 * std::abs(static_cast<double>(k) - 2.0) * kPi / 180.0;
    EXPECT_NEAR(aa.angle(), expected, 1e-6) << finger << ": spread times its distance from the middle in the list";
    if (k == 2) continue;
    EXPECT_GT(std::abs(aa.axis().dot(normal)), 1 - 1e-6) << finger << ": about the hand's normal";
    signed_turn[finger] = aa.axis().dot(normal) > 0 ? aa.angle() : -aa.angle();
    // The first joint stays; the second goes away from the middle finger's first joint.
    EXPECT_LT((position_of(world(s, joints[0])) - position_of(b.rest.at(joints[0]))).norm(), 1e-9);
    const double before = (position_of(b.rest.at(joints[1])) - middle_base).norm();
    EXPECT_GT((position_of(world(s, joints[1])) - middle_base).norm(), before + 1e-4) << finger << " spreads away";
    // The finger turns as one piece about its first joint.
    const Mat4 carry = turn_about(aa.axis(), aa.angle(), position_of(b.rest.at(joints[0])));
    for (const std::string& j : joints) EXPECT_LT(difference(world(s, j), carry * b.rest.at(j)), 1e-6) << j;
  }
  EXPECT_LT(signed_turn["index"] * signed_turn["ring"], 0) << "index and ring turn in opposite directions";
  EXPECT_GT(signed_turn["index"] * signed_turn["thumb"], 0) << "thumb and index on one side";
  EXPECT_GT(signed_turn["ring"] * signed_turn["pinky"], 0) << "ring and pinky on the other";
  std::set<std::string> others = finger_joints();
  for (const char* j : {"f_middle.01.L", "f_middle.02.L", "f_middle.03.L"}) others.erase(j);
  std::string worst;
  EXPECT_LT(pose_error(s, b.rest, &worst, others), 1e-9)
      << "the middle finger and everything outside the fingers stay (worst: " << worst << ")";
}

// ---- FK over curl, the hand control ------------------------------------------

TEST(RigHand, fk_finger_controls_work_on_top_of_the_curl) {
  BuiltRig b = built_rig(rig(Parent::kFkArm));
  ASSERT_TRUE(b.build);
  scene::Scene& s = *b.scene;
  set(s, Plug{at(s, "hero:hand_L/fingerCurl"), fa::kCurl, -1}, Value(30.0));
  const std::map<std::string, Mat4> curl_pose = joint_worlds(s);
  // index.1 is finger control 4 (thumb 0..2, index 3..5).
  const NodeId control = at(s, "hero:hand_L/finger[4]");
  EXPECT_LT(difference(s.world_matrix(control), curl_pose.at("f_index.02.L")), 1e-6) << "the control rides the curl";
  set(s, Plug{control, xform::kRotate, -1}, Value(Vec3(25, 0, 0)));
  Mat4 local = Mat4::Identity();
  local.topLeftCorner<3, 3>() = Eigen::AngleAxisd(25.0 * kPi / 180.0, Vec3::UnitX()).toRotationMatrix();
  const Mat4 expected = curl_pose.at("f_index.02.L") * local;
  EXPECT_LT(difference(world(s, "f_index.02.L"), expected), 1e-6)
      << "the FK control turns its joint from the curled pose";
  const Mat4 tip = expected * math::affine_inverse(curl_pose.at("f_index.02.L")) * curl_pose.at("f_index.03.L");
  EXPECT_LT(difference(world(s, "f_index.03.L"), tip), 1e-6) << "and carries the joint after it";
  EXPECT_LT(difference(world(s, "f_index.01.L"), curl_pose.at("f_index.01.L")), 1e-9) << "not the one before";
  // Curl back to 0: the FK rotation stays, from the rest pose.
  set(s, Plug{at(s, "hero:hand_L/fingerCurl"), fa::kCurl, -1}, Value(0.0));
  EXPECT_LT(difference(world(s, "f_index.02.L"), b.rest.at("f_index.02.L") * local), 1e-6);
}

TEST(RigHand, moving_the_hand_control_moves_hand_and_fingers_rigidly) {
  for (Parent parent : {Parent::kFkArm, Parent::kNone}) {
    BuiltRig b = built_rig(rig(parent));
    ASSERT_TRUE(b.build);
    scene::Scene& s = *b.scene;
    const NodeId control = at(s, "hero:hand_L/hand");
    set(s, Plug{control, xform::kTranslate, -1}, Value(Vec3(0.01, -0.02, 0.03)));
    set(s, Plug{control, xform::kRotate, -1}, Value(Vec3(10, -20, 35)));
    const Mat4 motion = world(s, "hand.L") * math::affine_inverse(b.rest.at("hand.L"));
    EXPECT_GT(difference(motion, Mat4::Identity()), 0.1) << "the hand control drives the hand joint";
    EXPECT_LT(difference(world(s, "hand.L"), s.world_matrix(control)), 1e-6) << "the hand joint is at its control";
    std::set<std::string> hand_side = finger_joints();
    for (const char* palm : {"palm.01.L", "palm.02.L", "palm.03.L", "palm.04.L"}) hand_side.insert(palm);
    for (const std::string& j : hand_side)
      EXPECT_LT(difference(world(s, j), motion * b.rest.at(j)), 1e-6) << j << " moves with the hand as one piece";
    std::set<std::string> moved = hand_side;
    moved.insert("hand.L");
    std::string worst;
    EXPECT_LT(pose_error(s, b.rest, &worst, moved), 1e-9) << "nothing else moves: " << worst;
  }
}

TEST(RigHand, under_a_limb_the_limb_keeps_the_wrist_and_the_fingers_follow) {
  BuiltRig b = built_rig(rig(Parent::kLimb));
  ASSERT_TRUE(b.build);
  scene::Scene& s = *b.scene;
  graph::Graph& g = s.graph();
  const NodeId hand_joint = g.find("hand.L");
  for (graph::AttrIndex channel : {xform::kTranslate, xform::kRotateQuaternion, xform::kScale}) {
    std::optional<Plug> source = g.source(Plug{hand_joint, channel, -1});
    ASSERT_TRUE(source.has_value()) << "hand.L is still driven by the limb";
    EXPECT_EQ(source->node, at(s, "hero:arm_L/fkIkSwitch")) << "by its fkIkSwitch, not by the hand control";
  }
  EXPECT_EQ(std::get<std::int64_t>(g.node(hand_joint)->value(xform::kRotateMode)), 1) << "still in quaternion mode";
  // FK: turning the elbow moves the hand; the fingers and the hand control follow it.
  set(s, Plug{at(s, "hero:arm_L/fk[1]"), xform::kRotate, -1}, Value(Vec3(30, 0, 20)));
  const Mat4 motion = world(s, "hand.L") * math::affine_inverse(b.rest.at("hand.L"));
  EXPECT_GT(difference(motion, Mat4::Identity()), 0.05);
  EXPECT_LT(difference(s.world_matrix(at(s, "hero:hand_L/hand")), world(s, "hand.L")), 1e-6)
      << "the hand control follows the hand joint";
  for (const std::string& j : finger_joints())
    EXPECT_LT(difference(world(s, j), motion * b.rest.at(j)), 1e-6) << j << " follows the hand";
  // IK: the wrist takes the IK control's orientation; the fingers still follow.
  set(s, Plug{at(s, "hero:arm_L/fkIkSwitch"), ops::util::fk_ik_attr::kFkIk, -1}, Value(1.0));
  set(s, Plug{at(s, "hero:arm_L/ik"), xform::kRotate, -1}, Value(Vec3(0, 0, 40)));
  const Mat4 ik_motion = world(s, "hand.L") * math::affine_inverse(b.rest.at("hand.L"));
  EXPECT_GT(difference(ik_motion, Mat4::Identity()), 0.05) << "the IK control turns the wrist";
  for (const std::string& j : finger_joints())
    EXPECT_LT(difference(world(s, j), ik_motion * b.rest.at(j)), 1e-6) << j << " follows the IK wrist";
  // Curl works on the limb's hand as well.
  set(s, Plug{at(s, "hero:hand_L/fingerCurl"), fa::kCurl, -1}, Value(20.0));
  const auto& index = fingers()[1].second;
  const std::vector<Mat4> expected = curled(b.rest, index, bend_axis(b.rest, index), 20.0 * kPi / 180.0);
  for (std::size_t j = 0; j < index.size(); ++j)
    EXPECT_LT(difference(world(s, index[j]), ik_motion * expected[j]), 1e-6) << index[j];
}

// ---- the node --------------------------------------------------------------------

TEST(RigHand, finger_curl_node_turns_spread_then_curl_and_names_a_bad_axis) {
  auto scene = metarig();
  ASSERT_TRUE(scene);
  graph::Graph& g = scene->graph();
  Result<NodeId> node = g.create_node(ops::util::kFingerCurlType, "curl");
  ASSERT_TRUE(node.is_ok()) << node.status().message();
  Mat4 rest = Mat4::Identity();
  rest.topRightCorner<3, 1>() = Vec3(1, 2, 3);
  // Control 0 (finger 0) spreads about z and curls about x; control 1
  // (finger 1) has a zero bend axis; control 2 (finger 1) only curls about y.
  set(*scene, Plug{*node, fa::kRestOffsetParentMatrix, -1}, Value(std::vector<Mat4>{rest, rest, rest}));
  set(*scene, Plug{*node, fa::kFinger, -1}, Value(std::vector<std::int64_t>{0, 1, 1}));
  set(*scene, Plug{*node, fa::kBendAxis, -1},
      Value(std::vector<Vec3>{Vec3::UnitX(), Vec3::Zero(), Vec3::UnitY()}));
  set(*scene, Plug{*node, fa::kSpreadAxis, -1}, Value(std::vector<Vec3>{Vec3::UnitZ(), Vec3::Zero(), Vec3::Zero()}));
  set(*scene, Plug{*node, fa::kSpreadWeight, -1}, Value(std::vector<double>{1.0, 0.0, 0.0}));
  const auto out_now = [&] { return std::get<std::vector<Mat4>>(g.evaluate(*node, fa::kOutOffsetParentMatrix)); };
  std::vector<Mat4> out = out_now();
  ASSERT_EQ(out.size(), 3u);
  for (const Mat4& m : out) EXPECT_EQ(m, rest) << "at zero: the rest offsets exactly";
  set(*scene, Plug{*node, fa::kSpread, -1}, Value(90.0));
  set(*scene, Plug{*node, fa::kCurl, -1}, Value(30.0));
  set(*scene, Plug{*node, fa::kFingerCurl, -1}, Value(std::vector<double>{60.0, 60.0}));
  out = out_now();
  // Control 0: Rz(90) * Rx(90), x -> y, y -> z, z -> x.
  Mat4 both = rest;
  both.topLeftCorner<3, 3>() << 0, 0, 1, 1, 0, 0, 0, 1, 0;
  EXPECT_LT(difference(out[0], both), 1e-12) << "the spread turn first, then the curl in the spread frame";
  EXPECT_EQ(out[1], rest) << "a zero bend axis: no turn";
  // Control 2: Ry(90), z -> x.
  Mat4 quarter = rest;
  quarter.topLeftCorner<3, 3>() << 0, 0, 1, 0, 1, 0, -1, 0, 0;
  EXPECT_LT(difference(out[2], quarter), 1e-12) << "curl + fingerCurl[1] = 90 degrees";
  const std::string problem = std::get<std::string>(g.evaluate(*node, fa::kError));
  EXPECT_NE(problem.find("bendAxis[1]"), std::string::npos) << problem;
}

// ---- errors ------------------------------------------------------------------

TEST(RigHand, bad_guides_fail_with_the_component_named) {
  struct Case {
    const char* what;
    std::vector<Guide> fingers;
    const char* expected;  // in the message
  };
  const Case cases[] = {
      {"not FINGER.N", {named("index", "f_index.01.L")}, "FINGER.N"},
      {"a gap in the numbers", {named("index.0", "f_index.01.L"), named("index.2", "f_index.02.L")}, "index.1"},
      {"a finger twice",
       {named("index.0", "f_index.01.L"), named("ring.0", "f_ring.01.L"), named("index.0", "f_index.02.L")},
       "listed twice"},
      {"not a child",
       {named("index.0", "f_index.01.L"), named("index.1", "f_index.03.L")},
       "not a child of 'f_index.01.L'"},
      {"not below the hand", {named("thumb.0", "thumb.01.R")}, "does not hang below the hand joint 'hand.L'"},
      {"a joint twice", {named("index.0", "f_index.01.L"), named("ring.0", "f_index.01.L")}, "used by another guide"},
      {"no such joint", {named("index.0", "no_such_finger")}, "no_such_finger"},
  };
  for (const Case& c : cases) {
    std::vector<Guide> guides = {named("hand", "hand.L")};
    guides.insert(guides.end(), c.fingers.begin(), c.fingers.end());
    Component h = component("hand", "hand", Side::kLeft, guides);
    auto scene = metarig();
    ASSERT_TRUE(scene);
    const std::string before = io::write_scene(*scene);
    auto b = Build::open(*scene, rig(Parent::kNone, h), builtin_components());
    ASSERT_TRUE(b.is_ok()) << c.what << ": " << b.status().message();
    const Status s = (*b)->build_all();
    EXPECT_FALSE(s.is_ok()) << c.what;
    EXPECT_NE(s.message().find("hand_L"), std::string::npos) << c.what << ": " << s.message();
    EXPECT_NE(s.message().find(c.expected), std::string::npos) << c.what << ": " << s.message();
    ASSERT_TRUE((*b)->remove().is_ok()) << c.what;
    EXPECT_TRUE(io::write_scene(*scene) == before) << c.what << ": a failed build leaves nothing behind";
  }
}

}  // namespace
}  // namespace rigel::rig
