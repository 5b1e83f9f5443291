// Keys on controls, keying groups (scope), auto-key, editing on a keyed
// frame, and merged characters with a carrier (keying.h).
#include <gtest/gtest.h>

#include <filesystem>

#include "ephemeral_test_util.h"
#include "rigel/ephemeral/keying.h"
#include "rigel/io/gltf_import.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/ops/anim/nodes.h"

namespace rigel::ephemeral {
namespace {

using namespace testing;  // NOLINT
using graph::Graph;

constexpr double kFps = 24.0;

std::size_t curve_count(const Graph& g) {
  std::size_t n = 0;
  for (NodeId id : g.nodes()) {
    const std::string& t = g.node(id)->type().name();
    if (t == ops::anim::kAnimCurveType || t == ops::anim::kAnimCurveVec3Type || t == ops::anim::kAnimCurveQuatType) ++n;
  }
  return n;
}

TEST(EphemeralKeys, character_scope_keys_the_whole_pose__one_undo_step) {
  Arm arm = make_arm();
  Graph& g = arm.scene->graph();
  const std::string before = io::write_scene(*arm.scene);
  EXPECT_EQ(key_scope(g, arm.rig.rig), KeyScope::kCharacter) << "the keying group is the default";
  EXPECT_FALSE(is_keyed(g, arm.c(2)));
  const std::size_t steps = g.undo_count();
  ASSERT_TRUE(succeeded(set_key(g, {arm.c(2)})));
  EXPECT_EQ(g.undo_count(), steps + 1);
  EXPECT_EQ(curve_count(g), 18u) << "three controls x (translate + rotate) x 3 components";
  for (int i = 0; i < 3; ++i) {
    EXPECT_TRUE(is_keyed(g, arm.c(i)));
    EXPECT_TRUE(has_key_now(g, arm.c(i)));
  }
  EXPECT_TRUE(has_key_now(g, arm.elbow)) << "a joint stands for its control";
  arm.scene->set_frame(10);
  EXPECT_FALSE(has_key_now(g, arm.c(0)));
  ASSERT_TRUE(succeeded(set_key(g, {arm.c(0)})));
  const std::vector<double> times = key_times(g, {arm.c(1)});
  ASSERT_EQ(times.size(), 2u);
  EXPECT_DOUBLE_EQ(times[0], 0.0);
  EXPECT_NEAR(times[1], 10 / kFps, 1e-12);
  ASSERT_TRUE(g.undo());
  ASSERT_TRUE(g.undo());
  arm.scene->set_frame(0);
  EXPECT_EQ(io::write_scene(*arm.scene), before) << "undo of both keys restores the scene exactly";
}

TEST(EphemeralKeys, controls_scope_keys_only_what_is_named) {
  Arm arm = make_arm();
  Graph& g = arm.scene->graph();
  ASSERT_TRUE(succeeded(set_key_scope(g, arm.rig.rig, KeyScope::kControls)));
  EXPECT_EQ(key_scope(g, arm.rig.rig), KeyScope::kControls);
  EXPECT_EQ(keying_set(g, {arm.c(2)}), std::vector<NodeId>{arm.c(2)});
  ASSERT_TRUE(succeeded(set_key(g, {arm.c(2)})));
  EXPECT_TRUE(is_keyed(g, arm.c(2)));
  EXPECT_FALSE(is_keyed(g, arm.c(0)));
  EXPECT_EQ(curve_count(g), 6u);
  EXPECT_EQ(std::string(key_scope_name(KeyScope::kControls)), "controls");
  EXPECT_EQ(key_scope_from_name("character"), KeyScope::kCharacter);
  EXPECT_FALSE(key_scope_from_name("bogus"));
}

TEST(EphemeralKeys, editing_on_a_keyed_frame_updates_the_pose__off_a_key_needs_auto_key) {
  Arm arm = make_arm();
  Graph& g = arm.scene->graph();
  const Vec3 rest_wrist = position(*arm.scene, arm.wrist);
  ASSERT_TRUE(succeeded(set_key(g, {arm.c(0)})));
  arm.scene->set_frame(10);
  ASSERT_TRUE(succeeded(set_key(g, {arm.c(0)})));

  Session session(*arm.scene);
  session.set_mode(Mode::kInverse);
  session.select({arm.c(2)});
  const Vec3 target = rest_wrist + Vec3(-0.3, 0.4, 0);
  ASSERT_TRUE(succeeded(session.drag(Delta{target - rest_wrist})));
  EXPECT_TRUE(vec_near(position(*arm.scene, arm.wrist), target, 1e-9)) << "the key at frame 10 took the pose";
  EXPECT_EQ(curve_count(g), 18u) << "no new curve";
  session.release();

  arm.scene->set_frame(0);
  EXPECT_TRUE(vec_near(position(*arm.scene, arm.wrist), rest_wrist, 1e-9)) << "frame 0 keeps its pose";
  arm.scene->set_frame(5);
  const Vec3 mid = position(*arm.scene, arm.wrist);
  EXPECT_FALSE(vec_near(mid, rest_wrist, 1e-3)) << "in between, the curves interpolate";

  // Off a key without auto-key: refused, naming the channel and the frame.
  session.select({arm.c(2)});
  const std::string before = io::write_scene(*arm.scene);
  Status refused = session.drag(Delta{Vec3(0.1, 0, 0)});
  ASSERT_FALSE(refused.is_ok());
  EXPECT_NE(refused.message().find("frame 5"), std::string::npos) << refused.message();
  EXPECT_NE(refused.message().find("auto-key"), std::string::npos) << refused.message();
  EXPECT_EQ(io::write_scene(*arm.scene), before) << "nothing written";

  // Auto-key: the keying group gets a key at frame 5, the drag lands in it.
  SessionOptions o;
  o.auto_key = true;
  session.set_options(o);
  const std::size_t steps = g.undo_count();
  ASSERT_TRUE(succeeded(session.drag(Delta{Vec3(0.05, 0, 0)})));
  ASSERT_TRUE(succeeded(session.drag(Delta{Vec3(0.05, 0, 0)})));
  EXPECT_EQ(g.undo_count(), steps + 1) << "the keys and every drag of the grab are one undo step";
  EXPECT_TRUE(vec_near(position(*arm.scene, arm.wrist), mid + Vec3(0.1, 0, 0), 1e-9));
  EXPECT_EQ(key_times(g, {arm.c(1)}).size(), 3u) << "every control of the character keyed at frame 5";
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(has_key_now(g, arm.c(i)));
  ASSERT_TRUE(g.undo());
  EXPECT_EQ(io::write_scene(*arm.scene), before);
}

TEST(EphemeralKeys, delete_key_removes_the_pose_and_empty_curves) {
  Arm arm = make_arm();
  Graph& g = arm.scene->graph();
  ASSERT_TRUE(succeeded(set_key(g, {arm.c(0)})));
  arm.scene->set_frame(10);
  ASSERT_TRUE(succeeded(set_key(g, {arm.c(0)})));
  EXPECT_EQ(delete_key(g, {arm.c(0)}).is_ok(), true);
  EXPECT_EQ(key_times(g, {arm.c(0)}).size(), 1u);
  arm.scene->set_frame(7);
  EXPECT_EQ(delete_key(g, {arm.c(0)}).code(), ErrorCode::kNotFound) << "no key at frame 7";
  arm.scene->set_frame(0);
  const Vec3 wrist = position(*arm.scene, arm.wrist);
  ASSERT_TRUE(succeeded(delete_key(g, {arm.c(0)})));
  EXPECT_EQ(curve_count(g), 0u) << "curves left without keys are deleted";
  EXPECT_FALSE(is_keyed(g, arm.c(1)));
  EXPECT_TRUE(vec_near(position(*arm.scene, arm.wrist), wrist, 1e-12)) << "the channels keep the pose";
}

TEST(EphemeralKeys, a_constraint_driven_channel_cannot_be_keyed) {
  Arm arm = make_arm();
  Graph& g = arm.scene->graph();
  Result<NodeId> src = arm.scene->create(scene::kLocatorType, "driver");
  ASSERT_TRUE(src.is_ok());
  ASSERT_TRUE(succeeded(g.connect(Plug{*src, xform::kRotate, -1}, Plug{arm.c(0), xform::kRotate, -1})));
  const std::string before = io::write_scene(*arm.scene);
  Status s = set_key(g, {arm.c(1)});
  ASSERT_FALSE(s.is_ok());
  EXPECT_NE(s.message().find("shoulder_ctrl.rotate"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("driver.rotate"), std::string::npos) << s.message();
  EXPECT_EQ(io::write_scene(*arm.scene), before) << "nothing keyed";
}

// An imported glTF character whose animation (tracks, in clips) moved onto
// its controls: a drag on a key time edits that key of the active clip.
TEST(EphemeralKeys, imported_tracks_are_edited_on_their_key_times) {
  io::GltfImportOptions options;
  options.registry = default_registry();
  auto loaded = io::import_gltf(std::filesystem::path(RIGEL_SOURCE_DIR) / "tests/data/gltf/RiggedSimple.glb", options);
  ASSERT_TRUE(loaded.is_ok()) << loaded.status().message();
  scene::Scene& s = **loaded;
  Graph& g = s.graph();
  Result<SetupResult> rig = setup_ephemeral(s);
  ASSERT_TRUE(rig.is_ok()) << rig.status().message();
  // The last joint with keys.
  NodeId keyed;
  for (NodeId c : rig->controls)
    if (is_keyed(g, c)) keyed = c;
  ASSERT_TRUE(keyed.is_valid()) << "RiggedSimple is animated";
  const std::vector<double> times = key_times(g, {keyed});
  ASSERT_GE(times.size(), 3u);
  g.set_time(times[1]);
  ASSERT_TRUE(has_key_now(g, keyed));
  Session session(s);
  session.set_mode(Mode::kForward);
  session.select({keyed});
  const Mat4 before = s.world_matrix(keyed);
  ASSERT_TRUE(succeeded(session.drag(Delta{Vec3::Zero(), Quat(Eigen::AngleAxisd(0.3, Vec3::UnitX()))})));
  const Mat4 after = s.world_matrix(keyed);
  EXPECT_FALSE(math::is_near(before, after, 1e-6)) << "the pose at the key changed";
  EXPECT_EQ(key_times(g, {keyed}).size(), times.size()) << "no key added";
  session.release();
  g.set_time(times[2]);
  g.set_time(times[1]);
  EXPECT_TRUE(math::is_near(s.world_matrix(keyed), after, 1e-9)) << "the key holds the edit";
  g.set_time(0.5 * (times[1] + times[2]));
  session.select({keyed});
  EXPECT_FALSE(session.drag(Delta{Vec3(0.1, 0, 0)}).is_ok()) << "between keys, without auto-key";
}

// ---- merged characters -------------------------------------------------------

struct ArmAndProp {
  Arm arm;
  NodeId prop_joint, prop_rig, prop_ctrl;
};

ArmAndProp make_arm_and_prop() {
  ArmAndProp a;
  a.arm = make_arm();
  scene::Scene& s = *a.arm.scene;
  a.prop_joint = joint(s, "sword", {}, position(s, a.arm.wrist) + Vec3(0.2, 0, 0));
  SetupOptions o;
  o.joints = {a.prop_joint};
  o.rig_name = "swordRig";
  Result<SetupResult> r = setup_ephemeral(s, o);
  EXPECT_TRUE(r.is_ok()) << r.status().message();
  a.prop_rig = r->rig;
  a.prop_ctrl = r->controls[0];
  return a;
}

TEST(EphemeralMerge, a_carried_prop_follows_the_hand_in_forward_and_body__until_unmerged) {
  ArmAndProp a = make_arm_and_prop();
  scene::Scene& s = *a.arm.scene;
  Graph& g = s.graph();
  EXPECT_EQ(set_carrier(g, a.prop_rig, a.arm.c(2)).code(), ErrorCode::kInvalidArgument) << "merge first";
  ASSERT_TRUE(succeeded(merge_characters(g, {a.arm.rig.rig, a.prop_rig})));
  EXPECT_EQ(merged_rigs(g, a.prop_rig).size(), 2u);
  EXPECT_EQ(set_carrier(g, a.prop_rig, a.prop_ctrl).code(), ErrorCode::kInvalidArgument) << "not its own control";
  ASSERT_TRUE(succeeded(set_carrier(g, a.prop_rig, a.arm.c(2))));
  EXPECT_EQ(carrier_of(g, a.prop_rig), a.arm.c(2));
  EXPECT_EQ(set_carrier(g, a.arm.rig.rig, a.prop_ctrl).code(), ErrorCode::kCycle) << "the sword cannot carry its hand";

  const Mat4 relative = math::affine_inverse(world(s, a.arm.wrist)) * world(s, a.prop_joint);
  Session session(s);
  session.set_mode(Mode::kForward);
  session.select({a.arm.c(0)});
  ASSERT_TRUE(succeeded(session.drag(Delta{Vec3::Zero(), about_z(40)})));
  EXPECT_TRUE(math::is_near(math::affine_inverse(world(s, a.arm.wrist)) * world(s, a.prop_joint), relative, 1e-9))
      << "the sword stays in the hand";

  // Keying one arm control keys the merged prop too.
  ASSERT_TRUE(succeeded(set_key(g, {a.arm.c(1)})));
  EXPECT_TRUE(is_keyed(g, a.prop_ctrl));

  session.set_mode(Mode::kBody);
  session.select({a.arm.c(0)});
  const Vec3 sword = position(s, a.prop_joint);
  const Vec3 wrist = position(s, a.arm.wrist);
  ASSERT_TRUE(succeeded(session.drag(Delta{Vec3(0, 1, 0)})));
  EXPECT_TRUE(vec_near(position(s, a.prop_joint), sword + Vec3(0, 1, 0), 1e-9)) << "body mode moves merged characters";
  EXPECT_TRUE(vec_near(position(s, a.arm.wrist), wrist + Vec3(0, 1, 0), 1e-9));

  ASSERT_TRUE(succeeded(unmerge_character(g, a.prop_rig)));
  EXPECT_FALSE(carrier_of(g, a.prop_rig).is_valid());
  EXPECT_EQ(merged_rigs(g, a.arm.rig.rig).size(), 1u);
  session.set_mode(Mode::kForward);
  session.select({a.arm.c(0)});
  const Vec3 left = position(s, a.prop_joint);
  ASSERT_TRUE(succeeded(session.drag(Delta{Vec3::Zero(), about_z(-20)})));
  EXPECT_TRUE(vec_near(position(s, a.prop_joint), left, 1e-12)) << "unmerged: the sword stays where it was left";
}

TEST(EphemeralMerge, merge_edits_are_undoable_and_saved) {
  ArmAndProp a = make_arm_and_prop();
  scene::Scene& s = *a.arm.scene;
  Graph& g = s.graph();
  const std::string before = io::write_scene(s);
  ASSERT_TRUE(succeeded(merge_characters(g, {a.arm.rig.rig, a.prop_rig})));
  ASSERT_TRUE(succeeded(set_carrier(g, a.prop_rig, a.arm.c(2))));
  auto reloaded = io::parse_scene(io::write_scene(s), "merged", default_registry());
  ASSERT_TRUE(reloaded.is_ok()) << reloaded.status().message();
  Graph& g2 = (*reloaded)->graph();
  const NodeId prop2 = g2.find("swordRig");
  EXPECT_EQ(g2.node(carrier_of(g2, prop2))->name(), "wrist_ctrl") << "the carrier survives a file round trip";
  ASSERT_TRUE(g.undo());
  ASSERT_TRUE(g.undo());
  EXPECT_EQ(io::write_scene(s), before);
  EXPECT_EQ(merge_characters(g, {a.prop_rig}).code(), ErrorCode::kInvalidArgument);
}

// ---- key times a hair off a frame (glTF stores seconds as float) -------------

// The elbow's rotation keyed at `frames` (a distinct angle each).
void key_arm_at(Arm& arm, const std::vector<double>& frames) {
  Graph& g = arm.scene->graph();
  for (std::size_t i = 0; i < frames.size(); ++i) {
    g.set_time(frames[i] / g.fps());
    ASSERT_TRUE(succeeded(write_channel(g, arm.c(1), xform::kRotate, Vec3(0, 0, 30 + 10.0 * i), true)));
  }
}

// Key times of the curve on the elbow's rotateZ.
std::vector<double> elbow_rotate_z_times(const Graph& g, const Arm& arm) {
  for (const graph::Connection& c : g.node(arm.c(1))->inputs())
    if (c.dst.attr == xform::kRotate && c.dst.component == 2) return ops::anim::curve_key_times(g, c.src.node);
  return {};
}

TEST(EphemeralKeys, a_key_within_a_thousandth_of_a_frame_is_that_frames_key) {
  for (double fps : {24.0, 30.0, 1000.0}) {
    for (double off : {-7.9e-5, 7.9e-5, -9e-4, 9e-4}) {
      SCOPED_TRACE("fps " + std::to_string(fps) + ", key " + std::to_string(off) + " frames off");
      Arm arm = make_arm();
      Graph& g = arm.scene->graph();
      ASSERT_TRUE(succeeded(g.set_fps(fps)));
      key_arm_at(arm, {10, 38 + off, 50});
      const std::size_t curves = curve_count(g);
      g.set_time(38 / fps);
      EXPECT_TRUE(has_key_now(g, arm.c(1))) << "frame 38 has a key";
      EXPECT_EQ(key_times(g, {arm.c(1)}).size(), 3u);
      // Keying frame 38 updates that key (no second key a hair away).
      ASSERT_TRUE(succeeded(set_key(g, {arm.c(0)})));
      std::vector<double> times = key_times(g, {arm.c(1)});
      ASSERT_EQ(times.size(), 3u);
      const std::vector<double> elbow = elbow_rotate_z_times(g, arm);
      ASSERT_EQ(elbow.size(), 3u);
      EXPECT_DOUBLE_EQ(elbow[1], (38 + off) / fps) << "the key keeps its time";
      EXPECT_EQ(curve_count(g), curves + 15) << "the other channels got curves keyed at frame 38";
      // A drag at frame 38 edits the key, off-key refusal does not apply;
      // auto-key adds nothing.
      for (bool auto_key : {false, true}) {
        SessionOptions o;
        o.auto_key = auto_key;
        Session session(*arm.scene, o);
        session.select({arm.c(1)});
        ASSERT_TRUE(succeeded(session.drag(Delta{Vec3::Zero(), about_z(5)})));
        session.release();
        EXPECT_EQ(key_times(g, {arm.c(1)}).size(), 3u);
        EXPECT_EQ(elbow_rotate_z_times(g, arm).size(), 3u);
      }
      // Deleting the key at frame 38 removes that key.
      ASSERT_TRUE(succeeded(delete_key(g, {arm.c(1)})));
      times = key_times(g, {arm.c(1)});
      ASSERT_EQ(times.size(), 2u);
      EXPECT_NEAR(times[0] * fps, 10, 1e-9);
      EXPECT_NEAR(times[1] * fps, 50, 1e-9);
    }
  }
}

TEST(EphemeralKeys, a_key_two_thousandths_of_a_frame_away_is_not_that_frames_key) {
  Arm arm = make_arm();
  Graph& g = arm.scene->graph();
  key_arm_at(arm, {10, 38.002});
  g.set_time(38 / g.fps());
  EXPECT_FALSE(has_key_now(g, arm.c(1)));
  Session session(*arm.scene);
  session.select({arm.c(1)});
  const Status s = session.drag(Delta{Vec3::Zero(), about_z(5)});
  EXPECT_FALSE(s.is_ok());
  EXPECT_NE(s.message().find("has no key"), std::string::npos) << s.message();
  EXPECT_EQ(key_time_tolerance(g), kKeyFrameTolerance / g.fps());
}

TEST(EphemeralKeys, the_imported_cesium_man_keys_sit_on_their_frames) {
  io::GltfImportOptions options;
  options.registry = default_registry();
  auto loaded = io::import_gltf(std::filesystem::path(RIGEL_SOURCE_DIR) / "tests" / "data" / "gltf" / "CesiumMan.glb", options);
  ASSERT_TRUE(loaded.is_ok()) << loaded.status().message();
  scene::Scene& s = **loaded;
  Result<SetupResult> r = setup_ephemeral(s);
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  Graph& g = s.graph();
  // Every key time of the clip is within the tolerance of a whole frame,
  // and at each of those frames every keyed control has its key.
  const std::vector<double> times = key_times(g, r->controls);
  ASSERT_GT(times.size(), 10u);
  std::size_t off_frame = 0;
  for (double t : times) {
    const double f = t * g.fps();
    off_frame += std::abs(f - std::round(f)) > 1e-6;
    ASSERT_LE(std::abs(f - std::round(f)), kKeyFrameTolerance) << "key at frame " << f;
  }
  EXPECT_GT(off_frame, 0u) << "the file's float times sit a hair off their frames";
  s.set_frame(38);
  for (NodeId c : r->controls)
    if (is_keyed(g, c)) {
      EXPECT_TRUE(has_key_now(g, c)) << g.node(c)->name();
    }
  SessionOptions o;
  o.auto_key = true;
  Session session(s, o);
  session.select({r->controls[3]});
  ASSERT_TRUE(succeeded(session.drag(Delta{Vec3::Zero(), about_z(5)})));
  EXPECT_EQ(key_times(g, r->controls).size(), times.size()) << "auto-key found the key at frame 38";
}

}  // namespace
}  // namespace rigel::ephemeral
