// Build graphs through the app layer: `rigel graph convert` of the example
// biped (every component type, the ephemeral jaw included) builds the same
// rig as the definition on its character.
#include <unistd.h>

#include <filesystem>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "../rig/rig_test_util.h"
#include "rigel/app/graphs.h"
#include "rigel/app/rig_files.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/rig/build_function.h"
#include "rigel/rig/spaces.h"
#include "rigel/tools/build_functions.h"
#include "rigel/tools/rigging.h"
#include "rigel/rig/manager.h"
#include "rigel/tools/data_files.h"

namespace rigel {
namespace {

namespace fs = std::filesystem;

// Every occurrence of `from` in `text` replaced by `to`.
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
  return text;
}

TEST(AppBuildGraph, the_converted_biped_builds_the_definitions_rig) {
  const fs::path definition = fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml";
  const fs::path dir = fs::temp_directory_path() / ("rigel_app_graph_" + std::to_string(::getpid()));
  fs::create_directories(dir / "graphs");
  const fs::path graph = dir / "graphs/biped.build.json";
  auto converted = app::convert_definition_file(definition, graph);
  ASSERT_TRUE(converted.is_ok()) << converted.status().message();
  // The geometry is found from the graph's own folder.
  auto from_graph_def = rig::read_definition(graph);
  ASSERT_TRUE(from_graph_def.is_ok()) << from_graph_def.status().message();
  auto from_def = rig::read_definition(definition);
  ASSERT_TRUE(from_def.is_ok());
  auto a = app::build_rig_file(*from_def, definition, tools::components());
  auto b = app::build_rig_file(*from_graph_def, graph, tools::components());
  ASSERT_TRUE(a.is_ok()) << a.status().message();
  ASSERT_TRUE(b.is_ok()) << b.status().message();
  EXPECT_EQ(b->components.size(), a->components.size());
  EXPECT_EQ(b->nodes, a->nodes);
  std::string worst;
  EXPECT_LT(rig::testing::pose_error(*b->scene, rig::testing::joint_worlds(*a->scene), &worst), 1e-9) << worst;
  // Node for node, metadata included, but for the file each was built from
  // (and the geometry's path from it).
  const std::string from_definition = rig::testing::normalized(*a->scene);
  const std::string from_graph =
      replaced(replaced(rig::testing::normalized(*b->scene), graph.string(), definition.string()),
               converted->rig.geometry.at(0).file, from_def->geometry.at(0).file);
  EXPECT_TRUE(from_graph == from_definition) << rig::testing::first_difference(from_graph, from_definition);
  // A graph name is required of the output.
  EXPECT_EQ(app::convert_definition_file(definition, dir / "biped.json").status().field(), "output");
  fs::remove_all(dir);
}

// A node of kind `kind` added to `g`, linked into the exec chain's end.
rig::GraphNode& append(rig::BuildGraph& g, const std::string& id, const std::string& kind) {
  // The chain's end: the node whose exec output nothing follows.
  std::string last = "start";
  for (bool moved = true; moved;) {
    moved = false;
    for (const rig::GraphLink& l : g.links)
      if (l.from.node == last && l.to.socket == "exec") {
        last = l.to.node;
        moved = true;
        break;
      }
  }
  rig::GraphNode n;
  n.id = id;
  n.kind = kind;
  g.nodes.push_back(std::move(n));
  g.links.push_back(rig::GraphLink{{last, "then"}, {id, "exec"}, {}});
  return g.nodes.back();
}

TEST(AppBuildGraph, the_shipped_functions_run_as_build_steps_on_the_biped) {
  tools::register_build_functions();
  auto definition = rig::read_definition(fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml");
  ASSERT_TRUE(definition.is_ok());
  rig::BuildGraph g = rig::convert_definition(*definition);
  append(g, "mirror", "function:rigel.mirrorControlShapes");
  g.links.push_back(rig::GraphLink{{"arm_L", "component"}, {"mirror", "component"}, {}});
  append(g, "colour", "function:rigel.setControlColor")
      .values.push_back(rig::Param{"color", math::Vec3(0.1, 0.2, 0.3), {}});
  g.links.push_back(rig::GraphLink{{"spine", "component"}, {"colour", "component"}, {}});
  rig::GraphNode& space = append(g, "space", "function:rigel.addSpace");
  space.values.push_back(rig::Param{"name", std::string("neck"), {}});
  g.links.push_back(rig::GraphLink{{"arm_L", "component"}, {"space", "component"}, {}});
  g.links.push_back(rig::GraphLink{{"neck", "component"}, {"space", "target"}, {}});
  rig::BuildGraphCompile compiled = rig::compile_build_graph(g);
  ASSERT_TRUE(compiled.ok()) << compiled.errors[0].str();

  // The same rig from the definition, the shapes mirrored by hand: what the call must give.
  rig::testing::BuiltRig plain;
  plain.scene = rig::testing::metarig(ephemeral::default_registry());
  ASSERT_TRUE(plain.scene);
  auto b0 = rig::Build::open(*plain.scene, *definition, tools::components());
  ASSERT_TRUE(b0.is_ok() && (*b0)->build_all().is_ok());
  graph::Graph& pg = plain.scene->graph();
  std::vector<graph::NodeId> left;
  for (graph::NodeId m : rig::meta_members(pg, rig::find_component(pg, rig::find_rig(pg, "hero"), "arm_L")))
    if (pg.node(m)->type().name() == scene::kControlType) left.push_back(m);
  ASSERT_TRUE(tools::mirror_shape_to_opposite(*plain.scene, left).is_ok());

  auto scene = rig::testing::metarig(ephemeral::default_registry());
  ASSERT_TRUE(scene);
  const std::string before = io::write_scene(*scene);
  auto b = rig::Build::open(*scene, compiled.definition, tools::components());
  ASSERT_TRUE(b.is_ok()) << b.status().message();
  const Status built = (*b)->build_all();
  ASSERT_TRUE(built.is_ok()) << built.message();
  graph::Graph& gg = scene->graph();
  const graph::NodeId hero = rig::find_rig(gg, "hero");
  for (const char* control : {"hero:arm_R/fk[0]", "hero:arm_R/ik[0]", "hero:arm_R/pole[0]"}) {
    auto mirrored = tools::control_look(gg, *rig::resolve_address(gg, control));
    auto expected = tools::control_look(pg, *rig::resolve_address(pg, control));
    ASSERT_TRUE(mirrored.is_ok() && expected.is_ok()) << control;
    EXPECT_EQ(mirrored->points, expected->points) << control;
  }
  EXPECT_EQ(rig::meta_string(gg, rig::find_component(gg, hero, "mirror"), rig::kOutputsAttr),
            "{\"count\":" + std::to_string(left.size()) + "}");
  int coloured = 0;
  for (graph::NodeId m : rig::meta_members(gg, rig::find_component(gg, hero, "spine")))
    if (gg.node(m)->type().name() == scene::kControlType) {
      EXPECT_EQ(tools::control_look(gg, m)->color, math::Vec3(0.1, 0.2, 0.3)) << gg.node(m)->name();
      ++coloured;
    }
  EXPECT_GT(coloured, 0);
  const rig::ControlSpaces spaces = rig::spaces_of(*scene, *rig::resolve_address(gg, "hero:arm_L/ik[0]"));
  ASSERT_FALSE(spaces.spaces.empty());
  EXPECT_EQ(spaces.spaces.back().name, "neck");
  // The calls are steps like the others: all undone exactly.
  ASSERT_TRUE((*b)->remove().is_ok());
  const std::string after = io::write_scene(*scene);
  EXPECT_TRUE(after == before) << rig::testing::first_difference(after, before);
}

}  // namespace
}  // namespace rigel

namespace rigel {
namespace {

TEST(AppBuildGraph, the_shipped_pure_functions_make_text_and_refuse_what_they_cannot) {
  tools::register_build_functions();
  const auto run = [](const char* id, std::map<std::string, rig::ParamValue> values) {
    const std::optional<rig::BuildFunction> f = rig::build_functions().find(id);
    EXPECT_TRUE(f && f->pure) << id;
    return rig::run_pure(*f, {std::move(values), {}});
  };
  auto joined = run("rigel.joinText", {{"a", std::string("arm")}, {"b", std::string("01")}, {"separator", std::string("_")}});
  ASSERT_TRUE(joined.is_ok());
  EXPECT_EQ(std::get<std::string>(joined->values.at("text")), "arm_01");
  auto padded = run("rigel.intText", {{"value", std::int64_t{7}}, {"digits", std::int64_t{3}}});
  ASSERT_TRUE(padded.is_ok());
  EXPECT_EQ(std::get<std::string>(padded->values.at("text")), "007");
  auto negative = run("rigel.intText", {{"value", std::int64_t{-12}}, {"digits", std::int64_t{3}}});
  ASSERT_TRUE(negative.is_ok());
  EXPECT_EQ(std::get<std::string>(negative->values.at("text")), "-012");
  auto lowest = run("rigel.intText", {{"value", std::numeric_limits<std::int64_t>::min()}});
  ASSERT_TRUE(lowest.is_ok());
  EXPECT_EQ(std::get<std::string>(lowest->values.at("text")), "-9223372036854775808");
  auto plain = run("rigel.intText", {{"value", std::int64_t{42}}});
  ASSERT_TRUE(plain.is_ok()) << "digits defaults to its zero";
  EXPECT_EQ(std::get<std::string>(plain->values.at("text")), "42");
  const auto refused = run("rigel.intText", {{"value", std::int64_t{1}}, {"digits", std::int64_t{99}}});
  EXPECT_EQ(refused.status().code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(refused.status().message().find("digits"), std::string::npos);
  // Lists: a range, a text split.
  const auto ints = [](const rig::ValueList& items) {
    std::vector<std::int64_t> out;
    for (const rig::ParamValue& v : items) out.push_back(std::get<std::int64_t>(v));
    return out;
  };
  auto range = run("rigel.range", {{"count", std::int64_t{4}}, {"start", std::int64_t{1}}, {"step", std::int64_t{-2}}});
  ASSERT_TRUE(range.is_ok());
  EXPECT_EQ(ints(range->lists.at("items")), (std::vector<std::int64_t>{1, -1, -3, -5}));
  EXPECT_EQ(run("rigel.range", {{"count", std::int64_t{0}}})->lists.at("items").size(), 0u);
  EXPECT_EQ(run("rigel.range", {{"count", std::int64_t{-1}}}).status().code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(run("rigel.range", {{"count", std::int64_t{10001}}}).status().code(), ErrorCode::kInvalidArgument);
  const auto split = [&](const char* text, const char* separator) {
    std::vector<std::string> out;
    auto r = run("rigel.splitText", {{"text", std::string(text)}, {"separator", std::string(separator)}});
    EXPECT_TRUE(r.is_ok()) << text;
    if (r)
      for (const rig::ParamValue& v : r->lists.at("items")) out.push_back(std::get<std::string>(v));
    return out;
  };
  EXPECT_EQ(split("thumb,index,,ring", ","), (std::vector<std::string>{"thumb", "index", "", "ring"}));
  EXPECT_EQ(split("a--b--", "--"), (std::vector<std::string>{"a", "b", ""}));
  EXPECT_EQ(split("", ","), std::vector<std::string>{});
  EXPECT_EQ(run("rigel.splitText", {{"text", std::string("a")}, {"separator", std::string()}}).status().code(),
            ErrorCode::kInvalidArgument);
}

TEST(AppBuildGraph, the_shipped_flow_kinds_run_parts_in_turn_and_repeat_a_body) {
  tools::register_build_functions();
  const std::optional<rig::FlowKind> sequence = rig::flow_kinds().find("rigel.sequence");
  const std::optional<rig::FlowKind> repeat = rig::flow_kinds().find("rigel.repeat");
  ASSERT_TRUE(sequence && repeat);
  auto parts = rig::run_flow(*sequence, {});
  ASSERT_TRUE(parts.is_ok());
  std::vector<std::string> exits;
  for (const auto& step : *parts) exits.push_back(step.exit);
  EXPECT_EQ(exits, (std::vector<std::string>{"first", "second", "third"}));
  auto passes = rig::run_flow(*repeat, {{{"count", std::int64_t{3}}}, {}});
  ASSERT_TRUE(passes.is_ok());
  ASSERT_EQ(passes->size(), 4u);
  for (std::int64_t i = 0; i < 3; ++i) {
    EXPECT_EQ((*passes)[static_cast<std::size_t>(i)].exit, "body");
    EXPECT_EQ(std::get<std::int64_t>((*passes)[static_cast<std::size_t>(i)].outputs.values.at("index")), i);
  }
  EXPECT_EQ(passes->back().exit, "completed");
  EXPECT_EQ(rig::run_flow(*repeat, {{{"count", std::int64_t{-1}}}, {}}).status().code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(rig::run_flow(*repeat, {})->size(), 3u) << "count defaults to 2";
}

}  // namespace
}  // namespace rigel
