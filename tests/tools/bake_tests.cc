// Baking: a rig's motion on the bundled character becomes keys on the
// joints; the joints then move the same way without the rig.

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "rigel/ephemeral/component.h"
#include "rigel/ephemeral/keying.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/ephemeral/session.h"
#include "rigel/io/bvh.h"
#include "rigel/io/bvh_import.h"
#include "rigel/io/gltf_import.h"
#include "rigel/io/scene_file.h"
#include "rigel/math/rotation.h"
#include "rigel/math/transform.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/ops/anim/nodes.h"
#include "rigel/rig/build.h"
#include "rigel/rig/manager.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"
#include "rigel/tools/bake.h"

namespace rigel::tools {
namespace {

namespace fs = std::filesystem;
using graph::NodeId;

std::unique_ptr<scene::Scene> metarig() {
  io::GltfImportOptions options;
  options.registry = ephemeral::default_registry();
  auto imported = io::import_gltf(fs::path(RIGEL_SOURCE_DIR) / "tests/data/gltf/rigify_human_metarig.glb", options);
  EXPECT_TRUE(imported.is_ok()) << imported.status().message();
  return std::move(*imported);
}

std::vector<math::Mat4> worlds(scene::Scene& s, const std::vector<NodeId>& nodes, double frame) {
  s.set_frame(frame);
  std::vector<math::Mat4> out;
  for (NodeId n : nodes) out.push_back(s.world_matrix(n));
  return out;
}

double worst(const std::vector<math::Mat4>& a, const std::vector<math::Mat4>& b) {
  double d = 0;
  for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, (a[i] - b[i]).cwiseAbs().maxCoeff());
  return d;
}

// An FK arm built from a definition, keyed at 0 and 12: after baking the
// arm joints over 0..12 and removing the rig, the joints move as before.
TEST(Bake, FkArmSurvivesTheRigsRemoval) {
  auto s = metarig();
  graph::Graph& g = s->graph();
  const fs::path def = fs::temp_directory_path() / ("rigel_bake_arm_" + std::to_string(::getpid()) + ".rig.json");
  {
    std::ofstream out(def);
    out << R"({"rig": {"name": "arm", "version": "1.0", "components": [{
      "type": "fkChain", "name": "arm", "side": "L", "version": "1.0",
      "rigId": "7c2d4b9e-3f1a-4e6b-8d0c-5a9b2e1f3c02",
      "guides": [{"joint": "upper_arm.L"}, {"joint": "forearm.L"}, {"joint": "hand.L"}]}]}})";
  }
  auto added = rig::add_rig(*s, def, ephemeral::components());
  ASSERT_TRUE(added.is_ok()) << added.status().message();
  fs::remove(def);
  // Key the FK controls: a bend at 12.
  std::vector<NodeId> controls;
  for (NodeId id : g.nodes())
    if (g.node(id)->type().name() == scene::kControlType) controls.push_back(id);
  ASSERT_EQ(controls.size(), 3u);
  for (NodeId c : controls) {
    ASSERT_TRUE(ops::anim::write_channel_key(g, c, scene::xform::kRotate, graph::Value(math::Vec3(0, 0, 0)), 0.0, true).is_ok());
    ASSERT_TRUE(ops::anim::write_channel_key(g, c, scene::xform::kRotate, graph::Value(math::Vec3(10, 40, -25)), 0.5, true)
                    .is_ok());
  }
  const std::vector<NodeId> joints = {g.find("upper_arm.L"), g.find("forearm.L"), g.find("hand.L")};
  std::vector<std::vector<math::Mat4>> before;
  for (double f : {0.0, 3.0, 6.0, 12.0}) before.push_back(worlds(*s, joints, f));
  ASSERT_GT(worst(before[0], before[3]), 0.05);  // the arm does move

  BakeOptions o;
  o.first = 0;
  o.last = 12;
  o.nodes = joints;
  double last_progress = -1;
  o.progress = [&](double p) {
    EXPECT_GE(p, last_progress);
    last_progress = p;
  };
  auto r = bake(*s, o);
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  EXPECT_EQ(r->nodes, 3u);
  EXPECT_EQ(r->frames, 13u);
  EXPECT_EQ(r->keys, 3u * 13u * 4u);
  EXPECT_GT(r->disconnected, 0u);
  EXPECT_EQ(last_progress, 1.0);
  EXPECT_EQ(s->frame(), 12.0);  // the time is where it was
  {
    int k = 0;
    for (double f : {0.0, 3.0, 6.0, 12.0})
      EXPECT_LT(worst(before[static_cast<std::size_t>(k++)], worlds(*s, joints, f)), 1e-9) << "baked, rig still there: " << f;
  }

  auto build = rig::Build::reopen(*s, "arm", ephemeral::components());
  ASSERT_TRUE(build.is_ok());
  ASSERT_TRUE((*build)->remove().is_ok());
  int i = 0;
  for (double f : {0.0, 3.0, 6.0, 12.0}) EXPECT_LT(worst(before[static_cast<std::size_t>(i++)], worlds(*s, joints, f)), 1e-9) << f;
  // Undo of the removal and of the bake brings the rig's drive back.
  while (g.can_undo() && g.undo_label() != "bake") g.undo();
  ASSERT_TRUE(g.undo());
  for (NodeId j : joints) {
    auto src = g.source(graph::Plug{j, scene::xform::kRotate});
    ASSERT_TRUE(src.has_value());
    EXPECT_NE(g.node(src->node)->type().name().rfind("animCurve", 0), 0u);
  }
}

// The quadruped's spring tail (examples/quadruped.rig.xml), its root keyed
// to swing: baking the tail over 0..48 gives keys that play what the
// playback gave (a spring is stepped frame by frame, as a bake samples),
// with the rig removed too.
TEST(Bake, ASpringChainBakesWhatItPlays) {
  auto loaded = io::load_scene(fs::path(RIGEL_SOURCE_DIR) / "examples/quadruped.rigel", ephemeral::default_registry());
  ASSERT_TRUE(loaded.is_ok()) << loaded.status().message();
  scene::Scene& s = **loaded;
  graph::Graph& g = s.graph();
  auto added = rig::add_rig(s, fs::path(RIGEL_SOURCE_DIR) / "examples/quadruped.rig.xml", ephemeral::components());
  ASSERT_TRUE(added.is_ok()) << added.status().message();
  auto root = rig::resolve_address(g, "horse:tail/fk[0]");
  ASSERT_TRUE(root.is_ok());
  for (const auto& [frame, angle] : {std::pair{0.0, 0.0}, std::pair{10.0, 35.0}, std::pair{20.0, -20.0}})
    ASSERT_TRUE(ops::anim::write_channel_key(g, *root, scene::xform::kRotate, graph::Value(math::Vec3(angle, angle, 0)),
                                             frame / g.fps(), true)
                    .is_ok());
  const std::vector<NodeId> tail = {g.find("tail"), g.find("tail.001"), g.find("tail.002"), g.find("tail.003")};
  std::vector<std::vector<math::Mat4>> played;
  for (int f = 0; f <= 48; ++f) played.push_back(worlds(s, tail, f));
  BakeOptions o;
  o.first = 0;
  o.last = 48;
  o.nodes = tail;
  ASSERT_TRUE(bake(s, o).is_ok());
  for (int f = 0; f <= 48; ++f)
    EXPECT_LT(worst(played[static_cast<std::size_t>(f)], worlds(s, tail, f)), 1e-9) << "baked, frame " << f;
  auto build = rig::Build::reopen(s, "horse", ephemeral::components());
  ASSERT_TRUE(build.is_ok());
  ASSERT_TRUE((*build)->remove().is_ok());
  for (int f = 48; f >= 0; f -= 6)
    EXPECT_LT(worst(played[static_cast<std::size_t>(f)], worlds(s, tail, f)), 1e-9) << "rig removed, frame " << f;
}

// Every joint of an ephemeral rig posed by inverse-mode drags on keys:
// baking the whole character keeps every joint where the rig put it, and
// the controls no longer move the joints.
TEST(Bake, EphemeralCharacterKeepsItsPose) {
  auto s = metarig();
  graph::Graph& g = s->graph();
  auto rig = ephemeral::setup_ephemeral(*s);
  ASSERT_TRUE(rig.is_ok());
  ephemeral::Session session(*s);
  const NodeId hand = ephemeral::control_of(g, g.find("hand.L"));
  session.select({hand});
  ASSERT_TRUE(ephemeral::set_key(g, {hand}).is_ok());
  s->set_frame(8);
  ASSERT_TRUE(ephemeral::set_key(g, {hand}).is_ok());
  session.set_mode(ephemeral::Mode::kInverse);
  ephemeral::Delta d;
  d.translate = math::Vec3(0.05, 0.2, 0.1);
  ASSERT_TRUE(session.drag(d).is_ok());
  session.release();
  std::vector<NodeId> joints;
  for (NodeId id : s->hierarchy())
    if (g.node(id)->type().name() == scene::kJointType) joints.push_back(id);
  const auto at0 = worlds(*s, joints, 0), at4 = worlds(*s, joints, 4), at8 = worlds(*s, joints, 8);
  ASSERT_GT(worst(at0, at8), 0.05);

  BakeOptions o;
  o.first = 0;
  o.last = 8;
  auto r = bake(*s, o);  // every joint
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  EXPECT_EQ(r->nodes, 159u);
  EXPECT_LT(worst(at0, worlds(*s, joints, 0)), 1e-9);
  EXPECT_LT(worst(at4, worlds(*s, joints, 4)), 1e-9);
  EXPECT_LT(worst(at8, worlds(*s, joints, 8)), 1e-9);
  // The joints are on their own keys now: only curves drive their channels.
  std::size_t curves = 0;
  for (const graph::Connection& c : g.connections()) {
    if (g.node(c.dst.node)->type().name() != scene::kJointType) continue;
    if (c.dst.attr != scene::xform::kTranslate && c.dst.attr != scene::xform::kRotate &&
        c.dst.attr != scene::xform::kRotateQuaternion && c.dst.attr != scene::xform::kScale)
      continue;
    EXPECT_EQ(g.node(c.src.node)->type().name().rfind("animCurve", 0), 0u) << g.plug_name(c.dst);
    ++curves;
  }
  EXPECT_GE(curves, 159u * 4);
}

TEST(Bake, RefusesBadFramesAndNodes) {
  auto s = metarig();
  BakeOptions o;
  o.first = 5;
  o.last = 2;
  EXPECT_FALSE(bake(*s, o).is_ok());
  o.first = 0;
  o.last = std::nan("");
  EXPECT_FALSE(bake(*s, o).is_ok());
  o.last = 2;
  o.nodes = {s->graph().find("metarig_skin1_skinCluster")};
  auto r = bake(*s, o);
  ASSERT_FALSE(r.is_ok());
  EXPECT_NE(r.status().message().find("not a transform"), std::string::npos) << r.status().message();
  EXPECT_FALSE(s->graph().can_undo());
}

// The motion capture clip of the tests (38 joints, 994 frames at 120 fps).
std::unique_ptr<scene::Scene> mocap() {
  auto file = io::load_bvh((fs::path(RIGEL_SOURCE_DIR) / "tests/data/bvh/cmu_131_01.bvh").string());
  EXPECT_TRUE(file.is_ok()) << file.status().message();
  auto imported = io::import_bvh(*file);
  EXPECT_TRUE(imported.is_ok()) << imported.status().message();
  return std::move(*imported);
}

// The arrays a bake's edits record for undo: every set's old value (an
// observer sees it) and its new one (in the node), in elements.
struct RecordedSets : graph::Observer {
  std::size_t elements = 0, sets = 0;
  void attribute_set(const graph::Graph& g, const graph::Plug& p, const graph::Value& before) override {
    ++sets;
    for (const graph::Value* v : {&before, &g.node(p.node)->value(p.attr)}) {
      std::visit(
          [&](const auto& x) {
            if constexpr (requires { x.size(); }) elements += x.size();
          },
          *v);
    }
  }
};

// Memory grew with the square of the frames: each frame's key was a set of
// every key array of the curve (the whole array recorded before and after
// for undo), so 2N frames recorded 4 times what N did (5.5 GB at 750
// frames of this clip). Now each curve's arrays are set once: twice the
// frames, twice the recorded elements, the same number of sets.
TEST(Bake, UndoRecordsGrowLinearlyWithTheFrames) {
  auto recorded = [](double last) {
    auto s = mocap();
    RecordedSets r;
    s->graph().add_observer(&r);
    BakeOptions o;
    o.first = 0;
    o.last = last;
    auto report = bake(*s, o);
    s->graph().remove_observer(&r);
    EXPECT_TRUE(report.is_ok()) << report.status().message();
    if (report) {
      EXPECT_EQ(report->frames, static_cast<std::size_t>(last) + 1);
    }
    EXPECT_EQ(s->graph().undo_count(), 1u);
    return r;
  };
  const RecordedSets small = recorded(99), large = recorded(199);
  EXPECT_EQ(small.sets, large.sets);
  const double ratio = static_cast<double>(large.elements) / static_cast<double>(small.elements);
  EXPECT_GT(ratio, 1.9);
  EXPECT_LT(ratio, 2.1) << small.elements << " elements for 100 frames, " << large.elements << " for 200";
}

// The baked clip moves as the clip did, with the keys the frames asked for
// (a last frame between whole ones keyed at that frame, one a hair past a
// whole frame taken as that frame's key), and undo puts the clip's curves
// back.
TEST(Bake, MocapClipKeepsItsMotion) {
  auto s = mocap();
  graph::Graph& g = s->graph();
  std::vector<NodeId> joints;
  for (NodeId id : s->hierarchy())
    if (g.node(id)->type().name() == scene::kJointType) joints.push_back(id);
  ASSERT_EQ(joints.size(), 38u);
  const std::vector<double> frames = {0, 1, 17, 40, 40.5};
  std::vector<std::vector<math::Mat4>> before;
  for (double f : frames) before.push_back(worlds(*s, joints, f));
  BakeOptions o;
  o.first = 0;
  o.last = 40.5;
  auto r = bake(*s, o);
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  EXPECT_EQ(r->frames, 42u);
  EXPECT_EQ(r->keys, 38u * 42u * 4u);
  for (std::size_t i = 0; i < frames.size(); ++i)
    EXPECT_LT(worst(before[i], worlds(*s, joints, frames[i])), 1e-9) << "frame " << frames[i];
  const auto hips = g.source(graph::Plug{joints[0], scene::xform::kTranslate, -1, 0});
  ASSERT_TRUE(hips.has_value());
  const auto& times = std::get<std::vector<double>>(g.node(hips->node)->value(ops::anim::curve_attr::kKeyTimes));
  ASSERT_EQ(times.size(), 42u);
  EXPECT_DOUBLE_EQ(times.back() * g.fps(), 40.5);
  ASSERT_TRUE(g.undo());
  for (std::size_t i = 0; i < frames.size(); ++i)
    EXPECT_LT(worst(before[i], worlds(*s, joints, frames[i])), 1e-12) << "undone, frame " << frames[i];
  o.last = 3 + 1e-8;
  r = bake(*s, o);
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  EXPECT_EQ(r->frames, 4u);
}

}  // namespace
}  // namespace rigel::tools
