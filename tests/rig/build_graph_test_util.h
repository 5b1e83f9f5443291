// Helpers of the build graph tests (build_graph_tests.cc,
// build_graph_loop_tests.cc): nodes and links drawn by hand, a graph
// compiled or read back, its problems as text.
#pragma once

#include <filesystem>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

#include "rig_test_util.h"
#include "rigel/rig/build_graph.h"
#include "rigel/rig/definition_io.h"

namespace rigel::rig::testing {

inline const std::filesystem::path kSource = RIGEL_SOURCE_DIR;

inline Definition example(const std::string& name) {
  ParseResult p = load_definition(kSource / "examples" / name);
  EXPECT_TRUE(p.ok()) << (p.errors.empty() ? "" : p.errors[0].str());
  return p.definition;
}

// The graph text, read back: the parse must succeed.
inline BuildGraph reread(const BuildGraph& g) {
  BuildGraphParse p = parse_build_graph(write_build_graph(g), "graph.build.json");
  EXPECT_TRUE(p.ok()) << (p.errors.empty() ? "" : p.errors[0].str());
  return p.graph;
}

inline Definition compiled(const BuildGraph& g) {
  BuildGraphCompile c = compile_build_graph(g);
  EXPECT_TRUE(c.ok()) << (c.errors.empty() ? "" : c.errors[0].str());
  return c.definition;
}

// Every problem's text, one per line.
inline std::string problems(const BuildGraph& g) {
  std::string out;
  for (const Diagnostic& d : compile_build_graph(g).errors) out += d.str() + "\n";
  return out;
}

inline std::string problems(std::string_view text) {
  BuildGraphParse p = parse_build_graph(text, "g.build.json");
  if (!p.ok()) {
    std::string out;
    for (const Diagnostic& d : p.errors) out += d.str() + "\n";
    return out;
  }
  return problems(p.graph);
}

inline GraphNode node(std::string id, std::string kind) {
  GraphNode n;
  n.id = std::move(id);
  n.kind = std::move(kind);
  return n;
}

inline GraphLink link(std::string from, std::string from_socket, std::string to, std::string to_socket) {
  return GraphLink{{std::move(from), std::move(from_socket)}, {std::move(to), std::move(to_socket)}, {}};
}

inline GraphNode component_node(const std::string& id, Component c) {
  GraphNode n = node(id, "component:" + c.type);
  c.children.clear();
  n.component = std::move(c);
  return n;
}

// The components a compile made under its one root (the global): for the
// loop and sub-graph tests, arm_L then arm_R, each with its own rigId;
// empty (with the failure) otherwise.
inline std::vector<Component> two_arms(const BuildGraphCompile& c) {
  EXPECT_TRUE(c.ok()) << (c.errors.empty() ? "" : c.errors[0].str());
  if (!c.ok() || c.definition.components.size() != 1u) return {};
  const std::vector<Component>& arms = c.definition.components[0].children;
  const bool two = arms.size() == 2u && arms[0].full_name() == "arm_L" && arms[1].full_name() == "arm_R" &&
                   arms[0].rig_id != arms[1].rig_id;
  EXPECT_TRUE(two) << write_definition(c.definition, Syntax::kJson);
  return two ? arms : std::vector<Component>{};
}

// A list of texts (built item by item: GCC 12 warns of a variant in an
// initializer list it cannot see initialised).
inline ValueList texts(std::initializer_list<const char*> items) {
  ValueList out;
  for (const char* item : items) out.emplace_back(std::string(item));
  return out;
}

// The global component, with a fixed rigId.
inline Component global_component() {
  Component global;
  global.type = "global";
  global.name = "global";
  global.rig_id = "7d0c5a52-8a4e-4c4b-9d8f-2b1a55e0c001";
  global.guides = {Guide{}};
  return global;
}

inline Component fk_chain(std::string name, Side side, std::vector<std::string> joints) {
  Component c;
  c.type = "fkChain";
  c.name = std::move(name);
  c.side = side;
  c.rig_id = new_rig_id();
  for (std::string& j : joints) c.guides.push_back(at_joint(std::move(j)));
  return c;
}

}  // namespace rigel::rig::testing
