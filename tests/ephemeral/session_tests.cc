// The session: plan lifecycle and each mode against hand-computed answers on
// a three-joint arm and short chains, one control and several at once.
#include <gtest/gtest.h>

#include "ephemeral_test_util.h"

namespace rigel::ephemeral::testing {
namespace {

const double kCos30 = std::sqrt(3.0) / 2.0;

TEST(EphemeralSession, plan_is_built_once__reused__and_dropped_on_selection_mode_undo_time) {
  Arm arm = make_arm();
  Session session(*arm.scene);
  EXPECT_EQ(session.drag(Delta{Vec3(1, 0, 0)}).code(), ErrorCode::kInvalidArgument) << "nothing grabbed";
  session.select({arm.c(1)});
  EXPECT_FALSE(session.has_plan()) << "the plan is built on the first change, not on selection";
  ASSERT_TRUE(succeeded(session.drag(Delta{Vec3(0, 0, 0.1)})));
  ASSERT_TRUE(succeeded(session.drag(Delta{Vec3(0, 0, 0.1)})));
  EXPECT_EQ(session.plans_built(), 1) << "reused while selection and mode stay";
  session.set_mode(Mode::kSuspended);
  EXPECT_FALSE(session.has_plan());
  ASSERT_TRUE(succeeded(session.drag(Delta{Vec3(0, 0, 0.1)})));
  EXPECT_EQ(session.plans_built(), 2);
  ASSERT_TRUE(arm.scene->graph().undo());
  EXPECT_FALSE(session.has_plan()) << "undo drops the plan";
  ASSERT_TRUE(succeeded(session.drag(Delta{Vec3(0, 0, 0.1)})));
  arm.scene->set_frame(3);
  EXPECT_FALSE(session.has_plan()) << "time change drops the plan";
  ASSERT_TRUE(succeeded(session.drag(Delta{Vec3(0, 0, 0.1)})));
  arm.scene->graph().select({arm.c(2)});
  EXPECT_FALSE(session.has_plan()) << "selection change drops the plan";
  ASSERT_TRUE(succeeded(arm.scene->graph().set_value(Plug{arm.c(0), xform::kTranslate, -1}, Vec3(0, 0, 1))));
  EXPECT_FALSE(session.has_plan()) << "an edit the session did not make drops the plan";
}

TEST(EphemeralSession, a_gesture_is_one_undo_step__a_new_grab_starts_another) {
  Arm arm = make_arm();
  graph::Graph& g = arm.scene->graph();
  const std::string before = io::write_scene(*arm.scene);
  Session session(*arm.scene);
  session.set_mode(Mode::kInverse);
  session.select({arm.c(2)});
  const std::size_t steps = g.undo_count();
  for (int i = 0; i < 50; ++i) ASSERT_TRUE(succeeded(session.drag(Delta{Vec3(0.01, 0.02, -0.01)})));
  EXPECT_EQ(g.undo_count(), steps + 1) << "fifty drag events of one grab are one step";
  const std::string dragged = io::write_scene(*arm.scene);
  session.release();
  session.select({arm.c(2)});
  ASSERT_TRUE(succeeded(session.drag(Delta{Vec3(0.1, 0, 0)})));
  EXPECT_EQ(g.undo_count(), steps + 2) << "a new grab is a new step";
  ASSERT_TRUE(g.undo());
  EXPECT_EQ(io::write_scene(*arm.scene), dragged);
  ASSERT_TRUE(g.undo());
  EXPECT_EQ(io::write_scene(*arm.scene), before) << "one undo takes back the whole gesture";
  ASSERT_TRUE(g.redo());
  EXPECT_EQ(io::write_scene(*arm.scene), dragged);
}

// A plan keeps the world matrices its last drag wrote instead of pulling
// the graph again: many drags of one grab must land where the same drags
// land with a release (a fresh read of the scene) between each.
TEST(EphemeralSession, many_drags_of_one_grab_match_drags_with_fresh_reads) {
  for (int m = 0; m < kModeCount; ++m) {
    const Mode mode = static_cast<Mode>(m);
    // Its shares come from distances at plan time: a new plan per drag
    // changes them by design.
    if (mode == Mode::kMagnetRadius) continue;
    Chain a = make_chain(6, 15), b = make_chain(6, 15);
    Session sa(*a.scene), sb(*b.scene);
    SessionOptions o;
    o.magnet_radius = 3;
    sa.set_options(o);
    sb.set_options(o);
    sa.set_mode(mode);
    sb.set_mode(mode);
    sa.select({a.rig.controls[4]});
    for (int i = 0; i < 25; ++i) {
      Delta d{Vec3(0.01 * std::sin(i), 0.02, -0.01 * i / 25.0), about_z(i % 2 ? 2.0 : -1.5)};
      if (mode == Mode::kBody) d.scale = Vec3::Constant(i % 2 ? 1.01 : 0.995);
      ASSERT_TRUE(succeeded(sa.drag(d))) << mode_name(mode);
      sb.select({b.rig.controls[4]});
      ASSERT_TRUE(succeeded(sb.drag(d))) << mode_name(mode);
      sb.release();
      b.scene->graph().select({});
    }
    // Inverse chains of four or more controls go through FABRIK, which stops
    // at its tolerance: the two paths start each drag from poses equal to
    // rounding, and where FABRIK stops for one it may take one more step for
    // the other, so the middle of the chain drifts by the solver's tolerance
    // over the 25 drags (1.5e-8 seen in the -O1 sanitizer build). A stale
    // matrix in the plan would be off by the drags' size (1e-2).
    const double tolerance = mode == Mode::kInverse ? 1e-7 : 1e-9;
    for (std::size_t k = 0; k < a.rig.controls.size(); ++k)
      EXPECT_TRUE(math::is_near(world(*a.scene, a.rig.controls[k]), world(*b.scene, b.rig.controls[k]), tolerance))
          << mode_name(mode) << " control " << k << ": off by "
          << (world(*a.scene, a.rig.controls[k]) - world(*b.scene, b.rig.controls[k])).cwiseAbs().maxCoeff();
  }
}

TEST(EphemeralSession, grab_and_release_leaves_no_trace__drag_undo_restores_the_file) {
  Arm arm = make_arm();
  const std::string before = io::write_scene(*arm.scene);
  const std::size_t nodes = arm.scene->graph().node_count();
  {
    Session session(*arm.scene);
    for (int m = 0; m < kModeCount; ++m) {
      session.set_mode(static_cast<Mode>(m));
      session.select({arm.c(2)});
      ASSERT_TRUE(session.plan().is_ok());
      session.release();
      EXPECT_EQ(io::write_scene(*arm.scene), before) << mode_name(static_cast<Mode>(m));
      const std::size_t steps = arm.scene->graph().undo_count();
      ASSERT_TRUE(succeeded(session.drag(Delta{Vec3(0.2, 0.1, 0.3), about_z(20)})));
      EXPECT_EQ(arm.scene->graph().undo_count(), steps + 1) << "a drag is one undo step";
      EXPECT_EQ(arm.scene->graph().node_count(), nodes) << "the plan is never nodes";
      ASSERT_TRUE(arm.scene->graph().undo());
      EXPECT_EQ(io::write_scene(*arm.scene), before) << "undo restores every value exactly: " << mode_name(static_cast<Mode>(m));
    }
  }
  arm.scene->graph().select({});
  EXPECT_EQ(io::write_scene(*arm.scene), before);
}

TEST(EphemeralForward, shoulder_rotation_carries_elbow_and_wrist__only_the_shoulder_is_written) {
  Arm arm = make_arm();
  Session session(*arm.scene);
  session.select({arm.c(0)});
  ASSERT_TRUE(succeeded(session.drag(Delta{Vec3::Zero(), about_z(90)})));
  EXPECT_TRUE(vec_near(position(*arm.scene, arm.elbow), Vec3(0, 1, 0), 1e-12));
  EXPECT_TRUE(vec_near(position(*arm.scene, arm.wrist), Vec3(-0.5, 1 + kCos30, 0), 1e-12));
  Graph& g = arm.scene->graph();
  EXPECT_TRUE(vec_near(std::get<Vec3>(g.node(arm.c(0))->value(xform::kRotate)), Vec3(0, 0, 90), 1e-9));
  EXPECT_EQ(std::get<Vec3>(g.node(arm.c(1))->value(xform::kRotate)), Vec3(0, 0, 30)) << "descendants keep their channels";
  const Plan* plan = *session.plan();
  EXPECT_EQ(plan->entries.size(), 3u);
  EXPECT_EQ(plan->entry_find(arm.c(2))->role, Role::kFollow);
}

TEST(EphemeralSuspended, only_the_grabbed_control_moves__children_keep_world) {
  Arm arm = make_arm();
  Session session(*arm.scene);
  session.set_mode(Mode::kSuspended);
  const Mat4 wrist = world(*arm.scene, arm.wrist);
  session.select({arm.c(1)});
  ASSERT_TRUE(succeeded(session.drag(Delta{Vec3(0, 0, 1), about_z(45)})));
  EXPECT_TRUE(vec_near(position(*arm.scene, arm.elbow), Vec3(1, 0, 1), 1e-12));
  EXPECT_TRUE(math::is_near(world(*arm.scene, arm.wrist), wrist, 1e-12));
  EXPECT_TRUE(vec_near(position(*arm.scene, arm.shoulder), Vec3::Zero(), 0));
}

TEST(EphemeralPseudoInverse, elbow_moves_half_the_delta_and_controls_reaim) {
  Arm arm = make_arm();
  Session session(*arm.scene);
  session.set_mode(Mode::kPseudoInverse);
  const Vec3 elbow = position(*arm.scene, arm.elbow), wrist = position(*arm.scene, arm.wrist);
  const Mat4 wrist_world = world(*arm.scene, arm.wrist);
  session.select({arm.c(2)});
  const Vec3 d(0, 1, 0.5);
  ASSERT_TRUE(succeeded(session.drag(Delta{d})));
  EXPECT_TRUE(vec_near(position(*arm.scene, arm.wrist), wrist + d, 1e-12));
  EXPECT_TRUE(vec_near(position(*arm.scene, arm.elbow), elbow + d / 2, 1e-12)) << "delta / (middle + 1)";
  EXPECT_TRUE(vec_near(position(*arm.scene, arm.shoulder), Vec3::Zero(), 1e-15));
  // Shoulder's x axis (its bone) aims at the elbow, elbow's at the wrist.
  const Mat4 s = world(*arm.scene, arm.shoulder), e = world(*arm.scene, arm.elbow);
  EXPECT_TRUE(vec_near(s.col(0).head<3>().normalized(), (elbow + d / 2).normalized(), 1e-12));
  EXPECT_TRUE(vec_near(e.col(0).head<3>().normalized(), (wrist + d - elbow - d / 2).normalized(), 1e-12));
  EXPECT_LE((world(*arm.scene, arm.wrist).topLeftCorner<3, 3>() - wrist_world.topLeftCorner<3, 3>()).cwiseAbs().maxCoeff(), 1e-12)
      << "the grabbed control keeps its orientation";
}

TEST(EphemeralPseudoInverse, length_variant_keeps_bone_lengths) {
  Chain chain = make_chain(4, 20);
  Session session(*chain.scene);
  session.set_mode(Mode::kPseudoInverseLength);
  session.select({chain.rig.controls[3]});
  ASSERT_TRUE(succeeded(session.drag(Delta{Vec3(0.3, 0.8, -0.4)})));
  for (int i = 1; i < 4; ++i)
    EXPECT_NEAR((position(*chain.scene, chain.joints[i]) - position(*chain.scene, chain.joints[i - 1])).norm(), 1.0, 1e-12);
}

TEST(EphemeralInverse, grab_and_release_without_moving_changes_nothing) {
  Arm arm = make_arm();
  Session session(*arm.scene);
  session.set_mode(Mode::kInverse);
  const std::string before = io::write_scene(*arm.scene);
  const std::size_t steps = arm.scene->graph().undo_count();
  session.select({arm.c(2)});
  ASSERT_TRUE(succeeded(session.drag_to(arm.c(2), world(*arm.scene, arm.c(2)))));
  ASSERT_TRUE(succeeded(session.drag(Delta{Vec3(0, 0, 1e-17)})));
  EXPECT_EQ(arm.scene->graph().undo_count(), steps) << "nothing to write: no pop of the middle joint";
  session.release();
  EXPECT_EQ(io::write_scene(*arm.scene), before);
}

TEST(EphemeralInverse, two_bone_reaches_keeps_lengths_and_bend_plane) {
  Arm arm = make_arm();
  Session session(*arm.scene);
  session.set_mode(Mode::kInverse);
  session.select({arm.c(2)});
  // In the bend plane (z = 0): the elbow stays in it, on the same side.
  const Vec3 target(1.2, 1.0, 0.0);
  Mat4 goal = world(*arm.scene, arm.c(2));
  goal.topRightCorner<3, 1>() = target;
  ASSERT_TRUE(succeeded(session.drag_to(arm.c(2), goal)));
  const Vec3 s = position(*arm.scene, arm.shoulder), e = position(*arm.scene, arm.elbow),
             w = position(*arm.scene, arm.wrist);
  EXPECT_TRUE(vec_near(w, target, 1e-12));
  EXPECT_NEAR((e - s).norm(), 1.0, 1e-12);
  EXPECT_NEAR((w - e).norm(), 1.0, 1e-12);
  EXPECT_NEAR(e.z(), 0.0, 1e-12) << "the elbow stays in its bend plane";
  EXPECT_GT((e - s).cross(w - e).z(), 0.0) << "and bends the same way (positive about z)";
  // Hand-computed: |target| = sqrt(2.44); the elbow angle from the target
  // direction is acos(d / 2) toward the elbow's side (clockwise here).
  const double d = target.norm();
  const double alpha = std::acos(d / 2.0);
  const double base = std::atan2(target.y(), target.x());
  EXPECT_TRUE(vec_near(e, Vec3(std::cos(base - alpha), std::sin(base - alpha), 0), 1e-12));
  // Out of the plane: lengths still exact, target reached.
  const Vec3 t2(0.8, 0.6, 0.9);
  goal.topRightCorner<3, 1>() = t2;
  ASSERT_TRUE(succeeded(session.drag_to(arm.c(2), goal)));
  EXPECT_TRUE(vec_near(position(*arm.scene, arm.wrist), t2, 1e-12));
  EXPECT_NEAR((position(*arm.scene, arm.elbow) - s).norm(), 1.0, 1e-12);
  EXPECT_NEAR((position(*arm.scene, arm.wrist) - position(*arm.scene, arm.elbow)).norm(), 1.0, 1e-12);
  // Out of reach: the arm straightens toward the target.
  goal.topRightCorner<3, 1>() = Vec3(5, 0, 0);
  ASSERT_TRUE(succeeded(session.drag_to(arm.c(2), goal)));
  EXPECT_TRUE(vec_near(position(*arm.scene, arm.wrist), Vec3(2, 0, 0), 1e-9));
}

TEST(EphemeralInverse, fabrik_beyond_three_controls_keeps_lengths) {
  Chain chain = make_chain(5, 15);
  Session session(*chain.scene);
  session.set_mode(Mode::kInverse);
  session.select({chain.rig.controls[4]});
  const Vec3 target(2.0, 1.5, 0.5);
  ASSERT_TRUE(succeeded(session.drag(Delta{target - position(*chain.scene, chain.joints[4])})));
  EXPECT_TRUE(vec_near(position(*chain.scene, chain.joints[4]), target, 1e-8));
  EXPECT_TRUE(vec_near(position(*chain.scene, chain.joints[0]), Vec3::Zero(), 1e-15));
  for (int i = 1; i < 5; ++i)
    EXPECT_NEAR((position(*chain.scene, chain.joints[i]) - position(*chain.scene, chain.joints[i - 1])).norm(), 1.0, 1e-9);
}

TEST(EphemeralMagnet, each_hop_gets_65_percent_up_and_down) {
  Chain chain = make_chain(5);
  Session session(*chain.scene);
  session.set_mode(Mode::kMagnet);
  std::vector<Vec3> before;
  for (NodeId j : chain.joints) before.push_back(position(*chain.scene, j));
  session.select({chain.rig.controls[2]});
  const Vec3 d(0, 1, 0);
  ASSERT_TRUE(succeeded(session.drag(Delta{d})));
  const double share[] = {0.65 * 0.65, 0.65, 1.0, 0.65, 0.65 * 0.65};
  for (int i = 0; i < 5; ++i)
    EXPECT_TRUE(vec_near(position(*chain.scene, chain.joints[i]), before[i] + share[i] * d, 1e-12)) << "control " << i;
}

TEST(EphemeralMagnet, radius_variant_falls_off_with_distance) {
  Chain chain = make_chain(5);
  Session session(*chain.scene);
  SessionOptions o;
  o.magnet_radius = 2.5;
  session.set_options(o);
  session.set_mode(Mode::kMagnetRadius);
  session.select({chain.rig.controls[0]});
  const Vec3 d(0, 0, 1);
  ASSERT_TRUE(succeeded(session.drag(Delta{d})));
  auto falloff = [](double x) { return 1 - x * x * (3 - 2 * x); };
  for (int i = 0; i < 5; ++i) {
    const double w = i == 0 ? 1.0 : (i < 2.5 ? falloff(i / 2.5) : 0.0);
    EXPECT_TRUE(vec_near(position(*chain.scene, chain.joints[i]), Vec3(i, 0, 0) + w * d, 1e-12)) << "control " << i;
  }
}

TEST(EphemeralBody, rotates_the_character_about_the_pivot__scale_repositions_without_scaling) {
  Arm arm = make_arm();
  Session session(*arm.scene);
  session.set_mode(Mode::kBody);
  session.select({arm.c(1)});
  Mat4 pivot = Mat4::Identity();
  pivot.topRightCorner<3, 1>() = Vec3(1, 0, 0);
  session.set_body_pivot(pivot);
  const Vec3 wrist = position(*arm.scene, arm.wrist);
  ASSERT_TRUE(succeeded(session.drag(Delta{Vec3::Zero(), about_z(180)})));
  EXPECT_TRUE(vec_near(position(*arm.scene, arm.shoulder), Vec3(2, 0, 0), 1e-12));
  EXPECT_TRUE(vec_near(position(*arm.scene, arm.elbow), Vec3(1, 0, 0), 1e-12));
  EXPECT_TRUE(vec_near(position(*arm.scene, arm.wrist), Vec3(2 - wrist.x(), -wrist.y(), 0), 1e-12));
  Delta grow;
  grow.scale = Vec3::Constant(2.0);
  ASSERT_TRUE(succeeded(session.drag(grow)));
  EXPECT_TRUE(vec_near(position(*arm.scene, arm.shoulder), Vec3(3, 0, 0), 1e-12)) << "positions scale about the pivot";
  EXPECT_TRUE(vec_near(position(*arm.scene, arm.wrist), Vec3(1 + 2 * (1 - wrist.x()), -2 * wrist.y(), 0), 1e-12));
  for (int i = 0; i < 3; ++i)
    EXPECT_EQ(std::get<Vec3>(arm.scene->graph().node(arm.c(i))->value(xform::kScale)), Vec3::Ones())
        << "controls are not scaled";
  EXPECT_EQ(session.drag(grow).code(), ErrorCode::kOk);
  session.set_mode(Mode::kForward);
  EXPECT_EQ(session.drag(grow).code(), ErrorCode::kInvalidArgument) << "scale is body mode's";
}

// ---- several controls at once -------------------------------------------------

TEST(EphemeralMulti, forward_rotating_every_tail_control_curls_the_tail) {
  Chain tail = make_chain(4);
  Session session(*tail.scene);
  session.select(tail.rig.controls);
  ASSERT_TRUE(succeeded(session.drag(Delta{Vec3::Zero(), about_z(10)})));
  for (int i = 0; i < 4; ++i) {
    const Mat4 w = world(*tail.scene, tail.joints[i]);
    EXPECT_NEAR(std::atan2(w(1, 0), w(0, 0)), math::to_radians(10.0 * (i + 1)), 1e-12)
        << "each control adds its own turn to its parent's: control " << i;
    EXPECT_TRUE(vec_near(std::get<Vec3>(tail.scene->graph().node(tail.rig.controls[i])->value(xform::kRotate)),
                         Vec3(0, 0, 10), 1e-9));
  }
  // Translating them all moves the tail once, rigidly.
  std::vector<Vec3> before;
  for (NodeId j : tail.joints) before.push_back(position(*tail.scene, j));
  ASSERT_TRUE(succeeded(session.drag(Delta{Vec3(0, 0, 2)})));
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(vec_near(position(*tail.scene, tail.joints[i]), before[i] + Vec3(0, 0, 2), 1e-12));
}

TEST(EphemeralMulti, inverse_two_hands_each_reach_their_target) {
  auto s = make_scene();
  NodeId chest = joint(*s, "chest", {}, Vec3::Zero());
  NodeId head = joint(*s, "head", chest, Vec3(0, 1, 0));
  (void)head;
  std::vector<NodeId> hands;
  for (double side : {1.0, -1.0}) {
    NodeId sh = joint(*s, side > 0 ? "l_shoulder" : "r_shoulder", chest, Vec3(side * 0.5, 0.8, 0));
    NodeId el = joint(*s, side > 0 ? "l_elbow" : "r_elbow", sh, Vec3(side, 0, 0), Vec3(0, 20, 0));
    hands.push_back(joint(*s, side > 0 ? "l_hand" : "r_hand", el, Vec3(side, 0, 0)));
  }
  Result<SetupResult> r = setup_ephemeral(*s);
  ASSERT_TRUE(r.is_ok());
  auto control_of = [&](NodeId j) { return r->controls[std::find(r->joints.begin(), r->joints.end(), j) - r->joints.begin()]; };
  Session session(*s);
  session.set_mode(Mode::kInverse);
  session.select({control_of(hands[0]), control_of(hands[1])});
  const Vec3 d(0, -0.3, 0);  // both hands stay within reach (1.99 of 2)
  const Vec3 l = position(*s, hands[0]) + d, rr = position(*s, hands[1]) + d;
  const Mat4 chest_world = world(*s, chest);
  ASSERT_TRUE(succeeded(session.drag(Delta{d})));
  EXPECT_TRUE(vec_near(position(*s, hands[0]), l, 1e-12));
  EXPECT_TRUE(vec_near(position(*s, hands[1]), rr, 1e-12));
  EXPECT_TRUE(math::is_near(world(*s, chest), chest_world, 0)) << "the chest is a branch: the anchor, untouched";
  const Plan* plan = *session.plan();
  ASSERT_EQ(plan->chains.size(), 2u);
  EXPECT_EQ(plan->chains[0].entries.size(), 3u);
  EXPECT_EQ(plan->chains[0].anchor_control, control_of(chest));
}

TEST(EphemeralMulti, inverse_elbow_and_wrist_are_both_targets__neither_pushed) {
  Arm arm = make_arm();
  Session session(*arm.scene);
  session.set_mode(Mode::kInverse);
  session.select({arm.c(1), arm.c(2)});
  const Vec3 d(0, 0, 0.5);
  const Vec3 elbow = position(*arm.scene, arm.elbow), wrist = position(*arm.scene, arm.wrist);
  ASSERT_TRUE(succeeded(session.drag(Delta{d})));
  // The elbow chain (shoulder -> elbow) aims the shoulder: the elbow lands
  // on the shoulder-length sphere toward its target. The wrist's chain
  // starts at the elbow (the grabbed control above is its top): the elbow
  // turns to aim at the wrist's own target (wrist + d, not pushed by the
  // elbow's motion), and the wrist lands on its bone's sphere toward it.
  const Vec3 e = position(*arm.scene, arm.elbow);
  EXPECT_NEAR(e.norm(), 1.0, 1e-12);
  EXPECT_TRUE(vec_near(e, (elbow + d).normalized(), 1e-12));
  const Vec3 w = position(*arm.scene, arm.wrist);
  EXPECT_NEAR((w - e).norm(), (wrist - elbow).norm(), 1e-12) << "the forearm keeps its length";
  EXPECT_TRUE(vec_near((w - e).normalized(), (wrist + d - e).normalized(), 1e-12)) << "toward the wrist's own target";
  EXPECT_EQ(session.notes().size(), 2u) << "neither target is within reach of its one bone";
}

TEST(EphemeralMulti, magnet_two_sources_nearest_wins) {
  Chain chain = make_chain(7);
  Session session(*chain.scene);
  session.set_mode(Mode::kMagnet);
  session.select({chain.rig.controls[1], chain.rig.controls[5]});
  const Vec3 d(0, 1, 0);
  ASSERT_TRUE(succeeded(session.drag(Delta{d})));
  const double f = 0.65;
  const double share[] = {f, 1, f, f * f, f, 1, f};
  for (int i = 0; i < 7; ++i)
    EXPECT_TRUE(vec_near(position(*chain.scene, chain.joints[i]), Vec3(i, 0, 0) + share[i] * d, 1e-12)) << "control " << i;
}

TEST(EphemeralRelationsInSession, pair_groups_move_as_one_and_removed_forward_relations_stop_fk) {
  Chain chain = make_chain(3);
  Graph& g = chain.scene->graph();
  const auto& c = chain.rig.controls;
  // Remove forward 1 -> 2: rotating 1 in forward mode leaves 2 where it is.
  ASSERT_TRUE(succeeded(relation_remove(g, chain.rig.rig, Relation{RelationKind::kForward, c[1], c[2]})));
  Session session(*chain.scene);
  session.select({c[1]});
  const Mat4 w2 = world(*chain.scene, chain.joints[2]);
  ASSERT_TRUE(succeeded(session.drag(Delta{Vec3::Zero(), about_z(45)})));
  EXPECT_TRUE(math::is_near(world(*chain.scene, chain.joints[2]), w2, 1e-12));
  // Group 0 and 2: suspended drag of 0 moves 2 with it.
  ASSERT_TRUE(succeeded(group_add(g, chain.rig.rig, {c[0], c[2]})));
  session.set_mode(Mode::kSuspended);
  session.select({c[0]});
  const Vec3 p2 = position(*chain.scene, chain.joints[2]);
  ASSERT_TRUE(succeeded(session.drag(Delta{Vec3(0, 0, 1)})));
  EXPECT_TRUE(vec_near(position(*chain.scene, chain.joints[2]), p2 + Vec3(0, 0, 1), 1e-12));
}

TEST(EphemeralSession, keyed_control_refuses_the_drag_writing_nothing) {
  Arm arm = make_arm();
  Graph& g = arm.scene->graph();
  Result<NodeId> src = arm.scene->create(scene::kLocatorType, "key");
  ASSERT_TRUE(src.is_ok());
  ASSERT_TRUE(succeeded(g.connect(Plug{*src, xform::kRotate, -1}, Plug{arm.c(0), xform::kRotate, -1})));
  Session session(*arm.scene);
  session.set_mode(Mode::kInverse);
  session.select({arm.c(2)});
  const std::string before = io::write_scene(*arm.scene);
  EXPECT_FALSE(session.drag(Delta{Vec3(0, 0.3, 0)}).is_ok());
  EXPECT_EQ(io::write_scene(*arm.scene), before);
}

}  // namespace
}  // namespace rigel::ephemeral::testing
