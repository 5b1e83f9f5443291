// The `ephemeral` component: an ephemeral rig built, driven and removed as
// part of a rig definition, on Rigify's human metarig.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "../rig/rig_test_util.h"
#include "rigel/ephemeral/component.h"
#include "rigel/ephemeral/keying.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/io/gltf_import.h"
#include "rigel/io/scene_file.h"
#include "rigel/math/rotation.h"
#include "rigel/math/transform.h"
#include "rigel/rig/build_function.h"
#include "rigel/rig/build.h"
#include "rigel/rig/definition_io.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"

namespace rigel::ephemeral {
namespace {

using graph::Plug;
using math::Mat4;
using math::Vec3;
namespace xform = scene::xform;

std::unique_ptr<scene::Scene> metarig() { return rig::testing::metarig(default_registry()); }

rig::Component component(std::string type, std::string name, std::string joint) {
  rig::Component c;
  c.type = std::move(type);
  c.name = std::move(name);
  c.rig_id = rig::new_rig_id();
  rig::Guide g;
  g.joint = std::move(joint);
  c.guides = {g};
  return c;
}

// global -> hip (spine) -> ephemeral on `joint`.
rig::Definition definition(const std::string& joint, const std::string& key_scope = "controls") {
  rig::Definition d;
  d.name = "hero";
  d.version = "1.0";
  rig::Component global = component("global", "global", "");
  global.guides[0].joint.clear();
  rig::Component hip = component("hip", "hip", "spine");
  rig::Component eph = component("ephemeral", "face", joint);
  eph.params.push_back(rig::Param{"keyScope", std::string(key_scope), {}});
  hip.children = {eph};
  global.children = {hip};
  d.components = {global};
  return d;
}

std::vector<NodeId> joints_below(const graph::Graph& g, NodeId root) {
  std::vector<NodeId> out, stack = {root};
  while (!stack.empty()) {
    NodeId j = stack.back();
    stack.pop_back();
    if (g.node(j)->type().name() == scene::kJointType) out.push_back(j);
    for (NodeId c : g.children(j)) stack.push_back(c);
  }
  return out;
}

TEST(EphemeralComponent, builds_one_control_per_joint_below_the_guide_linked_to_the_component) {
  auto scene = metarig();
  ASSERT_TRUE(scene);
  graph::Graph& g = scene->graph();
  const std::string plain = io::write_scene(*scene);
  std::vector<Mat4> rest;
  const std::vector<NodeId> face = joints_below(g, g.find("face"));
  ASSERT_GT(face.size(), 20u);
  for (NodeId j : face) rest.push_back(scene->world_matrix(j));

  auto b = rig::Build::open(*scene, definition("face"), components());
  ASSERT_TRUE(b.is_ok()) << b.status().message();
  {
    Status built = (*b)->build_all();
    ASSERT_TRUE(built.is_ok()) << built.message();
  }
  const NodeId root = rig::find_rig(g, "hero");
  const NodeId meta = rig::find_component(g, root, "face");
  ASSERT_TRUE(meta.is_valid());
  const NodeId eph = *rig::resolve_address(g, "hero:face/ephemeralRig");
  EXPECT_EQ(rig_controls(g, eph).size(), face.size());
  EXPECT_EQ(key_scope(g, eph), KeyScope::kControls) << "the keyScope param";
  for (NodeId c : rig_controls(g, eph)) EXPECT_EQ(rig::component_of(g, c), meta) << g.node(c)->name();
  // Nothing moves at rest.
  for (std::size_t i = 0; i < face.size(); ++i)
    EXPECT_TRUE(math::is_near(scene->world_matrix(face[i]), rest[i], 1e-9)) << g.node(face[i])->name();

  // The root control turns the face; the jaw's control turns the jaw only.
  const NodeId jaw = g.find("jaw");
  const NodeId jaw_ctrl = control_of(g, jaw);
  ASSERT_TRUE(jaw_ctrl.is_valid());
  EXPECT_EQ(*rig::resolve_address(g, "hero:face/joint[0]"), control_of(g, g.find("face"))) << "parent first";
  const Vec3 chin_before = scene->world_matrix(g.find("chin")).topRightCorner<3, 1>();
  const Vec3 nose_before = scene->world_matrix(g.find("nose")).topRightCorner<3, 1>();
  const Mat4 jaw_world = scene->world_matrix(jaw);
  // Quaternion joints: the control holds rotateQuaternion. Turn the jaw 20
  // degrees about its own x axis.
  const math::Quat q0 = std::get<math::Quat>(g.node(jaw_ctrl)->value(xform::kRotateQuaternion));
  const math::Quat turn(Eigen::AngleAxisd(20.0 * M_PI / 180.0, Vec3::UnitX()));
  ASSERT_TRUE(g.set_value(Plug{jaw_ctrl, xform::kRotateQuaternion, -1}, q0 * turn).is_ok());
  const Vec3 pivot = jaw_world.topRightCorner<3, 1>();
  const math::Mat3 axes = jaw_world.topLeftCorner<3, 3>();
  const Vec3 axis = (axes * Vec3::UnitX()).normalized();
  const Vec3 expected = pivot + Eigen::AngleAxisd(20.0 * M_PI / 180.0, axis) * (chin_before - pivot);
  EXPECT_LT((scene->world_matrix(g.find("chin")).topRightCorner<3, 1>() - expected).norm(), 1e-6);
  EXPECT_LT((scene->world_matrix(g.find("nose")).topRightCorner<3, 1>() - nose_before).norm(), 1e-12);

  // The hip control carries the whole face (the controls follow the skeleton).
  const NodeId hip = *rig::resolve_address(g, "hero:hip/main");
  const Mat4 nose = scene->world_matrix(g.find("nose"));
  const Mat4 spine = scene->world_matrix(g.find("spine"));
  ASSERT_TRUE(g.set_value(Plug{hip, xform::kTranslate, -1}, Vec3(0.0, 0.1, 0.0)).is_ok());
  ASSERT_TRUE(g.set_value(Plug{hip, xform::kRotate, -1}, Vec3(0.0, 30.0, 0.0)).is_ok());
  const Mat4 moved = scene->world_matrix(g.find("spine"));
  EXPECT_GT((moved - spine).norm(), 0.05);
  EXPECT_TRUE(math::is_near(scene->world_matrix(g.find("nose")), Mat4(moved * math::affine_inverse(spine) * nose), 1e-9))
      << "the face moves rigidly with the spine the hip drives";

  // Removing the rig gives back the character exactly.
  ASSERT_TRUE(g.set_value(Plug{hip, xform::kTranslate, -1}, Vec3(0.0, 0.0, 0.0)).is_ok());
  ASSERT_TRUE(g.set_value(Plug{hip, xform::kRotate, -1}, Vec3(0.0, 0.0, 0.0)).is_ok());
  ASSERT_TRUE(g.set_value(Plug{jaw_ctrl, xform::kRotateQuaternion, -1}, q0).is_ok());
  ASSERT_TRUE((*b)->remove().is_ok());
  EXPECT_TRUE(io::write_scene(*scene) == plain) << "remove gives back the file byte for byte";
}

TEST(EphemeralComponent, stepping_back_and_forward_from_every_index_gives_the_straight_build) {
  auto scene = metarig();
  ASSERT_TRUE(scene);
  auto b = rig::Build::open(*scene, definition("face"), components());
  ASSERT_TRUE(b.is_ok());
  {
    Status built = (*b)->build_all();
    ASSERT_TRUE(built.is_ok()) << built.message();
  }
  rig::testing::expect_stepping_gives_the_straight_build(**b, *scene);
}

TEST(EphemeralComponent, refuses_joints_another_component_drives_naming_them) {
  auto scene = metarig();
  ASSERT_TRUE(scene);
  // The hip drives `spine`: an ephemeral rig from it would take the hip's constraint over.
  auto b = rig::Build::open(*scene, definition("spine"), components());
  ASSERT_TRUE(b.is_ok());
  Status s = (*b)->build_all();
  ASSERT_FALSE(s.is_ok());
  EXPECT_NE(s.message().find("face (ephemeral): joint 'spine' is driven by"), std::string::npos) << s.message();
  EXPECT_EQ(rig::component_of(scene->graph(), scene->graph().find("spine")), NodeId{});
}

// ---- the bundled example: examples/biped.rig.xml -------------------------

rig::Definition example() {
  rig::ParseResult p = rig::load_definition(std::filesystem::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml");
  EXPECT_TRUE(p.ok()) << (p.ok() ? "" : p.errors.front().str());
  return p.definition;
}

// Between them the shipped example rigs (examples/*.rig.xml: the biped, the
// quadruped with its cart, the puppet) use every component type.
TEST(Examples, use_every_component_type) {
  std::set<std::string> used;
  int examples = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(RIGEL_SOURCE_DIR) / "examples")) {
    if (!entry.path().filename().string().ends_with(".rig.xml")) continue;
    rig::ParseResult p = rig::load_definition(entry.path());
    ASSERT_TRUE(p.ok()) << entry.path() << ": " << p.errors.front().str();
    EXPECT_TRUE(rig::validate(p.definition).empty()) << entry.path();
    for (const rig::Component* c : p.definition.all_components()) used.insert(c->type);
    ++examples;
  }
  EXPECT_GE(examples, 3);
  // A call runs a build graph's function: no rigging of its own to show.
  for (const std::string& type : components().types()) {
    if (type == rig::kCallType) continue;
    EXPECT_TRUE(used.count(type)) << "no example uses " << type;
  }
}

TEST(BipedExample, builds_on_the_metarig_without_moving_a_joint_and_removes_exactly) {
  auto scene = metarig();
  ASSERT_TRUE(scene);
  graph::Graph& g = scene->graph();
  const std::string plain = io::write_scene(*scene);
  std::vector<std::pair<NodeId, Mat4>> rest;
  for (NodeId id : g.nodes())
    if (g.node(id)->type().name() == scene::kJointType) rest.emplace_back(id, scene->world_matrix(id));
  auto b = rig::Build::open(*scene, example(), components());
  ASSERT_TRUE(b.is_ok()) << b.status().message();
  {
    Status built = (*b)->build_all();
    ASSERT_TRUE(built.is_ok()) << built.message();
  }
  for (const auto& [id, m] : rest)
    EXPECT_TRUE(math::is_near(scene->world_matrix(id), m, 1e-9)) << g.node(id)->name() << " moved at rest";

  // The parts work together: the left leg is in IK, so its ik control moves
  // the ankle; rolling the foot on its toes lifts the ankle further; a curl
  // moves the fingertips; the global control carries everything.
  auto set = [&](const std::string& address, graph::AttrIndex attr, graph::Value v) {
    Result<NodeId> id = rig::resolve_address(g, address);
    ASSERT_TRUE(id.is_ok()) << id.status().message();
    ASSERT_TRUE(g.set_value(Plug{*id, attr, -1}, std::move(v)).is_ok()) << address;
  };
  auto at = [&](const char* joint) -> Vec3 { return scene->world_matrix(g.find(joint)).topRightCorner<3, 1>(); };
  const Vec3 ankle = at("foot.L");
  set("hero:leg_L/ik", xform::kTranslate, Vec3(0.0, 0.1, 0.0));
  const Vec3 lifted = at("foot.L");
  EXPECT_GT((lifted - ankle).norm(), 0.05) << "the IK leg follows its ik control";
  const NodeId roll_node = *rig::resolve_address(g, "hero:foot_L/reverseFoot");
  ASSERT_TRUE(g.set_value(Plug{roll_node, g.node(roll_node)->type().attr_find("roll"), -1}, 60.0).is_ok());
  EXPECT_GT(at("foot.L").y(), lifted.y() + 0.01) << "rolling onto the toes lifts the ankle";
  const Vec3 tip = at("f_index.03.R");
  const NodeId curl = *rig::resolve_address(g, "hero:hand_R/fingerCurl");
  ASSERT_TRUE(g.set_value(Plug{curl, g.node(curl)->type().attr_find("curl"), -1}, 60.0).is_ok());
  EXPECT_GT((at("f_index.03.R") - tip).norm(), 0.005) << "curl moves the fingertips";
  const Vec3 nose = at("nose");
  set("hero:global/main", xform::kTranslate, Vec3(1.0, 0.0, 0.0));
  EXPECT_LT((at("nose") - (nose + Vec3(1, 0, 0))).norm(), 1e-9) << "the global control carries the head";

  ASSERT_TRUE((*b)->remove().is_ok());
  EXPECT_TRUE(io::write_scene(*scene) == plain) << "remove gives back the file byte for byte";
}

}  // namespace
}  // namespace rigel::ephemeral
