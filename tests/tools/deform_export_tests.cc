// The deform-only game export (io::GltfExportOptions::deform_only, seed
// 004's baker in skeleton mode) of a shot of the biped built on the
// bundled body: only the skin's joints and the mesh are written, the Khronos
// validator finds no error, and the file imported again puts every joint
// at the world matrix the rig gave it, at every frame.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "rigel/ephemeral/component.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/io/bvh.h"
#include "rigel/io/bvh_import.h"
#include "rigel/io/gltf_export.h"
#include "rigel/io/gltf_import.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/ops/deform/nodes.h"
#include "rigel/rig/manager.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"
#include "rigel/tools/match.h"
#include "../io/io_test_util.h"
#include "tools_test_util.h"

namespace rigel::tools {
namespace {

namespace fs = std::filesystem;
using graph::NodeId;
using graph::Plug;
using graph::Value;
using math::Mat4;
using math::Vec3;
namespace xform = scene::xform;


// The biped built on the bundled body (the metarig's 159 joints with a
// 10,037-vertex skinned body), with an animated shot: the left arm's FK,
// the right leg's IK and the spine keyed over 0..200.
std::unique_ptr<scene::Scene> shot() {
  auto s = testing::built_rig(testing::source("examples/biped.rig.xml"), testing::source("tests/data/gltf/rigify_human_body.glb"));
  graph::Graph& g = s->graph();
  auto key = [&](const std::string& address, graph::AttrIndex attr, double frame, const Vec3& v) {
    auto id = rig::resolve_address(g, address);
    ASSERT_TRUE(id.is_ok()) << address;
    ASSERT_TRUE(ops::anim::write_channel_key(g, *id, attr, Value(v), frame / g.fps(), true).is_ok()) << address;
  };
  key("hero:arm_L/fk[0]", xform::kRotate, 0, Vec3(0, 0, 0));
  key("hero:arm_L/fk[0]", xform::kRotate, 100, Vec3(40, -20, 30));
  key("hero:arm_L/fk[1]", xform::kRotate, 200, Vec3(0, 0, 60));
  key("hero:leg_R/ik", xform::kTranslate, 0, Vec3(0, 0, 0));
  key("hero:leg_R/ik", xform::kTranslate, 150, Vec3(0.05, 0.2, 0.25));
  key("hero:spine/fk[1]", xform::kRotate, 200, Vec3(10, 15, 0));
  return s;
}

// The transforms whose worldMatrix feeds a skinCluster.
std::set<std::string> skin_joints(const graph::Graph& g) {
  std::set<std::string> out;
  for (NodeId id : g.nodes())
    if (g.node(id)->type().name() == ops::kSkinClusterType)
      for (const graph::Connection& c : g.node(id)->inputs())
        if (c.dst.attr == ops::skin_cluster_attr::kJointMatrices) out.insert(g.node(c.src.node)->name());
  return out;
}

TEST(DeformExport, a_baked_shot_exports_the_skinned_skeleton_only_and_reimports_in_place) {
  auto s = shot();
  graph::Graph& g = s->graph();
  const std::set<std::string> deform = skin_joints(g);
  ASSERT_GT(deform.size(), 100u);
  io::testing::TempDir dir;
  const fs::path out = dir.path() / "game.glb";
  io::GltfExportOptions options;
  options.deform_only = true;
  options.frames = std::pair{0.0, 200.0};
  io::GltfExportReport report;
  const Status st = io::export_gltf(*s, out, options, &report);
  ASSERT_TRUE(st.is_ok()) << st.message();
  EXPECT_TRUE(report.baked);
  EXPECT_EQ(report.skin_count, 1u);
  EXPECT_VALID_GLTF(out);

  auto back = testing::import_character(out);
  ASSERT_TRUE(back);
  graph::Graph& b = back->graph();
  // Only the skin's joints and the mesh: no control, rig group or helper
  // (twist) joint.
  std::set<std::string> joints;
  for (NodeId id : back->hierarchy()) {
    const std::string& type = b.node(id)->type().name();
    EXPECT_NE(type, scene::kControlType) << b.node(id)->name();
    if (type == scene::kJointType) joints.insert(b.node(id)->name());
  }
  EXPECT_EQ(joints, deform);
  for (const std::string& name : joints) EXPECT_EQ(name.find("Twist"), std::string::npos) << name;
  // Every joint where the rig put it, at every 10th frame and the last.
  double worst = 0;
  std::string where;
  for (int f = 0; f <= 200; f += 10) {
    s->set_frame(f);
    back->set_frame(f);
    for (const std::string& name : joints) {
      const Mat4 want = s->world_matrix(g.find(name)), got = back->world_matrix(b.find(name));
      const double e = (got - want).cwiseAbs().maxCoeff() / std::max(1.0, want.cwiseAbs().maxCoeff());
      if (e > worst) {
        worst = e;
        where = name + " at frame " + std::to_string(f);
      }
    }
  }
  EXPECT_LT(worst, 1e-6) << where;
}

TEST(DeformExport, a_scene_without_skins_exports_its_joints_and_one_without_anything_is_refused) {
  io::testing::TempDir dir;
  auto file = io::load_bvh((fs::path(RIGEL_SOURCE_DIR) / "tests/data/bvh/cmu_131_01.bvh").string());
  ASSERT_TRUE(file.is_ok()) << file.status().message();
  auto bvh = io::import_bvh(*file);
  ASSERT_TRUE(bvh.is_ok()) << bvh.status().message();
  io::GltfExportOptions options;
  options.deform_only = true;
  options.frames = std::pair{0.0, 10.0};
  io::GltfExportReport report;
  ASSERT_TRUE(io::export_gltf(**bvh, dir.path() / "walk.glb", options, &report).is_ok());
  std::size_t joints = 0;
  for (NodeId id : (*bvh)->hierarchy()) joints += (*bvh)->graph().node(id)->type().name() == scene::kJointType;
  EXPECT_EQ(report.node_count, joints);
  EXPECT_VALID_GLTF(dir.path() / "walk.glb");

  scene::Scene empty;
  ASSERT_TRUE(empty.create(scene::kTransformType, "group").is_ok());
  const Status st = io::export_gltf(empty, dir.path() / "none.glb", options, &report);
  EXPECT_FALSE(st.is_ok());
  EXPECT_NE(st.message().find("deform-only"), std::string::npos) << st.message();
  EXPECT_FALSE(fs::exists(dir.path() / "none.glb"));
}

}  // namespace
}  // namespace rigel::tools
