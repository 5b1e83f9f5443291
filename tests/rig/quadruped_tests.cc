// quadLeg (a leg of three segments: ikThreeBone with a spring or pinned
// hock) and the quadruped built from components (examples/quadruped.rig.xml
// on examples/quadruped.rigel, the skeleton make_quadruped.py writes): rest
// kept, removal exact, stepping equal to the straight build, the solve's
// own behaviour, FK/IK matching both ways, and feet planted while the body
// moves. The skeleton is written in double precision, so every tolerance is
// 1e-9 but the matching's (1e-9 too) and the planted feet's (1e-6, the issue's).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "rig_test_util.h"
#include "rigel/io/scene_file.h"
#include "rigel/math/rotation.h"
#include "rigel/math/transform.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/ops/util/blend.h"
#include "rigel/ops/util/spring.h"
#include "rigel/rig/build.h"
#include "rigel/rig/components/limbs.h"
#include "rigel/rig/definition_io.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"

namespace rigel::rig {
namespace {

using graph::Plug;
using graph::Value;
using math::Mat4;
using math::Quat;
using math::Vec3;
using testing::at_joint;
namespace xform = scene::xform;
namespace fs = std::filesystem;

const fs::path kExamples = fs::path(RIGEL_SOURCE_DIR) / "examples";

Vec3 pos(const Mat4& m) { return m.topRightCorner<3, 1>(); }

struct Quad : testing::BuiltRig {
  std::string rig;
  NodeId at(const std::string& address) {
    Result<NodeId> id = resolve_address(g(), rig + ":" + address);
    EXPECT_TRUE(id.is_ok()) << address << ": " << id.status().message();
    return id.is_ok() ? *id : NodeId{};
  }
  Vec3 p(const std::string& joint) { return pos(scene->world_matrix(g().find(joint))); }
  void set(NodeId id, graph::AttrIndex attr, Value v) {
    Status s = g().set_value(Plug{id, attr, -1}, std::move(v));
    ASSERT_TRUE(s.is_ok()) << s.message();
  }
  // Moves a control (rotation kept) by `delta`, world.
  void move_by(NodeId control, const Vec3& delta) {
    const NodeId parent = g().parent(control);
    const Mat4 offset = std::get<Mat4>(g().evaluate(control, xform::kOffsetParentMatrix));
    const Mat4 space = (parent.is_valid() ? scene->world_matrix(parent) : Mat4(Mat4::Identity())) * offset;
    const Vec3 target = pos(scene->world_matrix(control)) + delta;
    const Mat4 inv = math::affine_inverse(space);
    set(control, xform::kTranslate, Value(Vec3(inv.topLeftCorner<3, 3>() * target + inv.topRightCorner<3, 1>())));
  }
  void rotate(NodeId control, const Vec3& degrees) { set(control, xform::kRotate, Value(degrees)); }
  NodeId meta(const std::string& component) { return find_component(g(), find_rig(g(), rig), component); }
};

std::unique_ptr<scene::Scene> quadruped() {
  auto loaded = io::load_scene(kExamples / "quadruped.rigel", default_registry());
  EXPECT_TRUE(loaded.is_ok()) << loaded.status().message();
  return loaded.is_ok() ? std::move(*loaded) : nullptr;
}

void build(Quad& q, Definition d) {
  q.rig = d.name;
  q.scene = quadruped();
  if (!q.scene) return;
  q.rest = testing::joint_worlds(*q.scene);
  q.before = io::write_scene(*q.scene);
  auto opened = Build::open(*q.scene, std::move(d), builtin_components());
  ASSERT_TRUE(opened.is_ok()) << opened.status().message();
  q.build = std::move(*opened);
  const Status s = q.build->build_all();
  ASSERT_TRUE(s.is_ok()) << s.message();
}

Component leg(const std::string& side, const std::string& hock_mode, bool stretch = false) {
  Component c = testing::make_component(
      "quadLeg", "hindLeg",
      {at_joint("femur." + side), at_joint("tibia." + side), at_joint("metatarsus." + side), at_joint("hoof." + side)},
      {testing::make_param("hockMode", hock_mode), testing::make_param("stretch", stretch)});
  c.side = side == "L" ? Side::kLeft : Side::kRight;
  return c;
}

Component tail() {
  return testing::make_component("springChain", "tail",
                                 {at_joint("tail"), at_joint("tail.001"), at_joint("tail.002"), at_joint("tail.003")});
}

// global -> hip -> a spring hind leg (L), a pinned one with stretch (R) and
// a spring chain on the tail.
Definition legs() {
  Definition d;
  d.name = "legs";
  Component global = testing::make_component("global", "global", {Guide{}});
  Component hip = testing::make_component("hip", "hip", {at_joint("hips")});
  hip.children = {leg("L", "spring"), leg("R", "pinned", true), tail()};
  global.children = {hip};
  d.components = {global};
  return d;
}

double angle_between(const Vec3& a, const Vec3& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }

TEST(QuadLeg, keeps_the_rest_pose_in_fk_and_ik_and_is_removed_byte_for_byte) {
  Quad q;
  build(q, legs());
  ASSERT_TRUE(q.build);
  std::string worst;
  EXPECT_LT(testing::pose_error(*q.scene, q.rest, &worst), 1e-9) << "IK at rest (worst: " << worst << ")";
  for (const char* c : {"hindLeg_L", "hindLeg_R"}) q.set(q.at(std::string(c) + "/fkIkSwitch"), ops::util::fk_ik_attr::kFkIk, 0.0);
  EXPECT_LT(testing::pose_error(*q.scene, q.rest, &worst), 1e-9) << "FK at rest (worst: " << worst << ")";
  ASSERT_TRUE(q.build->remove().is_ok());
  const std::string after = io::write_scene(*q.scene);
  EXPECT_TRUE(after == q.before) << testing::first_difference(after, q.before);
}

TEST(QuadLeg, stepping_back_and_forward_from_every_index_gives_the_straight_build) {
  Quad q;
  build(q, legs());
  ASSERT_TRUE(q.build);
  testing::expect_stepping_gives_the_straight_build(*q.build, *q.scene);
}

TEST(QuadLeg, a_spring_leg_reaches_its_ik_control_keeping_the_hock_bone_at_its_angle_to_the_femur) {
  Quad q;
  build(q, legs());
  ASSERT_TRUE(q.build);
  const auto bone = [&](const char* a, const char* b) { return Vec3(q.p(std::string(b) + ".L") - q.p(std::string(a) + ".L")); };
  const double femur = bone("femur", "tibia").norm(), tibia = bone("tibia", "metatarsus").norm(),
               cannon = bone("metatarsus", "hoof").norm();
  const double rest_angle = angle_between(bone("femur", "tibia"), bone("metatarsus", "hoof"));
  const NodeId ik = q.at("hindLeg_L/ik");
  for (const Vec3& delta : {Vec3(0, 0.15, 0.05), Vec3(0.03, 0.3, -0.1), Vec3(0, -0.02, 0.2)}) {
    const Vec3 target = pos(q.scene->world_matrix(ik)) + delta;
    q.move_by(ik, delta);
    EXPECT_LT((q.p("hoof.L") - target).norm(), 1e-9) << "the hoof reaches the ik control";
    EXPECT_NEAR(bone("femur", "tibia").norm(), femur, 1e-9);
    EXPECT_NEAR(bone("tibia", "metatarsus").norm(), tibia, 1e-9);
    EXPECT_NEAR(bone("metatarsus", "hoof").norm(), cannon, 1e-9);
    EXPECT_NEAR(angle_between(bone("femur", "tibia"), bone("metatarsus", "hoof")), rest_angle, 1e-9)
        << "the hock bone turns with the femur (spring)";
    q.move_by(ik, -delta);
  }
  EXPECT_LT((q.p("femur.L") - pos(q.rest.at("femur.L"))).norm(), 1e-12) << "the hip stays";
}

TEST(QuadLeg, a_pinned_legs_hock_control_swings_the_hock_bone_about_the_planted_hoof) {
  Quad q;
  build(q, legs());
  ASSERT_TRUE(q.build);
  const Vec3 hoof = q.p("hoof.R");
  const Vec3 cannon = q.p("hoof.R") - q.p("metatarsus.R");
  q.rotate(q.at("hindLeg_R/hock"), Vec3(15, 0, 0));
  EXPECT_LT((q.p("hoof.R") - hoof).norm(), 1e-9) << "the hoof stays where the ik control is";
  const Vec3 turned = q.p("hoof.R") - q.p("metatarsus.R");
  EXPECT_NEAR(angle_between(cannon, turned), 15.0 * M_PI / 180.0, 1e-9) << "the hock bone turned by the hock control";
  EXPECT_NEAR(turned.norm(), cannon.norm(), 1e-9);
  // Pulled past its reach the pinned leg stretches (stretch on) to keep the hoof planted.
  const NodeId hip = q.at("hip/main");
  q.move_by(hip, Vec3(0, 0.25, 0));
  EXPECT_LT((q.p("hoof.R") - hoof).norm(), 1e-9) << "stretched to the hock target";
  EXPECT_GT((q.p("tibia.R") - q.p("femur.R")).norm(), (pos(q.rest.at("tibia.R")) - pos(q.rest.at("femur.R"))).norm() + 1e-3);
}

TEST(QuadLeg, fk_and_ik_match_both_ways_exactly) {
  Quad q;
  build(q, legs());
  ASSERT_TRUE(q.build);
  for (const char* side : {"L", "R"}) {
    SCOPED_TRACE(side);
    const std::string c = std::string("hindLeg_") + side;
    const NodeId meta = q.meta(c);
    ASSERT_TRUE(meta.is_valid());
    // An IK pose -> FK.
    q.move_by(q.at(c + "/ik"), Vec3(0.02, 0.2, 0.1));
    q.rotate(q.at(c + "/ik"), Vec3(20, 5, -3));
    if (side == std::string("R")) q.rotate(q.at(c + "/hock"), Vec3(-10, 0, 4));
    auto ik_pose = testing::joint_worlds(*q.scene);
    ASSERT_TRUE(components::match_fk_to_ik(*q.scene, meta).is_ok());
    q.set(q.at(c + "/fkIkSwitch"), ops::util::fk_ik_attr::kFkIk, 0.0);
    std::string worst;
    EXPECT_LT(testing::pose_error(*q.scene, ik_pose, &worst), 1e-9) << "FK matched to IK (worst: " << worst << ")";
    // That FK pose, moved (the hip joint turned, the foot turned) -> IK.
    // (A spring leg's IK keeps the hock bone's angle to the femur, so only
    // poses that keep it are matched exactly; turning the whole leg does.)
    q.rotate(q.at(c + "/fk[0]"), Vec3(12, 4, -6));
    q.rotate(q.at(c + "/fk[3]"), Vec3(-25, 10, 0));
    if (side == std::string("R")) q.rotate(q.at(c + "/fk[2]"), Vec3(-18, 0, 0));
    auto fk_pose = testing::joint_worlds(*q.scene);
    ASSERT_TRUE(components::match_ik_to_fk(*q.scene, meta).is_ok());
    q.set(q.at(c + "/fkIkSwitch"), ops::util::fk_ik_attr::kFkIk, 1.0);
    EXPECT_LT(testing::pose_error(*q.scene, fk_pose, &worst), 1e-9) << "IK matched to FK (worst: " << worst << ")";
  }
}

TEST(QuadLeg, bad_guides_fail_naming_the_component) {
  Definition d = legs();
  Component& bad = d.components[0].children[0].children[0];
  bad.guides[3] = at_joint("tail");  // not a child of the metatarsus
  auto scene = quadruped();
  ASSERT_TRUE(scene);
  auto b = Build::open(*scene, d, builtin_components());
  ASSERT_TRUE(b.is_ok());
  const Status s = (*b)->build_all();
  ASSERT_FALSE(s.is_ok());
  EXPECT_NE(s.message().find("hindLeg_L (quadLeg): guide 3: 'tail' is not a child of 'metatarsus.L'"), std::string::npos)
      << s.message();
}

// ---- springChain -------------------------------------------------------------

// The tail's tip at frames 0..last played in order, the tail's root
// control keyed to swing 40 degrees by frame 12 and hold.
std::vector<Mat4> play(Quad& q, int last) {
  std::vector<Mat4> tips;
  for (int f = 0; f <= last; ++f) {
    q.scene->set_frame(f);
    tips.push_back(q.scene->world_matrix(q.g().find("tail.003")));
  }
  return tips;
}

void key_swing(Quad& q) {
  graph::Graph& g = q.g();
  const NodeId root = q.at("tail/fk[0]");
  for (const auto& [frame, angle] : {std::pair{0.0, 0.0}, std::pair{12.0, 40.0}})
    ASSERT_TRUE(ops::anim::write_channel_key(g, root, xform::kRotate, Value(Vec3(0, angle, 0)), frame / g.fps(), true)
                    .is_ok());
}

TEST(SpringChain, the_tail_lags_its_goal_settles_on_it_and_plays_the_same_every_time) {
  Quad q;
  build(q, legs());
  ASSERT_TRUE(q.build);
  key_swing(q);
  const std::vector<Mat4> first = play(q, 120);
  // The goal: the FK pose (the switch at 0).
  auto goal_at = [&](int frame) {
    q.scene->set_frame(frame);
    q.set(q.at("tail/fkIkSwitch"), ops::util::fk_ik_attr::kFkIk, 0.0);
    const Vec3 tip = q.p("tail.003");
    q.set(q.at("tail/fkIkSwitch"), ops::util::fk_ik_attr::kFkIk, 1.0);
    return tip;
  };
  EXPECT_GT((pos(first[12]) - goal_at(12)).norm(), 1e-2) << "the tip lags while the root swings";
  EXPECT_LT((pos(first[120]) - goal_at(120)).norm(), 1e-6) << "and settles on its goal once it stops";
  EXPECT_LT((pos(first[0]) - pos(q.rest.at("tail.003"))).norm(), 1e-12) << "at the start frame it rests";
  // Played again, scrubbed back, or built again in another scene: the same values.
  EXPECT_EQ(play(q, 120), first);
  q.scene->set_frame(30);
  EXPECT_EQ(q.scene->world_matrix(q.g().find("tail.003")), first[30]) << "scrubbing back to a played frame";
  Quad again;
  build(again, legs());
  key_swing(again);
  EXPECT_EQ(play(again, 120), first) << "deterministic";
  // Bone lengths are kept while it swings.
  q.scene->set_frame(14);
  EXPECT_NEAR((q.p("tail.003") - q.p("tail.002")).norm(),
              (pos(q.rest.at("tail.003")) - pos(q.rest.at("tail.002"))).norm(), 1e-9);
}

TEST(SpringChain, an_edited_key_is_played_with_the_new_value_and_bad_inputs_are_named) {
  Quad q;
  build(q, legs());
  ASSERT_TRUE(q.build);
  key_swing(q);
  const std::vector<Mat4> first = play(q, 40);
  ASSERT_TRUE(ops::anim::write_channel_key(q.g(), q.at("tail/fk[0]"), xform::kRotate, Value(Vec3(0, -30, 0)),
                                           12.0 / q.g().fps(), true)
                  .is_ok());
  const std::vector<Mat4> edited = play(q, 40);
  EXPECT_GT((pos(edited[20]) - pos(first[20])).norm(), 1e-2);
  Quad fresh;
  build(fresh, legs());
  key_swing(fresh);
  ASSERT_TRUE(ops::anim::write_channel_key(fresh.g(), fresh.at("tail/fk[0]"), xform::kRotate, Value(Vec3(0, -30, 0)),
                                           12.0 / fresh.g().fps(), true)
                  .is_ok());
  EXPECT_EQ(play(fresh, 40), edited) << "the edit played as if keyed from the start";
  const NodeId spring = q.at("tail/spring");
  q.set(spring, ops::util::spring_attr::kDamping, -1.0);
  EXPECT_EQ(std::get<std::string>(q.g().evaluate(spring, ops::util::spring_attr::kError)),
            "damping: must be a number from 0");
}

// ---- the quadruped example -------------------------------------------------

Definition example() {
  ParseResult p = load_definition(kExamples / "quadruped.rig.xml");
  EXPECT_TRUE(p.ok()) << (p.ok() ? "" : p.errors.front().str());
  return p.definition;
}

TEST(QuadrupedExample, builds_without_moving_a_joint_and_is_removed_byte_for_byte) {
  Quad q;
  build(q, example());
  ASSERT_TRUE(q.build);
  std::string worst;
  EXPECT_LT(testing::pose_error(*q.scene, q.rest, &worst), 1e-9) << "at rest (worst: " << worst << ")";
  ASSERT_TRUE(q.build->remove().is_ok());
  const std::string after = io::write_scene(*q.scene);
  EXPECT_TRUE(after == q.before) << testing::first_difference(after, q.before);
}

TEST(QuadrupedExample, the_ik_legs_keep_the_hooves_planted_while_the_body_moves) {
  Quad q;
  build(q, example());
  ASSERT_TRUE(q.build);
  const char* hooves[] = {"hoof.L", "hoof.R", "fhoof.L", "fhoof.R"};
  std::map<std::string, Vec3> planted;
  for (const char* h : hooves) planted[h] = q.p(h);
  const NodeId hip = q.at("hip/main");
  const NodeId chest = q.at("spine/fk[2]");
  // Moves that keep every leg within its reach (the legs do not stretch).
  for (const auto& [move, turn] :
       {std::pair{Vec3(0, -0.08, 0.05), Vec3(0, 4, 2)}, std::pair{Vec3(0.04, -0.05, -0.04), Vec3(-3, -5, 0)}}) {
    q.move_by(hip, move);
    q.rotate(hip, turn);
    q.rotate(chest, turn * 0.5);
    EXPECT_GT((q.p("hips") - pos(q.rest.at("hips"))).norm(), 0.05) << "the body moved";
    for (const char* h : hooves) EXPECT_LT((q.p(h) - planted[h]).norm(), 1e-6) << h << " stays planted";
    q.move_by(hip, -move);
  }
}

}  // namespace
}  // namespace rigel::rig
