// Helpers of the build graph tests (build_graph_tests.cc,
// build_graph_loop_tests.cc): nodes and links drawn by hand, a graph
// compiled or read back, its problems as text.
#pragma once

#include <filesystem>
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
