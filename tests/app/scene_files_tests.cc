// The app layer's scene-file operations (scene_files.h, rig_files.h)
// through the library, no driver: import, open, play a clip, export, bake
// and build a definition onto its character file.

#include "rigel/app/scene_files.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "rigel/app/rig_files.h"
#include "rigel/ephemeral/component.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/io/scene_file.h"
#include "rigel/ops/anim/clips.h"
#include "rigel/rig/manager.h"
#include "../io/io_test_util.h"

namespace rigel::app {
namespace {

using io::testing::TempDir;

fs::path source_path(const std::string& relative) { return fs::path(RIGEL_SOURCE_DIR) / relative; }

TEST(AppSceneFiles, import_character__counts_and_refuses_what_it_cannot_read) {
  auto glb = import_character(source_path("tests/data/gltf/CesiumMan.glb"));
  ASSERT_TRUE(glb.is_ok()) << glb.status().message();
  EXPECT_FALSE(glb->motion);
  EXPECT_EQ(glb->joints, 19u);
  EXPECT_EQ(glb->meshes, 1u);
  EXPECT_EQ(glb->clips, 1u);

  auto bvh = import_character(source_path("tests/data/bvh/cmu_131_01.bvh"), OpenOptions{0.0254, true});
  ASSERT_TRUE(bvh.is_ok()) << bvh.status().message();
  EXPECT_TRUE(bvh->motion);
  EXPECT_GT(bvh->joints, 20u);
  EXPECT_GT(bvh->frames, 100u);

  auto rigel_file = import_character(source_path("tests/data/scenes/two_joint_chain.rigel"));
  ASSERT_FALSE(rigel_file.is_ok());
  EXPECT_EQ(rigel_file.status().field(), "input");
  EXPECT_NE(rigel_file.status().message().find("unsupported file type '.rigel'"), std::string::npos);
  for (double scale : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    auto bad = import_character(source_path("tests/data/bvh/cmu_131_01.bvh"), OpenOptions{scale, false});
    ASSERT_FALSE(bad.is_ok()) << scale;
    EXPECT_EQ(bad.status().field(), "scale") << scale;
  }
}

TEST(AppSceneFiles, open_scene__imports_characters_and_reads_scene_files) {
  auto glb = open_scene(source_path("tests/data/gltf/rigify_human_metarig.glb"));
  ASSERT_TRUE(glb.is_ok()) << glb.status().message();
  EXPECT_TRUE(ephemeral::setup_ephemeral(**glb).is_ok()) << "over every node type of this build";
  auto file = open_scene(source_path("tests/data/scenes/two_joint_chain.rigel"));
  ASSERT_TRUE(file.is_ok()) << file.status().message();
  auto missing = open_scene(source_path("tests/data/scenes/no_such_file.rigel"));
  ASSERT_FALSE(missing.is_ok());
  EXPECT_NE(missing.status().message().find("no_such_file.rigel"), std::string::npos) << missing.status().message();
  EXPECT_TRUE(is_scene_file("a/b.RIGEL"));
  EXPECT_FALSE(is_scene_file("a/b.glb"));
  EXPECT_TRUE(is_importable("x.GLTF"));
}

TEST(AppSceneFiles, play_clip__by_name_or_index_and_the_active_one_by_default) {
  auto scene = open_scene(source_path("tests/data/scenes/two_clips.rigel"));
  ASSERT_TRUE(scene.is_ok()) << scene.status().message();
  auto active = play_clip(**scene, std::nullopt);
  ASSERT_TRUE(active.is_ok()) << active.status().message();
  EXPECT_EQ(active->value_or(""), "walk");
  auto jump = play_clip(**scene, std::string("jump"));
  ASSERT_TRUE(jump.is_ok()) << jump.status().message();
  EXPECT_EQ(jump->value_or(""), "jump");
  auto first = play_clip(**scene, std::string("0"));
  ASSERT_TRUE(first.is_ok());
  EXPECT_EQ(first->value_or(""), "walk");
  auto nope = play_clip(**scene, std::string("run"));
  ASSERT_FALSE(nope.is_ok());
  EXPECT_EQ(nope.status().field(), "clip");
  EXPECT_NE(nope.status().message().find("no clip 'run'"), std::string::npos) << nope.status().message();

  auto chain = open_scene(source_path("tests/data/scenes/two_joint_chain.rigel"));
  ASSERT_TRUE(chain.is_ok());
  auto none = play_clip(**chain, std::nullopt);
  ASSERT_TRUE(none.is_ok());
  EXPECT_FALSE(none->has_value());
  auto asked = play_clip(**chain, std::string("0"));
  ASSERT_FALSE(asked.is_ok());
  EXPECT_EQ(asked.status().field(), "clip");
}

TEST(AppSceneFiles, export_scene__writes_gltf_and_refuses_other_extensions) {
  TempDir dir;
  auto scene = open_scene(source_path("tests/data/gltf/CesiumMan.glb"));
  ASSERT_TRUE(scene.is_ok());
  io::GltfExportReport report;
  ASSERT_TRUE(export_scene(**scene, dir.path() / "man.glb", {}, &report).is_ok());
  EXPECT_TRUE(fs::exists(dir.path() / "man.glb"));
  EXPECT_EQ(report.skin_count, 1u);
  const Status obj = export_scene(**scene, dir.path() / "man.obj", {}, nullptr);
  ASSERT_FALSE(obj.is_ok());
  EXPECT_EQ(obj.field(), "output");
  EXPECT_FALSE(fs::exists(dir.path() / "man.obj"));
}

TEST(AppSceneFiles, bake_nodes__names_resolved_history_kept_or_cleared) {
  auto scene = open_scene(source_path("tests/data/gltf/CesiumMan.glb"));
  ASSERT_TRUE(scene.is_ok());
  auto unknown = bake_nodes(**scene, 0, 10, {"nobody"});
  ASSERT_FALSE(unknown.is_ok());
  EXPECT_EQ(unknown.status().field(), "nodes");
  EXPECT_NE(unknown.status().message().find("no node 'nobody'"), std::string::npos);
  int calls = 0;
  auto baked = bake_nodes(**scene, 0, 10, {}, [&](double) { ++calls; }, true);
  ASSERT_TRUE(baked.is_ok()) << baked.status().message();
  EXPECT_EQ(baked->frames, 11u);
  EXPECT_EQ(baked->nodes, 19u);
  EXPECT_GT(calls, 0);
  EXPECT_TRUE((*scene)->graph().can_undo());
  auto again = bake_nodes(**scene, 0, 4, {}, {}, false);
  ASSERT_TRUE(again.is_ok());
  EXPECT_FALSE((*scene)->graph().can_undo()) << "a one-shot bake drops its undo records";
}

TEST(AppRigFiles, build_rig_file__on_the_definitions_geometry_in_steps) {
  const fs::path path = source_path("examples/puppet.rig.xml");
  auto def = rig::read_definition(path);
  ASSERT_TRUE(def.is_ok()) << def.status().message();
  EXPECT_EQ(rig_character(*def, path), path.parent_path() / "../tests/data/gltf/rigify_human_metarig.glb");
  std::vector<int> seen;
  BuildFileOptions options;
  options.progress = [&](int step, int) { seen.push_back(step); };
  auto built = build_rig_file(*def, path, ephemeral::components(), options);
  ASSERT_TRUE(built.is_ok()) << built.status().message();
  EXPECT_EQ(built->rig, "puppet");
  EXPECT_EQ(built->steps, built->of);
  EXPECT_EQ(static_cast<int>(seen.size()), built->of);
  EXPECT_EQ(built->components.size(), 2u);
  EXPECT_GT(built->nodes, 160u);

  options.steps = 1;
  options.progress = {};
  auto partial = build_rig_file(*def, path, ephemeral::components(), options);
  ASSERT_TRUE(partial.is_ok());
  EXPECT_EQ(partial->steps, 1);
  options.steps = built->of + 1;
  auto too_many = build_rig_file(*def, path, ephemeral::components(), options);
  ASSERT_FALSE(too_many.is_ok());
  EXPECT_EQ(too_many.status().field(), "steps");
}

TEST(AppRigFiles, build_rig_file__lists_every_missing_guide_joint_and_wants_a_character) {
  const fs::path path = source_path("examples/biped.rig.xml");
  auto def = rig::read_definition(path);
  ASSERT_TRUE(def.is_ok()) << def.status().message();
  BuildFileOptions options;
  options.character = source_path("tests/data/gltf/CesiumMan.glb");  // other joint names
  std::vector<rig::Diagnostic> missing;
  auto built = build_rig_file(*def, path, ephemeral::components(), options, &missing);
  ASSERT_FALSE(built.is_ok());
  EXPECT_EQ(built.status().field(), "guides");
  EXPECT_GT(missing.size(), 1u);
  for (const rig::Diagnostic& d : missing) EXPECT_GT(d.where.line, 0) << d.str();

  rig::Definition bare = *def;
  bare.geometry.clear();
  auto nowhere = build_rig_file(bare, path, ephemeral::components());
  ASSERT_FALSE(nowhere.is_ok());
  EXPECT_EQ(nowhere.status().field(), "character");
}

TEST(AppSetupOptions, validate_names_the_option_at_fault) {
  ephemeral::SetupOptions ok;
  EXPECT_TRUE(ok.validate().is_ok());
  ephemeral::SetupOptions radius;
  radius.shape_radius = -1;
  EXPECT_EQ(radius.validate().field(), "shapeRadius");
  radius.shape_radius = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(radius.validate().field(), "shapeRadius");
  ephemeral::SetupOptions suffix;
  suffix.control_suffix = " c";
  EXPECT_EQ(suffix.validate().field(), "controlSuffix");
  ephemeral::SetupOptions name;
  name.rig_name = "my rig";
  EXPECT_EQ(name.validate().field(), "rigName");
  auto scene = open_scene(source_path("tests/data/gltf/rigify_human_metarig.glb"));
  ASSERT_TRUE(scene.is_ok());
  auto refused = ephemeral::setup_ephemeral(**scene, radius);
  ASSERT_FALSE(refused.is_ok());
  EXPECT_EQ(refused.status().field(), "shapeRadius");
  EXPECT_FALSE((*scene)->graph().can_undo()) << "nothing changed";
}

}  // namespace
}  // namespace rigel::app
