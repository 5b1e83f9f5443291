// Plugin node kinds (flow kinds, build_function.h) and lists through
// function nodes: a flow node steers the chain (a repeat builds one
// component per pass, a sequence runs its parts in turn); a pure
// function's list feeds a for-each; a build function takes and gives
// lists, passed to a later call; wrong kinds and bodies refused with the
// node or plugin named.
#include <algorithm>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "build_graph_test_util.h"
#include "rig_test_util.h"
#include "rigel/io/scene_file.h"
#include "rigel/rig/build_function.h"
#include "rigel/rig/build_graph.h"
#include "rigel/rig/meta.h"

namespace rigel::rig {
namespace {

using namespace testing;

// Test kinds and functions, registered once per process (origin "flow tests").
void register_flow_tests() {
  static const bool registered = [] {
    // Goes through `body` once per side of its list, the side on `side`.
    FlowKind per_side;
    per_side.id = "test.perSide";
    per_side.inputs = {{"sides", "list:string", ""}};
    per_side.outputs = {{"side", "string", ""}, {"index", "int", ""}};
    per_side.exits = {"body", "done"};
    per_side.repeats = {"body"};
    per_side.run = [](FlowCall& call) {
      std::int64_t i = 0;
      for (const ParamValue& side : *call.list("sides")) call.go("body", {{{"side", side}, {"index", i++}}, {}});
      call.go("done");
      return Status::ok();
    };
    per_side.origin = "flow tests";
    // first, then second: each part to its chain's end.
    FlowKind two;
    two.id = "test.twoParts";
    two.exits = {"first", "second"};
    two.run = [](FlowCall& call) {
      call.go("first");
      call.go("second");
      return Status::ok();
    };
    two.origin = "flow tests";
    // Misbehaving bodies.
    FlowKind raises = two;
    raises.id = "test.raises";
    raises.run = [](FlowCall&) { return error(ErrorCode::kFailedPrecondition, "refused on purpose"); };
    FlowKind stray = two;
    stray.id = "test.stray";
    stray.run = [](FlowCall& call) {
      call.go("third");
      return Status::ok();
    };
    FlowKind twice = two;
    twice.id = "test.twice";
    twice.run = [](FlowCall& call) {
      call.go("first");
      call.go("first");
      return Status::ok();
    };
    for (FlowKind* k : {&per_side, &two, &raises, &stray, &twice}) {
      const Status s = flow_kinds().add(std::move(*k));
      EXPECT_TRUE(s.is_ok()) << s.message();
    }
    const auto add = [](BuildFunction f) {
      f.origin = "flow tests";
      const Status s = build_functions().add(std::move(f));
      EXPECT_TRUE(s.is_ok()) << s.message();
    };
    // Pure: the sides a text names ("LR" -> ["L", "R"]).
    BuildFunction letters{"test.letters", "", "", "", {{"text", "string", ""}}, {{"items", "list:string", ""}}, {},
                          [](FunctionCall& call) -> Status {
                            ValueList items;
                            for (char c : std::get<std::string>(*call.value("text"))) items.emplace_back(std::string(1, c));
                            call.set_list_output("items", std::move(items));
                            return Status::ok();
                          },
                          {}};
    letters.pure = true;
    add(letters);
    // A build step: each number doubled (ints given are numbers).
    add({"test.doubleAll", "", "", "", {{"xs", "list:number", ""}}, {{"ys", "list:number", ""}, {"n", "int", ""}}, {},
         [](FunctionCall& call) -> Status {
           ValueList ys;
           for (const ParamValue& x : *call.list("xs")) ys.emplace_back(2.0 * std::get<double>(x));
           call.set_output("n", static_cast<std::int64_t>(ys.size()));
           call.set_list_output("ys", std::move(ys));
           return Status::ok();
         },
         {}});
    // A build step that sets a list output to a wrong item.
    add({"test.badList", "", "", "", {}, {{"ys", "list:int", ""}}, {},
         [](FunctionCall& call) -> Status {
           ValueList ys;
           ys.emplace_back(std::string("seven"));
           call.set_list_output("ys", std::move(ys));
           return Status::ok();
         },
         {}});
    return true;
  }();
  (void)registered;
}

// start -> global -> FLOW (its body: an arm drawn on the left joints, given
// the pass's side, under the global).
BuildGraph per_side(const std::string& kind, ValueList sides) {
  register_flow_tests();
  BuildGraph g;
  g.rig.name = "flows";
  Component arm = fk_chain("arm", Side::kLeft, {"upper_arm.L", "forearm.L", "hand.L"});
  arm.rig_id.clear();
  GraphNode flow = node("each", kind);
  flow.lists["sides"] = std::move(sides);
  g.nodes = {node("start", "start"), component_node("global", global_component()), flow, component_node("arm", arm)};
  g.links = {link("start", "then", "global", "exec"), link("global", "then", "each", "exec"),
             link("each", "body", "arm", "exec"), link("each", "side", "arm", "side"),
             link("global", "component", "arm", "parent")};
  return g;
}

TEST(BuildGraphFlowKinds, a_plugin_flow_node_repeats_its_body_with_its_outputs_each_pass_keyed) {
  const BuildGraph g = reread(per_side("flow:test.perSide", texts({"L", "R"})));
  const BuildGraphCompile c = compile_build_graph(g);
  const std::vector<Component> arms = two_arms(c);
  ASSERT_EQ(arms.size(), 2u);
  EXPECT_EQ(c.order, (std::vector<std::string>{"global", "each", "arm", "arm"}));
  // The pass's rigId is the for-each item's: the same graph, the same ids;
  // the left arm keeps its id when a pass is added after it.
  const BuildGraphCompile one = compile_build_graph(per_side("flow:test.perSide", texts({"L"})));
  ASSERT_TRUE(one.ok());
  EXPECT_EQ(one.definition.components[0].children[0].rig_id, arms[0].rig_id);
  // Built, then removed: the scene back byte for byte.
  BuiltRig r = built_rig(c.definition);
  ASSERT_TRUE(r.build);
  ASSERT_TRUE(r.build->remove().is_ok());
  const std::string text = io::write_scene(*r.scene);
  EXPECT_TRUE(text == r.before) << first_difference(text, r.before);
  // The palette offers the kind with its exits as exec outputs.
  bool offered = false;
  const nlohmann::ordered_json palette = graph_palette_json(builtin_node_kinds());
  for (const auto& k : palette["kinds"])
    if (k["id"] == "flow:test.perSide") {
      offered = true;
      EXPECT_EQ(k["category"], "Flow");
      EXPECT_EQ(k["outputs"][0]["name"], "body");
      EXPECT_EQ(k["outputs"][0]["type"], "exec");
      EXPECT_EQ(k["inputs"][1]["default"], nlohmann::ordered_json::array());
    }
  EXPECT_TRUE(offered);
}

TEST(BuildGraphFlowKinds, a_part_reads_what_an_earlier_part_made_and_the_chain_goes_on_through_the_last_exit) {
  register_flow_tests();
  BuildGraph g;
  g.rig.name = "parts";
  Component arm = fk_chain("arm", Side::kLeft, {"upper_arm.L", "forearm.L", "hand.L"});
  Component arm_r = fk_chain("arm", Side::kRight, {"upper_arm.R", "forearm.R", "hand.R"});
  g.nodes = {node("start", "start"), node("parts", "flow:test.twoParts"), component_node("global", global_component()),
             component_node("armL", arm), component_node("armR", arm_r)};
  g.links = {link("start", "then", "parts", "exec"),       link("parts", "first", "global", "exec"),
             link("parts", "second", "armL", "exec"),      link("armL", "then", "armR", "exec"),
             link("global", "component", "armL", "parent"), link("global", "component", "armR", "parent")};
  const BuildGraphCompile c = compile_build_graph(reread(g));
  ASSERT_TRUE(c.ok()) << c.errors[0].str();
  EXPECT_EQ(c.order, (std::vector<std::string>{"parts", "global", "armL", "armR"}));
  ASSERT_EQ(c.definition.components.size(), 1u);
  EXPECT_EQ(c.definition.components[0].children.size(), 2u);
  EXPECT_EQ(c.definition.components[0].children[0].rig_id, arm.rig_id) << "a part that does not repeat is not keyed";
}

TEST(BuildGraphFlowKinds, bad_flow_bodies_unknown_kinds_and_bad_registrations_are_refused_by_name) {
  const auto first_problem = [](const std::string& kind) {
    BuildGraph g = per_side(kind, texts({"L"}));
    g.nodes[2].lists.clear();
    g.links.push_back(link("each", "first", "arm", "exec"));
    std::erase_if(g.links, [](const GraphLink& l) { return l.from.socket == "body" || l.from.socket == "side"; });
    return problems(g);
  };
  EXPECT_NE(first_problem("flow:test.raises").find("node 'each': node kind test.raises (flow tests): refused on purpose"),
            std::string::npos)
      << first_problem("flow:test.raises");
  EXPECT_NE(first_problem("flow:test.stray").find("'third', which is not one of its exits"), std::string::npos);
  EXPECT_NE(first_problem("flow:test.twice").find("'first' twice"), std::string::npos);
  EXPECT_NE(problems(per_side("flow:test.nobody", {})).find("unknown node kind 'flow:test.nobody'"), std::string::npos);
  // Registrations.
  FlowKind again;
  again.id = "test.perSide";
  again.run = [](FlowCall&) { return Status::ok(); };
  again.origin = "other.py";
  Status s = flow_kinds().add(again);
  EXPECT_EQ(s.code(), ErrorCode::kAlreadyExists);
  EXPECT_NE(s.message().find("other.py"), std::string::npos);
  EXPECT_NE(s.message().find("flow tests"), std::string::npos);
  again.id = "test.fresh";
  again.repeats = {"body"};
  EXPECT_NE(flow_kinds().add(again).message().find("repeat 'body' is not one of its exits"), std::string::npos);
  again.repeats.clear();
  again.inputs = {{"c", "component", ""}};
  EXPECT_EQ(flow_kinds().add(again).code(), ErrorCode::kInvalidArgument) << "a flow runs before anything is built";
  again.inputs.clear();
  again.exits = {};
  EXPECT_EQ(flow_kinds().add(again).code(), ErrorCode::kInvalidArgument);
  EXPECT_FALSE(flow_kinds().find("test.fresh"));
}

TEST(BuildGraphFlowKinds, a_pure_functions_list_feeds_a_for_each) {
  register_flow_tests();
  BuildGraph g = per_side("forEach:string", {});
  g.nodes[2].lists.clear();
  g.nodes.push_back(node("letters", "function:test.letters"));
  g.nodes.back().values.push_back(Param{"text", std::string("LR"), {}});
  g.links.push_back(link("letters", "items", "each", "list"));
  for (GraphLink& l : g.links)
    if (l.from.socket == "side") l.from.socket = "element";
  const std::vector<Component> arms = two_arms(compile_build_graph(reread(g)));
  EXPECT_EQ(arms.size(), 2u);
}

// start -> double [1, 2.5] -> double its output; the lists kept on the calls' meta nodes.
BuildGraph doubled() {
  register_flow_tests();
  BuildGraph g;
  g.rig.name = "lists";
  GraphNode first = node("d1", "function:test.doubleAll");
  ValueList xs;
  xs.emplace_back(std::int64_t{1});
  xs.emplace_back(2.5);
  first.lists["xs"] = xs;
  g.nodes = {node("start", "start"), component_node("global", global_component()), first,
             node("d2", "function:test.doubleAll")};
  g.links = {link("start", "then", "global", "exec"), link("global", "then", "d1", "exec"),
             link("d1", "then", "d2", "exec"), link("d1", "ys", "d2", "xs")};
  return g;
}

TEST(BuildGraphFlowKinds, build_functions_take_and_give_lists_passed_to_later_calls) {
  const BuildGraph g = reread(doubled());
  EXPECT_NE(write_build_graph(g).find("\"xs\": [1.0, 2.5]"), std::string::npos) << write_build_graph(g);
  BuiltRig r = built_rig(compiled(g));
  ASSERT_TRUE(r.build);
  const NodeId root = find_rig(r.g(), "lists");
  const auto outputs = [&](const std::string& node) {
    const BuildGraphCompile c = compile_build_graph(g);
    for (const auto& [id, rig_id] : c.rig_ids)
      if (id == node) return meta_string(r.g(), find_component(r.g(), root, rig_id), kOutputsAttr);
    return std::string("(none)");
  };
  EXPECT_EQ(outputs("d1"), "{\"ys\":[2.0,5.0],\"n\":2}");
  EXPECT_EQ(outputs("d2"), "{\"ys\":[4.0,10.0],\"n\":2}");
  // A list the build makes is known only to the build: a for-each over it is refused.
  BuildGraph over = doubled();
  over.nodes.push_back(node("each", "forEach:number"));
  over.links.push_back(link("d2", "then", "each", "exec"));
  over.links.push_back(link("d2", "ys", "each", "list"));
  EXPECT_NE(problems(over).find("node 'each': input 'list' reads a value the build makes"), std::string::npos)
      << problems(over);
  // A wrong item in a list output fails the step, naming the call and output.
  BuildGraph bad = doubled();
  bad.nodes.push_back(node("bad", "function:test.badList"));
  bad.links.push_back(link("d2", "then", "bad", "exec"));
  BuiltRig failed;
  failed.scene = metarig();
  auto b = Build::open(*failed.scene, compiled(bad), builtin_components());
  ASSERT_TRUE(b.is_ok());
  const Status s = (*b)->build_all();
  EXPECT_FALSE(s.is_ok());
  EXPECT_NE(s.message().find("output 'ys' is not a list:int"), std::string::npos) << s.message();
  // Registration refuses a list of components.
  BuildFunction wrong{"test.wrongList", "", "", "", {{"xs", "list:component", ""}}, {}, {},
                      [](FunctionCall&) { return Status::ok(); }, "flow tests"};
  EXPECT_EQ(build_functions().add(wrong).code(), ErrorCode::kInvalidArgument);
}

}  // namespace
}  // namespace rigel::rig
