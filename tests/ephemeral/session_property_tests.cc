// Random sequences of selections, mode switches and drags on random
// skeletons and a real character: controls outside the plan do not move,
// bone lengths hold in forward, inverse and body modes, undo restores every
// value exactly, and nothing temporary is ever left in the scene.
#include <gtest/gtest.h>

#include <random>

#include "ephemeral_test_util.h"
#include "rigel/ephemeral/keying.h"
#include "rigel/io/gltf_import.h"
#include "rigel/ops/anim/nodes.h"

namespace rigel::ephemeral::testing {
namespace {

namespace fs = std::filesystem;

struct Rig {
  std::unique_ptr<scene::Scene> scene;
  SetupResult rig;
};

Rig random_rig(std::mt19937& rng, int joints) {
  Rig r;
  r.scene = make_scene();
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<NodeId> made;
  for (int i = 0; i < joints; ++i) {
    NodeId parent = made.empty() ? NodeId{} : made[std::uniform_int_distribution<int>(0, static_cast<int>(made.size()) - 1)(rng)];
    if (made.size() > 2 && u(rng) < 0.2) parent = made.back();
    Vec3 t(u(rng), u(rng), u(rng));
    t = t.normalized() * (0.5 + 0.5 * (u(rng) + 1));
    NodeId j = joint(*r.scene, std::string("j").append(std::to_string(i)), parent, t, Vec3(40 * u(rng), 40 * u(rng), 40 * u(rng)));
    Graph& g = r.scene->graph();
    EXPECT_TRUE(succeeded(g.set_value(Plug{j, xform::kRotateOrder, -1}, std::int64_t{i % 6})));
    if (i % 4 == 3) {
      EXPECT_TRUE(succeeded(g.set_value(Plug{j, xform::kRotateMode, -1}, std::int64_t{1})));
      EXPECT_TRUE(succeeded(g.set_value(Plug{j, xform::kRotateQuaternion, -1},
                                        Quat(Eigen::AngleAxisd(u(rng), Vec3(u(rng), u(rng), 1).normalized())))));
    }
    made.push_back(j);
  }
  Result<SetupResult> s = setup_ephemeral(*r.scene);
  EXPECT_TRUE(s.is_ok()) << s.status().message();
  r.rig = *s;
  return r;
}

Rig import_character(const std::string& file) {
  Rig r;
  // Over the registry that knows ephemeralRig.
  io::GltfImportOptions options;
  options.registry = default_registry();
  auto loaded = io::import_gltf(fs::path(RIGEL_SOURCE_DIR) / "tests" / "data" / "gltf" / file, options);
  EXPECT_TRUE(loaded.is_ok()) << loaded.status().message();
  if (!loaded) return r;
  r.scene = std::move(*loaded);
  SetupOptions o;
  o.keep_animation = false;
  Result<SetupResult> s = setup_ephemeral(*r.scene, o);
  EXPECT_TRUE(s.is_ok()) << s.status().message();
  if (s) r.rig = *s;
  return r;
}

// Nodes and connections that are not animation curves (keys add curves;
// nothing else may appear).
bool is_curve(const Graph& g, NodeId id) {
  const std::string& t = g.node(id)->type().name();
  return t == ops::anim::kAnimCurveType || t == ops::anim::kAnimCurveVec3Type || t == ops::anim::kAnimCurveQuatType;
}
std::size_t non_curve_nodes(const Graph& g) {
  std::size_t n = 0;
  for (NodeId id : g.nodes()) n += is_curve(g, id) ? 0 : 1;
  return n;
}
std::size_t non_curve_connections(const Graph& g) {
  std::size_t n = 0;
  for (const graph::Connection& c : g.connections()) n += is_curve(g, c.src.node) ? 0 : 1;
  return n;
}

struct Snapshot {
  std::vector<Mat4> worlds;
};

Snapshot snapshot(Rig& r) {
  Snapshot s;
  for (NodeId c : r.rig.controls) s.worlds.push_back(r.scene->world_matrix(c));
  return s;
}

// Runs `steps` random actions and checks the invariants after each drag.
// `length_tolerance` is relative: a character whose parents carry
// non-uniform scale cannot take an exact world rotation as a local rotation
// (the solve projects onto the nearest one).
// With `keys`, some actions key the grabbed controls (keying groups) and
// the session auto-keys, so drags also write keys.
void run_sequence(Rig& r, std::uint32_t seed, int steps, double length_tolerance = 1e-9, bool keys = false) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  Graph& g = r.scene->graph();
  const std::size_t nodes = non_curve_nodes(g);
  const std::size_t connections = non_curve_connections(g);
  const int n = static_cast<int>(r.rig.controls.size());
  std::vector<int> parent_of(n, -1);
  for (int i = 0; i < n; ++i) {
    auto it = std::find(r.rig.controls.begin(), r.rig.controls.end(), g.parent(r.rig.controls[i]));
    if (it != r.rig.controls.end()) parent_of[i] = static_cast<int>(it - r.rig.controls.begin());
  }
  Session session(*r.scene);
  if (keys) {
    SessionOptions o;
    o.auto_key = true;
    session.set_options(o);
  }
  int drags = 0, keyed_drags = 0;
  std::string gesture_start;
  for (int step = 0; step < steps; ++step) {
    SCOPED_TRACE("seed " + std::to_string(seed) + " step " + std::to_string(step));
    const int action = std::uniform_int_distribution<int>(0, 9)(rng);
    if (action == 0 || session.grabbed().empty()) {
      std::vector<NodeId> sel;
      const int count = std::uniform_int_distribution<int>(1, 3)(rng);
      for (int k = 0; k < count; ++k) sel.push_back(r.rig.controls[std::uniform_int_distribution<int>(0, n - 1)(rng)]);
      session.select(sel);
      continue;
    }
    if (action == 1) {
      session.set_mode(static_cast<Mode>(std::uniform_int_distribution<int>(0, kModeCount - 1)(rng)));
      continue;
    }
    if (action == 2) {
      r.scene->set_frame(std::uniform_int_distribution<int>(0, 5)(rng));
      continue;
    }
    if (keys && action == 4) {
      ASSERT_TRUE(succeeded(set_key(g, session.grabbed())));
      for (NodeId c : keying_set(g, session.grabbed())) EXPECT_TRUE(has_key_now(g, c));
      continue;
    }
    Delta d;
    d.translate = Vec3(u(rng), u(rng), u(rng)) * 0.3;
    d.rotate = Quat(Eigen::AngleAxisd(0.5 * u(rng), Vec3(u(rng), u(rng), u(rng) + 2).normalized()));
    const Mode mode = session.mode();
    const Snapshot before = snapshot(r);
    // A gesture (all drags of one plan) is one undo step: remember the
    // scene as it was at the grab.
    if (!session.has_plan()) gesture_start = io::write_scene(*r.scene);
    const std::vector<NodeId> grabbed_controls = session.grabbed();
    const std::size_t grabbed = grabbed_controls.size();
    if (keys && !grabbed_controls.empty() && is_keyed(g, grabbed_controls[0])) ++keyed_drags;
    Status s = session.drag(d);
    ASSERT_TRUE(succeeded(s)) << mode_name(mode);
    ++drags;
    const Plan* plan = *session.plan();
    const Snapshot after = snapshot(r);
    for (int i = 0; i < n; ++i) {
      if (plan->entry_find(r.rig.controls[i])) continue;
      EXPECT_TRUE(math::is_near(after.worlds[i], before.worlds[i], 1e-9))
          << g.node(r.rig.controls[i])->name() << " is outside the plan and moved (" << mode_name(mode) << ")";
    }
    const bool rigid = mode == Mode::kForward || mode == Mode::kBody || (mode == Mode::kInverse && grabbed == 1);
    if (rigid) {
      for (int i = 0; i < n; ++i) {
        if (parent_of[i] < 0) continue;
        // Forward mode's grabbed controls translate relative to their
        // parents (FK translation is the animator's explicit stretch).
        if (mode == Mode::kForward &&
            std::find(grabbed_controls.begin(), grabbed_controls.end(), r.rig.controls[i]) != grabbed_controls.end())
          continue;
        const double l0 = (before.worlds[i].col(3) - before.worlds[parent_of[i]].col(3)).norm();
        const double l1 = (after.worlds[i].col(3) - after.worlds[parent_of[i]].col(3)).norm();
        EXPECT_NEAR(l1, l0, length_tolerance * std::max(1.0, l0)) << "bone " << g.node(r.rig.controls[i])->name() << " ("
                                                       << mode_name(mode) << ") grabbed " << [&] {
                                                         std::string names;
                                                         for (NodeId c : grabbed_controls) names += g.node(c)->name() + " ";
                                                         return names;
                                                       }();
      }
    }
    if (action == 3) {
      ASSERT_TRUE(g.undo());
      EXPECT_EQ(io::write_scene(*r.scene), gesture_start)
          << "undo restores every value of the grab exactly (" << mode_name(mode) << ")";
    }
    EXPECT_EQ(non_curve_nodes(g), nodes);
    EXPECT_EQ(non_curve_connections(g), connections);
  }
  EXPECT_GT(drags, steps / 3);
  if (keys) {
    EXPECT_GT(keyed_drags, 0) << "drags on keyed controls were exercised";
  }
  session.release();
  EXPECT_EQ(non_curve_nodes(g), nodes) << "nothing temporary remains";
  EXPECT_EQ(non_curve_connections(g), connections);
}

TEST(EphemeralProperty, random_skeletons_selections_modes_and_drags) {
  for (std::uint32_t seed = 1; seed <= 12; ++seed) {
    std::mt19937 rng(seed);
    Rig r = random_rig(rng, 14);
    run_sequence(r, seed, 60);
    if (HasFatalFailure()) return;
  }
}

TEST(EphemeralProperty, random_sequences_with_keys_and_auto_key) {
  for (std::uint32_t seed = 101; seed <= 106; ++seed) {
    std::mt19937 rng(seed);
    Rig r = random_rig(rng, 10);
    run_sequence(r, seed, 60, 1e-9, true);
    if (HasFatalFailure()) return;
  }
}

TEST(EphemeralCharacter, rigged_figure_setup_matches_joints_and_modes_hold_invariants) {
  Rig r = import_character("RiggedFigure.glb");
  ASSERT_TRUE(r.scene);
  ASSERT_GE(r.rig.controls.size(), 15u);
  for (std::size_t i = 0; i < r.rig.controls.size(); ++i)
    EXPECT_TRUE(math::is_near(r.scene->world_matrix(r.rig.controls[i]), r.scene->world_matrix(r.rig.joints[i]), 1e-9));
  run_sequence(r, 99, 80, 1e-6);  // its animated scales are floats a few 1e-8 from 1
}

TEST(EphemeralCharacter, rigged_figure_inverse_arm_reaches_and_keeps_lengths) {
  Rig r = import_character("RiggedFigure.glb");
  ASSERT_TRUE(r.scene);
  Graph& g = r.scene->graph();
  // The deepest control: the end of a limb.
  NodeId end;
  int depth = -1;
  for (NodeId c : r.rig.controls)
    if (r.scene->depth(c) > depth) depth = r.scene->depth(c), end = c;
  NodeId mid = g.parent(end), top = g.parent(mid);
  Session session(*r.scene);
  SessionOptions o;
  o.max_chain = 3;
  session.set_options(o);
  session.set_mode(Mode::kInverse);
  session.select({end});
  const std::string before = io::write_scene(*r.scene);
  ASSERT_TRUE(succeeded(session.drag_to(end, r.scene->world_matrix(end))));
  EXPECT_EQ(io::write_scene(*r.scene), before) << "grab and release without moving changes nothing";
  auto p = [&](NodeId id) { return Vec3(r.scene->world_matrix(id).topRightCorner<3, 1>()); };
  const double a = (p(mid) - p(top)).norm(), b = (p(end) - p(mid)).norm();
  const Vec3 target = p(top) + (p(end) - p(top)) * 0.8 + Vec3(0, 0, 0.1 * (a + b));
  Mat4 goal = r.scene->world_matrix(end);
  goal.topRightCorner<3, 1>() = target;
  ASSERT_TRUE(succeeded(session.drag_to(end, goal)));
  // 1e-6: the figure's animated scales are floats a few 1e-8 from 1, and a
  // world rotation under non-uniform parent scale is projected onto the
  // nearest local rotation.
  EXPECT_TRUE(vec_near(p(end), target, 1e-6 * (a + b)));
  EXPECT_NEAR((p(mid) - p(top)).norm(), a, 1e-6 * a);
  EXPECT_NEAR((p(end) - p(mid)).norm(), b, 1e-6 * b);
  const Plan* plan = *session.plan();
  ASSERT_EQ(plan->chains.size(), 1u);
  EXPECT_EQ(plan->chains[0].entries.size(), 3u);
}

// Body mode on the Rigify metarig, whose offset matrices are floats: every
// control turns by the pivot's rotation and is repositioned by its scale,
// and below the roots no rotation channel is rewritten (local rotations do
// not change, so drags of the plan keep their exact world cache).
TEST(EphemeralCharacter, rigify_body_scale_turns_and_repositions__local_rotations_untouched) {
  Rig r = import_character("rigify_human_metarig.glb");
  ASSERT_TRUE(r.scene);
  ASSERT_GE(r.rig.controls.size(), 150u);
  Graph& g = r.scene->graph();
  const NodeId grabbed = g.find("spine_ctrl");
  ASSERT_TRUE(grabbed.is_valid());
  const Mat4 pivot = r.scene->world_matrix(grabbed);
  std::vector<Mat4> before;
  std::vector<graph::Value> rotations, quaternions;
  for (NodeId c : r.rig.controls) {
    before.push_back(r.scene->world_matrix(c));
    rotations.push_back(g.node(c)->value(xform::kRotate));
    quaternions.push_back(g.node(c)->value(xform::kRotateQuaternion));
  }
  Session session(*r.scene);
  session.set_mode(Mode::kBody);
  session.select({grabbed});
  const Quat turn(Eigen::AngleAxisd(0.4, Vec3(0.2, 1, -0.3).normalized()));
  Delta d;
  d.rotate = turn;
  d.scale = Vec3(1.3, 0.8, 1.1);
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(succeeded(session.drag(i == 0 ? d : Delta{Vec3(0.01, 0, 0)})));
  const math::Mat3 rot = turn.toRotationMatrix();
  const math::Mat3 lp = pivot.topLeftCorner<3, 3>();
  const math::Mat3 m = rot * lp * d.scale.asDiagonal() * lp.inverse();
  const Vec3 o = pivot.topRightCorner<3, 1>();
  for (std::size_t i = 0; i < r.rig.controls.size(); ++i) {
    const NodeId c = r.rig.controls[i];
    const Mat4 w = r.scene->world_matrix(c);
    const Vec3 expected = o + Vec3(0.02, 0, 0) + m * (before[i].topRightCorner<3, 1>() - o);
    EXPECT_TRUE(vec_near(Vec3(w.topRightCorner<3, 1>()), expected, 1e-9)) << g.node(c)->name();
    const bool turned = w.topLeftCorner<3, 3>().isApprox(rot * before[i].topLeftCorner<3, 3>(), 1e-9);
    EXPECT_TRUE(turned) << g.node(c)->name();
    if (std::find(r.rig.controls.begin(), r.rig.controls.end(), g.parent(c)) != r.rig.controls.end()) {
      EXPECT_TRUE(graph::values_identical(g.node(c)->value(xform::kRotate), rotations[i])) << g.node(c)->name();
      EXPECT_TRUE(graph::values_identical(g.node(c)->value(xform::kRotateQuaternion), quaternions[i]))
          << g.node(c)->name();
    }
  }
}

}  // namespace
}  // namespace rigel::ephemeral::testing
