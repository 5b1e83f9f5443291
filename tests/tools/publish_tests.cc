// Publishing (tools/publish.h): an asset with the biped's definition on the
// body, published twice: each version a new folder (never overwritten) with
// the built scene, a manifest of checksums and checks, and the log; hand
// edits exported as data (a control's shape, a painted weight, a sculpted
// blend shape target, a driven pose) come back in the rebuilt version
// exactly; a project of a character and a prop, each published twice with
// its hand edits; a scene from a version reports its asset's newer one; a
// broken definition publishes nothing.

#include "rigel/tools/publish.h"

#include <gtest/gtest.h>

#include <fstream>

#include <nlohmann/json.hpp>

#include "rigel/io/scene_file.h"
#include "rigel/ops/deform/nodes.h"
#include "rigel/rig/meta.h"
#include "rigel/tools/driven_poses.h"
#include "rigel/tools/blendshape_data.h"
#include "rigel/tools/shape_data.h"
#include "rigel/tools/skin_weights.h"
#include "../io/io_test_util.h"
#include "tools_test_util.h"

namespace rigel::tools {
namespace {

namespace fs = std::filesystem;
using io::testing::read_text;
using io::testing::write_text;

struct Published {
  io::testing::TempDir dir;
  Asset asset;
};

std::unique_ptr<Published> asset_with_biped() {
  auto p = std::make_unique<Published>();
  auto project = create_project(p->dir.path() / "show");
  EXPECT_TRUE(project.is_ok());
  auto a = create_asset(*project, "hero", "character", testing::source("tests/data/gltf/rigify_human_body.glb"));
  EXPECT_TRUE(a.is_ok()) << a.status().message();
  p->asset = *a;
  fs::copy_file(testing::source("examples/biped.rig.xml"), a->dir / "build" / "biped.rig.xml");
  return p;
}

std::unique_ptr<scene::Scene> load(const fs::path& file) {
  auto s = io::load_scene(file, ephemeral::default_registry());
  EXPECT_TRUE(s.is_ok()) << s.status().message();
  return s ? std::move(*s) : nullptr;
}

TEST(Publish, two_versions_with_hand_made_data_rebuilt_exactly) {
  auto p = asset_with_biped();
  auto v1 = publish_asset(p->asset, ephemeral::components(), {"", true, "test"});
  ASSERT_TRUE(v1.is_ok()) << v1.status().message();
  EXPECT_EQ(v1->version, 1);
  EXPECT_EQ(v1->dir, p->asset.dir / "rig" / "v001");
  EXPECT_LT(v1->rest_error, 1e-9);
  const auto manifest = nlohmann::json::parse(read_text(v1->manifest));
  EXPECT_EQ(manifest["version"], 1);
  EXPECT_EQ(manifest["definitions"][0]["file"], "build/biped.rig.xml");
  EXPECT_EQ(manifest["definitions"][0]["checksum"], *file_checksum(p->asset.dir / "build" / "biped.rig.xml"));
  EXPECT_EQ(manifest["skeleton"]["checksum"], *file_checksum(p->asset.dir / "skeleton" / "rigify_human_body.glb"));
  EXPECT_NE(read_text(v1->log).find("built hero"), std::string::npos);

  // Hand edits on version 1: a control's shape, a painted weight; exported.
  auto scene = load(v1->scene);
  graph::Graph& g = scene->graph();
  const graph::NodeId rig = rig::find_rig(g, "hero");
  const graph::NodeId ik = testing::at(g, "hero:arm_L/ik");
  const ControlLook drawn{{math::Vec3(0, 0, 0), math::Vec3(0.1, 0.1, 0)}, false, math::Vec3(1, 0.5, 0)};
  ASSERT_TRUE(paste_control_look(g, {ik}, drawn).is_ok());
  auto weights = *capture_skin_weights(*scene);
  auto& body = weights.back();
  for (std::int64_t k = body.offsets[42]; k < body.offsets[43]; ++k)
    body.weights[static_cast<std::size_t>(k)] = k == body.offsets[42] ? 1.0 : 0.0;
  ASSERT_TRUE(apply_skin_weights(*scene, weights).is_ok());
  write_text(p->asset.dir / "data/shapes/hero.shapes.json", control_shapes_to_json(*capture_control_shapes(g, rig)));
  write_text(p->asset.dir / "data/weights/body.weights.json", skin_weights_to_json(*capture_skin_weights(*scene)));
  // And a target sculpted on the body (whose glTF has none): a new blendShape.
  graph::NodeId mesh;
  for (graph::NodeId id : g.nodes())
    if (g.node(id)->type().name() == scene::kMeshType) mesh = id;
  const std::size_t vertices = std::get<std::vector<math::Vec3>>(g.evaluate(mesh, scene::mesh_attr::kPoints)).size();
  BlendShapeSet sculpt{"body_blendShape", g.node(mesh)->name(), vertices, {BlendTarget{0, "belly", 0.5, {7, 8}, {{0, 0.01, 0}, {0, 0.02, 0}}}}};
  ASSERT_TRUE(apply_blend_shapes(g, {sculpt}).is_ok());
  const std::string blend_file = blend_shapes_to_json(*capture_blend_shapes(g));
  write_text(p->asset.dir / "data/blendshapes/body.blendshapes.json", blend_file);

  auto v2 = publish_asset(p->asset, ephemeral::components(), {"", true, "test"});
  ASSERT_TRUE(v2.is_ok()) << v2.status().message();
  EXPECT_EQ(v2->version, 2);
  EXPECT_GT(v2->shapes_set, 50u);
  EXPECT_GT(v2->weights_vertices, 10000u);
  EXPECT_EQ(v2->blend_shape_targets, 1u);
  EXPECT_TRUE(fs::exists(p->asset.dir / "rig/v001/rig.rigel")) << "version 1 kept";
  EXPECT_EQ(published_versions(p->asset), (std::vector<int>{1, 2}));
  auto rebuilt = load(v2->scene);
  const ControlLook got = *control_look(rebuilt->graph(), testing::at(rebuilt->graph(), "hero:arm_L/ik"));
  EXPECT_EQ(got.points, drawn.points);
  EXPECT_EQ(got.color, drawn.color);
  const auto back = *capture_skin_weights(*rebuilt);
  ASSERT_EQ(back.back().weights.size(), weights.back().weights.size());
  for (std::size_t k = 0; k < back.back().weights.size(); ++k) EXPECT_NEAR(back.back().weights[k], weights.back().weights[k], 1e-6);
  EXPECT_EQ(blend_shapes_to_json(*capture_blend_shapes(rebuilt->graph())), blend_file) << "the sculpted target, exactly";
  const auto data = nlohmann::json::parse(read_text(v2->manifest))["data"];
  ASSERT_EQ(data.size(), 3u);
  EXPECT_EQ(data[0]["kind"], "weights");
  EXPECT_EQ(data[2]["kind"], "blendshapes") << "in the kinds' order: weights, shapes, blendshapes";
  EXPECT_EQ(data[2]["checksum"], *file_checksum(p->asset.dir / "data/blendshapes/body.blendshapes.json"));

  // A scene of version 1 knows version 2 is newer.
  auto old = load(v1->scene);
  const std::vector<PublishedRig> published = published_rigs(old->graph());
  ASSERT_EQ(published.size(), 1u);
  EXPECT_EQ(published[0].asset, "hero");
  EXPECT_EQ(published[0].version, 1);
  EXPECT_EQ(published[0].newest, 2);
  EXPECT_TRUE(published[0].out_of_date());
  EXPECT_FALSE(published_rigs(rebuilt->graph())[0].out_of_date());
}

TEST(Publish, a_broken_definition_or_a_missing_skeleton_publishes_nothing) {
  auto p = asset_with_biped();
  write_text(p->asset.dir / "build" / "biped.rig.xml", "<Rig name=\"hero\" version=\"1.0\">\n  <Component type=\"nosuch\"/>\n</Rig>\n");
  auto r = publish_asset(p->asset, ephemeral::components());
  ASSERT_FALSE(r.is_ok());
  EXPECT_NE(r.status().message().find("biped.rig.xml:"), std::string::npos) << r.status().message();
  EXPECT_TRUE(published_versions(p->asset).empty());
  std::size_t left = 0;
  for (const auto& e : fs::directory_iterator(p->asset.dir / "rig")) left += !e.path().empty();
  EXPECT_EQ(left, 0u) << "nothing staged is left";
  Asset bare = p->asset;
  bare.skeleton.clear();
  EXPECT_EQ(publish_asset(bare, ephemeral::components()).status().field(), "asset");
  fs::remove(p->asset.dir / "build" / "biped.rig.xml");
  EXPECT_EQ(publish_asset(p->asset, ephemeral::components()).status().field(), "asset");
}

// A prop: Khronos' RiggedSimple (a cylinder on two joints) with a global
// control and an FK chain.
constexpr const char* kCrate = R"(<?xml version="1.0" encoding="UTF-8"?>
<rig name="crate" version="1.0">
  <component type="global" name="global" side="C" version="1.0" rigId="6a1f3c2e-4b5d-4e6f-8a7b-9c0d1e2f3a4b">
    <guide name="main"/>
    <control role="main" shape="square" color="yellow" size="1"/>
    <component type="fkChain" name="bend" side="C" version="1.0" rigId="7b2e4d3f-5c6e-4f70-9b8c-0d1e2f3a4b5c">
      <guide joint="node_2"/>
      <guide joint="node_3"/>
      <control role="fk" shape="circle" color="yellow" size="0.5"/>
    </component>
  </component>
</rig>
)";

std::string channel(const graph::Graph& g, const std::string& address, const std::string& attr) {
  return g.node(testing::at(g, address))->name() + "." + attr;
}

double value_at(graph::Graph& g, const std::string& driver, double at, const std::string& driven) {
  auto d = g.plug_find(driver);
  EXPECT_TRUE(d.is_ok()) << driver;
  EXPECT_TRUE(g.set_value(*d, graph::Value(at)).is_ok()) << driver;
  auto p = g.plug_find(driven);
  EXPECT_TRUE(p.is_ok()) << driven;
  return std::get<double>(*g.evaluate(*p));
}

TEST(Publish, a_character_and_a_prop_published_twice_give_back_every_hand_edit) {
  io::testing::TempDir dir;
  auto project = create_project(dir.path() / "show");
  ASSERT_TRUE(project.is_ok()) << project.status().message();
  auto hero = create_asset(*project, "hero", "character", testing::source("tests/data/gltf/rigify_human_body.glb"));
  ASSERT_TRUE(hero.is_ok()) << hero.status().message();
  fs::copy_file(testing::source("examples/biped.rig.xml"), hero->dir / "build" / "biped.rig.xml");
  auto crate = create_asset(*project, "crate", "prop", testing::source("tests/data/gltf/RiggedSimple.glb"));
  ASSERT_TRUE(crate.is_ok()) << crate.status().message();
  EXPECT_EQ(crate->dir, dir.path() / "show" / "props" / "crate");
  write_text(crate->dir / "build" / "crate.rig.xml", kCrate);
  for (const Asset* a : {&*hero, &*crate}) {
    auto v1 = publish_asset(*a, ephemeral::components(), {"", true, "test"});
    ASSERT_TRUE(v1.is_ok()) << a->name << ": " << v1.status().message();
    EXPECT_EQ(v1->version, 1);
  }

  // Hand edits on version 1 of the character: a control's shape, a painted
  // weight, a driven pose (the shoulder's turn bends both elbows).
  auto h = load(hero->dir / "rig/v001/rig.rigel");
  graph::Graph& hg = h->graph();
  const ControlLook drawn{{math::Vec3(0, 0, 0), math::Vec3(0.1, 0.1, 0), math::Vec3(0, 0.2, 0.1)}, true, math::Vec3(0.3, 0.6, 0.9)};
  ASSERT_TRUE(paste_control_look(hg, {testing::at(hg, "hero:arm_L/ik")}, drawn).is_ok());
  auto weights = *capture_skin_weights(*h);
  auto& skin = weights.back();
  const std::int64_t first = skin.offsets[1234], end = skin.offsets[1235];
  ASSERT_GT(end - first, 1);
  for (std::int64_t k = first; k < end; ++k)  // a brush stroke: a quarter on the first influence, the rest shared
    skin.weights[static_cast<std::size_t>(k)] = k == first ? 0.25 : 0.75 / static_cast<double>(end - first - 1);
  ASSERT_TRUE(apply_skin_weights(*h, weights).is_ok());
  const std::string driver = channel(hg, "hero:arm_L/fk[0]", "rotateX");
  const std::string elbow_l = channel(hg, "hero:arm_L/fk[1]", "rotateZ"), elbow_r = channel(hg, "hero:arm_R/fk[1]", "rotateZ");
  ASSERT_TRUE(set_driven_key(hg, {driver, 0.0, {{elbow_l, 0.0}, {elbow_r, 0.0}}}).is_ok());
  ASSERT_TRUE(set_driven_key(hg, {driver, 80.0, {{elbow_l, -35.5}, {elbow_r, 12.25}}, ops::anim::TangentType::kSpline}).is_ok());
  const std::string hero_shapes = control_shapes_to_json(*capture_control_shapes(hg, rig::find_rig(hg, "hero")));
  const auto hero_weights = *capture_skin_weights(*h);
  const std::string hero_poses = driven_poses_to_json(*capture_driven_poses(hg, DrivenData::kPoses));
  write_text(hero->dir / "data/shapes/hero.shapes.json", hero_shapes);
  // (the weights as a studio with a large character keeps them: the
  // arrays in a binary side file, data.weights = binary)
  ASSERT_TRUE(write_skin_weights(hero->dir / "data/weights/body.weights.json", hero_weights, WeightsFormat::kBinary).is_ok());
  write_text(hero->dir / "data/driven_poses/hero.drivenposes.json", hero_poses);

  // ... and on the prop: its FK control's shape and a driven pose.
  auto c = load(crate->dir / "rig/v001/rig.rigel");
  graph::Graph& cg = c->graph();
  ASSERT_TRUE(edit_control_shape(cg, {testing::at(cg, "crate:bend/fk[0]")}, ShapeEdit::kFlip).is_ok());
  const std::string bend = channel(cg, "crate:bend/fk[0]", "rotateZ"), tip = channel(cg, "crate:bend/fk[1]", "rotateZ");
  ASSERT_TRUE(set_driven_key(cg, {bend, 0.0, {{tip, 0.0}}}).is_ok());
  ASSERT_TRUE(set_driven_key(cg, {bend, 45.0, {{tip, 30.0}}}).is_ok());
  const std::string crate_shapes = control_shapes_to_json(*capture_control_shapes(cg, rig::find_rig(cg, "crate")));
  const std::string crate_poses = driven_poses_to_json(*capture_driven_poses(cg, DrivenData::kPoses));
  write_text(crate->dir / "data/shapes/crate.shapes.json", crate_shapes);
  write_text(crate->dir / "data/driven_poses/crate.drivenposes.json", crate_poses);

  // Version 2 of each, built from scratch: every edit back.
  auto v2 = publish_asset(*hero, ephemeral::components(), {"", true, "test"});
  ASSERT_TRUE(v2.is_ok()) << v2.status().message();
  EXPECT_EQ(v2->version, 2);
  EXPECT_EQ(v2->driven_curves, 2u);
  EXPECT_EQ(nlohmann::json::parse(read_text(v2->manifest))["data"].size(), 3u);
  auto h2 = load(v2->scene);
  graph::Graph& hg2 = h2->graph();
  EXPECT_EQ(control_shapes_to_json(*capture_control_shapes(hg2, rig::find_rig(hg2, "hero"))), hero_shapes) << "shapes exact";
  EXPECT_EQ(driven_poses_to_json(*capture_driven_poses(hg2, DrivenData::kPoses)), hero_poses) << "driven poses exact";
  const auto back = *capture_skin_weights(*h2);
  ASSERT_EQ(back.back().weights.size(), hero_weights.back().weights.size());
  double worst = 0;
  for (std::size_t k = 0; k < back.back().weights.size(); ++k)
    worst = std::max(worst, std::abs(back.back().weights[k] - hero_weights.back().weights[k]));
  EXPECT_LE(worst, 1e-6) << "weights";
  EXPECT_EQ(back.back().joints, hero_weights.back().joints);
  EXPECT_EQ(back.back().weights, hero_weights.back().weights) << "float64 in the side file: exact";
  for (double at : {-10.0, 20.0, 80.0, 100.0})
    EXPECT_EQ(value_at(hg2, driver, at, elbow_r), value_at(hg, driver, at, elbow_r)) << at;

  auto c2 = publish_asset(*crate, ephemeral::components(), {"", true, "test"});
  ASSERT_TRUE(c2.is_ok()) << c2.status().message();
  EXPECT_EQ(c2->version, 2);
  auto crate2 = load(c2->scene);
  graph::Graph& cg2 = crate2->graph();
  EXPECT_EQ(control_shapes_to_json(*capture_control_shapes(cg2, rig::find_rig(cg2, "crate"))), crate_shapes);
  EXPECT_EQ(driven_poses_to_json(*capture_driven_poses(cg2, DrivenData::kPoses)), crate_poses);
  EXPECT_EQ(value_at(cg2, bend, 30.0, tip), value_at(cg, bend, 30.0, tip));
  auto assets = list_assets(*project);
  ASSERT_TRUE(assets.is_ok());
  ASSERT_EQ(assets->size(), 2u);
  for (const Asset& a : *assets) EXPECT_EQ(published_versions(a), (std::vector<int>{1, 2})) << a.name;
}

}  // namespace
}  // namespace rigel::tools
