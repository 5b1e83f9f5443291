// Build functions (seed 004 §4.11: Luna's registered functions): what a
// build graph's function node runs. A function has an id, a nice name and a
// category for the editor's palette, typed inputs (a value, or a component
// the build made) and typed outputs (values), and a C++ body; plugins
// register more (from C++, or from Python through the `rigel` module).
//
// A function node compiles to a component of type `call` (params
// `function`: the id, `args`: its inputs as JSON): its one step, `run`,
// calls the function under the build's recorder, so it is a build step
// like any other: stepped back and forth, rebuilt when what it reads is
// rebuilt (Component::after), removed exactly, and found in the metadata
// network (metaType "call"). Its outputs are kept on its meta node
// (attribute `outputs`, JSON), where later calls read them, in this process
// or a later one.
#pragma once

#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/rig/build_graph.h"
#include "rigel/rig/definition.h"
#include "rigel/scene/scene.h"

namespace rigel::rig {

// The component type a function node compiles to.
inline constexpr const char* kCallType = "call";
// The attribute of a call's meta node holding its outputs (JSON {NAME: VALUE}).
inline constexpr const char* kOutputsAttr = "outputs";

// What a function's body sees: the scene being built, the rig, its inputs
// and where its outputs go. Everything it changes goes through the graph
// under the build's recorder, so the call is undone exactly.
class FunctionCall {
 public:
  FunctionCall(scene::Scene& scene, const Definition& definition, graph::NodeId rig, graph::NodeId call,
               std::map<std::string, ParamValue> values, std::map<std::string, graph::NodeId> components,
               std::map<std::string, std::vector<graph::NodeId>> nodes = {},
               std::map<std::string, ValueList> lists = {})
      : scene_(&scene),
        definition_(&definition),
        rig_(rig),
        call_(call),
        values_(std::move(values)),
        components_(std::move(components)),
        nodes_(std::move(nodes)),
        lists_(std::move(lists)) {}
  // A pure function's call (BuildFunction::pure), while the graph
  // compiles: its values only, no scene.
  explicit FunctionCall(std::map<std::string, ParamValue> values, std::map<std::string, ValueList> lists = {})
      : values_(std::move(values)), lists_(std::move(lists)) {}
  // False for a pure function's call: scene(), definition(), rig() and
  // call() are not there.
  bool has_scene() const { return scene_ != nullptr; }
  scene::Scene& scene() { return *scene_; }
  // The definition being built (the graph compiled).
  const Definition& definition() const { return *definition_; }
  // A component input's component as the definition says (nullptr otherwise).
  const Component* component_definition(std::string_view input) const;
  graph::NodeId rig() const { return rig_; }    // the metaRoot
  graph::NodeId call() const { return call_; }  // the call's metaComponent
  // A value input (nullptr for a component input or an unknown name).
  const ParamValue* value(std::string_view input) const;
  // A component input: the meta node of the component (invalid otherwise).
  graph::NodeId component(std::string_view input) const;
  const std::map<std::string, ParamValue>& values() const { return values_; }
  const std::map<std::string, graph::NodeId>& components() const { return components_; }
  // A list:control, list:joint or list:node input: the controls, joints or
  // hooks of the component linked to it (nullptr for another input).
  const std::vector<graph::NodeId>* nodes(std::string_view input) const;
  const std::map<std::string, std::vector<graph::NodeId>>& node_lists() const { return nodes_; }
  // A list input's items (list:bool, list:int, list:number, list:string,
  // list:vector; nullptr for another input).
  const ValueList* list(std::string_view input) const;
  const std::map<std::string, ValueList>& lists() const { return lists_; }
  void set_output(const std::string& output, ParamValue value) { outputs_[output] = std::move(value); }
  // A list output's items.
  void set_list_output(const std::string& output, ValueList items) { list_outputs_[output] = std::move(items); }
  const std::map<std::string, ParamValue>& outputs() const { return outputs_; }
  const std::map<std::string, ValueList>& list_outputs() const { return list_outputs_; }

 private:
  scene::Scene* scene_ = nullptr;
  const Definition* definition_ = nullptr;
  graph::NodeId rig_, call_;
  std::map<std::string, ParamValue> values_;
  std::map<std::string, graph::NodeId> components_;
  std::map<std::string, std::vector<graph::NodeId>> nodes_;
  std::map<std::string, ValueList> lists_;
  std::map<std::string, ParamValue> outputs_;
  std::map<std::string, ValueList> list_outputs_;
};

struct BuildFunction {
  std::string id;         // unique: "rigel.mirrorControlShapes", "studio.scaleShapes"
  std::string nice_name;  // the palette's and the node's title
  std::string category;   // the palette's group
  std::string help;
  // Inputs: a value type, a list of one (list:number, ...), `component`,
  // or what a component node's build makes (list:control, list:joint,
  // list:node); outputs: value types and lists of them.
  std::vector<SocketSpec> inputs, outputs;
  // Values of inputs a node leaves unlinked and unset (else the type's zero).
  std::vector<Param> defaults;
  std::function<Status(FunctionCall&)> run;
  // Where it was registered from: "rigel" for the built-in ones, a
  // plugin's file for a plugin's (messages name it).
  std::string origin;
  // A pure function: from values to values, run when the graph compiles
  // (a value node: no exec sockets, evaluated where an input reads it, so
  // in a for-each body once per item), never a build step. Its inputs and
  // outputs are value types.
  bool pure = false;
  const SocketSpec* input(std::string_view name) const;
  const SocketSpec* output(std::string_view name) const;
};

// What registries of plugins' things (functions, flow kinds) share: ids
// unique, each with its origin; reading is thread-safe against changing.
template <class T>
class PluginRegistry {
 public:
  // Removes every item of `origin` (a plugin reloaded); returns how many.
  std::size_t remove_origin(std::string_view origin) {
    std::lock_guard lock(mutex_);
    return std::erase_if(items_, [&](const T& t) { return t.origin == origin; });
  }
  // Removes one; false when there is none of that id.
  bool remove(std::string_view id) {
    std::lock_guard lock(mutex_);
    return std::erase_if(items_, [&](const T& t) { return t.id == id; }) > 0;
  }
  // A copy (the registry may change after).
  std::optional<T> find(std::string_view id) const {
    std::lock_guard lock(mutex_);
    for (const T& t : items_)
      if (t.id == id) return t;
    return std::nullopt;
  }
  std::vector<T> all() const {
    std::lock_guard lock(mutex_);
    return items_;
  }

 protected:
  // Adds `t` unless its id is taken (kAlreadyExists naming both origins).
  Status insert(T t, const std::string& who) {
    std::lock_guard lock(mutex_);
    for (const T& other : items_)
      if (other.id == t.id)
        return Status(ErrorCode::kAlreadyExists,
                      who + ": the id is taken by " + (other.origin.empty() ? std::string("another") : other.origin));
    items_.push_back(std::move(t));
    return Status::ok();
  }

 private:
  mutable std::mutex mutex_;
  std::vector<T> items_;
};

// The process's build functions. Registering happens when a driver starts
// or loads a plugin; reading is thread-safe against it.
class FunctionRegistry : public PluginRegistry<BuildFunction> {
 public:
  // Fails (kAlreadyExists) on an id that is taken, naming both origins;
  // (kInvalidArgument) on an empty id, no body, a socket type that is not
  // a value type or a list of one (outputs; inputs also component and the
  // component's lists), two sockets of one name, or a default of the wrong
  // type.
  Status add(BuildFunction function);
  std::vector<BuildFunction> functions() const { return all(); }
};

FunctionRegistry& build_functions();

// A function's values in or out: one value per value socket, items per
// list socket.
struct FunctionValues {
  std::map<std::string, ParamValue> values;
  std::map<std::string, ValueList> lists;
};
// Runs a pure function on its inputs' values (each given, else its
// default, else its type's zero; a list: none): its outputs, each as set or
// its type's zero (a list: empty); the function's failure, or
// kInvalidArgument for an output that is not one of its own or not of its
// type.
Result<FunctionValues> run_pure(const BuildFunction& function, FunctionValues inputs);

// A JSON value (a call's argument or output) as a value of data type
// `type` ("": by the JSON's kind); nullopt when it is not one. A plugin's
// type holds any JSON, kept as its text.
std::optional<ParamValue> value_from_json(const nlohmann::ordered_json& json, std::string_view type);
// A JSON array as the items of list type `list_type`; nullopt when it is
// not one.
std::optional<ValueList> list_from_json(const nlohmann::ordered_json& json, std::string_view list_type);

// The node kind of a function ("function:ID"): exec in, its inputs, then,
// its outputs (a pure function's: its inputs and outputs only).
NodeKind function_node_kind(const BuildFunction& function);

// ---- flow kinds: node kinds plugins register ------------------------------------
//
// A flow kind (kind id "flow:ID") steers the exec chain while the graph
// compiles, as Luna's plugin nodes and Unreal's Sequence and For Loop do:
// from its inputs' values its body says through which of its exec outputs
// (`exits`) the chain goes on, in order, once or many times, each time with
// values on its data outputs. It makes no build step itself; the nodes it
// runs do. An exit in `repeats` may be taken many times, each pass keyed
// as a for-each body's (components made in it get rigIds from the pass's
// index); another exit at most once. The chain goes on after the flow node
// through the last exit taken when that one does not repeat; else it ends
// there.

// What a flow kind's body sees: its inputs' values; go() takes an exit.
class FlowCall {
 public:
  explicit FlowCall(FunctionValues inputs) : in_(std::move(inputs)) {}
  const ParamValue* value(std::string_view input) const;
  const ValueList* list(std::string_view input) const;
  const FunctionValues& inputs() const { return in_; }
  struct Step {
    std::string exit;
    FunctionValues outputs;  // the data outputs' values for this pass (unset: the type's zero)
  };
  void go(std::string exit, FunctionValues outputs = {}) { steps_.push_back({std::move(exit), std::move(outputs)}); }
  const std::vector<Step>& steps() const { return steps_; }

 private:
  FunctionValues in_;
  std::vector<Step> steps_;
};

struct FlowKind {
  std::string id;         // unique: "rigel.sequence", "studio.perSide"
  std::string nice_name;  // the palette's and the node's title
  std::string category;   // the palette's group ("Flow" when empty)
  std::string help;
  std::vector<SocketSpec> inputs, outputs;  // value types and lists of them
  std::vector<std::string> exits{"then"};   // its exec outputs
  std::vector<std::string> repeats;         // the exits it may take many times
  std::vector<Param> defaults;              // of value inputs
  std::function<Status(FlowCall&)> run;
  std::string origin;  // "rigel", or a plugin's file
  const SocketSpec* input(std::string_view name) const;
  const SocketSpec* output(std::string_view name) const;
};

class FlowKindRegistry : public PluginRegistry<FlowKind> {
 public:
  // Fails (kAlreadyExists) on an id that is taken, naming both origins;
  // (kInvalidArgument) on an empty id, no body, no exits, a socket that is
  // not a value type or a list of one, two sockets or exits of one name, a
  // repeat that is not an exit, or a default of the wrong type.
  Status add(FlowKind kind);
  std::vector<FlowKind> kinds() const { return all(); }
};

FlowKindRegistry& flow_kinds();

// Runs a flow kind's body on its inputs (each given, else its default,
// else its type's zero; a list: none): the exits it took, in order, each
// with every output (unset: its type's zero). Its failure, or
// kInvalidArgument for an exit or output not its own, an output not of its
// type, or an exit that does not repeat taken twice.
Result<std::vector<FlowCall::Step>> run_flow(const FlowKind& kind, FunctionValues inputs);

// The node kind of a flow kind ("flow:ID"): exec in and its inputs; its
// exits (exec) and outputs.
NodeKind flow_node_kind(const FlowKind& kind);

class ComponentFactory;
// Adds the `call` component class (its step `run` calls the function).
Status add_call_component(ComponentFactory& factory);

}  // namespace rigel::rig
