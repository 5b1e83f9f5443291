// Blend shapes as data (tools/blendshape_data.h) on Khronos' SimpleMorph
// (a triangle with two morph targets whose weights are animated) and the
// bundled body (10,037 vertices, skinned, no morph targets): export and
// import round trip byte for byte; a target sculpted on the body (a new
// blendShape in front of its skinCluster) comes back on a fresh import; a
// character with named morph targets (the sculpted body written as glTF)
// gets an edited delta and weight back on a fresh import of its file,
// targets found by name; bad files and mismatches are refused naming the
// place, and nothing changes.

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "rigel/io/gltf_export.h"
#include "rigel/ops/deform/nodes.h"
#include "rigel/scene/transform_types.h"
#include "rigel/tools/blendshape_data.h"
#include "../io/io_test_util.h"
#include "tools_test_util.h"

namespace rigel::tools {
namespace {

namespace bs = ops::blend_shape_attr;
namespace sc = ops::skin_cluster_attr;
namespace ma = scene::mesh_attr;
using graph::NodeId;
using graph::Plug;
using math::Vec3;

std::unique_ptr<scene::Scene> simple_morph() {
  return testing::import_character(testing::source("tests/data/gltf/SimpleMorph.gltf"));
}
std::unique_ptr<scene::Scene> body() { return testing::import_character(testing::source("tests/data/gltf/rigify_human_body.glb")); }

NodeId first_of(const graph::Graph& g, const char* type) {
  for (NodeId id : g.nodes())
    if (g.node(id)->type().name() == type) return id;
  return {};
}

std::vector<Vec3> mesh_points(scene::Scene& s) {
  return std::get<std::vector<Vec3>>(s.graph().evaluate(first_of(s.graph(), scene::kMeshType), ma::kPoints));
}

std::string exported(scene::Scene& s) {
  auto sets = capture_blend_shapes(s.graph());
  EXPECT_TRUE(sets.is_ok()) << sets.status().message();
  return sets ? blend_shapes_to_json(*sets) : std::string();
}

// Two targets sculpted by hand on the body's mesh: the brows up, a cheek out.
BlendShapeSet sculpted(scene::Scene& s) {
  const std::string mesh = s.graph().node(first_of(s.graph(), scene::kMeshType))->name();
  BlendShapeSet set{mesh + "_blendShape", mesh, mesh_points(s).size(), {}};
  BlendTarget brow{0, "brow_up", 0.75, {}, {}}, cheek{1, "cheek_puff", 0.5, {}, {}};
  for (std::int64_t v = 100; v < 120; ++v) brow.vertices.push_back(v), brow.deltas.emplace_back(0, 0.001 * static_cast<double>(v - 99), 0);
  for (std::int64_t v = 5000; v < 5010; ++v) cheek.vertices.push_back(v), cheek.deltas.emplace_back(0.02, 0, 0.001);
  set.targets = {brow, cheek};
  return set;
}

void expect_points_near(const std::vector<Vec3>& got, const std::vector<Vec3>& want, double tolerance) {
  ASSERT_EQ(got.size(), want.size());
  std::size_t off = 0;
  for (std::size_t v = 0; v < got.size(); ++v) off += (got[v] - want[v]).norm() > tolerance;
  EXPECT_EQ(off, 0u) << "vertices further than " << tolerance << " from the expected";
}

TEST(BlendShapesData, simple_morph_captures_and_round_trips_byte_for_byte) {
  auto s = simple_morph();
  ASSERT_TRUE(s);
  auto sets = capture_blend_shapes(s->graph());
  ASSERT_TRUE(sets.is_ok()) << sets.status().message();
  ASSERT_EQ(sets->size(), 1u);
  const BlendShapeSet& set = sets->front();
  EXPECT_EQ(set.mesh, s->graph().node(first_of(s->graph(), scene::kMeshType))->name());
  EXPECT_EQ(set.vertex_count, 3u);
  ASSERT_EQ(set.targets.size(), 2u);
  // Dense in the glTF; only the vertex that moves in the file.
  EXPECT_EQ(set.targets[0].vertices, (std::vector<std::int64_t>{2}));
  EXPECT_EQ(set.targets[0].deltas, (std::vector<Vec3>{Vec3(-1, 1, 0)}));
  EXPECT_EQ(set.targets[1].deltas, (std::vector<Vec3>{Vec3(1, 1, 0)}));
  EXPECT_EQ(set.targets[1].index, 1u);
  EXPECT_EQ(set.targets[1].name, "");
  s->graph().set_time(2.0);  // the animated weights (1, 1)
  const std::string text = exported(*s);
  EXPECT_NE(text.find("\"weight\": 1.0"), std::string::npos) << text;
  EXPECT_NE(text.find("\n            [2, -1.0, 1.0, 0.0]\n"), std::string::npos) << "one line per moved vertex:\n" << text;
  auto back = blend_shapes_from_json(text, "tri.blendshapes.json");
  ASSERT_TRUE(back.is_ok()) << back.status().message();
  auto r = apply_blend_shapes(s->graph(), *back);
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  EXPECT_EQ(r->blend_shapes, 1u);
  EXPECT_EQ(r->targets, 2u);
  EXPECT_TRUE(r->driven.empty()) << "the file's weights are what the animation gives now";
  EXPECT_TRUE(r->added.empty());
  EXPECT_EQ(exported(*s), text) << "byte for byte";
  expect_points_near(mesh_points(*s), {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 2.5, 0)}, 1e-6);
  // A driven weight the file gives otherwise is left to its driver and
  // reported; a weight nothing drives is set from the file.
  const NodeId shape = first_of(s->graph(), ops::kBlendShapeType);
  ASSERT_TRUE(s->graph().disconnect_input(Plug{shape, bs::kWeights, 1}).is_ok());
  (*back)[0].targets[0].weight = 0.5;
  (*back)[0].targets[1].weight = 0.25;
  r = apply_blend_shapes(s->graph(), *back);
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  EXPECT_EQ(r->driven, (std::vector<std::string>{s->graph().node(shape)->name() + ".weights[0]"}));
  expect_points_near(mesh_points(*s), {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(-0.25, 1.75, 0)}, 1e-6);
  EXPECT_EQ(s->graph().undo_label(), "import blend shapes");
}

TEST(BlendShapesData, a_target_sculpted_on_a_mesh_without_blend_shapes_comes_back_on_a_fresh_import) {
  auto s = body();
  ASSERT_TRUE(s);
  EXPECT_FALSE(capture_blend_shapes(s->graph()).is_ok()) << "the body has no morph targets";
  const std::vector<Vec3> rest = mesh_points(*s);
  const std::size_t before = s->graph().undo_count();
  auto r = apply_blend_shapes(s->graph(), {sculpted(*s)});
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  ASSERT_EQ(r->created.size(), 1u);
  EXPECT_EQ(r->added.size(), 2u);
  EXPECT_EQ(s->graph().undo_count(), before + 1) << "one undo step";
  // Wired as the glTF importer wires one: in front of the skinCluster.
  graph::Graph& g = s->graph();
  const NodeId shape = first_of(g, ops::kBlendShapeType), skin = first_of(g, ops::kSkinClusterType);
  const auto source = g.source(Plug{skin, sc::kBindPoints, -1});
  ASSERT_TRUE(source);
  EXPECT_EQ(source->node, shape);
  const std::vector<Vec3> sculpt = mesh_points(*s);
  EXPECT_NEAR((sculpt[110] - rest[110]).norm(), 0.75 * 0.011, 1e-6) << "the brow target at weight 0.75, at rest";
  EXPECT_NEAR((sculpt[5005] - rest[5005]).norm(), 0.5 * Vec3(0.02, 0, 0.001).norm(), 1e-6);
  EXPECT_LT((sculpt[3000] - rest[3000]).norm(), 1e-12);
  const std::string file = exported(*s);

  // A rebuild from scratch: the glTF again, then the file.
  auto fresh = body();
  auto back = blend_shapes_from_json(file, "body.blendshapes.json");
  ASSERT_TRUE(back.is_ok()) << back.status().message();
  ASSERT_TRUE(apply_blend_shapes(fresh->graph(), *back).is_ok());
  expect_points_near(mesh_points(*fresh), sculpt, 1e-12);
  EXPECT_EQ(exported(*fresh), file) << "byte for byte";

  // Undone: no blendShape, the skin's bind points its own again.
  ASSERT_TRUE(g.undo());
  EXPECT_FALSE(first_of(g, ops::kBlendShapeType).is_valid());
  EXPECT_FALSE(g.source(Plug{skin, sc::kBindPoints, -1}));
  expect_points_near(mesh_points(*s), rest, 0);
  // Made only when asked.
  BlendShapesImport keep;
  keep.create = false;
  auto refused = apply_blend_shapes(g, *back, keep);
  ASSERT_FALSE(refused.is_ok());
  EXPECT_EQ(refused.status().field(), "blendShape");
}

TEST(BlendShapesData, an_edited_delta_and_weight_come_back_on_a_fresh_import_of_a_character_with_morph_targets) {
  // The character: the sculpted body written as glTF (its targets named
  // in the mesh's extras.targetNames).
  io::testing::TempDir dir;
  const auto character = dir.path() / "body_morph.glb";
  {
    auto s = body();
    ASSERT_TRUE(apply_blend_shapes(s->graph(), {sculpted(*s)}).is_ok());
    ASSERT_TRUE(io::export_gltf(*s, character).is_ok());
  }
  auto s = testing::import_character(character);
  ASSERT_TRUE(s);
  graph::Graph& g = s->graph();
  const NodeId shape = first_of(g, ops::kBlendShapeType);
  ASSERT_TRUE(shape.is_valid());
  EXPECT_EQ(std::get<std::vector<std::string>>(g.evaluate(shape, bs::kTargetNames)), (std::vector<std::string>{"brow_up", "cheek_puff"}));
  // Edits by hand: a delta of the cheek target (dense, as imported) and the brow's weight.
  auto deltas = std::get<std::vector<Vec3>>(g.evaluate(shape, bs::kTargetDeltas));
  const auto offsets = std::get<std::vector<std::int64_t>>(g.evaluate(shape, bs::kTargetOffsets));
  ASSERT_EQ(offsets.size(), 3u);
  deltas[static_cast<std::size_t>(offsets[1]) + 7000] = Vec3(0, 0, 0.03);
  ASSERT_TRUE(g.set_value(Plug{shape, bs::kTargetDeltas, -1}, graph::Value(deltas)).is_ok());
  ASSERT_TRUE(g.set_value(Plug{shape, bs::kWeights, 0}, graph::Value(0.3)).is_ok());
  const std::vector<Vec3> edited = mesh_points(*s);
  const std::string file = exported(*s);
  EXPECT_NE(file.find("\"name\": \"cheek_puff\""), std::string::npos);
  EXPECT_NE(file.find("[7000, 0.0, 0.0, 0.03]"), std::string::npos) << file.substr(0, 2000);

  auto fresh = testing::import_character(character);
  ASSERT_TRUE(fresh);
  const std::vector<Vec3> unedited = mesh_points(*fresh);
  EXPECT_GT((unedited[7000] - edited[7000]).norm(), 0.004) << "the fresh import lacks the edits";
  auto back = blend_shapes_from_json(file, "body.blendshapes.json");
  ASSERT_TRUE(back.is_ok()) << back.status().message();
  auto r = apply_blend_shapes(fresh->graph(), *back);
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  EXPECT_TRUE(r->created.empty());
  EXPECT_TRUE(r->added.empty());
  expect_points_near(mesh_points(*fresh), edited, 1e-9);
  EXPECT_EQ(exported(*fresh), file) << "byte for byte";

  // Targets are found by name: the file's in another order, one renamed to a
  // name the scene lacks (added), come back where they belong.
  std::vector<BlendShapeSet> swapped = *back;
  std::swap(swapped[0].targets[0], swapped[0].targets[1]);
  swapped[0].targets[0].index = 0;
  swapped[0].targets[1].index = 1;
  swapped[0].targets.push_back(swapped[0].targets[1]);
  swapped[0].targets[2].name = "brow_down";
  swapped[0].targets[2].index = 2;
  for (Vec3& d : swapped[0].targets[2].deltas) d = -d;
  auto again = testing::import_character(character);
  r = apply_blend_shapes(again->graph(), swapped);
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  const std::string shape_name = again->graph().node(first_of(again->graph(), ops::kBlendShapeType))->name();
  EXPECT_EQ(r->added, (std::vector<std::string>{shape_name + ": brow_down"}));
  const auto got = *capture_blend_shapes(again->graph());
  ASSERT_EQ(got[0].targets.size(), 3u);
  EXPECT_EQ(got[0].targets[0].name, "brow_up");
  EXPECT_EQ(got[0].targets[0].deltas, (*back)[0].targets[0].deltas);
  EXPECT_EQ(got[0].targets[0].weight, 0.3);
  EXPECT_EQ(got[0].targets[1].name, "cheek_puff");
  EXPECT_EQ(got[0].targets[2].name, "brow_down");
}

TEST(BlendShapesData, malformed_files_are_refused_naming_the_file_and_place) {
  auto bad = [](const std::string& text) { return blend_shapes_from_json(text, "f.blendshapes.json").status(); };
  auto place = [&](const std::string& text) { return bad(text).message(); };
  EXPECT_EQ(bad("{\"rigelBlendShapes\": 1,\n  \"blendShapes\": [}").code(), ErrorCode::kParseError);
  EXPECT_EQ(place("{\"rigelBlendShapes\": 1,\n  \"blendShapes\": [}").rfind("f.blendshapes.json:2:", 0), 0u)
      << place("{\"rigelBlendShapes\": 1,\n  \"blendShapes\": [}");
  EXPECT_NE(place(R"({"rigelWeights": 1})").find("rigelBlendShapes: not a rigel blend shapes file"), std::string::npos);
  EXPECT_EQ(bad(R"({"rigelBlendShapes": 2, "blendShapes": []})").code(), ErrorCode::kFailedPrecondition);
  const std::string head = R"({"rigelBlendShapes": 1, "blendShapes": [{"blendShape": "b", "mesh": "m", "vertexCount": 3, "targets": [)";
  const std::string ok = R"({"index": 0, "name": "a", "weight": 0, "deltas": [[0, 1, 0, 0]]}, )";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"({"index": 1, "name": "b", "weight": 0.5, "deltas": [[1, 0, 0, 1], [3, 0, 0, 1]]})", "blendShapes[0].targets[1].deltas[1]: vertex 3 is not one of the 3"},
      {R"({"index": 1, "name": "b", "weight": 0.5, "deltas": [[1, 0, 0, 1], [1, 0, 0, 2]]})", "blendShapes[0].targets[1].deltas[1]: vertex 1 is listed twice"},
      {R"({"index": 1, "name": "b", "weight": 0.5, "deltas": [[1, 0, 0]]})", "blendShapes[0].targets[1].deltas[0]: expected [vertex, dx, dy, dz]"},
      {R"({"index": 1, "name": "b", "weight": 0.5, "deltas": [[1, 0, "x", 0]]})", "blendShapes[0].targets[1].deltas[0]: expected three finite"},
      {R"({"index": 1, "name": "b", "deltas": []})", "blendShapes[0].targets[1].weight"},
      {R"({"index": 0, "name": "b", "weight": 0, "deltas": []})", "blendShapes[0].targets[1].index: 0 is also targets[0]'s"},
      {R"({"index": 1, "name": "a", "weight": 0, "deltas": []})", "blendShapes[0].targets[1].name: 'a' is also targets[0]'s"},
      {R"({"index": -1, "name": "b", "weight": 0, "deltas": []})", "blendShapes[0].targets[1].index"},
  };
  for (const auto& [target, expected] : cases) {
    const std::string message = place(head + ok + target + "]}]}");
    EXPECT_EQ(message.rfind("f.blendshapes.json: ", 0), 0u) << message;
    EXPECT_NE(message.find(expected), std::string::npos) << message;
  }
  EXPECT_NE(place(R"({"rigelBlendShapes": 1, "blendShapes": [{"blendShape": "b", "mesh": "m", "targets": []}]})").find("blendShapes[0].vertexCount"),
            std::string::npos);
  EXPECT_TRUE(blend_shapes_from_json(head + R"({"index": 0, "name": "", "weight": 0, "deltas": []}]}]})", "f").is_ok());
}

TEST(BlendShapesData, a_missing_blend_shape_or_a_vertex_out_of_range_is_refused_and_nothing_changes) {
  auto s = simple_morph();
  ASSERT_TRUE(s);
  graph::Graph& g = s->graph();
  const std::string before = exported(*s);
  const std::size_t steps = g.undo_count();
  const BlendShapeSet good = capture_blend_shapes(g)->front();
  auto expect_refused = [&](const std::vector<BlendShapeSet>& sets, const std::string& field, const std::string& part) {
    auto r = apply_blend_shapes(g, sets);
    ASSERT_FALSE(r.is_ok());
    EXPECT_EQ(r.status().field(), field) << r.status().message();
    EXPECT_NE(r.status().message().find(part), std::string::npos) << r.status().message();
    EXPECT_EQ(exported(*s), before) << "nothing changed";
    EXPECT_EQ(g.undo_count(), steps);
  };
  // The first entry would apply; the second names what the scene lacks.
  BlendShapeSet missing = good;
  missing.blend_shape = "nose_blendShape";
  missing.mesh = "nose";
  expect_refused({good, missing}, "blendShape", "blendShape 'nose_blendShape': the scene has no such blendShape, nor one on mesh 'nose'");
  BlendShapeSet out_of_range = good;
  out_of_range.targets[1].vertices = {99};
  expect_refused({out_of_range}, "blendShape", "target 1: vertex 99 is out of range (the mesh has 3 vertices)");
  BlendShapeSet other_mesh = good;
  other_mesh.vertex_count = 4;
  expect_refused({other_mesh}, "blendShape", "4 vertices in the file, 3 in the scene");
  expect_refused({good, good}, "blendShape", "twice");
  // A mesh whose points come from elsewhere cannot take a new blendShape.
  auto copy = g.create_node(scene::kMeshType, "copy");
  ASSERT_TRUE(copy.is_ok());
  ASSERT_TRUE(g.connect(Plug{first_of(g, scene::kMeshType), ma::kPoints, -1}, Plug{*copy, ma::kPoints, -1}).is_ok());
  const std::size_t made = g.undo_count();
  BlendShapeSet on_copy = good;
  on_copy.blend_shape = "copy_blendShape";
  on_copy.mesh = "copy";
  auto r = apply_blend_shapes(g, {on_copy});
  ASSERT_FALSE(r.is_ok());
  EXPECT_EQ(r.status().field(), "mesh");
  EXPECT_NE(r.status().message().find("mesh 'copy': its points come from"), std::string::npos) << r.status().message();
  EXPECT_EQ(g.undo_count(), made);
}

}  // namespace
}  // namespace rigel::tools
