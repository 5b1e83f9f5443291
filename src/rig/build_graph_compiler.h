// The build graph compiler (build_graph.h's compile_build_graph), shared by
// its two files: build_graph_compile.cc checks a graph (its variables,
// nodes, links, data cycles, reach) and nests what the run made;
// build_graph_run.cc runs its exec chain, values flowing along it, making
// components and calls, for-each bodies once per item and sub-graphs
// (graph:PATH nodes) by a compiler of their own.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "rigel/rig/build_function.h"
#include "rigel/rig/build_graph.h"

namespace rigel::rig::detail {

// What a data socket holds while the chain runs: a value, a list, a
// component the chain made (its index in the order made), or an output of
// a function node, which only the build makes (the call's rigId and the
// output).
struct Flow {
  std::optional<ParamValue> value;
  int component = -1;
  std::string call, output;
  std::optional<ValueList> items;
  bool runtime() const { return !call.empty(); }
};
Flow value_flow(ParamValue v);
Flow list_flow(ValueList items);
Flow runtime_flow(std::string call, std::string output);

// A value of data type `type` as it goes into a socket of that type (an
// int into a number becomes a double).
ParamValue as_type(const ParamValue& v, std::string_view type);

// A rigId made from the rig's name and a node's path: FNV-1a, 128 bits,
// shaped as a UUID v4, so it stays as long as they do.
std::string derived_rig_id(const std::string& rig, const std::string& node);

// The most components and calls one graph may make, and the most nodes one
// run of its chain may run (for-each nodes multiply them): past them the
// graph is refused, not built for minutes. Sub-graphs nest at most
// kMaxSubgraphDepth deep.
inline constexpr std::size_t kMaxMade = 10000;
inline constexpr std::size_t kMaxRuns = 200000;
inline constexpr std::size_t kMaxSubgraphDepth = 16;

// What the compilers of a graph and of its sub-graphs make together.
struct CompileRun {
  CompileRun(const SchemaRegistry& s, BuildGraphCompile& o) : schemas(s), kinds(builtin_node_kinds(s)), out(o) {}
  const SchemaRegistry& schemas;
  // The kinds every graph has, made once per compile (a sub-graph's
  // compiler, one per use, adds only its graph:PATH kinds).
  const NodeKindRegistry kinds;
  BuildGraphCompile& out;
  std::string rig;  // the top graph's rig name (rigIds are made from it)
  std::vector<Component> made, calls;
  std::vector<int> parent, depth;
  // Who made each component: its node's path ("arm/ik") and place.
  struct Maker {
    std::string node, source;
    SourceLocation where;
  };
  std::vector<Maker> made_by;
  std::size_t runs = 0;             // nodes and for-each items run, all compilers together
  std::vector<std::size_t> keys;    // the item each for-each around the node now running is at
  std::vector<std::string> files;   // the sub-graph files being checked, outermost first
  std::map<std::string, std::shared_ptr<const BuildGraph>> loaded;  // sub-graphs read, by path
};

class Compiler {
 public:
  // `prefix`: "" for the top graph, else the path of the sub-graph node
  // that runs it ("arm/"), which names its nodes in messages and rigIds.
  Compiler(const BuildGraph& graph, CompileRun& run, std::string prefix);

  // The static checks; false when they found a problem.
  bool check();
  // Runs the chain from start, its variables taking `inputs` where given
  // (a sub-graph node's inputs); false on an error.
  bool run_chain(const std::map<std::string, Flow>& inputs = {});
  // The variables as the chain left them (a sub-graph node's outputs).
  const std::map<std::string, Flow>& variables() const { return variables_; }
  // Nests the components made, the calls after them (the top compiler).
  void assemble();

 private:
  void fail(SourceLocation where, std::string message) {
    run_.out.errors.push_back({g_.source, where, std::move(message)});
  }
  void fail(std::size_t node, std::string message) {
    fail(g_.nodes[node].where, "node '" + path_of(node) + "': " + std::move(message));
  }
  bool failed() const { return !run_.out.errors.empty(); }
  std::string path_of(std::size_t node) const { return prefix_ + g_.nodes[node].id; }
  static std::string name(const SocketRef& s) { return "'" + s.node + "." + s.socket + "'"; }
  std::string socket_type(std::size_t n, const SocketSpec& s) const;

  // build_graph_compile.cc
  void check_variables();
  void check_nodes();
  void check_values(std::size_t i, const NodeKind& kind);
  const NodeKind* subgraph_kind(std::size_t i);
  void check_links();
  void check_data_cycles();
  void check_reachable();

  // build_graph_run.cc
  std::optional<Flow> input(std::size_t n, const std::string& socket);
  std::optional<Flow> known_input(std::size_t n, const std::string& socket);
  std::optional<ParamValue> value_input(std::size_t n, const std::string& socket);
  std::optional<ValueList> list_input(std::size_t n, const std::string& socket);
  std::optional<Flow> pure_output(std::size_t n, const std::string& output, const std::string& type);
  bool known_values(std::size_t n, const std::vector<SocketSpec>& sockets, FunctionValues& into);
  bool run_flow_node(std::size_t n, std::string& next);
  bool walk(std::size_t n, std::string next);
  bool run_node(std::size_t n, std::string& next);
  bool run_loop(std::size_t n);
  bool run_subgraph(std::size_t n);
  std::optional<Flow> own_value(std::size_t n, const GraphVariable& v);
  std::string iteration_key() const;
  std::string rig_id_of(const std::string& own, std::size_t node) const;
  std::string top_node(std::size_t node) const;
  bool within_limit(std::size_t n);
  bool make_component(std::size_t n);
  bool make_call(std::size_t n);

  const BuildGraph& g_;
  CompileRun& run_;
  std::string prefix_;
  std::map<std::string, NodeKind> subgraph_kinds_;  // this graph's graph:PATH kinds
  std::vector<const NodeKind*> kind_of_;
  std::map<std::size_t, std::shared_ptr<const BuildGraph>> subgraph_of_;  // graph:PATH nodes' graphs
  std::map<std::string, std::size_t> index_;
  std::map<std::pair<std::size_t, std::string>, std::size_t> exec_next_;  // (node, exec output) -> link
  std::map<std::pair<std::size_t, std::string>, std::size_t> feeds_;      // (node, data input) -> link
  std::map<std::size_t, Flow> ran_;                                       // nodes run, with their output
  std::map<std::string, Flow> variables_;
  std::map<std::size_t, std::pair<Flow, Flow>> loop_;                // a for-each's element and index now
  std::map<std::size_t, std::map<std::string, Flow>> outputs_of_;    // a sub-graph node's outputs
  std::map<std::size_t, FunctionValues> flow_out_;                   // a flow node's outputs now
  std::vector<std::size_t> path_;                                    // the exec chain walked to here
  std::vector<std::size_t> run_log_;                                 // this graph's nodes run, in order
};

}  // namespace rigel::rig::detail
