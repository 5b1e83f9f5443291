// Rigger actions (tools/rigging.h) on the biped built on the metarig:
// looks copied and pasted in parts, shapes mirrored and flipped in place
// (twice gives them back bit for bit), mirrored onto the opposite control
// (mirror images in the world whatever the axes), locators at nodes, and
// joint chains mirrored with their names swapped; each one undo step,
// refusals naming the field and changing nothing.

#include "rigel/tools/rigging.h"

#include <gtest/gtest.h>

#include "rigel/math/transform.h"
#include "rigel/scene/shapes.h"
#include "tools_test_util.h"

namespace rigel::tools {
namespace {

using graph::NodeId;
using math::Mat4;
using math::Vec3;
using testing::at;
namespace xform = scene::xform;

const Mat4 kMirrorX = Vec3(-1, 1, 1).homogeneous().asDiagonal();

std::vector<Vec3> world_points(scene::Scene& s, NodeId control) {
  auto look = control_look(s.graph(), control);
  EXPECT_TRUE(look.is_ok());
  std::vector<Vec3> out;
  for (const Vec3& p : look->points) out.push_back((s.world_matrix(control) * p.homogeneous()).head<3>());
  return out;
}

TEST(RiggerShapes, copy_and_paste_the_shape_the_colour_or_both) {
  auto s = testing::built_rig();
  ASSERT_TRUE(s);
  graph::Graph& g = s->graph();
  const NodeId arm = at(g, "hero:arm_L/ik"), leg = at(g, "hero:leg_L/ik");
  const ControlLook a = *control_look(g, arm), l = *control_look(g, leg);
  ASSERT_NE(a.points, l.points) << "the arm's cube is 0.08, the leg's 0.12";

  ASSERT_TRUE(paste_control_look(g, {leg}, a, {true, false}).is_ok());
  EXPECT_EQ(control_look(g, leg)->points, a.points);
  EXPECT_EQ(control_look(g, leg)->color, l.color) << "the shape only";
  EXPECT_EQ(g.undo_label(), "paste control shape");
  ASSERT_TRUE(g.undo());
  EXPECT_EQ(control_look(g, leg)->points, l.points);

  ControlLook red = a;
  red.color = Vec3(1, 0, 0);
  ASSERT_TRUE(paste_control_look(g, {arm, leg}, red, {false, true}).is_ok());
  EXPECT_EQ(control_look(g, leg)->color, Vec3(1, 0, 0));
  EXPECT_EQ(control_look(g, leg)->points, l.points) << "the colour only";
  EXPECT_EQ(control_look(g, arm)->color, Vec3(1, 0, 0));

  red.color = Vec3(2, 0, 0);
  EXPECT_EQ(paste_control_look(g, {leg}, red).field(), "shape.color");
  red.color = Vec3(1, 0, 0);
  red.points[1].x() = std::nan("");
  EXPECT_EQ(paste_control_look(g, {leg}, red).field(), "shape.points[1]");
  EXPECT_EQ(paste_control_look(g, {g.find("hand.L")}, a).field(), "controls") << "a joint is not a control";
  EXPECT_EQ(paste_control_look(g, {}, a).field(), "controls");
  EXPECT_EQ(control_look(g, g.find("hand.L")).status().field(), "controls");
}

TEST(RiggerShapes, mirror_and_flip_in_place_and_twice_give_the_shape_back) {
  auto s = testing::built_rig();
  ASSERT_TRUE(s);
  graph::Graph& g = s->graph();
  const NodeId c = at(g, "hero:arm_L/pole");
  const std::vector<Vec3> before = control_look(g, c)->points;
  ASSERT_TRUE(edit_control_shape(g, {c}, ShapeEdit::kMirror).is_ok());
  const std::vector<Vec3> mirrored = control_look(g, c)->points;
  ASSERT_EQ(mirrored.size(), before.size());
  for (std::size_t i = 0; i < before.size(); ++i)
    EXPECT_EQ(mirrored[i], Vec3(-before[i].x(), before[i].y(), before[i].z()));
  EXPECT_EQ(g.undo_label(), "mirror control shape");
  ASSERT_TRUE(edit_control_shape(g, {c}, ShapeEdit::kMirror).is_ok());
  EXPECT_EQ(control_look(g, c)->points, before) << "bit for bit";

  ASSERT_TRUE(edit_control_shape(g, {c}, ShapeEdit::kFlip).is_ok());
  const std::vector<Vec3> flipped = control_look(g, c)->points;
  for (std::size_t i = 0; i < before.size(); ++i)
    EXPECT_EQ(flipped[i], Vec3(-before[i].x(), before[i].y(), -before[i].z())) << "a half turn about Y";
  ASSERT_TRUE(g.undo());
  EXPECT_EQ(control_look(g, c)->points, before);
}

TEST(RiggerShapes, mirrored_to_the_opposite_control_is_its_mirror_image_in_the_world) {
  auto s = testing::built_rig();
  ASSERT_TRUE(s);
  graph::Graph& g = s->graph();
  const NodeId left = at(g, "hero:arm_L/pole"), right = at(g, "hero:arm_R/pole");
  EXPECT_EQ(*opposite_control(g, left), right) << "paired by the metadata";
  // An asymmetric shape on the left: the right gets its mirror image.
  ControlLook look = *control_look(g, left);
  look.points = {Vec3(0.1, 0, 0), Vec3(0, 0.2, 0), Vec3(0, 0, 0.3), Vec3(0.05, -0.1, 0.2)};
  look.closed = false;
  ASSERT_TRUE(paste_control_look(g, {left}, look, {true, false}).is_ok());
  const Vec3 right_color = control_look(g, right)->color;
  auto pairs = mirror_shape_to_opposite(*s, {left});
  ASSERT_TRUE(pairs.is_ok()) << pairs.status().message();
  ASSERT_EQ(pairs->size(), 1u);
  EXPECT_EQ((*pairs)[0].to, right);
  const auto wl = world_points(*s, left), wr = world_points(*s, right);
  ASSERT_EQ(wr.size(), wl.size());
  for (std::size_t i = 0; i < wl.size(); ++i)
    EXPECT_LT((Vec3(-wl[i].x(), wl[i].y(), wl[i].z()) - wr[i]).norm(), 1e-12) << i;
  EXPECT_FALSE(control_look(g, right)->closed);
  EXPECT_EQ(control_look(g, right)->color, right_color) << "each side keeps its colour";
  EXPECT_EQ(g.undo_label(), "mirror control shape to the opposite side");

  const NodeId centre = at(g, "hero:hip/main");
  EXPECT_EQ(opposite_control(g, centre).status().field(), "controls");
  EXPECT_EQ(mirror_shape_to_opposite(*s, {centre}).status().field(), "controls");
}

TEST(RiggerShapes, an_unbuilt_control_pairs_by_its_name) {
  auto s = testing::import_character(testing::source("tests/data/gltf/rigify_human_metarig.glb"));
  ASSERT_TRUE(s);
  graph::Graph& g = s->graph();
  auto l = s->create(scene::kControlType, "box.L"), r = s->create(scene::kControlType, "box.R");
  auto lone = s->create(scene::kControlType, "box_C");
  ASSERT_TRUE(l && r && lone);
  EXPECT_EQ(*opposite_control(g, *l), *r);
  EXPECT_EQ(*opposite_control(g, *r), *l);
  EXPECT_NE(opposite_control(g, *lone).status().message().find("names no side"), std::string::npos);
}

TEST(Locators, at_each_node_its_world_position_and_rotation) {
  auto s = testing::built_rig();
  ASSERT_TRUE(s);
  graph::Graph& g = s->graph();
  const NodeId hand = g.find("hand.L"), ik = at(g, "hero:arm_L/ik");
  auto locs = create_locators(*s, {hand, ik}, 0.05);
  ASSERT_TRUE(locs.is_ok()) << locs.status().message();
  ASSERT_EQ(locs->size(), 2u);
  EXPECT_EQ(g.node((*locs)[0])->name(), "hand.L_loc");
  EXPECT_EQ(g.node((*locs)[0])->type().name(), scene::kControlType);
  EXPECT_EQ(g.undo_label(), "create locators");
  for (std::size_t i = 0; i < 2; ++i) {
    const math::Decomposed want = math::decompose(s->world_matrix(i ? ik : hand));
    const math::Decomposed got = math::decompose(s->world_matrix((*locs)[i]));
    EXPECT_LT((got.translate - want.translate).norm(), 1e-12);
    EXPECT_LT(got.rotation.angularDistance(want.rotation), 1e-9);
    EXPECT_LT((got.scale - Vec3::Ones()).norm(), 1e-12) << "unit scale";
  }
  EXPECT_EQ(control_look(g, (*locs)[0])->points.size(), scene::control_shape("locator")->points.size());
  auto again = create_locators(*s, {hand});
  ASSERT_TRUE(again.is_ok());
  EXPECT_NE(g.node((*again)[0])->name(), "hand.L_loc") << "a unique name";
  ASSERT_TRUE(g.undo());
  ASSERT_TRUE(g.undo());
  EXPECT_FALSE(g.find("hand.L_loc").is_valid());
  EXPECT_EQ(create_locators(*s, {}).status().field(), "nodes");
  EXPECT_EQ(create_locators(*s, {hand}, 0).status().field(), "size");
}

TEST(MirrorJoints, a_new_chain_is_mirrored_with_its_names_and_back_gives_it_again) {
  auto s = testing::import_character(testing::source("tests/data/gltf/rigify_human_metarig.glb"));
  ASSERT_TRUE(s);
  graph::Graph& g = s->graph();
  const NodeId chest = g.find("spine.003");
  ASSERT_TRUE(chest.is_valid());
  auto a = s->create(scene::kJointType, "wing_a.L", chest);
  ASSERT_TRUE(a);
  auto b = s->create(scene::kJointType, "wing_b.L", *a);
  ASSERT_TRUE(b);
  auto tip = s->create(scene::kJointType, "wing_tip.L", *b);
  ASSERT_TRUE(tip);
  ASSERT_TRUE(g.set_value({*a, xform::kTranslate}, graph::Value(Vec3(0.2, 0.1, -0.05))).is_ok());
  ASSERT_TRUE(g.set_value({*a, xform::kRotate}, graph::Value(Vec3(10, 35, -20))).is_ok());
  ASSERT_TRUE(g.set_value({*b, xform::kTranslate}, graph::Value(Vec3(0.05, 0.3, 0.02))).is_ok());
  ASSERT_TRUE(g.set_value({*b, xform::kRotate}, graph::Value(Vec3(-15, 5, 40))).is_ok());
  ASSERT_TRUE(g.set_value({*tip, xform::kTranslate}, graph::Value(Vec3(0, 0.25, 0))).is_ok());
  const std::vector<NodeId> left{*a, *b, *tip};
  std::vector<Mat4> before;
  for (NodeId j : left) before.push_back(s->world_matrix(j));

  auto r = mirror_joints(*s, {*a});
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  ASSERT_EQ(r->created.size(), 3u);
  EXPECT_TRUE(r->updated.empty());
  EXPECT_EQ(g.undo_label(), "mirror joints");
  const char* names[] = {"wing_a.R", "wing_b.R", "wing_tip.R"};
  for (std::size_t i = 0; i < 3; ++i) {
    const NodeId m = r->created[i];
    EXPECT_EQ(g.node(m)->name(), names[i]);
    EXPECT_EQ(g.node(m)->type().name(), scene::kJointType);
    const Mat4 w = s->world_matrix(m);
    EXPECT_LT((w - kMirrorX * before[i] * kMirrorX).cwiseAbs().maxCoeff(), 1e-12) << names[i];
    EXPECT_GT((w.block<3, 3>(0, 0).determinant()), 0) << "a right-handed frame";
  }
  EXPECT_EQ(g.parent(r->created[0]), chest) << "a centre parent is kept";
  EXPECT_EQ(g.parent(r->created[1]), r->created[0]);

  // Again: refused (the names exist), unless existing joints are updated.
  EXPECT_EQ(mirror_joints(*s, {*a}).status().field(), "joints");
  EXPECT_NE(mirror_joints(*s, {*a}).status().message().find("wing_a.R"), std::string::npos);
  // The right side mirrored back onto the left: the left is as it was.
  MirrorJointsOptions update;
  update.update_existing = true;
  auto back = mirror_joints(*s, {r->created[0]}, update);
  ASSERT_TRUE(back.is_ok()) << back.status().message();
  EXPECT_EQ(back->updated, left) << "the same joints, moved";
  for (std::size_t i = 0; i < 3; ++i) EXPECT_LT((s->world_matrix(left[i]) - before[i]).cwiseAbs().maxCoeff(), 1e-12);
  // The right side turned, then updated from the left: back at the mirror.
  ASSERT_TRUE(g.set_value({r->created[0], xform::kRotate}, graph::Value(Vec3(0, 0, 5))).is_ok());
  ASSERT_TRUE(mirror_joints(*s, {*a}, update).is_ok());
  for (std::size_t i = 0; i < 3; ++i)
    EXPECT_LT((s->world_matrix(r->created[i]) - kMirrorX * before[i] * kMirrorX).cwiseAbs().maxCoeff(), 1e-12);

  EXPECT_EQ(mirror_joints(*s, {chest}).status().field(), "joints") << "a centre joint";
  EXPECT_NE(mirror_joints(*s, {chest}).status().message().find("names no side"), std::string::npos);
  auto ctl = s->create(scene::kControlType, "ctl.L");
  ASSERT_TRUE(ctl);
  EXPECT_EQ(mirror_joints(*s, {*ctl}).status().field(), "joints");
}

TEST(MirrorJoints, updating_the_metarig_s_right_arm_from_its_left_keeps_it_symmetric) {
  auto s = testing::import_character(testing::source("tests/data/gltf/rigify_human_metarig.glb"));
  ASSERT_TRUE(s);
  graph::Graph& g = s->graph();
  MirrorJointsOptions update;
  update.update_existing = true;
  auto r = mirror_joints(*s, {g.find("upper_arm.L")}, update);
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  EXPECT_TRUE(r->created.empty());
  EXPECT_GT(r->updated.size(), 10u) << "the arm, the hand and the fingers";
  EXPECT_EQ(g.parent(g.find("upper_arm.R")), g.find("shoulder.R")) << "kept under its parent";
  for (const char* name : {"upper_arm", "forearm", "hand", "f_index.03"}) {
    const Mat4 l = s->world_matrix(g.find(std::string(name) + ".L"));
    const Mat4 rr = s->world_matrix(g.find(std::string(name) + ".R"));
    EXPECT_LT((rr - kMirrorX * l * kMirrorX).cwiseAbs().maxCoeff(), 1e-9) << name;
  }
}

}  // namespace
}  // namespace rigel::tools
