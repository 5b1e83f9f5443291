// `rigel graph run|convert|validate` (build graphs; docs/BUILD_GRAPH.md):
// the example biped converted, checked and built gives the definition's
// rig; a graph built into a scene is updated from its file like a
// definition; a wrong graph is refused with the node and socket named, and
// nothing is written.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_test_util.h"

namespace rigel::cli {
namespace {

using namespace rigel::cli::testing;  // NOLINT: the CLI runner
using Json = nlohmann::ordered_json;
namespace fs = std::filesystem;

const std::string kBiped = (fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml").string();

// Every occurrence of `from` in `text` replaced by `to`; fails the test when there is none.
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

void write(const fs::path& file, const std::string& text) { std::ofstream(file, std::ios::binary) << text; }

TEST(CliGraph, the_converted_biped_validates_and_builds_the_definitions_rig) {
  TempDir dir;
  const std::string graph = (dir.path() / "biped.build.json").string();
  const CliRun convert = rigel({"graph", "convert", kBiped, "-o", graph, "--json"});
  ASSERT_TRUE(exited_with(convert, 0)) << convert;
  EXPECT_EQ(Json::parse(convert.out)["nodes"], 22) << convert;
  const CliRun validate = rigel({"graph", "validate", graph, "--json"});
  ASSERT_TRUE(exited_with(validate, 0)) << validate;
  const Json report = Json::parse(validate.out)["files"][0];
  EXPECT_EQ(report["valid"], true);
  EXPECT_EQ(report["order"].size(), 21u);
  EXPECT_EQ(report["order"][0], "global");
  const std::string from_graph = (dir.path() / "from_graph.rigel").string();
  const std::string from_definition = (dir.path() / "from_definition.rigel").string();
  const CliRun run = rigel({"graph", "run", graph, "-o", from_graph, "--json"});
  ASSERT_TRUE(exited_with(run, 0)) << run;
  EXPECT_EQ(Json::parse(run.out)["components"].size(), 21u);
  ASSERT_TRUE(exited_with(rigel({"build", kBiped, "-o", from_definition}), 0));
  // The same pose at a frame, node for node.
  const CliRun a = rigel({"eval", from_graph, "--frame", "3", "--json"});
  const CliRun b = rigel({"eval", from_definition, "--frame", "3", "--json"});
  ASSERT_TRUE(exited_with(a, 0) && exited_with(b, 0)) << a << b;
  EXPECT_EQ(Json::parse(a.out)["nodes"], Json::parse(b.out)["nodes"]);
  // `rigel build` takes a graph as it takes a definition.
  EXPECT_TRUE(exited_with(rigel({"build", graph, "-o", (dir.path() / "built.rigel").string()}), 0));

  // The rig keeps the graph as its definition: an update reads it again.
  write(graph, replaced(read_text(graph), "\"name\": \"neck\",\n          \"side\": \"C\",\n          \"version\": \"1.0\"",
                        "\"name\": \"neck\",\n          \"side\": \"C\",\n          \"version\": \"1.1\""));
  const CliRun update = rigel({"update", from_graph, "-o", (dir.path() / "v2.rigel").string(), "--json"});
  ASSERT_TRUE(exited_with(update, 0)) << update;
  // The neck and what hangs from it; not the legs.
  const Json rebuilt = Json::parse(update.out)["rigs"][0]["rebuilt"];
  EXPECT_NE(std::find(rebuilt.begin(), rebuilt.end(), "neck"), rebuilt.end()) << update;
  EXPECT_EQ(std::find(rebuilt.begin(), rebuilt.end(), "leg_L"), rebuilt.end()) << update;
}

TEST(CliGraph, a_wrong_graph_is_refused_naming_the_node_and_socket_and_nothing_is_written) {
  TempDir dir;
  const fs::path graph = dir.path() / "biped.build.json";
  ASSERT_TRUE(exited_with(rigel({"graph", "convert", kBiped, "-o", graph.string()}), 0));
  write(graph, replaced(read_text(graph.string()), "{\"from\": \"hip.component\", \"to\": \"spine.parent\"}",
                        "{\"from\": \"hip.component\", \"to\": \"spine.kinematicType\"}"));
  const CliRun validate = rigel({"graph", "validate", graph.string()});
  EXPECT_TRUE(exited_with(validate, 1)) << validate;
  EXPECT_TRUE(contains(validate.err, "link 'hip.component' -> 'spine.kinematicType': a component output cannot feed a "
                                     "string input"))
      << validate;
  // --json places it on the input's node and socket, for tools that mark them.
  const CliRun json = rigel({"graph", "validate", graph.string(), "--json"});
  ASSERT_TRUE(exited_with(json, 1)) << json;
  const Json error = Json::parse(json.out)["files"][0]["errors"][0];
  EXPECT_EQ(error["node"], "spine") << json;
  EXPECT_EQ(error["socket"], "kinematicType") << json;
  const fs::path out = dir.path() / "out.rigel";
  const CliRun run = rigel({"graph", "run", graph.string(), "-o", out.string()});
  EXPECT_TRUE(exited_with(run, 1)) << run;
  EXPECT_TRUE(contains(run.err, "spine.kinematicType")) << run;
  EXPECT_FALSE(fs::exists(out));
  // Usage: a definition is not a graph, a graph's name ends in .build.json.
  EXPECT_TRUE(exited_with(rigel({"graph", "run", kBiped, "-o", out.string()}), 2));
  EXPECT_TRUE(exited_with(rigel({"graph", "convert", kBiped, "-o", (dir.path() / "g.json").string()}), 2));
  EXPECT_TRUE(exited_with(rigel({"graph"}), 2));
  const CliRun missing = rigel({"graph", "validate", (dir.path() / "none.build.json").string()});
  EXPECT_TRUE(exited_with(missing, 1)) << missing;
}

// An arm drawn on the left joints, hanging from its `parent` variable, of
// side `side`.
constexpr const char* kArmGraph = R"({"buildGraph": {"format": 1, "rig": {"name": "arm", "version": "1.0"},
  "variables": [{"name": "side", "type": "string", "value": "L"}, {"name": "parent", "type": "component", "value": null}],
  "nodes": [{"id": "start", "kind": "start"},
    {"id": "arm", "kind": "component:fkChain", "component": {"type": "fkChain", "name": "arm", "side": "L",
      "version": "1.0", "guides": [{"joint": "upper_arm.L"}, {"joint": "forearm.L"}, {"joint": "hand.L"}]}},
    {"id": "side", "kind": "variable:get", "variable": "side"},
    {"id": "parent", "kind": "variable:get", "variable": "parent"}],
  "links": [{"from": "start.then", "to": "arm.exec"}, {"from": "side.value", "to": "arm.side"},
    {"from": "parent.value", "to": "arm.parent"}]}})";

// For each side in ["L", "R"], the arm sub-graph under the global.
constexpr const char* kHeroGraph = R"({"buildGraph": {"format": 1, "rig": {"name": "hero", "version": "1.0"},
  "nodes": [{"id": "start", "kind": "start"},
    {"id": "global", "kind": "component:global", "component": {"type": "global", "name": "global", "side": "C",
      "version": "1.0", "guides": [{"name": "main"}]}},
    {"id": "sides", "kind": "constant:list:string", "value": ["L", "R"]},
    {"id": "each", "kind": "forEach:string"},
    {"id": "arm", "kind": "graph:lib/arm.build.json"}],
  "links": [{"from": "start.then", "to": "global.exec"}, {"from": "global.then", "to": "each.exec"},
    {"from": "sides.value", "to": "each.list"}, {"from": "each.body", "to": "arm.exec"},
    {"from": "each.element", "to": "arm.side"}, {"from": "global.component", "to": "arm.parent"}]}})";

TEST(CliGraph, a_graph_with_a_for_each_over_a_sub_graph_builds_one_arm_per_side) {
  TempDir dir;
  fs::create_directories(dir.path() / "lib");
  write(dir.path() / "lib" / "arm.build.json", kArmGraph);
  const fs::path hero = dir.path() / "hero.build.json";
  write(hero, kHeroGraph);
  const std::string character = (fs::path(RIGEL_SOURCE_DIR) / "tests/data/gltf/rigify_human_metarig.glb").string();
  const CliRun validate = rigel({"graph", "validate", hero.string(), "--json"});
  ASSERT_TRUE(exited_with(validate, 0)) << validate;
  EXPECT_EQ(Json::parse(validate.out)["files"][0]["order"],
            Json::parse(R"(["global", "each", "arm", "arm/arm", "arm", "arm/arm"])"));
  const fs::path out = dir.path() / "hero.rigel";
  const CliRun run = rigel({"graph", "run", hero.string(), "--character", character, "-o", out.string(), "--json"});
  ASSERT_TRUE(exited_with(run, 0)) << run;
  const Json report = Json::parse(run.out);
  std::vector<std::string> made;
  for (const Json& c : report["components"]) made.push_back(c["name"].get<std::string>() + "_" + c["side"].get<std::string>());
  std::sort(made.begin(), made.end());
  EXPECT_EQ(made, (std::vector<std::string>{"arm_L", "arm_R", "global_C"})) << run;

  // A problem in the sub-graph names its file; nothing is written.
  write(dir.path() / "lib" / "arm.build.json",
        replaced(kArmGraph, R"({"from": "side.value", "to": "arm.side"})", R"({"from": "side.value", "to": "arm.parent"})"));
  const CliRun broken = rigel({"graph", "run", hero.string(), "--character", character, "-o", (dir.path() / "x.rigel").string()});
  EXPECT_TRUE(exited_with(broken, 1)) << broken;
  EXPECT_TRUE(contains(broken.err, "arm.build.json")) << broken;
  EXPECT_FALSE(fs::exists(dir.path() / "x.rigel"));
}

// The shipped node kinds from the binary: a repeat (count from the length
// of a split text) builds one chain per pass, each named from the
// pass's index; a sequence runs the global first, then the repeat.
constexpr const char* kRepeatGraph = R"({"buildGraph": {"format": 1, "rig": {"name": "chains", "version": "1.0"},
  "nodes": [{"id": "start", "kind": "start"},
    {"id": "parts", "kind": "flow:rigel.sequence"},
    {"id": "global", "kind": "component:global", "component": {"type": "global", "name": "global", "side": "C",
      "version": "1.0", "guides": [{"name": "main"}]}},
    {"id": "names", "kind": "function:rigel.splitText", "values": {"text": "a;b;c", "separator": ";"}},
    {"id": "each", "kind": "forEach:string"},
    {"id": "again", "kind": "flow:rigel.repeat", "values": {"count": 2}},
    {"id": "number", "kind": "function:rigel.intText", "values": {"digits": 2}},
    {"id": "name", "kind": "function:rigel.joinText", "values": {"separator": "_"}},
    {"id": "chain", "kind": "component:fkChain", "component": {"type": "fkChain", "name": "chain", "side": "L",
      "version": "1.0", "guides": [{"joint": "upper_arm.L"}, {"joint": "forearm.L"}]}}],
  "links": [{"from": "start.then", "to": "parts.exec"}, {"from": "parts.first", "to": "global.exec"},
    {"from": "parts.second", "to": "each.exec"}, {"from": "names.items", "to": "each.list"},
    {"from": "each.body", "to": "again.exec"}, {"from": "again.body", "to": "chain.exec"},
    {"from": "again.index", "to": "number.value"}, {"from": "each.element", "to": "name.a"},
    {"from": "number.text", "to": "name.b"}, {"from": "name.text", "to": "chain.name"},
    {"from": "global.component", "to": "chain.parent"}]}})";

TEST(CliGraph, the_shipped_node_kinds_and_list_functions_run_from_the_binary) {
  TempDir dir;
  const fs::path graph = dir.path() / "chains.build.json";
  write(graph, kRepeatGraph);
  const CliRun validate = rigel({"graph", "validate", graph.string(), "--json"});
  ASSERT_TRUE(exited_with(validate, 0)) << validate;
  const fs::path out = dir.path() / "chains.rigel";
  const std::string character = (fs::path(RIGEL_SOURCE_DIR) / "tests/data/gltf/rigify_human_metarig.glb").string();
  const CliRun run = rigel({"graph", "run", graph.string(), "--character", character, "-o", out.string(), "--json"});
  ASSERT_TRUE(exited_with(run, 0)) << run;
  std::vector<std::string> made;
  const Json report = Json::parse(run.out);
  for (const Json& c : report["components"]) made.push_back(c["name"].get<std::string>());
  std::sort(made.begin(), made.end());
  EXPECT_EQ(made, (std::vector<std::string>{"a_00", "a_01", "b_00", "b_01", "c_00", "c_01", "global"})) << run;
  // A count the repeat refuses is reported at its node; nothing is written.
  write(graph, replaced(kRepeatGraph, R"("count": 2)", R"("count": -3)"));
  const CliRun refused =
      rigel({"graph", "run", graph.string(), "--character", character, "-o", (dir.path() / "x.rigel").string()});
  EXPECT_TRUE(exited_with(refused, 1)) << refused;
  EXPECT_TRUE(contains(refused.err, "node 'again'") && contains(refused.err, "count: -3")) << refused;
  EXPECT_FALSE(fs::exists(dir.path() / "x.rigel"));
}

}  // namespace
}  // namespace rigel::cli
