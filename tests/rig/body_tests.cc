// The body component classes (spine, neck, tail, eye, simple) built on
// Rigify's human metarig: the rest pose is kept exactly, the controls move
// what they should, and builds are undone byte for byte.
//
// Tolerances: the rest pose is compared at 1e-9. Posed comparisons use 1e-6:
// the metarig's rotations are float32 quaternions up to ~5e-8 off unit
// length, so its matrices are rotations times |q|^2, and a constraint that
// writes T/R/S channels reproduces such a matrix only to that order once it
// turns.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>

#include "rig_test_util.h"
#include "rigel/io/gltf_import.h"
#include "rigel/io/scene_file.h"
#include "rigel/math/transform.h"
#include "rigel/rig/build.h"
#include "rigel/rig/component.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"

namespace rigel::rig {
namespace {

using testing::first_difference;
using testing::normalized;
using testing::at_joint;
using testing::metarig;
using testing::at;
using testing::built_rig;
using testing::BuiltRig;
using testing::joint_worlds;
using testing::pose_error;

namespace fs = std::filesystem;
using graph::Plug;
using graph::Value;
using math::Mat4;
using math::Vec3;
namespace xform = scene::xform;

std::vector<Guide> joints(std::initializer_list<const char*> names) {
  std::vector<Guide> out;
  for (const char* n : names) out.push_back(at_joint(n));
  return out;
}

Component component(std::string type, std::string name, std::vector<Guide> guides, std::vector<Param> params = {}) {
  Component c;
  c.type = std::move(type);
  c.name = std::move(name);
  c.side = Side::kCenter;
  c.rig_id = new_rig_id();
  c.guides = std::move(guides);
  c.params = std::move(params);
  return c;
}

Param param(std::string name, ParamValue value) {
  Param p;
  p.name = std::move(name);
  p.value = std::move(value);
  return p;
}

// global -> hip (spine joint) -> the given components.
Definition rig_with(std::vector<Component> under_hip) {
  Definition d;
  d.name = "body";
  d.version = "1.0";
  Component global = component("global", "global", {Guide{}});
  Component hip = component("hip", "hip", {at_joint("spine")});
  hip.children = std::move(under_hip);
  global.children = {hip};
  d.components = {global};
  return d;
}

Component spine(const std::string& kinematic) {
  return component("spine", "spine", joints({"spine.001", "spine.002", "spine.003"}),
                   {param("kinematicType", kinematic)});
}

// Every component type at once: spine (spline IK) -> neck (world head) ->
// eyes; a tail on spine.004 .. spine.006 cannot share joints with the neck,
// so it has a definition of its own (tail_rig); simple wraps the breasts.
Definition everything() {
  Component neck = component("neck", "neck", joints({"spine.004", "spine.005", "spine.006"}),
                             {param("headOrient", std::string("world"))});
  neck.attach = "END";
  Component eyes = component("eye", "eyes", joints({"eye.L", "eye.R"}), {param("aimDistance", 0.4)});
  eyes.attach = "END";
  neck.children = {eyes};
  Component s = spine("stretchySplineIK");
  Component breasts = component("simple", "breasts", joints({"breast.L", "breast.R"}));
  breasts.attach = "END";
  s.children = {neck, breasts};
  return rig_with({s});
}

Definition tail_rig(std::int64_t controls, bool stretch) {
  return rig_with({component("tail", "tail",
                             joints({"spine.001", "spine.002", "spine.003", "spine.004", "spine.005", "spine.006"}),
                             {param("controlCount", controls), param("stretch", stretch)})});
}

Vec3 position(scene::Scene& s, NodeId id) { return s.world_matrix(id).topRightCorner<3, 1>(); }
Vec3 position(scene::Scene& s, const char* joint) { return position(s, s.graph().find(joint)); }

void set(scene::Scene& s, NodeId node, graph::AttrIndex attr, const Vec3& v) {
  ASSERT_TRUE(s.graph().set_value(Plug{node, attr, -1}, Value(v)).is_ok());
}

std::vector<double> bone_lengths(scene::Scene& s, std::initializer_list<const char*> chain) {
  std::vector<Vec3> p;
  for (const char* j : chain) p.push_back(position(s, j));
  std::vector<double> out;
  for (std::size_t i = 1; i < p.size(); ++i) out.push_back((p[i] - p[i - 1]).norm());
  return out;
}

// ---- rest, remove, stepping ------------------------------------------------

TEST(RigBody, every_component_keeps_the_rest_pose_and_is_removed_byte_for_byte) {
  for (const Definition& d : {everything(), tail_rig(3, true), tail_rig(2, false),
                              rig_with({spine("fk")}), rig_with({spine("splineIK")})}) {
    BuiltRig b = built_rig(d);
    ASSERT_TRUE(b.build);
    std::string worst;
    EXPECT_LT(pose_error(*b.scene, b.rest, &worst), 1e-9) << d.components[0].children[0].children[0].type
                                                          << ": at rest nothing moves (worst: " << worst << ")";
    ASSERT_TRUE(b.build->remove().is_ok());
    const std::string after = io::write_scene(*b.scene);
    EXPECT_TRUE(after == b.before) << first_difference(after, b.before);
  }
}

TEST(RigBody, stepping_back_and_forward_from_every_index_gives_the_straight_build) {
  BuiltRig b = built_rig(everything());
  ASSERT_TRUE(b.build);
  Build& build = *b.build;
  testing::expect_stepping_gives_the_straight_build(build, *b.scene);
}

// ---- spine -------------------------------------------------------------------

TEST(RigBody, spine_fk_rotation_carries_the_chain) {
  BuiltRig b = built_rig(rig_with({spine("fk")}));
  ASSERT_TRUE(b.build);
  scene::Scene& s = *b.scene;
  const Vec3 top = position(s, "spine.003"), neck = position(s, "spine.004");
  set(s, at(s, "body:spine/fk[0]"), xform::kRotate, Vec3(25, 0, 0));
  EXPECT_GT((position(s, "spine.003") - top).norm(), 0.05) << "turning the first FK control moves the chain's top";
  EXPECT_GT((position(s, "spine.004") - neck).norm(), 0.05) << "and what hangs from it";
  // The bone lengths stay: FK only turns.
  b.scene->graph().clear_history();
  const std::vector<double> now = bone_lengths(s, {"spine.001", "spine.002", "spine.003", "spine.004"});
  set(s, at(s, "body:spine/fk[0]"), xform::kRotate, Vec3(0, 0, 0));
  const std::vector<double> rest = bone_lengths(s, {"spine.001", "spine.002", "spine.003", "spine.004"});
  for (std::size_t i = 0; i < rest.size(); ++i) EXPECT_NEAR(now[i], rest[i], 1e-8);
  EXPECT_LT((position(s, "spine.003") - top).norm(), 1e-9) << "back at zero: the rest pose";
}

TEST(RigBody, spline_spine_shoulder_pulls_the_top_and_keeps_the_lengths) {
  BuiltRig b = built_rig(rig_with({spine("splineIK")}));
  ASSERT_TRUE(b.build);
  scene::Scene& s = *b.scene;
  const auto chain = {"spine.001", "spine.002", "spine.003", "spine.004"};
  const std::vector<double> rest = bone_lengths(s, chain);
  const NodeId shoulder = at(s, "body:spine/shoulder");
  const Vec3 top = position(s, "spine.003");
  EXPECT_LT((position(s, shoulder) - top).norm(), 1e-9) << "the shoulder control sits at the top joint";
  // Forward (glTF +z) and a little down: the chain must bend.
  set(s, shoulder, xform::kTranslate, Vec3(0, -0.02, 0.12));
  const Vec3 target = position(s, shoulder);
  const Vec3 moved = position(s, "spine.003");
  EXPECT_LT((moved - target).norm(), (top - target).norm() - 0.05) << "the top joint goes toward the shoulder";
  const std::vector<double> now = bone_lengths(s, chain);
  for (std::size_t i = 0; i < rest.size(); ++i) EXPECT_NEAR(now[i], rest[i], 1e-5) << "bone " << i << " keeps its length";
  EXPECT_LT((position(s, "spine.001") - b.rest.at("spine.001").topRightCorner<3, 1>()).norm(), 1e-9)
      << "the base stays with the hip";
  // Turning the last FK control carries the shoulder (FK under the IK).
  set(s, shoulder, xform::kTranslate, Vec3(0, 0, 0));
  set(s, at(s, "body:spine/fk[0]"), xform::kRotate, Vec3(20, 0, 0));
  EXPECT_GT((position(s, "spine.003") - top).norm(), 0.05);
  // Turning the hip turns the whole spine rigidly: no twist from the spline's up.
  set(s, at(s, "body:spine/fk[0]"), xform::kRotate, Vec3(0, 0, 0));
  const NodeId hip = at(s, "body:hip/main");
  set(s, hip, xform::kRotate, Vec3(0, 90, 0));
  const Mat4 hip_motion = s.world_matrix(s.graph().find("spine")) * math::affine_inverse(b.rest.at("spine"));
  for (const char* j : {"spine.001", "spine.002", "spine.003"}) {
    const Mat4 expected = hip_motion * b.rest.at(j);
    EXPECT_LT((s.world_matrix(s.graph().find(j)) - expected).cwiseAbs().maxCoeff(), 1e-6)
        << j << " turns with the hip as one piece";
  }
}

TEST(RigBody, stretchy_spline_spine_reaches_the_shoulder) {
  BuiltRig b = built_rig(rig_with({spine("stretchySplineIK")}));
  ASSERT_TRUE(b.build);
  scene::Scene& s = *b.scene;
  const auto chain = {"spine.001", "spine.002", "spine.003"};
  const std::vector<double> rest = bone_lengths(s, chain);
  const NodeId shoulder = at(s, "body:spine/shoulder");
  // Straight up (the spine is roughly along +y): 8 cm further.
  set(s, shoulder, xform::kTranslate, Vec3(0, 0.08, 0));
  const Vec3 target = position(s, shoulder);
  EXPECT_LT((position(s, "spine.003") - target).norm(), 1e-4) << "the stretchy spine reaches its shoulder control";
  const std::vector<double> now = bone_lengths(s, chain);
  EXPECT_GT(now[0] + now[1], rest[0] + rest[1] + 0.04) << "the bones stretch";
}

TEST(RigBody, the_stretch_feature_switches_the_spline_stretch) {
  BuiltRig b = built_rig(rig_with({spine("stretchySplineIK")}));
  ASSERT_TRUE(b.build);
  scene::Scene& s = *b.scene;
  const auto chain = {"spine.001", "spine.002", "spine.003"};
  const std::vector<double> rest = bone_lengths(s, chain);
  ASSERT_TRUE(b.build->set_feature("stretch", false).is_ok());
  std::string worst;
  EXPECT_LT(pose_error(s, b.rest, &worst), 1e-9) << worst;
  set(s, at(s, "body:spine/shoulder"), xform::kTranslate, Vec3(0, 0.08, 0));
  std::vector<double> now = bone_lengths(s, chain);
  for (std::size_t i = 0; i < rest.size(); ++i) EXPECT_NEAR(now[i], rest[i], 1e-5) << "stretch off: lengths kept";
  set(s, at(s, "body:spine/shoulder"), xform::kTranslate, Vec3(0, 0, 0));
  ASSERT_TRUE(b.build->set_feature("stretch", true).is_ok());
  set(s, at(s, "body:spine/shoulder"), xform::kTranslate, Vec3(0, 0.08, 0));
  EXPECT_LT((position(s, "spine.003") - position(s, at(s, "body:spine/shoulder"))).norm(), 1e-4)
      << "stretch on again: the top reaches the shoulder";
}

// ---- neck --------------------------------------------------------------------

TEST(RigBody, neck_world_head_keeps_its_orientation_when_the_body_turns) {
  for (const char* orient : {"world", "local"}) {
    Component neck = component("neck", "neck", joints({"spine.004", "spine.005", "spine.006"}),
                               {param("headOrient", std::string(orient))});
    BuiltRig b = built_rig(rig_with({neck}));
    ASSERT_TRUE(b.build);
    scene::Scene& s = *b.scene;
    std::string worst;
    EXPECT_LT(pose_error(s, b.rest, &worst), 1e-9) << worst;
    const NodeId head = s.graph().find("spine.006");
    const Vec3 head_position = position(s, head);
    set(s, at(s, "body:hip/main"), xform::kRotate, Vec3(0, 40, 15));
    const Mat4 w = s.world_matrix(head);
    const double rotation_change = (w.topLeftCorner<3, 3>() - b.rest.at("spine.006").topLeftCorner<3, 3>()).norm();
    EXPECT_GT((position(s, head) - head_position).norm(), 0.05) << orient << ": the head goes with the neck";
    if (std::string(orient) == "world") {
      EXPECT_LT(rotation_change, 1e-6) << "headOrient=world: the head keeps its world rotation";
    } else {
      EXPECT_GT(rotation_change, 0.1) << "headOrient=local: the head turns with the body";
    }
    // The neck controls turn the neck joints.
    set(s, at(s, "body:hip/main"), xform::kRotate, Vec3(0, 0, 0));
    const Vec3 mid = position(s, "spine.005");
    set(s, at(s, "body:neck/neck[0]"), xform::kRotate, Vec3(30, 0, 0));
    EXPECT_GT((position(s, "spine.005") - mid).norm(), 0.02);
  }
}

// ---- eye ---------------------------------------------------------------------

// The direction of an eye's +y (its aim axis) and the direction to a point.
double aim_error(scene::Scene& s, const char* eye, NodeId target) {
  const Mat4 w = s.world_matrix(s.graph().find(eye));
  const Vec3 axis = w.block<3, 1>(0, 1).normalized();
  const Vec3 to = (position(s, target) - w.topRightCorner<3, 1>()).normalized();
  return (axis - to).norm();
}

TEST(RigBody, eyes_aim_at_their_controls_and_the_master_moves_both) {
  Component neck = component("neck", "neck", joints({"spine.004", "spine.005", "spine.006"}));
  neck.attach = "END";
  Component eyes = component("eye", "eyes", joints({"eye.L", "eye.R"}), {param("aimDistance", 0.4)});
  eyes.attach = "END";
  neck.children = {eyes};
  BuiltRig b = built_rig(rig_with({neck}));
  ASSERT_TRUE(b.build);
  scene::Scene& s = *b.scene;
  const NodeId aim_l = at(s, "body:eyes/aim[0]"), aim_r = at(s, "body:eyes/aim[1]");
  const NodeId master = at(s, "body:eyes/master");
  EXPECT_NEAR((position(s, aim_l) - position(s, "eye.L")).norm(), 0.4, 1e-9) << "aimDistance in front of the eye";
  EXPECT_LT(aim_error(s, "eye.L", aim_l), 1e-7) << "at rest the eye looks at its control";
  set(s, aim_l, xform::kTranslate, Vec3(0.1, 0.05, 0));
  EXPECT_LT(aim_error(s, "eye.L", aim_l), 1e-6) << "the left eye looks at its moved control";
  EXPECT_GT((s.world_matrix(s.graph().find("eye.L")) - b.rest.at("eye.L")).norm(), 0.1);
  EXPECT_LT((s.world_matrix(s.graph().find("eye.R")) - b.rest.at("eye.R")).norm(), 1e-9) << "the right eye stays";
  set(s, aim_l, xform::kTranslate, Vec3(0, 0, 0));
  const Mat4 right_rest = s.world_matrix(s.graph().find("eye.R"));
  set(s, master, xform::kTranslate, Vec3(-0.15, 0.1, 0));
  EXPECT_LT(aim_error(s, "eye.L", aim_l), 1e-6);
  EXPECT_LT(aim_error(s, "eye.R", aim_r), 1e-6);
  EXPECT_GT((s.world_matrix(s.graph().find("eye.R")) - right_rest).norm(), 0.1) << "the master moves both aims";
  // The head carries the eyes and their aims: turning it keeps the aim.
  set(s, at(s, "body:neck/head"), xform::kRotate, Vec3(0, 30, 0));
  EXPECT_LT(aim_error(s, "eye.R", aim_r), 1e-6);
}

// ---- tail --------------------------------------------------------------------

TEST(RigBody, tail_controls_bend_the_chain_and_stretch_follows_the_feature) {
  for (bool stretch : {false, true}) {
    BuiltRig b = built_rig(tail_rig(3, stretch));
    ASSERT_TRUE(b.build);
    scene::Scene& s = *b.scene;
    const auto chain = {"spine.001", "spine.002", "spine.003", "spine.004", "spine.005", "spine.006"};
    const std::vector<double> rest = bone_lengths(s, chain);
    std::vector<NodeId> controls;
    for (int k = 0; k < 3; ++k) controls.push_back(at(s, "body:tail/main[" + std::to_string(k) + "]"));
    EXPECT_LT((position(s, controls[0]) - position(s, "spine.001")).norm(), 1e-9) << "the first control at the root";
    EXPECT_LT((position(s, controls[2]) - position(s, "spine.006")).norm(), 1e-9) << "the last at the tip";
    const Vec3 tip = position(s, "spine.006");
    // Pull the tip control out along the chain (+y) and forward.
    set(s, controls[2], xform::kTranslate, Vec3(0, 0.1, 0.1));
    const Vec3 target = position(s, controls[2]);
    EXPECT_LT((position(s, "spine.006") - target).norm(), (tip - target).norm() - 0.02);
    const std::vector<double> now = bone_lengths(s, chain);
    double rest_sum = 0, now_sum = 0;
    for (std::size_t i = 0; i < rest.size(); ++i) {
      rest_sum += rest[i];
      now_sum += now[i];
    }
    if (stretch) {
      EXPECT_LT((position(s, "spine.006") - target).norm(), 1e-4) << "stretch: the tip reaches its control";
      EXPECT_GT(now_sum, rest_sum + 0.05);
    } else {
      for (std::size_t i = 0; i < rest.size(); ++i) EXPECT_NEAR(now[i], rest[i], 1e-5) << "bone " << i;
    }
  }
}

// ---- simple ------------------------------------------------------------------

TEST(RigBody, simple_drives_its_nodes_and_adopts_controls) {
  for (const char* mode : {"parent", "point", "orient", "none"}) {
    Component simple = component("simple", "simple", joints({"breast.L"}), {param("constrain", std::string(mode))});
    BuiltRig b = built_rig(rig_with({simple}));
    ASSERT_TRUE(b.build);
    scene::Scene& s = *b.scene;
    const NodeId c = at(s, "body:simple/main");
    const NodeId breast = s.graph().find("breast.L");
    const Mat4 rest = s.world_matrix(breast);
    const Mat4 control_rest = s.world_matrix(c);
    set(s, c, xform::kTranslate, Vec3(0.05, 0, 0));
    set(s, c, xform::kRotate, Vec3(0, 0, 30));
    const Mat4 w = s.world_matrix(breast);
    const double moved = (w.topRightCorner<3, 1>() - rest.topRightCorner<3, 1>()).norm();
    const double turned = (w.topLeftCorner<3, 3>() - rest.topLeftCorner<3, 3>()).norm();
    const std::string m = mode;
    EXPECT_EQ(moved > 1e-3, m == "parent" || m == "point") << mode;
    EXPECT_EQ(turned > 1e-3, m == "parent" || m == "orient") << mode;
    if (m == "parent") {
      EXPECT_LT((w - s.world_matrix(c) * math::affine_inverse(control_rest) * rest).cwiseAbs().maxCoeff(), 1e-6)
          << "parent: the node moves with the control as one piece";
    }
  }
  // An existing control is adopted as it is: nothing made for it but a hook.
  auto scene = metarig();
  ASSERT_TRUE(scene);
  graph::Graph& g = scene->graph();
  Result<NodeId> mine = scene->create(scene::kControlType, "my_ctrl", g.find("spine.003"));
  ASSERT_TRUE(mine.is_ok());
  g.clear_history();
  const std::string before = io::write_scene(*scene);
  auto opened = Build::open(*scene, rig_with({component("simple", "adopt", joints({"my_ctrl", "breast.R"}))}),
                            builtin_components());
  ASSERT_TRUE(opened.is_ok()) << opened.status().message();
  ASSERT_TRUE((*opened)->build_all().is_ok());
  Result<NodeId> hook = resolve_address(g, "body:adopt/hook[0]");
  ASSERT_TRUE(hook.is_ok()) << hook.status().message();
  EXPECT_EQ(g.parent(*hook), *mine) << "the hook hangs from the adopted control";
  EXPECT_EQ(g.node(*mine)->tag_find(kTagRole), nullptr) << "the adopted control is not tagged";
  EXPECT_FALSE(component_of(g, *mine).is_valid()) << "nor linked";
  EXPECT_TRUE(resolve_address(g, "body:adopt/joint[1]/main").is_ok()) << "breast.R gets a control of its own";
  ASSERT_TRUE((*opened)->remove().is_ok());
  EXPECT_TRUE(io::write_scene(*scene) == before);
}

// ---- errors ------------------------------------------------------------------

TEST(RigBody, bad_guides_fail_with_the_component_named) {
  auto scene = metarig();
  ASSERT_TRUE(scene);
  Component eye = component("eye", "eyes", joints({"no_such_eye"}));
  auto b = Build::open(*scene, rig_with({eye}), builtin_components());
  ASSERT_TRUE(b.is_ok()) << b.status().message();
  const Status s = (*b)->build_all();
  EXPECT_FALSE(s.is_ok());
  EXPECT_NE(s.message().find("eyes"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("no_such_eye"), std::string::npos) << s.message();
}

}  // namespace
}  // namespace rigel::rig
