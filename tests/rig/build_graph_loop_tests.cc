// Build graphs' lists and for-each nodes (build_graph.h): a body run once
// per item builds one component per item, each with its own rigId that
// stays from compile to compile; list values in the file; wrong lists,
// cycles through a body and runaway loops refused with the node named.
#include <algorithm>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "build_graph_test_util.h"
#include "rig_test_util.h"
#include "rigel/io/scene_file.h"
#include "rigel/rig/build_function.h"
#include "rigel/rig/build_graph.h"

namespace rigel::rig {
namespace {

using namespace testing;

// start -> global -> for each side in ["L", "R"]: an arm (fkChain) drawn
// on the left joints, given the item's side (the right one is built
// mirrored, on the right joints).
BuildGraph sides() {
  BuildGraph g;
  g.rig.name = "sides";
  Component arm = fk_chain("arm", Side::kLeft, {"upper_arm.L", "forearm.L", "hand.L"});
  arm.rig_id.clear();  // made per item from the node's id
  GraphNode list = node("sides", "constant:list:string");
  list.lists["value"] = texts({"L", "R"});
  g.nodes = {node("start", "start"), component_node("global", global_component()), list, node("each", "forEach:string"),
             component_node("arm", arm)};
  g.links = {link("start", "then", "global", "exec"),    link("global", "then", "each", "exec"),
             link("sides", "value", "each", "list"),     link("each", "body", "arm", "exec"),
             link("each", "element", "arm", "side"),     link("global", "component", "arm", "parent")};
  return g;
}

TEST(BuildGraphLoops, a_for_each_body_builds_one_component_per_item_each_with_its_own_rig_id) {
  const BuildGraph g = reread(sides());
  const BuildGraphCompile c = compile_build_graph(g);
  const std::vector<Component> arms = two_arms(c);
  ASSERT_EQ(arms.size(), 2u);
  EXPECT_EQ(c.order, (std::vector<std::string>{"global", "each", "arm", "arm"}));
  ASSERT_EQ(c.rig_ids.size(), 3u);
  EXPECT_EQ(c.rig_ids[1], (std::pair<std::string, std::string>{"arm", arms[0].rig_id}));
  EXPECT_EQ(c.rig_ids[2], (std::pair<std::string, std::string>{"arm", arms[1].rig_id}));
  // The same graph gives the same rigIds: a rebuild finds its components.
  EXPECT_EQ(compile_build_graph(sides()).definition.components[0].children[1].rig_id, arms[1].rig_id);
  // The file keeps the list: written, read and written again, the same bytes.
  EXPECT_EQ(write_build_graph(g), write_build_graph(sides()));
  EXPECT_NE(write_build_graph(g).find("\"value\": [\"L\", \"R\"]"), std::string::npos) << write_build_graph(g);
}

TEST(BuildGraphLoops, a_graph_with_a_loop_steps_rebuilds_one_item_and_is_removed_exactly) {
  // One item first; the second, added, is built and the first kept.
  BuildGraph g = sides();
  g.nodes[2].lists["value"] = texts({"L"});
  BuiltRig r = built_rig(compiled(g));
  ASSERT_TRUE(r.build);
  std::set<std::string> before;
  for (NodeId id : r.g().nodes()) before.insert(r.g().node(id)->uuid().str());
  const Definition both = compiled(sides());
  ASSERT_EQ(both.components[0].children.size(), 2u);
  auto rebuilt = r.build->rebuild_changed(both);
  ASSERT_TRUE(rebuilt.is_ok()) << rebuilt.status().message();
  EXPECT_EQ(*rebuilt, std::vector<std::string>{both.components[0].children[1].rig_id});
  int kept = 0;
  for (NodeId id : r.g().nodes()) {
    const std::string name = r.g().node(id)->name();
    if (name.find("arm_L") != std::string::npos) {
      EXPECT_TRUE(before.count(r.g().node(id)->uuid().str())) << name << " was built again";
      ++kept;
    }
  }
  EXPECT_GT(kept, 0);
  ASSERT_TRUE(r.build->remove().is_ok());
  const std::string text = io::write_scene(*r.scene);
  EXPECT_TRUE(text == r.before) << first_difference(text, r.before);
  // Both built straight: stepping back to every step and forward again
  // gives the same scene; the right arm stands on the right joints.
  BuiltRig straight = built_rig(both);
  ASSERT_TRUE(straight.build);
  EXPECT_EQ(both.components[0].children[1].guides[0].joint, "upper_arm.R");
  expect_stepping_gives_the_straight_build(*straight.build, *straight.scene);
}

TEST(BuildGraphLoops, nested_loops_and_variables_carry_lists_and_indices) {
  // For each side in a list variable, for each name of ["a", "b"]: an
  // IK chain named by the inner element, its pole distance the inner index
  // (an int into a number).
  BuildGraph g = sides();
  g.variables.push_back(GraphVariable{"sides", "list:string", {}, {std::string("L"), std::string("R")}, {}});
  g.nodes[2] = node("sides", "variable:get");
  g.nodes[2].variable = "sides";
  g.nodes[4].kind = "component:ikChain";
  g.nodes[4].component.type = "ikChain";
  GraphNode names = node("names", "constant:list:string");
  names.lists["value"] = texts({"a", "b"});
  g.nodes.push_back(names);
  g.nodes.push_back(node("inner", "forEach:string"));
  g.links[3] = link("each", "body", "inner", "exec");
  g.links.push_back(link("names", "value", "inner", "list"));
  g.links.push_back(link("inner", "body", "arm", "exec"));
  g.links.push_back(link("inner", "element", "arm", "name"));
  g.links.push_back(link("inner", "index", "arm", "poleDistance"));
  const BuildGraphCompile c = compile_build_graph(reread(g));
  ASSERT_TRUE(c.ok()) << c.errors[0].str();
  std::vector<std::string> made;
  std::vector<double> poles;
  for (const Component& arm : c.definition.components[0].children) {
    made.push_back(arm.full_name());
    poles.push_back(std::get<double>(arm.param("poleDistance")->value));
  }
  EXPECT_EQ(made, (std::vector<std::string>{"a_L", "b_L", "a_R", "b_R"}));
  EXPECT_EQ(poles, (std::vector<double>{0.0, 1.0, 0.0, 1.0}));
  std::set<std::string> ids;
  for (const auto& [node_id, rig_id] : c.rig_ids) ids.insert(rig_id);
  EXPECT_EQ(ids.size(), 5u) << "global and four arms, each its own rigId";
  // An empty list runs no body: nothing made, the chain goes on.
  g.variables[0].items.clear();
  EXPECT_TRUE(compiled(g).components[0].children.empty());
}

TEST(BuildGraphLoops, wrong_lists_and_loops_are_refused_naming_the_node) {
  const auto expect_problem = [](const auto& g, const std::string& part) {
    const std::string p = problems(g);
    EXPECT_NE(p.find(part), std::string::npos) << "expected '" << part << "' in:\n" << p;
  };
  BuildGraph g = sides();
  g.nodes[2].lists["value"] = texts({"L"});
  g.nodes[2].lists["value"].emplace_back(2.0);
  expect_problem(g, "node 'sides': the value of 'value' is not a list:string");
  g = sides();
  g.nodes[2].kind = "constant:string";
  g.nodes[2].lists.clear();
  expect_problem(g, "link 'sides.value' -> 'each.list': a string output cannot feed a list:string input");
  g = sides();
  g.links.push_back(link("arm", "then", "global", "exec"));
  expect_problem(g, "exec links form a cycle: global -> each -> arm -> global");
  g = sides();
  g.links.push_back(link("each", "index", "arm", "name"));
  expect_problem(g, "link 'each.index' -> 'arm.name': a int output cannot feed a string input");
  // Two items of one side: the two arms are one name twice.
  g = sides();
  g.nodes[2].lists["value"] = texts({"L", "L"});
  expect_problem(g, "duplicate component name 'arm' on side L");
  // Loops in loops past the limit are refused, not run for minutes.
  g = sides();
  GraphNode many = node("many", "constant:list:int");
  for (int i = 0; i < 1000; ++i) many.lists["value"].push_back(std::int64_t{i});
  g.nodes.push_back(many);
  for (const char* inner : {"l1", "l2"}) g.nodes.push_back(node(inner, "forEach:int"));
  g.links[3] = link("each", "body", "l1", "exec");
  g.links.push_back(link("l1", "body", "l2", "exec"));
  g.links.push_back(link("many", "value", "l1", "list"));
  g.links.push_back(link("many", "value", "l2", "list"));
  g.links.push_back(link("l2", "body", "arm", "exec"));
  expect_problem(g, "components and calls (for-each bodies multiply them): the limit");
  // Without the arm, the loops make nothing but still run too many nodes.
  std::erase_if(g.nodes, [](const GraphNode& n) { return n.id == "arm"; });
  std::erase_if(g.links, [](const GraphLink& l) { return l.from.node == "arm" || l.to.node == "arm"; });
  g.nodes.push_back(node("l3", "forEach:int"));
  g.links.push_back(link("many", "value", "l3", "list"));
  g.links.push_back(link("l2", "body", "l3", "exec"));
  expect_problem(g, "the exec chain runs more than 200000 nodes and items");
  // In the file: a list that is not an array, an item of the wrong type.
  const std::string text =
      "{\"buildGraph\": {\"format\": 1,\n"
      "  \"variables\": [{\"name\": \"v\", \"type\": \"list:int\", \"value\": 3}],\n"
      "  \"nodes\": [{\"id\": \"start\", \"kind\": \"start\"},\n"
      "    {\"id\": \"c\", \"kind\": \"constant:list:number\", \"value\": [1, \"x\"]}]}}";
  const std::string p = problems(std::string_view(text));
  EXPECT_NE(p.find("g.build.json:2:"), std::string::npos) << p;
  EXPECT_NE(p.find("'v' is a list:int: an array of int values"), std::string::npos) << p;
  EXPECT_NE(p.find("g.build.json:4:"), std::string::npos) << p;
  EXPECT_NE(p.find("'value': item 1 is not a number"), std::string::npos) << p;
}

TEST(BuildGraphLoops, pure_functions_make_values_per_item_while_the_graph_compiles) {
  static const bool registered = [] {
    BuildFunction named{"test.named", "Name", "", "", {{"prefix", "string", ""}, {"n", "int", ""}},
                        {{"text", "string", ""}}, {Param{"prefix", std::string("x"), {}}},
                        [](FunctionCall& call) -> Status {
                          if (call.has_scene()) return error(ErrorCode::kFailedPrecondition, "a pure call has no scene");
                          call.set_output("text", std::get<std::string>(*call.value("prefix")) +
                                                      std::to_string(std::get<std::int64_t>(*call.value("n"))));
                          return Status::ok();
                        },
                        "test"};
    named.pure = true;
    BuildFunction refuses = named;
    refuses.id = "test.refuses";
    refuses.run = [](FunctionCall&) { return error(ErrorCode::kInvalidArgument, "no name for you"); };
    BuildFunction impure = named;
    impure.id = "test.pureComponent";
    impure.inputs = {{"component", "component", ""}};
    impure.defaults.clear();
    return build_functions().add(named).is_ok() && build_functions().add(refuses).is_ok() &&
           build_functions().add(impure).code() == ErrorCode::kInvalidArgument;
  }();
  ASSERT_TRUE(registered) << "a pure function takes values only";
  const NodeKindRegistry kinds = builtin_node_kinds();
  const NodeKind* kind = kinds.find("function:test.named");
  ASSERT_TRUE(kind);
  EXPECT_FALSE(kind->has_exec()) << "a value node";
  // For each index: a chain named f0, f1 (the name made per item).
  BuildGraph g = sides();
  g.nodes.push_back(node("name", "function:test.named"));
  g.nodes.back().values.push_back(Param{"prefix", std::string("f"), {}});
  g.links.push_back(link("each", "index", "name", "n"));
  g.links.push_back(link("name", "text", "arm", "name"));
  const BuildGraphCompile c = compile_build_graph(reread(g));
  ASSERT_TRUE(c.ok()) << c.errors[0].str();
  const auto& arms = c.definition.components[0].children;
  ASSERT_EQ(arms.size(), 2u);
  EXPECT_EQ(arms[0].full_name(), "f0_L");
  EXPECT_EQ(arms[1].full_name(), "f1_R");
  EXPECT_EQ(c.order, (std::vector<std::string>{"global", "each", "arm", "arm"})) << "a value node is no step";
  // Its failure is the compile's, at the node.
  g.nodes.back().kind = "function:test.refuses";
  EXPECT_NE(problems(g).find("node 'name': function test.refuses (test): no name for you"), std::string::npos)
      << problems(g);
}

TEST(BuildGraphLoops, list_types_and_for_each_kinds_are_in_the_palette) {
  const NodeKindRegistry kinds = builtin_node_kinds();
  for (const char* element : {"bool", "int", "number", "string", "vector"}) {
    const std::string list = std::string("list:") + element;
    EXPECT_EQ(list_element(list), element);
    EXPECT_TRUE(holds_values(list));
    ASSERT_TRUE(kinds.find("constant:" + list)) << list;
    const NodeKind* each = kinds.find(std::string("forEach:") + element);
    ASSERT_TRUE(each) << element;
    EXPECT_EQ(each->input("list")->type, list);
    EXPECT_EQ(each->output("element")->type, element);
    EXPECT_EQ(each->output("index")->type, "int");
  }
  EXPECT_EQ(list_element("number"), "");
  EXPECT_EQ(list_element("list:component"), "");
  EXPECT_FALSE(holds_values("component"));
  const auto palette = graph_palette_json(kinds);
  bool found = false;
  for (const auto& k : palette["kinds"])
    if (k["id"] == "forEach:vector") {
      found = true;
      EXPECT_EQ(k["inputs"][1]["default"], nlohmann::ordered_json::array());
    }
  EXPECT_TRUE(found);
}

}  // namespace
}  // namespace rigel::rig
