// Build graphs (seed 004 §4.11, Luna's rig builder after Unreal's
// Blueprints): a rig build drawn as an execution graph. Each node is a
// component, a constant, a variable's get or set, or a branch; linking
// exec sockets orders the build (from the one `start` node), and typed data
// sockets pass values (a data type registry refuses a link between types
// that do not match, naming both sockets). Graph variables keep a value for
// later nodes.
//
// A build graph compiles to a rig definition (definition.h): its exec
// chain is run once, data flowing along it, and each component node it
// reaches becomes a component, its linked inputs (name, side, attach,
// parameters) taking the values that reach them and its `parent` input
// nesting it under the component that feeds it, children in exec order.
// The definition is built by the same procedural build as a `.rig.xml`
// (build.h): steps, stepping, rebuilds of what changed (components keep
// their rigIds in the graph), removal, the metadata network and updates
// work on graph-built rigs as on definition-built ones, and everything that
// reads a definition file (load_definition) reads a `.build.json`.
// `convert_definition` makes the graph of a definition: compiling it gives
// the definition back.
//
// The file, `.build.json`, is diffable JSON (docs/BUILD_GRAPH.md): the rig's
// settings as in a `.rig.json`, the variables, one block per node (stable
// ids, editor positions; a component node holds its component in the
// `.rig.json` syntax) and one line per link.
#pragma once

#include <deque>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "rigel/base/status.h"
#include "rigel/rig/definition.h"
#include "rigel/rig/definition_io.h"
#include "rigel/rig/schema.h"

namespace rigel::rig {

// ---- data types ---------------------------------------------------------------

// What flows through a socket. "exec" orders nodes and carries no value.
struct DataType {
  std::string name;   // "number", "component", ...
  std::string color;  // the socket's colour in the editor, "#rrggbb"
  // The parameter type a value of it is (constants, variables, component
  // parameters); nullopt for types a graph cannot hold as a constant
  // (exec, component: a component node's output).
  std::optional<ParamType> value_type;
  std::string help;
  // "" for the built-in types; else who registered it (a plugin's file),
  // which messages name. A plugin's type carries any JSON value from a
  // function's output to a function's input (a curve, a weight map, a
  // studio's asset record); no constant or variable holds it.
  std::string origin;
};

// Reading is thread-safe against adding; a type found stays valid until
// its origin is removed.
class DataTypeRegistry {
 public:
  // Fails (kAlreadyExists) on a name that is taken, naming who has it;
  // (kInvalidArgument) on an empty name or a colour that is not "#rrggbb".
  Status add(DataType type);
  // Removes the types of `origin` (a plugin reloaded); how many.
  std::size_t remove_origin(std::string_view origin);
  const DataType* find(std::string_view name) const;
  std::vector<DataType> types() const;
  // Whether a value of `from` may flow into a socket of `to`: the same type,
  // or an int into a number.
  static bool can_link(std::string_view from, std::string_view to);

 private:
  mutable std::mutex mutex_;
  std::deque<DataType> types_;  // a deque: adding keeps what find() gave valid
};

// The process's data types: exec, bool, int, number, string, vector, component, a list of each
// value type (list:bool, list:int, list:number, list:string, list:vector),
// and what a component node's build makes, which only function nodes take:
// list:control (its controls), list:joint (its guides' joints), list:node
// (its hooks); then those plugins registered.
const DataTypeRegistry& builtin_data_types();
// Registers a plugin's data type (its origin must be set; no ':' or '$' in
// its name, which the built-in families use): kAlreadyExists naming both
// origins when the name is taken. Register types before the functions
// whose sockets have them.
Status register_data_type(DataType type);
// Removes every data type `origin` registered; how many.
std::size_t unregister_data_types(std::string_view origin);
// Whether `type` is a plugin's (registered with an origin).
bool is_plugin_type(std::string_view type);

// A list type's element type ("list:number" -> "number"); "" for a type
// that is not a list. A list type has no value_type (no component
// parameter or function socket takes one); constants, variables and
// for-each nodes hold its values as a ValueList.
std::string list_element(std::string_view type);
// Whether `type` holds a value a constant or a variable can keep: a value
// type or a list of one.
bool holds_values(std::string_view type);
using ValueList = std::vector<ParamValue>;
// Whether every item of `list` is a value of the list type's element type.
bool list_fits(const ValueList& list, std::string_view list_type);
// The data type of a component parameter (an enum is a string).
const char* data_type_of(ParamType type);
// Whether `value` is a value of `type` (an int is a double's too).
bool value_fits(const ParamValue& value, ParamType type);
// The zero of `type`: false, 0, 0.0, "", (0, 0, 0).
ParamValue zero_value(ParamType type);

// ---- node kinds ---------------------------------------------------------------

struct SocketSpec {
  std::string name;
  // A DataType name, or kVariableType: the type of the node's variable.
  std::string type;
  std::string help;
};
inline constexpr const char* kVariableType = "$variable";

// What a node does, by its kind id:
//   start                 where the exec chain begins (one per graph)
//   component:TYPE        builds one component of TYPE
//   constant:TYPE         a value (bool, int, number, string, vector)
//   variable:get / :set   reads / writes a graph variable
//   branch                goes on through `true` or `false` by `condition`
//   forEach:TYPE          runs `body` once per item of its `list` (a
//                         list:TYPE), `element` and `index` the item's,
//                         then goes on through `completed`
//   graph:PATH            runs the build graph in file PATH (relative to
//                         the graph's folder, inside it): its variables
//                         are the node's inputs (unlinked: the node's own
//                         values, else the sub-graph's) and, as its chain
//                         leaves them, its outputs; its components join
//                         the rig, each use with its own rigIds
//   function:ID           runs build function ID (build_function.h)
struct NodeKind {
  std::string id;
  std::string nice_name;  // the palette's and the node's title
  std::string category;   // the palette's group
  std::vector<SocketSpec> inputs, outputs;
  std::string help;
  const SocketSpec* input(std::string_view name) const;
  const SocketSpec* output(std::string_view name) const;
  bool has_exec() const;  // it runs on the exec chain (else it is pure data)
};

class NodeKindRegistry {
 public:
  // Fails (kAlreadyExists) on an id that is taken; (kInvalidArgument) on a
  // socket whose type `types` does not hold or two sockets of one name.
  Status add(NodeKind kind, const DataTypeRegistry& types = builtin_data_types());
  const NodeKind* find(std::string_view id) const;
  const std::vector<NodeKind>& kinds() const { return kinds_; }

 private:
  std::vector<NodeKind> kinds_;
};

// The kinds a graph over `schemas` has: start, one component kind per
// component type (inputs: exec, parent, name, side, attach and every
// parameter; outputs: then, component, controls, joints, hooks), the
// constants, the variables'
// get and set, branch, a for-each per list type, and one function kind per build function
// registered now (build_functions()).
NodeKindRegistry builtin_node_kinds(const SchemaRegistry& schemas = builtin_schemas());

struct BuildGraph;
// The kind of a graph:PATH node running `sub`: exec and one input per
// variable of `sub`; then and one output per variable (category "Graphs").
NodeKind subgraph_node_kind(const std::string& path, const BuildGraph& sub);

// The palette an editor offers, as JSON: {"types": [{name, color, value
// (whether a constant or a variable holds it), help}], "kinds": [{id,
// niceName, category, help, inputs: [{name, type, help, default?}],
// outputs: [...]}]}. An input's default is the value it takes unlinked on
// a new node: a component parameter's schema default, a function input's
// default, else its type's zero.
nlohmann::ordered_json graph_palette_json(const NodeKindRegistry& kinds, const SchemaRegistry& schemas = builtin_schemas());

// ---- the graph ----------------------------------------------------------------

struct GraphVariable {
  std::string name;
  // A DataType with a value type, a list of one, or `component` (none
  // until a set node gives it a component node's output).
  std::string type;
  ParamValue value;  // its value when the build starts
  ValueList items;   // a list type's: its items when the build starts
  SourceLocation where;
};

struct GraphNode {
  std::string id;    // unique in the graph, stable across edits
  std::string kind;  // a NodeKind id
  std::optional<std::pair<double, double>> position;  // in the editor
  // component:TYPE: the component (type TYPE, no children). Its name,
  // side, attach and parameters are the values of those inputs when they
  // are not linked. A component drawn for one side (L or R) whose linked
  // `side` brings the other is built mirrored (mirror_component: its
  // guides' joints and rotations, its attach), so a for-each over sides
  // builds both from one node.
  Component component;
  // Other kinds: the values of inputs that are not linked (a branch's
  // condition, a set's value) and a constant's `value`.
  std::vector<Param> values;
  // The values of list inputs that are not linked (a for-each's `list`, a
  // set's `value` of a list variable) and a list constant's `value`.
  std::map<std::string, ValueList> lists;
  std::string variable;  // variable:get / :set
  // function:ID: the rigId of the call it builds (empty: made from the
  // rig's name and the node's id, so it stays as long as they do).
  std::string rig_id;
  SourceLocation where;
  const Param* value(std::string_view name) const;
};

// node.socket
struct SocketRef {
  std::string node;
  std::string socket;
  friend bool operator==(const SocketRef&, const SocketRef&) = default;
};

// From an output to an input: exec then -> exec, or a value.
struct GraphLink {
  SocketRef from, to;
  SourceLocation where;
};

struct BuildGraph {
  // The rig's settings (name, version, geometry, features, data); its
  // components are the component nodes.
  Definition rig;
  std::vector<GraphVariable> variables;
  std::vector<GraphNode> nodes;
  std::vector<GraphLink> links;
  std::string source;  // the file it was read from, for messages
  // Where its graph:PATH nodes' files are ("": the folder of `source`).
  std::filesystem::path folder;

  const GraphNode* find(std::string_view id) const;
  const GraphVariable* variable(std::string_view name) const;
};

// ---- files --------------------------------------------------------------------

// ".build.json"
bool is_build_graph_path(const std::filesystem::path& path);

struct BuildGraphParse {
  BuildGraph graph;
  std::vector<Diagnostic> errors;  // empty = read
  bool ok() const { return errors.empty(); }
};
// Reads `.build.json` text: every structural problem (unknown key, a value
// of the wrong kind, a component object as a `.rig.json` reader would
// refuse it) at file:line:column. What the nodes mean is compile's check.
BuildGraphParse parse_build_graph(std::string_view text, const std::string& source,
                                  const SchemaRegistry& schemas = builtin_schemas());
BuildGraphParse load_build_graph(const std::filesystem::path& path, const SchemaRegistry& schemas = builtin_schemas());
// Deterministic, diffable text (the same graph gives the same bytes).
std::string write_build_graph(const BuildGraph& graph);
// Atomic: written beside the file, then renamed over it.
Status save_build_graph(const BuildGraph& graph, const std::filesystem::path& path);

// ---- compiling and converting -------------------------------------------------

struct BuildGraphCompile {
  Definition definition;
  // Every problem, each naming the node and socket (and the file place):
  // unknown kinds and sockets, links between types that do not match, two
  // links into one input or out of one exec output, a cycle in exec or data
  // flow, a node with exec sockets the chain from start never reaches, an
  // input read before the node feeding it runs, and what validate() finds
  // in the definition, at the component's node.
  std::vector<Diagnostic> errors;
  // What builds but not as drawn: component nodes the chain runs in an
  // order the build cannot keep (a build is depth first: a component's
  // children right after it).
  std::vector<Diagnostic> warnings;
  // The ids of the nodes the chain ran, in order (a for-each's body once
  // per item).
  std::vector<std::string> order;
  // (node id, rigId) of each component and function node the chain ran (a
  // node in a for-each's body once per item: its rigId made from its own,
  // or its id, and the item's index), so
  // an editor can show which node a build step or a rebuilt rigId is.
  std::vector<std::pair<std::string, std::string>> rig_ids;
  bool ok() const { return errors.empty(); }
};
BuildGraphCompile compile_build_graph(const BuildGraph& graph, const SchemaRegistry& schemas = builtin_schemas());
// A graph file read and compiled: what `rigel graph validate` reports (the
// file's problems when it cannot be read, else compile's).
BuildGraphCompile check_build_graph(const std::filesystem::path& path, const SchemaRegistry& schemas = builtin_schemas());

// What a diagnostic of `graph` is about, for an editor to mark: the node
// its message names ("node 'ID'", or a link's "'ID.socket'"), else the node
// whose block in the file holds its place; the socket is the input whose
// value or link is at that place (or that the message names). Empty when
// it is about the rig's settings, a variable, or nothing of a node.
struct GraphPlace {
  std::string node, socket;
};
GraphPlace place_of(const BuildGraph& graph, const Diagnostic& diagnostic);

// The graph of a definition: start, then one component node per component
// in build order (depth first) on the exec chain, each child's `parent`
// linked from its parent's `component`, then each `call` component as its
// function node (its args' values as the node's, its references to
// components and calls as links), laid out for the editor.
// compile_build_graph() of it gives `definition` back.
BuildGraph convert_definition(const Definition& definition);

}  // namespace rigel::rig
