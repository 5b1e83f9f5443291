// Sub-graphs (build_graph.h's graph:PATH nodes): a graph file used as a
// node, its variables the node's inputs and outputs, each use building its
// own components with their own rigIds; built, stepped and removed like
// any graph; missing files, paths out of the folder, files that include
// each other and problems inside a sub-graph refused with the file and the
// node named.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "build_graph_test_util.h"
#include "rig_test_util.h"
#include "rigel/io/scene_file.h"
#include "rigel/rig/build_graph.h"

namespace rigel::rig {
namespace {

using namespace testing;
namespace fs = std::filesystem;

// A folder with lib/arm.build.json: an arm (fkChain drawn on the left
// joints) hanging from its `parent` variable, of side `side`, that leaves
// its component in `arm`.
class SubGraphs : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("rigel_subgraphs_" + std::to_string(::getpid()));
    fs::create_directories(dir_ / "lib");
    ASSERT_TRUE(save_build_graph(arm_graph(), dir_ / "lib" / "arm.build.json").is_ok());
  }
  void TearDown() override { fs::remove_all(dir_); }

  static BuildGraph arm_graph() {
    BuildGraph g;
    g.rig.name = "arm";
    g.variables = {GraphVariable{"side", "string", std::string("L"), {}, {}},
                   GraphVariable{"parent", "component", {}, {}, {}},
                   GraphVariable{"arm", "component", {}, {}, {}}};
    Component arm = fk_chain("arm", Side::kLeft, {"upper_arm.L", "forearm.L", "hand.L"});
    arm.rig_id.clear();
    g.nodes = {node("start", "start"), component_node("arm", arm), node("side", "variable:get"),
               node("parent", "variable:get"), node("keep", "variable:set")};
    g.nodes[2].variable = "side";
    g.nodes[3].variable = "parent";
    g.nodes[4].variable = "arm";
    g.links = {link("start", "then", "arm", "exec"), link("side", "value", "arm", "side"),
               link("parent", "value", "arm", "parent"), link("arm", "then", "keep", "exec"),
               link("arm", "component", "keep", "value")};
    return g;
  }

  // start -> global -> arm (left) -> arm (right, its side from a constant)
  // -> a hand chain hanging from the right arm (the sub-graph's output).
  BuildGraph top() const {
    BuildGraph g;
    g.rig.name = "two_arms";
    g.source = (dir_ / "hero.build.json").string();
    Component fingers = fk_chain("finger", Side::kRight, {"f_index.01.R", "f_index.02.R"});
    GraphNode right = node("right", "constant:string");
    right.values.push_back(Param{"value", std::string("R"), {}});
    g.nodes = {node("start", "start"), component_node("global", global_component()), node("armL", "graph:lib/arm.build.json"),
               node("armR", "graph:lib/arm.build.json"), right, component_node("fingers", fingers)};
    g.links = {link("start", "then", "global", "exec"),      link("global", "then", "armL", "exec"),
               link("armL", "then", "armR", "exec"),         link("armR", "then", "fingers", "exec"),
               link("global", "component", "armL", "parent"), link("global", "component", "armR", "parent"),
               link("right", "value", "armR", "side"),        link("armR", "arm", "fingers", "parent")};
    return g;
  }

  fs::path dir_;
};

TEST_F(SubGraphs, each_use_of_a_sub_graph_builds_its_own_components_and_passes_its_outputs_on) {
  const BuildGraph g = top();
  const BuildGraphCompile c = compile_build_graph(g);
  const std::vector<Component> arms = two_arms(c);
  ASSERT_EQ(arms.size(), 2u);
  EXPECT_EQ(arms[1].guides[0].joint, "upper_arm.R") << "drawn on the left, given R: mirrored";
  ASSERT_EQ(arms[1].children.size(), 1u) << "the fingers hang from the right arm, the sub-graph's output";
  EXPECT_EQ(arms[1].children[0].full_name(), "finger_R");
  EXPECT_EQ(c.order, (std::vector<std::string>{"global", "armL", "armL/arm", "armL/keep", "armR", "armR/arm", "armR/keep",
                                               "fingers"}));
  // Each use's components are its node's, for an editor.
  EXPECT_EQ(c.rig_ids[1], (std::pair<std::string, std::string>{"armL", arms[0].rig_id}));
  EXPECT_EQ(c.rig_ids[2], (std::pair<std::string, std::string>{"armR", arms[1].rig_id}));
  // The same files give the same rigIds.
  EXPECT_EQ(compile_build_graph(top()).definition.components[0].children[1].rig_id, arms[1].rig_id);
  // Saved beside the library and read back, the same graph.
  ASSERT_TRUE(save_build_graph(g, g.source).is_ok());
  const ParseResult loaded = load_definition(g.source);
  ASSERT_TRUE(loaded.ok()) << loaded.errors[0].str();
  EXPECT_EQ(write_definition(loaded.definition, Syntax::kJson), write_definition(c.definition, Syntax::kJson));
  // The kind's sockets are the sub-graph's variables.
  const NodeKind kind = subgraph_node_kind("lib/arm.build.json", arm_graph());
  EXPECT_EQ(kind.id, "graph:lib/arm.build.json");
  EXPECT_EQ(kind.input("parent")->type, "component");
  EXPECT_EQ(kind.output("arm")->type, "component");
  EXPECT_EQ(kind.input("side")->type, "string");
}

TEST_F(SubGraphs, a_graph_with_sub_graphs_steps_and_is_removed_exactly) {
  BuiltRig r = built_rig(compiled(top()));
  ASSERT_TRUE(r.build);
  expect_stepping_gives_the_straight_build(*r.build, *r.scene);
  ASSERT_TRUE(r.build->remove().is_ok());
  const std::string text = io::write_scene(*r.scene);
  EXPECT_TRUE(text == r.before) << first_difference(text, r.before);
}

TEST_F(SubGraphs, a_sub_graph_is_refused_with_its_file_and_node_named) {
  const auto expect_problem = [](const BuildGraph& g, const std::string& part) {
    const std::string p = problems(g);
    EXPECT_NE(p.find(part), std::string::npos) << "expected '" << part << "' in:\n" << p;
  };
  BuildGraph g = top();
  g.nodes[2].kind = "graph:lib/leg.build.json";
  expect_problem(g, "node 'armL': sub-graph 'lib/leg.build.json' cannot be read");
  g.nodes[2].kind = "graph:../arm.build.json";
  expect_problem(g, "no '..'");
  g.nodes[2].kind = "graph:" + (dir_ / "lib" / "arm.build.json").string();
  expect_problem(g, "relative to the graph's folder");
  g.nodes[2].kind = "graph:lib/arm.rig.json";
  expect_problem(g, "not a .build.json file");
  // A value of the wrong type for a sub-graph's input.
  g = top();
  g.nodes[2].values.push_back(Param{"side", 3.0, {}});
  expect_problem(g, "node 'armL': the value of 'side' is not a string");
  // A sub-graph output of one type into an input of another.
  g = top();
  g.links.push_back(link("armL", "arm", "fingers", "name"));
  expect_problem(g, "a component output cannot feed a string input");
  // A problem inside the sub-graph: its file and its node, under the use.
  BuildGraph broken = arm_graph();
  broken.links.pop_back();
  broken.links.push_back(link("side", "value", "keep", "value"));
  ASSERT_TRUE(save_build_graph(broken, dir_ / "lib" / "arm.build.json").is_ok());
  const BuildGraphCompile c = compile_build_graph(top());
  ASSERT_FALSE(c.ok());
  EXPECT_NE(c.errors[0].str().find("a string output cannot feed a component input"), std::string::npos)
      << c.errors[0].str();
  EXPECT_EQ(c.errors[0].file, (dir_ / "lib" / "arm.build.json").string());
  EXPECT_EQ(place_of(top(), c.errors[0]).node, "") << "a link of the sub-graph names no node of this one";
  // Files that include each other, by any path.
  BuildGraph loop = arm_graph();
  loop.nodes.push_back(node("again", "graph:arm.build.json"));
  loop.links[3] = link("arm", "then", "again", "exec");
  loop.links.push_back(link("again", "then", "keep", "exec"));
  ASSERT_TRUE(save_build_graph(loop, dir_ / "lib" / "arm.build.json").is_ok());
  expect_problem(top(), "sub-graphs include each other");
  // A node in the sub-graph that the problem names is placed on its use.
  BuildGraph unknown = arm_graph();
  unknown.nodes[4].variable = "colour";
  ASSERT_TRUE(save_build_graph(unknown, dir_ / "lib" / "arm.build.json").is_ok());
  const BuildGraphCompile u = compile_build_graph(top());
  ASSERT_FALSE(u.ok());
  EXPECT_NE(u.errors[0].message.find("node 'armL/keep'"), std::string::npos) << u.errors[0].str();
  EXPECT_EQ(place_of(top(), u.errors[0]).node, "armL");
}

}  // namespace
}  // namespace rigel::rig
