// The workspace's rigger actions: match position / rotation (align) of an
// ephemeral control through the session, of a built rig's control and of a
// locator by their channels, each one undo step with the selection kept;
// joints mirrored from an ephemeral control's joint; refusals naming the
// field.

#include <gtest/gtest.h>

#include <memory>

#include "rigel/app/workspace.h"
#include "rigel/ephemeral/component.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/io/gltf_import.h"
#include "rigel/math/transform.h"
#include "rigel/rig/meta.h"

namespace rigel::app {
namespace {

fs::path source_path(const std::string& relative) { return fs::path(RIGEL_SOURCE_DIR) / relative; }

std::unique_ptr<scene::Scene> character() {
  io::GltfImportOptions options;
  options.registry = ephemeral::default_registry();
  auto imported = io::import_gltf(source_path("tests/data/gltf/rigify_human_metarig.glb"), options);
  EXPECT_TRUE(imported.is_ok()) << imported.status().message();
  return std::move(*imported);
}

Vec3 at(Workspace& ws, NodeId n) { return ws.scene().world_matrix(n).block<3, 1>(0, 3); }
Quat turn(Workspace& ws, NodeId n) { return math::decompose(ws.scene().world_matrix(n)).rotation; }

TEST(WorkspaceRigging, an_ephemeral_hand_matches_a_locator_s_position_in_inverse_mode) {
  auto scene = character();
  ASSERT_TRUE(ephemeral::setup_ephemeral(*scene).is_ok());
  scene->graph().clear_history();
  Workspace ws(std::move(scene), {}, {}, ephemeral::components());
  const NodeId hand = ws.graph().find("hand.L_ctrl"), head = ws.graph().find("spine.006_ctrl");
  ASSERT_TRUE(hand.is_valid() && head.is_valid());
  auto loc = ws.create_locators({hand});
  ASSERT_TRUE(loc.is_ok()) << loc.status().message();
  const NodeId l = loc->front();
  ASSERT_TRUE(ws.graph().set_value({l, scene::xform::kTranslate}, graph::Value(Vec3(at(ws, hand) + Vec3(0.05, 0.08, 0.02)))).is_ok());
  const Vec3 before = at(ws, hand);
  ws.select({head});
  ws.set_mode(ephemeral::Mode::kInverse);
  const std::size_t steps = ws.graph().undo_count();
  auto moved = ws.align({hand}, l, true, false);
  ASSERT_TRUE(moved.is_ok()) << moved.status().message();
  EXPECT_EQ(*moved, std::vector<NodeId>{hand});
  EXPECT_LT((at(ws, hand) - at(ws, l)).norm(), 1e-6) << "the arm reaches the locator";
  EXPECT_EQ(ws.graph().undo_count(), steps + 1) << "one undo step";
  EXPECT_EQ(ws.graph().undo_label(), "match position");
  EXPECT_EQ(ws.selection(), std::vector<NodeId>{head}) << "the selection is kept";
  ASSERT_TRUE(ws.undo().is_ok());
  EXPECT_LT((at(ws, hand) - before).norm(), 1e-12);

  // Joints mirrored from an ephemeral control: its joint's chain.
  tools::MirrorJointsOptions update;
  update.update_existing = true;
  auto mirrored = ws.mirror_joints({ws.graph().find("f_index.01.L_ctrl")}, update);
  ASSERT_TRUE(mirrored.is_ok()) << mirrored.status().message();
  ASSERT_EQ(mirrored->updated.size(), 3u);
  EXPECT_EQ(ws.graph().node(mirrored->updated[0])->name(), "f_index.01.R");
  const math::Mat4 m = Vec3(-1, 1, 1).homogeneous().asDiagonal();
  for (const char* n : {"f_index.01", "f_index.03"}) {
    const math::Mat4 l = ws.scene().world_matrix(ws.graph().find(std::string(n) + ".L"));
    const math::Mat4 r = ws.scene().world_matrix(ws.graph().find(std::string(n) + ".R"));
    EXPECT_LT((r - m * l * m).cwiseAbs().maxCoeff(), 1e-9) << n << ": moved through its control";
  }
}

TEST(WorkspaceRigging, a_built_control_and_a_locator_match_position_and_rotation) {
  Workspace ws(character(), {}, {}, ephemeral::components());
  ASSERT_TRUE(ws.add_rig(source_path("examples/biped.rig.xml")).is_ok());
  ws.graph().clear_history();
  const NodeId ik = *rig::resolve_address(ws.graph(), "hero:arm_L/ik");
  const NodeId hip = *rig::resolve_address(ws.graph(), "hero:hip/main");
  auto loc = ws.create_locators({hip});
  ASSERT_TRUE(loc.is_ok());
  const NodeId l = loc->front();
  ASSERT_TRUE(ws.graph().set_value({l, scene::xform::kRotate}, graph::Value(Vec3(20, -30, 45))).is_ok());
  ASSERT_TRUE(ws.graph().set_value({l, scene::xform::kTranslate}, graph::Value(Vec3(0.3, 1.1, 0.2))).is_ok());
  const Quat before = turn(ws, ik);
  auto both = ws.align({ik}, l, true, true);
  ASSERT_TRUE(both.is_ok()) << both.status().message();
  EXPECT_LT((at(ws, ik) - at(ws, l)).norm(), 1e-9);
  EXPECT_LT(turn(ws, ik).angularDistance(turn(ws, l)), 1e-9);
  EXPECT_EQ(ws.graph().undo_label(), "match transform");
  ASSERT_TRUE(ws.undo().is_ok());
  // Rotation only: the position stays.
  const Vec3 place = at(ws, ik);
  ASSERT_TRUE(ws.align({ik}, l, false, true).is_ok());
  EXPECT_LT((at(ws, ik) - place).norm(), 1e-9);
  EXPECT_LT(turn(ws, ik).angularDistance(turn(ws, l)), 1e-9);
  EXPECT_GT(turn(ws, ik).angularDistance(before), 0.1);
  // The locator onto the control (a plain transform).
  ASSERT_TRUE(ws.align({l}, ik, true, false).is_ok());
  EXPECT_LT((at(ws, l) - at(ws, ik)).norm(), 1e-9);

  EXPECT_EQ(ws.align({ik}, ik, true, true).status().field(), "nodes") << "nothing besides the target";
  EXPECT_EQ(ws.align({ik}, l, false, false).status().field(), "match");
  EXPECT_EQ(ws.align({ik}, rig::find_rig(ws.graph(), "hero"), true, true).status().field(), "target");
  EXPECT_EQ(ws.create_locators({}).status().field(), "nodes");
  EXPECT_EQ(ws.mirror_joints({}).status().field(), "joints");
  EXPECT_EQ(ws.paste_control_look({}, {}).field(), "controls");
}

}  // namespace
}  // namespace rigel::app
