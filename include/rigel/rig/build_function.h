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
               std::map<std::string, std::vector<graph::NodeId>> nodes = {})
      : scene_(&scene),
        definition_(&definition),
        rig_(rig),
        call_(call),
        values_(std::move(values)),
        components_(std::move(components)),
        nodes_(std::move(nodes)) {}
  // A pure function's call (BuildFunction::pure), while the graph
  // compiles: its values only, no scene.
  explicit FunctionCall(std::map<std::string, ParamValue> values) : values_(std::move(values)) {}
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
  void set_output(const std::string& output, ParamValue value) { outputs_[output] = std::move(value); }
  const std::map<std::string, ParamValue>& outputs() const { return outputs_; }

 private:
  scene::Scene* scene_ = nullptr;
  const Definition* definition_ = nullptr;
  graph::NodeId rig_, call_;
  std::map<std::string, ParamValue> values_;
  std::map<std::string, graph::NodeId> components_;
  std::map<std::string, std::vector<graph::NodeId>> nodes_;
  std::map<std::string, ParamValue> outputs_;
};

struct BuildFunction {
  std::string id;         // unique: "rigel.mirrorControlShapes", "studio.scaleShapes"
  std::string nice_name;  // the palette's and the node's title
  std::string category;   // the palette's group
  std::string help;
  // Inputs: a value type, `component`, or what a component node's build
  // makes (list:control, list:joint, list:node); outputs: value types.
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

// The process's build functions. Registering happens when a driver starts
// or loads a plugin; reading is thread-safe against it.
class FunctionRegistry {
 public:
  // Fails (kAlreadyExists) on an id that is taken, naming both origins;
  // (kInvalidArgument) on an empty id, no body, a socket type that is not
  // a value type (outputs) or a value type or component (inputs), two
  // sockets of one name, or a default of the wrong type.
  Status add(BuildFunction function);
  // Removes every function of `origin` (a plugin reloaded); returns how many.
  std::size_t remove_origin(std::string_view origin);
  // Removes one function; false when there is none of that id.
  bool remove(std::string_view id);
  // A copy (the registry may change after).
  std::optional<BuildFunction> find(std::string_view id) const;
  std::vector<BuildFunction> functions() const;

 private:
  mutable std::mutex mutex_;
  std::vector<BuildFunction> functions_;
};

FunctionRegistry& build_functions();

// Runs a pure function on its inputs' values (each given, else its
// default, else its type's zero): its outputs, each as set or its type's
// zero; the function's failure, or kInvalidArgument for an output that is
// not one of its own or not of its type.
Result<std::map<std::string, ParamValue>> run_pure(const BuildFunction& function,
                                                   std::map<std::string, ParamValue> values);

// A JSON value (a call's argument or output) as a value of data type
// `type` ("": by the JSON's kind); nullopt when it is not one. A plugin's
// type holds any JSON, kept as its text.
std::optional<ParamValue> value_from_json(const nlohmann::ordered_json& json, std::string_view type);

// The node kind of a function ("function:ID"): exec in, its inputs, then,
// its outputs (a pure function's: its inputs and outputs only).
NodeKind function_node_kind(const BuildFunction& function);

class ComponentFactory;
// Adds the `call` component class (its step `run` calls the function).
Status add_call_component(ComponentFactory& factory);

}  // namespace rigel::rig
