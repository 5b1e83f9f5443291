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

}  // namespace
}  // namespace rigel::cli
