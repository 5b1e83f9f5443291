// Build graphs from Python (docs/BUILD_GRAPH.md): graph files checked and
// made from definitions, and build functions written in Python, registered
// into the process's rig::build_functions() beside the shipped ones, so a
// graph's function node runs them when a build runs here. (Loading a
// plugin folder is rigel.load_plugins, in the pure-Python part.)

#include "rig_common.h"
#include "rigel/app/rig_files.h"
#include "rigel/rig/build_function.h"
#include "rigel/rig/build_graph.h"
#include "rigel/rig/meta.h"

#include <nlohmann/json.hpp>

namespace rigel::python {
namespace {

// What a Python function sees: the call, and the scene it builds, as a
// Scene that does not own it. Valid while the function runs.
struct CallRef {
  rig::FunctionCall* call = nullptr;
  SceneRef scene;
  rig::FunctionCall& get() const {
    if (!call) raise(ErrorCode::kFailedPrecondition, "this FunctionCall has ended: use it only while the function runs");
    return *call;
  }
  // The call of a function that runs in a build (not a pure one).
  rig::FunctionCall& built() const {
    rig::FunctionCall& c = get();
    if (!c.has_scene())
      raise(ErrorCode::kFailedPrecondition, "a pure function's call has no scene: it runs while the graph compiles");
    return c;
  }
};

// A Python value as a value of data type `type`.
rig::ParamValue value_from_python(py::handle v, const std::string& type, const std::string& where) {
  const bool is_bool = py::isinstance<py::bool_>(v);
  if (type == "bool" && is_bool) return v.cast<bool>();
  if (type == "int" && py::isinstance<py::int_>(v) && !is_bool) return v.cast<std::int64_t>();
  if (type == "number" && (py::isinstance<py::float_>(v) || py::isinstance<py::int_>(v)) && !is_bool)
    return v.cast<double>();
  if (type == "string" && py::isinstance<py::str>(v)) return v.cast<std::string>();
  if (type == "vector") return vec3_from_python(v, where);
  // A plugin's type: any value JSON can write, kept as its text.
  if (rig::is_plugin_type(type)) {
    try {
      return py::module_::import("json").attr("dumps")(v).cast<std::string>();
    } catch (py::error_already_set& e) {
      raise(ErrorCode::kInvalidArgument, where + ": a " + type + " is a value JSON can write: " + e.what());
    }
  }
  raise(ErrorCode::kInvalidArgument, where + ": " + std::string(py::str(py::repr(v))) + " is not a " + type);
}

// A Python list (or tuple) as the items of list type `type`.
rig::ValueList list_from_python(py::handle v, const std::string& type, const std::string& where) {
  if (!py::isinstance<py::list>(v) && !py::isinstance<py::tuple>(v))
    raise(ErrorCode::kInvalidArgument, where + ": " + std::string(py::str(py::repr(v))) + " is not a " + type + " (a list)");
  const std::string element = rig::list_element(type);
  rig::ValueList items;
  std::size_t i = 0;
  for (py::handle item : py::reinterpret_borrow<py::sequence>(v))
    items.push_back(value_from_python(item, element, where + "[" + std::to_string(i++) + "]"));
  return items;
}

// Sets output `o` of `call` from a Python value.
void set_output_from_python(rig::FunctionCall& call, const rig::SocketSpec& o, py::handle v, const std::string& where) {
  if (!rig::list_element(o.type).empty()) call.set_list_output(o.name, list_from_python(v, o.type, where));
  else call.set_output(o.name, value_from_python(v, o.type, where));
}

// [(name, type), ...] or {name: type} as sockets.
std::vector<rig::SocketSpec> sockets_from_python(py::handle h, const std::string& where) {
  std::vector<rig::SocketSpec> out;
  if (h.is_none()) return out;
  py::iterable items = py::isinstance<py::dict>(h) ? py::iterable(h.attr("items")()) : py::reinterpret_borrow<py::iterable>(h);
  for (py::handle item : items) {
    auto pair = py::reinterpret_borrow<py::sequence>(item);
    if (pair.size() != 2) raise(ErrorCode::kInvalidArgument, where + ": each socket is (name, type)");
    out.push_back({pair[0].cast<std::string>(), pair[1].cast<std::string>(), ""});
  }
  return out;
}

// The body of a Python function: fn(call, **inputs); None, a value (one
// output) or {output: value}. Any exception is the step's failure, with
// the function's origin named.
std::function<Status(rig::FunctionCall&)> python_body(py::function fn, std::string id, std::string origin,
                                                      std::vector<rig::SocketSpec> inputs,
                                                      std::vector<rig::SocketSpec> outputs) {
  // The function object is released under the GIL whenever the registry lets it go.
  auto held = std::shared_ptr<py::function>(new py::function(std::move(fn)), [](py::function* f) {
    py::gil_scoped_acquire gil;
    delete f;
  });
  return [held, id, origin, inputs, outputs](rig::FunctionCall& call) -> Status {
    py::gil_scoped_acquire gil;
    const std::string who = "python function " + id + (origin.empty() ? "" : " (" + origin + ")");
    auto ref = std::make_shared<CallRef>();
    ref->call = &call;
    // A pure function's call has no scene (it runs while the graph compiles).
    if (call.has_scene()) ref->scene = SceneRef(&call.scene(), [](scene::Scene*) {});
    try {
      py::dict kwargs;
      for (const auto& [name, value] : call.values()) {
        const auto in = std::find_if(inputs.begin(), inputs.end(), [&](const rig::SocketSpec& s) { return s.name == name; });
        // A plugin type's value arrives as the Python value of its JSON.
        if (in != inputs.end() && rig::is_plugin_type(in->type))
          kwargs[py::str(name)] = py::module_::import("json").attr("loads")(std::get<std::string>(value));
        else
          kwargs[py::str(name)] = param_to_python(value);
      }
      for (const auto& [name, items] : call.lists()) {
        py::list list;
        for (const rig::ParamValue& v : items) list.append(param_to_python(v));
        kwargs[py::str(name)] = list;
      }
      for (const auto& [name, meta] : call.components()) kwargs[py::str(name)] = node_ref(ref->scene, meta);
      // A component's controls, joints or hooks: a list of nodes.
      for (const auto& [name, ids] : call.node_lists()) {
        py::list nodes;
        for (NodeId id : ids) nodes.append(node_ref(ref->scene, id));
        kwargs[py::str(name)] = nodes;
      }
      py::object result = (*held)(py::cast(ref), **kwargs);
      ref->call = nullptr;
      if (result.is_none()) return Status::ok();
      // A dict is {output: value} when its keys are outputs' names; else,
      // with one output, that output's value (a plugin type's may be a dict).
      bool by_output = py::isinstance<py::dict>(result);
      if (by_output && outputs.size() == 1)
        for (auto [key, value] : py::reinterpret_borrow<py::dict>(result))
          if (!py::isinstance<py::str>(key) || py::str(key).cast<std::string>() != outputs[0].name) by_output = false;
      if (by_output) {
        for (auto [key, value] : py::reinterpret_borrow<py::dict>(result)) {
          const std::string name = py::str(key);
          const rig::SocketSpec* o = nullptr;
          for (const rig::SocketSpec& s : outputs)
            if (s.name == name) o = &s;
          if (!o) return error(ErrorCode::kInvalidArgument, who + ": returned '" + name + "', which is not one of its outputs");
          set_output_from_python(call, *o, value, who + ": output '" + name + "'");
        }
        return Status::ok();
      }
      if (outputs.size() != 1)
        return error(ErrorCode::kInvalidArgument, who + ": return a dict {output: value} (it has " +
                                                      std::to_string(outputs.size()) + " outputs)");
      set_output_from_python(call, outputs[0], result, who + ": its return value");
      return Status::ok();
    } catch (py::error_already_set& e) {
      ref->call = nullptr;
      return error(ErrorCode::kFailedPrecondition, who + " raised " + e.what());
    } catch (const StatusError& e) {
      ref->call = nullptr;
      return e.status().with_context(who);
    }
  };
}

// The ids of the functions registered from Python: removed before the
// interpreter goes (their bodies are Python objects).
std::vector<std::string>& python_ids() {
  static std::vector<std::string> ids;
  return ids;
}
// The same for flow kinds.
std::vector<std::string>& python_flow_ids() {
  static std::vector<std::string> ids;
  return ids;
}

// What a Python flow kind's body sees: go(exit, **outputs). Valid while it runs.
struct FlowCallRef {
  rig::FlowCall* call = nullptr;
  std::vector<rig::SocketSpec> outputs;
  std::string who;
  rig::FlowCall& get() const {
    if (!call) raise(ErrorCode::kFailedPrecondition, "this FlowCall has ended: use it only while the node kind runs");
    return *call;
  }
  void go(const std::string& exit, const py::kwargs& values) const {
    rig::FunctionValues out;
    for (auto [key, value] : values) {
      const std::string name = py::str(key);
      const auto o = std::find_if(outputs.begin(), outputs.end(), [&](const rig::SocketSpec& s) { return s.name == name; });
      if (o == outputs.end()) raise(ErrorCode::kInvalidArgument, who + ": go() got '" + name + "', which is not one of its outputs");
      const std::string where = who + ": output '" + name + "'";
      if (!rig::list_element(o->type).empty()) out.lists[name] = list_from_python(value, o->type, where);
      else out.values[name] = value_from_python(value, o->type, where);
    }
    get().go(exit, std::move(out));
  }
};

// The body of a Python flow kind: fn(call, **inputs) calls call.go(exit,
// **outputs) per pass (or returns an exit's name: go through it).
std::function<Status(rig::FlowCall&)> python_flow_body(py::function fn, const rig::FlowKind& kind) {
  auto held = std::shared_ptr<py::function>(new py::function(std::move(fn)), [](py::function* f) {
    py::gil_scoped_acquire gil;
    delete f;
  });
  const std::string who = "python node kind " + kind.id + (kind.origin.empty() ? "" : " (" + kind.origin + ")");
  return [held, who, outputs = kind.outputs](rig::FlowCall& call) -> Status {
    py::gil_scoped_acquire gil;
    auto ref = std::make_shared<FlowCallRef>();
    ref->call = &call;
    ref->outputs = outputs;
    ref->who = who;
    try {
      py::dict kwargs;
      for (const auto& [name, value] : call.inputs().values) kwargs[py::str(name)] = param_to_python(value);
      for (const auto& [name, items] : call.inputs().lists) {
        py::list list;
        for (const rig::ParamValue& v : items) list.append(param_to_python(v));
        kwargs[py::str(name)] = list;
      }
      py::object result = (*held)(py::cast(ref), **kwargs);
      if (py::isinstance<py::str>(result)) ref->go(result.cast<std::string>(), py::kwargs());
      else if (!result.is_none())
        raise(ErrorCode::kInvalidArgument, who + ": return None (after call.go(...)) or an exit's name");
      ref->call = nullptr;
      return Status::ok();
    } catch (py::error_already_set& e) {
      ref->call = nullptr;
      return error(ErrorCode::kFailedPrecondition, who + " raised " + e.what());
    } catch (const StatusError& e) {
      ref->call = nullptr;
      return e.status().with_context(who);
    }
  };
}

// A plugin's defaults {name: value} as Params of its value inputs.
std::vector<rig::Param> defaults_from_python(py::object defaults, const std::vector<rig::SocketSpec>& inputs,
                                             const std::string& who) {
  std::vector<rig::Param> out;
  if (defaults.is_none()) return out;
  for (auto [key, value] : defaults.cast<py::dict>()) {
    const std::string name = py::str(key);
    const rig::SocketSpec* in = nullptr;
    for (const rig::SocketSpec& s : inputs)
      if (s.name == name) in = &s;
    if (!in) raise(ErrorCode::kInvalidArgument, who + ": default for '" + name + "', which is not an input");
    out.push_back(rig::Param{name, value_from_python(value, in->type, "default '" + name + "'"), {}});
  }
  return out;
}

py::dict function_record(const rig::BuildFunction& f) {
  py::dict d;
  d["id"] = f.id;
  d["nice_name"] = f.nice_name;
  d["category"] = f.category;
  d["help"] = f.help;
  d["origin"] = f.origin;
  py::list in, out;
  for (const rig::SocketSpec& s : f.inputs) in.append(py::make_tuple(s.name, s.type));
  for (const rig::SocketSpec& s : f.outputs) out.append(py::make_tuple(s.name, s.type));
  d["inputs"] = in;
  d["outputs"] = out;
  return d;
}

py::list diagnostics(const std::vector<rig::Diagnostic>& list) {
  py::list out;
  for (const rig::Diagnostic& d : list) out.append(d.str());
  return out;
}

// Node kinds written in Python (flow kinds).
void wrap_node_kinds(py::module_& m) {
  py::class_<FlowCallRef, std::shared_ptr<FlowCallRef>>(
      m, "FlowCall", "What a node kind written in Python sees while it runs: go(exit, **outputs) per pass.")
      .def("go", &FlowCallRef::go, py::arg("exit"),
           "Goes on through exit `exit` (an exec output), its data outputs given as keywords (unset: the type's zero).");
  m.def(
      "register_node_kind",
      [](py::function fn, const std::string& id, py::object inputs, py::object outputs, std::vector<std::string> exits,
         std::vector<std::string> repeats, const std::string& nice_name, const std::string& category,
         const std::string& help, py::object defaults, const std::string& origin) {
        rig::FlowKind k;
        k.id = id;
        k.nice_name = nice_name;
        k.category = category;
        k.help = help;
        k.origin = origin;
        k.inputs = sockets_from_python(inputs, "register_node_kind '" + id + "': inputs");
        k.outputs = sockets_from_python(outputs, "register_node_kind '" + id + "': outputs");
        k.exits = std::move(exits);
        k.repeats = std::move(repeats);
        k.defaults = defaults_from_python(defaults, k.inputs, "register_node_kind '" + id + "'");
        k.run = python_flow_body(std::move(fn), k);
        if (Status s = rig::flow_kinds().add(std::move(k)); !s) raise(s);
        python_flow_ids().push_back(id);
      },
      py::arg("fn"), py::arg("id"), py::arg("inputs") = py::none(), py::arg("outputs") = py::none(),
      py::arg("exits") = std::vector<std::string>{"then"}, py::arg("repeats") = std::vector<std::string>{},
      py::arg("nice_name") = "", py::arg("category") = "", py::arg("help") = "", py::arg("defaults") = py::none(),
      py::arg("origin") = "",
      "Registers a node kind written in Python (a flow node, kind flow:ID): while the graph compiles, "
      "fn(call, **inputs) calls call.go(exit, **outputs) for each pass through its exits (exec outputs), in "
      "order, or returns one exit's name. repeats: the exits it may take many times (each pass keyed as a "
      "for-each item). Inputs and outputs are values and lists of them. AlreadyExistsError when the id is taken.");
  m.def(
      "node_kinds",
      []() {
        py::list out;
        for (const rig::FlowKind& k : rig::flow_kinds().kinds()) {
          py::dict d;
          d["id"] = k.id;
          d["nice_name"] = k.nice_name;
          d["category"] = k.category;
          d["origin"] = k.origin;
          d["exits"] = k.exits;
          d["repeats"] = k.repeats;
          out.append(d);
        }
        return out;
      },
      "Every registered node kind (flow kind): id, nice_name, category, origin, exits, repeats.");
}

}  // namespace

void wrap_build_graph(py::module_& m) {
  wrap_node_kinds(m);
  py::module_::import("atexit").attr("register")(py::cpp_function([] {
    for (const std::string& id : python_ids()) rig::build_functions().remove(id);
    python_ids().clear();
    for (const std::string& id : python_flow_ids()) rig::flow_kinds().remove(id);
    python_flow_ids().clear();
  }));
  py::class_<CallRef, std::shared_ptr<CallRef>>(m, "FunctionCall",
                                                "What a build function written in Python sees while it runs: the "
                                                "scene being built, the rig, its inputs. Valid during the call only.")
      .def_property_readonly("scene", [](const CallRef& c) { (void)c.get(); return c.scene; })
      .def_property_readonly("rig", [](const CallRef& c) { return node_ref(c.scene, c.built().rig()); },
                             "The rig's metaRoot node.")
      .def_property_readonly("node", [](const CallRef& c) { return node_ref(c.scene, c.built().call()); },
                             "The call's own metaComponent node.")
      .def("controls",
           [](const CallRef& c, const std::string& input) {
             const NodeId meta = c.built().component(input);
             if (!meta.is_valid()) raise(ErrorCode::kInvalidArgument, "'" + input + "' is not a component input");
             return node_list(c.scene, rig::meta_controls(c.scene->graph(), meta));
           },
           py::arg("input"), "The controls of a component input's component, in build order.")
      .def("members",
           [](const CallRef& c, const std::string& input) {
             const NodeId meta = c.built().component(input);
             if (!meta.is_valid()) raise(ErrorCode::kInvalidArgument, "'" + input + "' is not a component input");
             return node_list(c.scene, rig::meta_members(c.scene->graph(), meta));
           },
           py::arg("input"), "Every node a component input's component built.");

  m.def(
      "register_function",
      [](py::function fn, const std::string& id, py::object inputs, py::object outputs, const std::string& nice_name,
         const std::string& category, const std::string& help, py::object defaults, const std::string& origin,
         bool pure) {
        rig::BuildFunction f;
        f.id = id;
        f.pure = pure;
        f.nice_name = nice_name;
        f.category = category;
        f.help = help;
        f.origin = origin;
        f.inputs = sockets_from_python(inputs, "register_function '" + id + "': inputs");
        f.outputs = sockets_from_python(outputs, "register_function '" + id + "': outputs");
        f.defaults = defaults_from_python(defaults, f.inputs, "register_function '" + id + "'");
        f.run = python_body(std::move(fn), id, origin, f.inputs, f.outputs);
        if (Status s = rig::build_functions().add(std::move(f)); !s) raise(s);
        python_ids().push_back(id);
      },
      py::arg("fn"), py::arg("id"), py::arg("inputs") = py::none(), py::arg("outputs") = py::none(),
      py::arg("nice_name") = "", py::arg("category") = "", py::arg("help") = "", py::arg("defaults") = py::none(),
      py::arg("origin") = "", py::arg("pure") = false,
      "Registers a build function written in Python: fn(call, **inputs) returns None, the value of its one "
      "output or {output: value}. inputs and outputs are [(name, type)] or {name: type} (bool, int, number, "
      "string, vector, a list of one: list:int, ... as a Python list; inputs also component, which arrives as the "
      "component's meta node, and list:control, "
      "list:joint or list:node, which arrive as the linked component's controls, joints or hooks). pure: it "
      "maps values to values and runs while the graph compiles (a value node without exec sockets; its call "
      "has no scene). "
      "AlreadyExistsError "
      "when the id is taken (naming who has it).");
  m.def(
      "unregister_functions",
      [](const std::string& origin) {
        rig::unregister_data_types(origin);
        rig::flow_kinds().remove_origin(origin);
        return rig::build_functions().remove_origin(origin);
      },
      py::arg("origin"),
      "Removes every build function, node kind and data type registered from `origin` (a plugin's file); how "
      "many functions.");
  m.def(
      "register_data_type",
      [](const std::string& name, const std::string& color, const std::string& help, const std::string& origin) {
        rig::DataType t;
        t.name = name;
        t.color = color;
        t.help = help;
        t.origin = origin;
        if (Status s = rig::register_data_type(std::move(t)); !s) raise(s);
      },
      py::arg("name"), py::arg("color"), py::arg("help") = "", py::arg("origin"),
      "Registers a plugin's data type: a socket colour (#rrggbb) and values (anything JSON can write) that "
      "its functions' outputs pass to functions' inputs. AlreadyExistsError naming both origins when the name is "
      "taken.");
  m.def(
      "data_types",
      []() {
        py::list out;
        for (const rig::DataType& t : rig::builtin_data_types().types()) {
          py::dict d;
          d["name"] = t.name;
          d["color"] = t.color;
          d["help"] = t.help;
          d["origin"] = t.origin;
          out.append(d);
        }
        return out;
      },
      "The build graphs' data types: the built-in ones (origin \"\"), then the plugins'.");
  m.def(
      "build_functions",
      []() {
        py::list out;
        for (const rig::BuildFunction& f : rig::build_functions().functions()) out.append(function_record(f));
        return out;
      },
      "Every registered build function: id, nice_name, category, help, origin, inputs, outputs.");
  m.def(
      "validate_graph",
      [](const std::string& path) {
        const rig::BuildGraphCompile checked = rig::check_build_graph(path);
        py::dict d;
        d["valid"] = checked.ok();
        d["errors"] = diagnostics(checked.errors);
        d["warnings"] = diagnostics(checked.warnings);
        d["order"] = checked.order;
        return record(d);
      },
      py::arg("path"), "Checks a build graph (.build.json): valid, errors and warnings (file:line:column: message, "
                       "node and socket named), and the ids of the nodes its exec chain runs.");
  m.def(
      "convert_definition",
      [](const std::string& definition, const std::string& graph) {
        auto converted = app::convert_definition_file(definition, graph);
        if (!converted) raise(converted.status());
        py::dict d;
        d["graph"] = graph;
        d["nodes"] = converted->nodes.size();
        d["links"] = converted->links.size();
        return record(d);
      },
      py::arg("definition"), py::arg("graph"),
      "Writes the build graph of a definition (graph: a .build.json path); its files made relative to it.");
  m.def(
      "graph_palette",
      [] {
        const auto& schemas = rig::builtin_schemas();
        return py::module_::import("json").attr("loads")(rig::graph_palette_json(rig::builtin_node_kinds(schemas), schemas).dump());
      },
      "What the graph editor's palette offers now: {types: [...], kinds: [{id, niceName, category, help, inputs, "
      "outputs}]}, the functions registered in this process included.");
}

}  // namespace rigel::python
