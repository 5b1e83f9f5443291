// Build graphs (build_graph.h): the file, compiling to a definition, the
// definition's graph, and graph-built rigs stepped, rebuilt in part and
// removed like definition-built ones; every malformed graph refused with
// the node and socket named.
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "build_graph_test_util.h"
#include "rig_test_util.h"
#include "rigel/rig/build_function.h"
#include "rigel/rig/build_graph.h"
#include "rigel/rig/definition_io.h"

namespace rigel::rig {
namespace {

using namespace testing;
namespace fs = std::filesystem;

// global -> hip -> torso (fkChain), drawn by hand: the arm's side comes
// from a variable that a set node changes between two arms.
BuildGraph drawn() {
  BuildGraph g;
  g.rig.name = "drawn";
  g.variables.push_back(GraphVariable{"side", "string", std::string("L"), {}, {}});
  Component global;
  global.type = "global";
  global.name = "global";
  global.rig_id = new_rig_id();
  global.guides = {Guide{}};
  Component hip;
  hip.type = "hip";
  hip.name = "hip";
  hip.rig_id = new_rig_id();
  hip.guides = {at_joint("spine")};
  Component arm_l = fk_chain("arm", Side::kCenter, {"shoulder.L", "upper_arm.L", "forearm.L", "hand.L"});
  Component arm_r = fk_chain("arm", Side::kCenter, {"shoulder.R", "upper_arm.R", "forearm.R", "hand.R"});
  g.nodes = {node("start", "start"), component_node("global", global), component_node("hip", hip),
             component_node("armL", arm_l), node("toR", "variable:set"), component_node("armR", arm_r),
             node("side", "variable:get"), node("side2", "variable:get"), node("right", "constant:string")};
  g.nodes[4].variable = g.nodes[6].variable = g.nodes[7].variable = "side";
  g.nodes[8].values.push_back(Param{"value", std::string("R"), {}});
  g.links = {link("start", "then", "global", "exec"),    link("global", "then", "hip", "exec"),
             link("hip", "then", "armL", "exec"),         link("armL", "then", "toR", "exec"),
             link("toR", "then", "armR", "exec"),         link("global", "component", "hip", "parent"),
             link("hip", "component", "armL", "parent"),  link("hip", "component", "armR", "parent"),
             link("side", "value", "armL", "side"),       link("right", "value", "toR", "value"),
             link("side2", "value", "armR", "side")};
  return g;
}

TEST(BuildGraph, a_definitions_graph_compiles_to_the_definition_and_its_file_reads_back_the_same) {
  for (const char* name : {"biped.rig.xml", "puppet.rig.xml"}) {
    const Definition d = example(name);
    const BuildGraph g = convert_definition(d);
    const std::string text = write_build_graph(g);
    const BuildGraph back = reread(g);
    EXPECT_EQ(write_build_graph(back), text) << name;
    EXPECT_EQ(write_definition(compiled(back), Syntax::kJson), write_definition(d, Syntax::kJson)) << name;
    EXPECT_TRUE(compile_build_graph(back).warnings.empty()) << name;
  }
  // Nodes are one block each, links one line each.
  const std::string text = write_build_graph(convert_definition(example("biped.rig.xml")));
  EXPECT_NE(text.find("{\"from\": \"start.then\", \"to\": \"global.exec\"}"), std::string::npos) << text.substr(0, 2000);
}

TEST(BuildGraph, a_graph_file_is_read_wherever_a_definition_is) {
  const fs::path dir = fs::temp_directory_path() / ("rigel_graph_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path file = dir / "drawn.build.json";
  ASSERT_TRUE(save_build_graph(drawn(), file).is_ok());
  ParseResult loaded = load_definition(file);
  ASSERT_TRUE(loaded.ok()) << loaded.errors[0].str();
  EXPECT_TRUE(check_definition(file).empty());
  EXPECT_EQ(loaded.definition.source, file.string());
  // A definition is not saved over a graph; a graph needs its suffix.
  EXPECT_EQ(save_definition(loaded.definition, file).code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(save_build_graph(drawn(), dir / "drawn.json").code(), ErrorCode::kInvalidArgument);
  fs::remove_all(dir);
}

TEST(BuildGraph, variables_and_links_carry_values_along_the_exec_chain) {
  const Definition d = compiled(drawn());
  ASSERT_EQ(d.components.size(), 1u);
  const Component& hip = d.components[0].children.at(0);
  ASSERT_EQ(hip.children.size(), 2u);
  EXPECT_EQ(hip.children[0].full_name(), "arm_L") << "read before the set";
  EXPECT_EQ(hip.children[1].full_name(), "arm_R") << "read after the set";
  // A branch takes the way its condition says; the other way is not built.
  BuildGraph g = drawn();
  g.nodes.push_back(node("which", "branch"));
  g.nodes.back().values.push_back(Param{"condition", false, {}});
  g.links[3] = link("armL", "then", "which", "exec");
  g.links.push_back(link("which", "false", "toR", "exec"));
  EXPECT_EQ(compiled(g).components[0].children[0].children.size(), 2u);
  g.nodes.back().values[0].value = true;
  EXPECT_EQ(compiled(g).components[0].children[0].children.size(), 1u);
  // A linked parameter takes the value that reaches it (an int into a number).
  g = drawn();
  g.nodes[3].kind = "component:ikChain";
  g.nodes[3].component.type = "ikChain";
  g.nodes.push_back(node("distance", "constant:int"));
  g.nodes.back().values.push_back(Param{"value", std::int64_t{3}, {}});
  g.links.push_back(link("distance", "value", "armL", "poleDistance"));
  const Definition with_distance = compiled(g);
  const Param* distance = with_distance.components[0].children[0].children[0].param("poleDistance");
  ASSERT_TRUE(distance);
  EXPECT_EQ(std::get<double>(distance->value), 3.0);
}

TEST(BuildGraph, a_graph_build_steps_rebuilds_what_a_changed_node_feeds_and_is_removed_exactly) {
  BuildGraph g = drawn();
  BuiltRig r = built_rig(compiled(g));
  ASSERT_TRUE(r.build);
  expect_stepping_gives_the_straight_build(*r.build, *r.scene);
  // Uuids of every built node, by name.
  const auto uuids = [&] {
    std::map<std::string, std::string> out;
    for (NodeId id : r.g().nodes()) out[r.g().node(id)->name()] = r.g().node(id)->uuid().str();
    return out;
  };
  const auto before = uuids();
  // The right arm's chain gets one joint fewer: only it is built again.
  g.nodes[5].component.guides.pop_back();
  auto rebuilt = r.build->rebuild_changed(compiled(g));
  ASSERT_TRUE(rebuilt.is_ok()) << rebuilt.status().message();
  EXPECT_EQ(*rebuilt, std::vector<std::string>{g.nodes[5].component.rig_id});
  const auto after = uuids();
  int kept = 0, remade = 0;
  for (const auto& [name, uuid] : after) {
    const auto it = before.find(name);
    if (it == before.end()) continue;
    if (name.find("arm_R") != std::string::npos) remade += it->second != uuid;
    else EXPECT_EQ(it->second, uuid) << name << " was built again";
    kept += it->second == uuid;
  }
  EXPECT_GT(remade, 0);
  EXPECT_GT(kept, 100);
  ASSERT_TRUE(r.build->remove().is_ok());
  const std::string text = io::write_scene(*r.scene);
  EXPECT_TRUE(text == r.before) << first_difference(text, r.before);
}

TEST(BuildGraph, wrong_graphs_are_refused_naming_the_node_and_socket) {
  const auto expect_problem = [](const BuildGraph& g, const std::string& part) {
    const std::string p = problems(g);
    EXPECT_NE(p.find(part), std::string::npos) << "expected '" << part << "' in:\n" << p;
  };
  BuildGraph g = drawn();
  g.links.push_back(link("global", "component", "armL", "parent"));
  expect_problem(g, "input 'armL.parent' has two links (from 'hip.component' and 'global.component')");
  g = drawn();
  g.links.push_back(link("right", "value", "armL", "parent"));
  expect_problem(g, "link 'right.value' -> 'armL.parent': a string output cannot feed a component input");
  g = drawn();
  g.links.push_back(link("global", "component", "armL", "name"));
  expect_problem(g, "link 'global.component' -> 'armL.name': a component output cannot feed a string input");
  g = drawn();
  g.links.push_back(link("armL", "then", "hip", "exec"));
  expect_problem(g, "exec output 'armL.then' has two links");
  g = drawn();
  g.links[4] = link("toR", "then", "hip", "exec");  // armR is left off the chain, and hip runs twice
  expect_problem(g, "node 'armR': not on the exec chain from start");
  g.nodes.erase(g.nodes.begin() + 5);
  g.links.erase(std::remove_if(g.links.begin(), g.links.end(),
                               [](const GraphLink& l) { return l.to.node == "armR" || l.from.node == "armR"; }),
                g.links.end());
  expect_problem(g, "exec links form a cycle: hip -> armL -> toR -> hip");
  g = drawn();
  g.links.push_back(link("armL", "component", "global", "parent"));
  expect_problem(g, "data links form a cycle");
  g = drawn();
  g.links[5] = link("hip", "component", "global", "parent");
  g.links[6] = link("global", "component", "armL", "parent");
  expect_problem(g, "node 'global': input 'parent' reads 'hip.component', but 'hip' has not run by then");
  g = drawn();
  g.nodes[2].kind = "component:elbow";
  expect_problem(g, "node 'hip': unknown node kind 'component:elbow'");
  g = drawn();
  g.nodes[0].kind = "constant:bool";
  expect_problem(g, "the graph has no start node");
  g = drawn();
  g.nodes[4].variable = "colour";
  expect_problem(g, "node 'toR': variable 'colour' is not one of the graph's variables");
  g = drawn();
  g.links.push_back(link("armL", "then", "nowhere", "exec"));
  expect_problem(g, "no node 'nowhere'");
  g = drawn();
  g.links.push_back(link("right", "colour", "armL", "name"));
  expect_problem(g, "constant:string has no output 'colour'");
  g = drawn();
  g.nodes[8].values[0].value = 2.0;
  expect_problem(g, "the value of 'value' is not a string");
  g = drawn();
  g.nodes[8].values[0].value = std::string("Q");
  expect_problem(g, "node 'armR': input 'side': 'Q' is not C, L or R");
  // What validate() finds in the definition is reported at the node's place.
  g = drawn();
  g.nodes[1].component.params.push_back(Param{"colour", std::string("x"), {}});
  expect_problem(g, "colour");
}

TEST(BuildGraph, a_malformed_file_is_reported_at_its_line) {
  EXPECT_NE(problems("{\"buildGraph\": {\"format\": 1, \"nodes\": [").find("g.build.json:1:"), std::string::npos);
  EXPECT_NE(problems("{\"buildGraph\": {\"format\": 2, \"nodes\": []}}").find("'format' must be 1"), std::string::npos);
  const std::string text =
      "{\"buildGraph\": {\"format\": 1,\n"
      "  \"nodes\": [{\"id\": \"start\", \"kind\": \"start\"},\n"
      "    {\"id\": \"a\", \"kind\": \"component:global\", \"component\": {\"name\": \"g\", \"children\": []}},\n"
      "    {\"id\": \"b\", \"kind\": \"start\", \"colour\": 1}],\n"
      "  \"links\": [{\"from\": \"start\", \"to\": \"a.exec\"}]}}";
  const std::string p = problems(text);
  EXPECT_NE(p.find("g.build.json:3:"), std::string::npos) << p;
  EXPECT_NE(p.find("nest with a 'parent' link"), std::string::npos) << p;
  EXPECT_NE(p.find("g.build.json:4:"), std::string::npos) << p;
  EXPECT_NE(p.find("unknown key 'colour'"), std::string::npos) << p;
  EXPECT_NE(p.find("'from' must be NODE.OUTPUT"), std::string::npos) << p;
  // A graph that does not compile is no definition: nothing is built from it.
  const fs::path file = fs::temp_directory_path() / ("rigel_bad_" + std::to_string(::getpid()) + ".build.json");
  {
    std::ofstream(file) << text;
  }
  EXPECT_FALSE(load_definition(file).ok());
  fs::remove(file);
}

TEST(BuildGraph, node_kinds_follow_the_schemas_and_types_refuse_what_does_not_fit) {
  const NodeKindRegistry kinds = builtin_node_kinds();
  for (const std::string& type : builtin_schemas().types()) {
    const NodeKind* k = kinds.find("component:" + type);
    ASSERT_TRUE(k) << type;
    for (const ParamSpec& p : builtin_schemas().find(type)->params) {
      ASSERT_TRUE(k->input(p.name)) << type << "." << p.name;
      EXPECT_EQ(k->input(p.name)->type, data_type_of(p.type));
    }
  }
  EXPECT_TRUE(DataTypeRegistry::can_link("int", "number"));
  EXPECT_FALSE(DataTypeRegistry::can_link("number", "int"));
  DataTypeRegistry types;
  DataType number;
  number.name = "number";
  number.color = "#000000";
  number.value_type = ParamType::kDouble;
  ASSERT_TRUE(types.add(number).is_ok());
  EXPECT_EQ(types.add(number).code(), ErrorCode::kAlreadyExists);
  DataType curve;
  curve.name = "curve";
  curve.color = "red";
  EXPECT_EQ(types.add(curve).code(), ErrorCode::kInvalidArgument);
  NodeKindRegistry more = kinds;
  EXPECT_EQ(more.add(NodeKind{"branch", "", "", {}, {}, ""}).code(), ErrorCode::kAlreadyExists);
  EXPECT_EQ(more.add(NodeKind{"x", "", "", {{"a", "curve", ""}}, {}, ""}).code(), ErrorCode::kInvalidArgument);
}

}  // namespace
}  // namespace rigel::rig

// ---- function nodes -------------------------------------------------------------

namespace rigel::rig {
namespace {

// Test functions, registered once per process (origin "rig tests").
void register_test_functions() {
  static const bool registered = [] {
    FunctionRegistry& r = build_functions();
    const auto add = [&](BuildFunction f) {
      f.origin = "rig tests";
      const Status s = r.add(std::move(f));
      EXPECT_TRUE(s.is_ok()) << s.message();
    };
    // Colours each control of a component (a change to nodes another step made).
    add({"test.colorControls", "Colour controls", "Test", "",
         {{"component", "component", ""}, {"color", "vector", ""}}, {{"count", "int", ""}}, {},
         [](FunctionCall& call) -> Status {
           graph::Graph& g = call.scene().graph();
           std::int64_t count = 0;
           for (NodeId m : meta_members(g, call.component("component")))
             if (g.node(m)->type().name() == scene::kControlType) {
               const graph::Plug color{m, scene::control_attr::kShapeColor, -1};
               if (Status s = g.set_value(color, graph::Value(std::get<math::Vec3>(*call.value("color")))); !s)
                 return s;
               ++count;
             }
           call.set_output("count", count);
           return Status::ok();
         },
         {}});
    add({"test.double", "Double", "Test", "", {{"x", "number", ""}}, {{"y", "number", ""}},
         {Param{"x", 1.0, {}}},
         [](FunctionCall& call) -> Status {
           call.set_output("y", 2.0 * std::get<double>(*call.value("x")));
           return Status::ok();
         },
         {}});
    add({"test.fail", "Fail", "Test", "", {}, {}, {},
         [](FunctionCall&) { return error(ErrorCode::kFailedPrecondition, "refused on purpose"); }, {}});
    return true;
  }();
  (void)registered;
}

// drawn(), then: colour the left arm's controls; double 1.5 into variable v;
// double v twice more (one variable, two later readers).
BuildGraph with_functions() {
  register_test_functions();
  BuildGraph g = drawn();
  g.variables.push_back(GraphVariable{"v", "number", 0.0, {}, {}});
  const auto add = [&](std::string id, std::string kind) {
    g.nodes.push_back(node(std::move(id), std::move(kind)));
    return &g.nodes.back();
  };
  add("tag", "function:test.colorControls");
  add("grey", "constant:vector")->values.push_back(Param{"value", math::Vec3(0.25, 0.5, 0.75), {}});
  add("dbl", "function:test.double")->values.push_back(Param{"x", 1.5, {}});
  add("toV", "variable:set")->variable = "v";
  add("v1", "variable:get")->variable = "v";
  add("v2", "variable:get")->variable = "v";
  add("dbl2", "function:test.double");
  add("dbl3", "function:test.double");
  for (GraphLink l : {link("armR", "then", "tag", "exec"), link("tag", "then", "dbl", "exec"),
                      link("dbl", "then", "toV", "exec"), link("toV", "then", "dbl2", "exec"),
                      link("dbl2", "then", "dbl3", "exec"), link("armL", "component", "tag", "component"),
                      link("grey", "value", "tag", "color"), link("dbl", "y", "toV", "value"),
                      link("v1", "value", "dbl2", "x"), link("v2", "value", "dbl3", "x")})
    g.links.push_back(l);
  return g;
}

const Component* component_named(const Definition& d, const std::string& name) {
  for (const Component* c : d.all_components())
    if (c->name == name) return c;
  return nullptr;
}

TEST(BuildGraphFunctions, function_nodes_compile_to_calls_after_what_they_read) {
  const Definition d = compiled(with_functions());
  ASSERT_EQ(d.components.size(), 5u) << "global, then the calls tag, dbl, dbl2, dbl3 as roots";
  const Component* tag = component_named(d, "tag");
  const Component* dbl = component_named(d, "dbl");
  const Component* dbl2 = component_named(d, "dbl2");
  const Component* arm_l = component_named(d, "arm");
  ASSERT_TRUE(tag && dbl && dbl2 && arm_l);
  EXPECT_EQ(tag->type, kCallType);
  EXPECT_EQ(tag->after, std::vector<std::string>{arm_l->rig_id});
  EXPECT_EQ(std::get<std::string>(tag->param("args")->value),
            "{\"component\":{\"$component\":\"" + arm_l->rig_id + "\"},\"color\":[0.25,0.5,0.75]}");
  EXPECT_EQ(std::get<std::string>(dbl->param("args")->value), "{\"x\":1.5}");
  EXPECT_EQ(std::get<std::string>(dbl2->param("args")->value), "{\"x\":{\"$output\":[\"" + dbl->rig_id + "\",\"y\"]}}");
  EXPECT_EQ(dbl2->after, std::vector<std::string>{dbl->rig_id});
  // Stable ids: the same graph compiles to the same rigIds.
  EXPECT_EQ(component_named(compiled(with_functions()), "dbl2")->rig_id, dbl2->rig_id);
  // The definition's graph has the calls as function nodes again, and
  // compiles to the same definition.
  const BuildGraph back = convert_definition(d);
  ASSERT_TRUE(back.find("dbl2") && back.find("tag"));
  EXPECT_EQ(back.find("dbl2")->kind, "function:test.double");
  EXPECT_EQ(back.find("tag")->rig_id, tag->rig_id);
  EXPECT_EQ(write_definition(compiled(reread(back)), Syntax::kJson), write_definition(d, Syntax::kJson));
  for (const auto& k : graph_palette_json(builtin_node_kinds())["kinds"].get<std::vector<nlohmann::ordered_json>>())
    EXPECT_NE(k["id"], "component:call") << "the palette offers functions, not their calls";
  // The definition round-trips through both syntaxes with its calls.
  for (Syntax syntax : {Syntax::kXml, Syntax::kJson}) {
    ParseResult back = parse_definition(write_definition(d, syntax), syntax, "calls");
    ASSERT_TRUE(back.ok());
    EXPECT_EQ(write_definition(back.definition, Syntax::kJson), write_definition(d, Syntax::kJson));
  }
}

TEST(BuildGraphFunctions, calls_are_build_steps_stepped_rebuilt_by_data_flow_and_removed_exactly) {
  BuildGraph g = with_functions();
  BuiltRig r = built_rig(compiled(g));
  ASSERT_TRUE(r.build);
  graph::Graph& graph = r.g();
  // The metaRoot is made again when the build steps back to 0: found each time.
  const auto rig = [&] { return find_rig(graph, "drawn"); };
  const auto output = [&](const std::string& call) {
    const NodeId meta = find_component(graph, rig(), call);
    return meta.is_valid() ? meta_string(graph, meta, kOutputsAttr) : std::string("(none)");
  };
  EXPECT_EQ(output("dbl"), "{\"y\":3.0}");
  EXPECT_EQ(output("dbl2"), "{\"y\":6.0}");
  EXPECT_EQ(output("dbl3"), "{\"y\":6.0}");
  EXPECT_EQ(output("tag"), "{\"count\":4}");
  const NodeId fk0 = *resolve_address(graph, "drawn:arm_L/fk[0]");
  EXPECT_EQ(std::get<math::Vec3>(graph.node(fk0)->value(scene::control_attr::kShapeColor)), math::Vec3(0.25, 0.5, 0.75));
  expect_stepping_gives_the_straight_build(*r.build, *r.scene);

  const auto uuids = [&] {
    std::map<std::string, std::string> out;
    for (NodeId id : graph.nodes()) out[graph.node(id)->name()] = graph.node(id)->uuid().str();
    return out;
  };
  // A new constant: only the calls that read it, directly or through the variable.
  for (GraphNode& n : g.nodes)
    if (n.id == "dbl") n.values[0].value = 2.0;
  auto rebuilt = r.build->rebuild_changed(compiled(g));
  ASSERT_TRUE(rebuilt.is_ok()) << rebuilt.status().message();
  std::vector<std::string> names;
  for (const std::string& id : *rebuilt)
    names.push_back(meta_string(graph, find_component(graph, rig(), id), "componentName"));
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"dbl", "dbl2", "dbl3"}));
  EXPECT_EQ(output("dbl3"), "{\"y\":8.0}");
  // The left arm's chain changes: it and the call that reads it.
  const auto before = uuids();
  for (GraphNode& n : g.nodes)
    if (n.id == "armL") n.component.guides.pop_back();
  rebuilt = r.build->rebuild_changed(compiled(g));
  ASSERT_TRUE(rebuilt.is_ok()) << rebuilt.status().message();
  names.clear();
  for (const std::string& id : *rebuilt)
    names.push_back(meta_string(graph, find_component(graph, rig(), id), "componentName"));
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"arm_L", "tag"}));
  const auto after = uuids();
  for (const std::string kept : {"drawn_arm_R_fk0", "drawn_global_main"}) {
    ASSERT_TRUE(before.count(kept) && after.count(kept)) << kept;
    EXPECT_EQ(before.at(kept), after.at(kept)) << kept;
  }
  EXPECT_EQ(output("tag"), "{\"count\":3}");
  ASSERT_TRUE(r.build->remove().is_ok());
  const std::string text = io::write_scene(*r.scene);
  EXPECT_TRUE(text == r.before) << first_difference(text, r.before);
}

TEST(BuildGraphFunctions, a_component_nodes_controls_joints_and_hooks_reach_a_function) {
  static const bool registered = [] {
    BuildFunction f{"test.countMade", "Count what a component made", "Test", "",
                    {{"controls", "list:control", ""}, {"joints", "list:joint", ""}, {"hooks", "list:node", ""}},
                    {{"controls", "int", ""}, {"joints", "string", ""}, {"hooks", "int", ""}},
                    {},
                    [](FunctionCall& call) -> Status {
                      const graph::Graph& g = call.scene().graph();
                      std::string joints;
                      for (NodeId j : *call.nodes("joints")) joints += g.node(j)->name() + " ";
                      call.set_output("controls", static_cast<std::int64_t>(call.nodes("controls")->size()));
                      call.set_output("joints", joints);
                      call.set_output("hooks", static_cast<std::int64_t>(call.nodes("hooks")->size()));
                      return Status::ok();
                    },
                    {}};
    return build_functions().add(std::move(f)).is_ok();
  }();
  ASSERT_TRUE(registered);
  BuildGraph g = drawn();
  g.nodes.push_back(node("count", "function:test.countMade"));
  g.links.push_back(link("armR", "then", "count", "exec"));
  for (const char* what : {"controls", "joints", "hooks"}) g.links.push_back(link("armL", what, "count", what));
  const Definition d = compiled(g);
  const Component* count = component_named(d, "count");
  ASSERT_TRUE(count);
  const std::string arm = component_named(d, "arm")->rig_id;
  EXPECT_EQ(std::get<std::string>(count->param("args")->value),
            "{\"controls\":{\"$controls\":\"" + arm + "\"},\"joints\":{\"$joints\":\"" + arm +
                "\"},\"hooks\":{\"$hooks\":\"" + arm + "\"}}");
  BuiltRig r = built_rig(d);
  ASSERT_TRUE(r.build);
  const NodeId meta = find_component(r.g(), find_rig(r.g(), "drawn"), "count");
  EXPECT_EQ(meta_string(r.g(), meta, kOutputsAttr),
            "{\"controls\":4,\"joints\":\"shoulder.L upper_arm.L forearm.L hand.L \",\"hooks\":4}");
  // Only function nodes take them; a function's node-list input needs its link.
  g.links.push_back(link("armL", "controls", "armR", "parent"));
  EXPECT_NE(problems(g).find("a list:control output cannot feed a component input"), std::string::npos) << problems(g);
  g.links.pop_back();
  g.links.pop_back();
  EXPECT_NE(problems(g).find("node 'count': input 'hooks' needs a link from a component node's 'hooks' output"),
            std::string::npos)
      << problems(g);
}

TEST(BuildGraphFunctions, a_plugins_data_type_carries_a_value_from_one_function_to_another) {
  DataType curve;
  curve.name = "test.curve";
  curve.color = "#12ab34";
  curve.origin = "curves.py";
  ASSERT_TRUE(register_data_type(curve).is_ok());
  DataType again = curve;
  again.origin = "other.py";
  const Status taken = register_data_type(again);
  EXPECT_EQ(taken.code(), ErrorCode::kAlreadyExists);
  EXPECT_NE(taken.message().find("other.py"), std::string::npos) << taken.message();
  EXPECT_NE(taken.message().find("by curves.py"), std::string::npos) << taken.message();
  again.name = "list:curve";
  EXPECT_EQ(register_data_type(again).code(), ErrorCode::kInvalidArgument);
  again.name = "curve2";
  again.origin.clear();
  EXPECT_EQ(register_data_type(again).code(), ErrorCode::kInvalidArgument);
  EXPECT_TRUE(is_plugin_type("test.curve"));
  EXPECT_FALSE(is_plugin_type("number"));
  ASSERT_TRUE(build_functions()
                  .add({"test.makeCurve", "Make a curve", "Test", "", {}, {{"curve", "test.curve", ""}}, {},
                        [](FunctionCall& call) -> Status {
                          call.set_output("curve", std::string(R"({"points": [0, 0.5, 1]})"));
                          return Status::ok();
                        },
                        "curves.py"})
                  .is_ok());
  ASSERT_TRUE(build_functions()
                  .add({"test.curveLength", "Count a curve's points", "Test", "", {{"curve", "test.curve", ""}},
                        {{"points", "int", ""}}, {},
                        [](FunctionCall& call) -> Status {
                          const auto j = nlohmann::json::parse(std::get<std::string>(*call.value("curve")));
                          call.set_output("points", static_cast<std::int64_t>(j.is_null() ? -1 : j["points"].size()));
                          return Status::ok();
                        },
                        "curves.py"})
                  .is_ok());
  BuildGraph g = drawn();
  g.nodes.push_back(node("make", "function:test.makeCurve"));
  g.nodes.push_back(node("length", "function:test.curveLength"));
  g.nodes.push_back(node("none", "function:test.curveLength"));
  g.links.push_back(link("armR", "then", "make", "exec"));
  g.links.push_back(link("make", "then", "length", "exec"));
  g.links.push_back(link("length", "then", "none", "exec"));
  g.links.push_back(link("make", "curve", "length", "curve"));
  // The palette shows the type, with its colour and origin.
  bool listed = false;
  const auto palette = graph_palette_json(builtin_node_kinds());
  for (const auto& t : palette["types"]) listed |= t["name"] == "test.curve";
  EXPECT_TRUE(listed);
  // A constant or a variable cannot hold it; a value of it is no input's.
  BuildGraph wrong = g;
  wrong.variables.push_back(GraphVariable{"c", "test.curve", {}, {}, {}});
  EXPECT_NE(problems(wrong).find("type 'test.curve' is not one a variable holds"), std::string::npos);
  BuiltRig r = built_rig(compiled(g));
  ASSERT_TRUE(r.build);
  const NodeId rig = find_rig(r.g(), "drawn");
  EXPECT_EQ(meta_string(r.g(), find_component(r.g(), rig, "make"), kOutputsAttr), R"({"curve":{"points":[0,0.5,1]}})");
  EXPECT_EQ(meta_string(r.g(), find_component(r.g(), rig, "length"), kOutputsAttr), R"({"points":3})");
  EXPECT_EQ(meta_string(r.g(), find_component(r.g(), rig, "none"), kOutputsAttr), R"({"points":-1})")
      << "an unlinked input of a plugin's type is null";
  EXPECT_EQ(build_functions().remove_origin("curves.py"), 2u);
  EXPECT_EQ(unregister_data_types("curves.py"), 1u);
  EXPECT_FALSE(is_plugin_type("test.curve"));
}

TEST(BuildGraphFunctions, a_function_that_fails_stops_the_build_at_its_step_naming_it) {
  BuildGraph g = with_functions();
  g.nodes.push_back(node("oops", "function:test.fail"));
  g.links.push_back(link("dbl3", "then", "oops", "exec"));
  BuiltRig r;
  r.scene = metarig();
  ASSERT_TRUE(r.scene);
  auto b = Build::open(*r.scene, compiled(g), builtin_components());
  ASSERT_TRUE(b.is_ok()) << b.status().message();
  const Status s = (*b)->build_all();
  ASSERT_FALSE(s.is_ok());
  EXPECT_NE(s.message().find("call 'oops' (test.fail): refused on purpose"), std::string::npos) << s.message();
  // Everything before it is built; its own step was rolled back.
  EXPECT_EQ((*b)->position(), static_cast<int>((*b)->plan().size()) - 1);
  const NodeId oops = find_component(r.g(), find_rig(r.g(), "drawn"), "oops");
  EXPECT_TRUE(oops.is_valid()) << "its meta step is built";
  EXPECT_EQ(meta_string(r.g(), oops, kOutputsAttr), "");
}

TEST(BuildGraphFunctions, function_nodes_are_refused_where_they_cannot_work) {
  register_test_functions();
  // Reading a function's output where a value is needed before the build.
  BuildGraph g = drawn();
  g.nodes[3].kind = "component:ikChain";
  g.nodes[3].component.type = "ikChain";
  g.nodes.push_back(node("early", "function:test.double"));
  g.links[2] = link("hip", "then", "early", "exec");
  g.links.push_back(link("early", "then", "armL", "exec"));
  g.links.push_back(link("early", "y", "armL", "poleDistance"));
  EXPECT_NE(problems(g).find("node 'armL': input 'poleDistance' reads a value the build makes"), std::string::npos)
      << problems(g);
  // A function's component input must be linked.
  g = with_functions();
  std::erase_if(g.links, [](const GraphLink& l) { return l.to.node == "tag" && l.to.socket == "component"; });
  EXPECT_NE(problems(g).find("node 'tag': input 'component' needs a link from a component node"), std::string::npos)
      << problems(g);
  // An unregistered function is an unknown kind.
  g = drawn();
  g.nodes.push_back(node("x", "function:studio.nothing"));
  g.links.push_back(link("armR", "then", "x", "exec"));
  EXPECT_NE(problems(g).find("node 'x': unknown node kind 'function:studio.nothing'"), std::string::npos) << problems(g);
  // A second registration of an id names both origins.
  BuildFunction again{"test.double", "", "", "", {}, {}, {}, [](FunctionCall&) { return Status::ok(); }, "plugin.py"};
  const Status s = build_functions().add(again);
  EXPECT_EQ(s.code(), ErrorCode::kAlreadyExists);
  EXPECT_NE(s.message().find("plugin.py"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("rig tests"), std::string::npos) << s.message();
  // Sockets of types a function cannot take.
  BuildFunction bad{"test.bad", "", "", "", {{"x", "exec", ""}}, {}, {}, [](FunctionCall&) { return Status::ok(); }, ""};
  EXPECT_EQ(build_functions().add(bad).code(), ErrorCode::kInvalidArgument);
  // A definition whose `after` names no component, or closes a cycle.
  Definition d = compiled(with_functions());
  d.components[1].after.push_back(new_rig_id());
  std::string text;
  for (const Diagnostic& p : validate(d)) text += p.message + "\n";
  EXPECT_NE(text.find("after '"), std::string::npos) << text;
  EXPECT_NE(text.find("no component has that rigId"), std::string::npos) << text;
  d = compiled(with_functions());
  d.components[2].after.push_back(d.components[3].rig_id);  // dbl after dbl2, which reads dbl
  text.clear();
  for (const Diagnostic& p : validate(d)) text += p.message + "\n";
  EXPECT_NE(text.find("cycle"), std::string::npos) << text;
}

}  // namespace
}  // namespace rigel::rig
