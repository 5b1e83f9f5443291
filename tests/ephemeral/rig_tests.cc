// setup_ephemeral and relation editing.
#include <gtest/gtest.h>

#include "ephemeral_test_util.h"

namespace rigel::ephemeral::testing {
namespace {

TEST(EphemeralSetup, one_control_per_joint__mirrors_hierarchy_and_world) {
  auto s = make_scene();
  NodeId a = joint(*s, "a", {}, Vec3(0, 1, 0));
  NodeId b = joint(*s, "b", a, Vec3(1, 0, 0), Vec3(10, 20, 30));
  NodeId c = joint(*s, "c", b, Vec3(0, 2, 0));
  NodeId d = joint(*s, "d", b, Vec3(0, 0, 1));
  Result<SetupResult> r = setup_ephemeral(*s);
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  ASSERT_EQ(r->controls.size(), 4u);
  EXPECT_EQ(r->joints, (std::vector<NodeId>{a, b, c, d}));
  Graph& g = s->graph();
  EXPECT_EQ(g.node(r->controls[1])->name(), "b_ctrl");
  EXPECT_EQ(g.parent(r->controls[2]), r->controls[1]) << "controls mirror the joint hierarchy";
  for (std::size_t i = 0; i < 4; ++i)
    EXPECT_TRUE(math::is_near(world(*s, r->controls[i]), world(*s, r->joints[i]), 1e-12));
  // Joints follow their controls.
  ASSERT_TRUE(succeeded(g.set_value(Plug{r->controls[1], xform::kRotate, -1}, Vec3(0, 0, 90))));
  EXPECT_TRUE(math::is_near(world(*s, r->controls[2]), world(*s, c), 1e-12));
  Result<std::vector<Relation>> rel = relations(g, r->rig);
  ASSERT_TRUE(rel.is_ok());
  EXPECT_EQ(rel->size(), 6u) << "forward and inverse for each of the 3 parent-child pairs";
  EXPECT_NE(std::find(rel->begin(), rel->end(), Relation{RelationKind::kForward, r->controls[1], r->controls[3]}), rel->end());
  EXPECT_NE(std::find(rel->begin(), rel->end(), Relation{RelationKind::kInverse, r->controls[3], r->controls[1]}), rel->end());
}

TEST(EphemeralSetup, the_side_a_name_says_colours_the_circle_blue_left_red_right_yellow_centre) {
  for (const char* n : {"thigh.L", "f_index.01.L", "ear.L.001", "lip.T.L", "arm_l", "mixamorig:LeftArm", "UpperArmLeft",
                        "hand-L", "Left"})
    EXPECT_EQ(side_from_name(n), NameSide::kLeft) << n;
  for (const char* n : {"thigh.R", "shoulder_R", "mixamorig:RightUpLeg", "foot r", "RIGHT_hand"})
    EXPECT_EQ(side_from_name(n), NameSide::kRight) << n;
  for (const char* n : {"spine.003", "Leftover", "Lower", "head", "", "Root", "brow.T", "L:spine"})
    EXPECT_EQ(side_from_name(n), NameSide::kCenter) << n;

  auto s = make_scene();
  NodeId hips = joint(*s, "hips", {}, Vec3(0, 1, 0));
  joint(*s, "thigh.L", hips, Vec3(0.1, 0, 0));
  joint(*s, "thigh.R", hips, Vec3(-0.1, 0, 0));
  SetupOptions o;
  o.shape_radius = 0.03;
  Result<SetupResult> r = setup_ephemeral(*s, o);
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  const Graph& g = s->graph();
  auto color = [&](std::size_t i) { return std::get<Vec3>(g.node(r->controls[i])->value(scene::control_attr::kShapeColor)); };
  EXPECT_EQ(color(0), Vec3(1, 1, 0)) << "centre: yellow";
  EXPECT_EQ(color(1), Vec3(0, 0, 1)) << "left: blue";
  EXPECT_EQ(color(2), Vec3(1, 0, 0)) << "right: red";
}

TEST(EphemeralSetup, sized_from_bones_a_third_of_the_shortest_bone_within_a_tenth_and_the_radius) {
  auto s = make_scene();
  NodeId hips = joint(*s, "hips", {}, Vec3(0, 1, 0));
  NodeId spine = joint(*s, "spine", hips, Vec3(0, 0.3, 0));   // hips' shortest bone: 0.06 to the thigh
  NodeId thigh = joint(*s, "thigh.L", hips, Vec3(0.06, 0, 0));
  joint(*s, "shin.L", thigh, Vec3(0, -0.45, 0));               // a leaf: its bone from the thigh
  NodeId lip = joint(*s, "lip", spine, Vec3(0, 0.003, 0));    // a tiny bone: the floor
  joint(*s, "lip.001", lip, Vec3(0, 0.003, 0));
  SetupOptions o;
  o.shape_radius = 0.05;
  o.size_from_bones = true;
  Result<SetupResult> r = setup_ephemeral(*s, o);
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  const Graph& g = s->graph();
  ASSERT_EQ(r->controls.size(), 6u);
  auto radius = [&](const char* joint_name) {
    for (std::size_t i = 0; i < r->joints.size(); ++i)
      if (g.node(r->joints[i])->name() == joint_name)
        return std::get<std::vector<Vec3>>(g.node(r->controls[i])->value(scene::control_attr::kShapePoints))[0].norm();
    return -1.0;
  };
  EXPECT_NEAR(radius("hips"), 0.02, 1e-12) << "a third of its shortest bone, 0.06 to the thigh";
  EXPECT_NEAR(radius("spine"), 0.005, 1e-12) << "a third of 0.003 is below the floor, a tenth of 0.05";
  EXPECT_NEAR(radius("thigh.L"), 0.05, 1e-12) << "a third of 0.45 is above the radius";
  EXPECT_NEAR(radius("shin.L"), 0.05, 1e-12) << "a leaf: its bone from the thigh";
  EXPECT_NEAR(radius("lip.001"), 0.005, 1e-12) << "a leaf's tiny bone: the floor";
  o.size_from_bones = false;
  auto t = make_scene();
  joint(*t, "a", {}, Vec3::Zero());
  r = setup_ephemeral(*t, o);
  ASSERT_TRUE(r.is_ok());
  EXPECT_NEAR(std::get<std::vector<Vec3>>(t->graph().node(r->controls[0])->value(scene::control_attr::kShapePoints))[0].norm(),
              0.05, 1e-12) << "fixed: every circle at the radius";
}

TEST(EphemeralSetup, is_one_undo_step__and_undo_restores_the_file_exactly) {
  auto s = make_scene();
  NodeId a = joint(*s, "a", {}, Vec3(0, 1, 0));
  joint(*s, "b", a, Vec3(1, 0, 0));
  const std::string before = io::write_scene(*s);
  const std::size_t steps = s->graph().undo_count();
  ASSERT_TRUE(setup_ephemeral(*s).is_ok());
  EXPECT_EQ(s->graph().undo_count(), steps + 1);
  ASSERT_TRUE(s->graph().undo());
  EXPECT_EQ(io::write_scene(*s), before);
}

TEST(EphemeralSetup, refuses_bad_input__changing_nothing) {
  auto s = make_scene();
  EXPECT_EQ(setup_ephemeral(*s).status().code(), ErrorCode::kNotFound) << "no joints";
  NodeId a = joint(*s, "a", {}, Vec3::Zero());
  ASSERT_TRUE(succeeded(s->graph().set_value(Plug{a, scene::joint_attr::kJointOrient, -1}, Vec3(0, 0, 10))));
  const std::string before = io::write_scene(*s);
  EXPECT_EQ(setup_ephemeral(*s).status().code(), ErrorCode::kUnsupported) << "joint orient is refused";
  EXPECT_EQ(io::write_scene(*s), before);
  ASSERT_TRUE(succeeded(s->graph().set_value(Plug{a, scene::joint_attr::kJointOrient, -1}, Vec3(0, 0, 0))));
  ASSERT_TRUE(setup_ephemeral(*s).is_ok());
  EXPECT_EQ(setup_ephemeral(*s).status().code(), ErrorCode::kAlreadyExists) << "a joint already has a control";
  auto plain = std::make_unique<scene::Scene>();  // scene types only
  joint(*plain, "x", {}, Vec3::Zero());
  EXPECT_EQ(setup_ephemeral(*plain).status().code(), ErrorCode::kUnsupported);
}

TEST(EphemeralSetup, animation_moves_to_the_controls_or_is_dropped) {
  for (bool keep : {true, false}) {
    auto s = make_scene();
    NodeId a = joint(*s, "a", {}, Vec3::Zero());
    Result<NodeId> src = s->create(scene::kLocatorType, "driver");
    ASSERT_TRUE(src.is_ok());
    ASSERT_TRUE(succeeded(s->graph().set_value(Plug{*src, xform::kTranslate, -1}, Vec3(1, 2, 3))));
    ASSERT_TRUE(succeeded(s->graph().connect(Plug{*src, xform::kTranslate, -1}, Plug{a, xform::kTranslate, -1})));
    SetupOptions o;
    o.keep_animation = keep;
    Result<SetupResult> r = setup_ephemeral(*s, o);
    ASSERT_TRUE(r.is_ok()) << r.status().message();
    NodeId c = r->controls[0];
    auto from = s->graph().source(Plug{c, xform::kTranslate, -1});
    EXPECT_EQ(from.has_value(), keep);
    EXPECT_TRUE(vec_near(position(*s, a), Vec3(1, 2, 3), 1e-12));
    ASSERT_TRUE(succeeded(s->graph().set_value(Plug{*src, xform::kTranslate, -1}, Vec3(4, 5, 6))));
    EXPECT_TRUE(vec_near(position(*s, a), keep ? Vec3(4, 5, 6) : Vec3(1, 2, 3), 1e-12));
  }
}

TEST(EphemeralRelations, add_remove_edit_group__each_one_undo_step) {
  Arm arm = make_arm();
  Graph& g = arm.scene->graph();
  const NodeId rig = arm.rig.rig;
  const Relation magnet{RelationKind::kMagnet, arm.c(0), arm.c(2)};
  ASSERT_TRUE(succeeded(relation_add(g, rig, magnet)));
  EXPECT_EQ(relation_add(g, rig, magnet).code(), ErrorCode::kAlreadyExists);
  EXPECT_EQ(relation_add(g, rig, Relation{RelationKind::kPair, arm.c(0), arm.c(0)}).code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(relation_add(g, rig, Relation{RelationKind::kPair, arm.c(0), arm.wrist}).code(), ErrorCode::kInvalidArgument)
      << "relations join controls, not joints";
  ASSERT_TRUE(succeeded(relation_set_kind(g, rig, magnet, RelationKind::kPair)));
  EXPECT_EQ(relations(g, rig)->size(), 5u);
  ASSERT_TRUE(succeeded(relation_remove(g, rig, Relation{RelationKind::kPair, arm.c(0), arm.c(2)})));
  EXPECT_EQ(relation_remove(g, rig, magnet).code(), ErrorCode::kNotFound);
  ASSERT_TRUE(succeeded(group_add(g, rig, {arm.c(0), arm.c(1), arm.c(2)})));
  EXPECT_EQ(relations(g, rig)->size(), 4u + 6u) << "a group of three: pairs both ways between each two";
  ASSERT_TRUE(g.undo());
  EXPECT_EQ(relations(g, rig)->size(), 4u);
}

TEST(EphemeralRelations, survive_renames_and_a_file_round_trip) {
  Arm arm = make_arm();
  Graph& g = arm.scene->graph();
  ASSERT_TRUE(succeeded(relation_add(g, arm.rig.rig, Relation{RelationKind::kMagnet, arm.c(0), arm.c(2)})));
  ASSERT_TRUE(succeeded(g.rename(arm.c(2), "hand_ctrl")));
  Result<std::vector<Relation>> rel = relations(g, arm.rig.rig);
  ASSERT_TRUE(rel.is_ok());
  EXPECT_EQ(rel->back(), (Relation{RelationKind::kMagnet, arm.c(0), arm.c(2)})) << "relations name controls by uuid";
  const std::string text = io::write_scene(*arm.scene);
  auto loaded = io::parse_scene(text, "arm.rigel", default_registry());
  ASSERT_TRUE(loaded.is_ok()) << loaded.status().message();
  Graph& lg = (*loaded)->graph();
  std::vector<NodeId> rigs = rigs_find(lg);
  ASSERT_EQ(rigs.size(), 1u);
  Result<std::vector<Relation>> lrel = relations(lg, rigs[0]);
  ASSERT_TRUE(lrel.is_ok());
  ASSERT_EQ(lrel->size(), rel->size());
  for (std::size_t i = 0; i < rel->size(); ++i) {
    EXPECT_EQ((*lrel)[i].kind, (*rel)[i].kind);
    EXPECT_EQ(lg.node((*lrel)[i].from)->name(), g.node((*rel)[i].from)->name());
    EXPECT_EQ(lg.node((*lrel)[i].to)->name(), g.node((*rel)[i].to)->name());
  }
  EXPECT_EQ(io::write_scene(**loaded), text);
  EXPECT_EQ(rig_of(lg, lg.find("hand_ctrl")), rigs[0]);
}

}  // namespace
}  // namespace rigel::ephemeral::testing
