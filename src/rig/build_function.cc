// Build functions (build_function.h): the registry, and the `call`
// component class whose step runs one.
#include "rigel/rig/build_function.h"

#include <algorithm>
#include <charconv>
#include <set>

#include <nlohmann/json.hpp>

#include "definition_io_internal.h"
#include "rigel/rig/component.h"
#include "rigel/rig/meta.h"

namespace rigel::rig {
namespace {

using Json = nlohmann::ordered_json;

const SocketSpec* find_socket(const std::vector<SocketSpec>& list, std::string_view name) {
  for (const SocketSpec& s : list)
    if (s.name == name) return &s;
  return nullptr;
}

// The input types that take what a component node's build makes: its
// controls, joints or hooks, as {"$controls" | "$joints" | "$hooks": rigId}.
bool is_node_list_type(const std::string& type) {
  return type == "list:control" || type == "list:joint" || type == "list:node";
}

// What a component input of one of those types gives: its controls (build
// order), the joints its guides name, or its hooks (by index).
Result<std::vector<graph::NodeId>> component_nodes(BuildContext& ctx, graph::NodeId meta, const std::string& what) {
  const graph::Graph& g = ctx.graph();
  if (what == "controls") return meta_controls(g, meta);
  std::vector<graph::NodeId> out;
  if (what == "hooks") {
    std::vector<std::pair<int, graph::NodeId>> hooks;
    for (graph::NodeId m : meta_members(g, meta))
      if (const std::string* h = g.node(m)->tag_find(kTagHook)) {
        int index = 0;
        if (std::from_chars(h->data(), h->data() + h->size(), index).ec == std::errc()) hooks.emplace_back(index, m);
      }
    std::stable_sort(hooks.begin(), hooks.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& [index, node] : hooks) out.push_back(node);
    return out;
  }
  const Component* c = ctx.definition().find_by_rig_id(meta_string(g, meta, "rigId"));
  if (!c) return error(ErrorCode::kNotFound, "its component is not in the definition");
  for (const Guide& guide : c->guides) {
    if (guide.joint.empty()) continue;
    const graph::NodeId j = g.find(guide.joint);
    if (!j.is_valid()) return error(ErrorCode::kNotFound, "the scene has no joint '" + guide.joint + "'");
    out.push_back(j);
  }
  return out;
}

bool is_value_type(const std::string& type) {
  const DataType* t = builtin_data_types().find(type);
  return t && t->value_type;
}

// list:bool, list:int, list:number, list:string, list:vector.
bool is_value_list(const std::string& type) { return !list_element(type).empty(); }

Json list_json(const ValueList& items) {
  Json out = Json::array();
  for (const ParamValue& v : items) out.push_back(detail::param_value_json(v));
  return out;
}

// The items of an output a function set, as its list type's items (an int
// into a list:number becomes a double); nullopt when one does not fit.
std::optional<ValueList> typed_items(const ValueList& items, const std::string& type) {
  const DataType* element = builtin_data_types().find(list_element(type));
  ValueList out;
  out.reserve(items.size());
  for (const ParamValue& v : items) {
    if (!element || !value_fits(v, *element->value_type)) return std::nullopt;
    if (*element->value_type == ParamType::kDouble && std::holds_alternative<std::int64_t>(v))
      out.push_back(static_cast<double>(std::get<std::int64_t>(v)));
    else
      out.push_back(v);
  }
  return out;
}


// Whether `v` is a value of data type `type` (a value type: the sockets
// of a registered function are checked to be).
bool fits_type(const ParamValue& v, const std::string& type) {
  if (is_plugin_type(type)) {
    const auto* text = std::get_if<std::string>(&v);
    return text && Json::accept(*text);
  }
  const DataType* t = builtin_data_types().find(type);
  return t && t->value_type && value_fits(v, *t->value_type);
}

// The value of an input no node gives: its type's zero (a plugin type's: null).
ParamValue zero(const std::string& type) {
  if (is_plugin_type(type)) return std::string("null");
  return zero_value(*builtin_data_types().find(type)->value_type);
}

// An output as it is kept on the call's meta node: a plugin type's as the
// JSON its text holds.
Json output_json(const ParamValue& v, const std::string& type) {
  if (is_plugin_type(type)) return Json::parse(std::get<std::string>(v));
  return detail::param_value_json(v);
}

// The outputs a body set, checked against `sockets`, with those it did
// not set as their type's zero (a list: empty).
Result<FunctionValues> checked_outputs(const std::vector<SocketSpec>& sockets,
                                       const std::map<std::string, ParamValue>& values,
                                       const std::map<std::string, ValueList>& lists) {
  FunctionValues out;
  for (const auto& [name, value] : values) {
    const SocketSpec* o = find_socket(sockets, name);
    if (!o) return error(ErrorCode::kInvalidArgument, "it set '" + name + "', which is not one of its outputs");
    if (is_value_list(o->type) || !fits_type(value, o->type))
      return error(ErrorCode::kInvalidArgument, "output '" + name + "' is not a " + o->type);
    out.values[name] = value;
  }
  for (const auto& [name, items] : lists) {
    const SocketSpec* o = find_socket(sockets, name);
    if (!o) return error(ErrorCode::kInvalidArgument, "it set '" + name + "', which is not one of its outputs");
    std::optional<ValueList> typed = is_value_list(o->type) ? typed_items(items, o->type) : std::nullopt;
    if (!typed) return error(ErrorCode::kInvalidArgument, "output '" + name + "' is not a " + o->type);
    out.lists[name] = std::move(*typed);
  }
  for (const SocketSpec& o : sockets) {
    if (is_value_list(o.type)) out.lists.try_emplace(o.name);
    else out.values.try_emplace(o.name, zero(o.type));
  }
  return out;
}
Result<FunctionValues> checked_outputs(const BuildFunction& f, const FunctionCall& call) {
  return checked_outputs(f.outputs, call.outputs(), call.list_outputs());
}

// The inputs no one gave: each value input its default, else its type's
// zero; each list input none.
void fill_inputs(const std::vector<SocketSpec>& sockets, const std::vector<Param>& defaults, FunctionValues& in) {
  for (const SocketSpec& s : sockets) {
    if (is_value_list(s.type)) {
      in.lists.try_emplace(s.name);
      continue;
    }
    if (in.values.count(s.name)) continue;
    const auto d = std::find_if(defaults.begin(), defaults.end(), [&](const Param& p) { return p.name == s.name; });
    in.values[s.name] = d != defaults.end() ? d->value : zero(s.type);
  }
}

// Sockets named once each, of types `fits` takes (`kinds` says which, for
// the message); defaults each of a value input's type.
Status check_sockets(const std::string& who, const std::vector<SocketSpec>& inputs,
                     const std::vector<SocketSpec>& outputs, const std::vector<Param>& defaults,
                     const std::function<bool(const SocketSpec&, bool input)>& fits, const char* kinds) {
  for (const auto* list : {&inputs, &outputs}) {
    std::set<std::string> names;
    for (const SocketSpec& s : *list) {
      if (s.name.empty() || !names.insert(s.name).second)
        return error(ErrorCode::kInvalidArgument, who + ": an empty or repeated socket name '" + s.name + "'");
      if (!fits(s, list == &inputs))
        return error(ErrorCode::kInvalidArgument,
                     who + ": socket '" + s.name + "' has type '" + s.type + "' (" + kinds + ")");
    }
  }
  for (const Param& d : defaults) {
    const SocketSpec* in = find_socket(inputs, d.name);
    if (!in || !is_value_type(in->type) || !fits_type(d.value, in->type))
      return error(ErrorCode::kInvalidArgument,
                   who + ": the default of '" + d.name + "' is not one of its value inputs' type");
  }
  return Status::ok();
}

// The `call` component: one step that runs its function.
Status run_call(BuildContext& ctx) {
  const std::string id = ctx.param_string("function");
  const std::string who = "call '" + ctx.component().full_name() + "' (" + id + ")";
  const std::optional<BuildFunction> fn = build_functions().find(id);
  if (!fn)
    return error(ErrorCode::kNotFound,
                 who + ": no build function '" + id + "' is registered (is the plugin that registers it loaded?)");
  Json args;
  try {
    args = Json::parse(ctx.param_string("args"));
  } catch (const Json::exception& e) {
    return error(ErrorCode::kInvalidArgument, who + ": args: not JSON: " + e.what());
  }
  if (!args.is_object()) return error(ErrorCode::kInvalidArgument, who + ": args must be a JSON object");
  graph::Graph& g = ctx.graph();
  std::map<std::string, ParamValue> values;
  std::map<std::string, graph::NodeId> components;
  std::map<std::string, std::vector<graph::NodeId>> nodes;
  std::map<std::string, ValueList> lists;
  for (auto it = args.begin(); it != args.end(); ++it)
    if (!fn->input(it.key()))
      return error(ErrorCode::kInvalidArgument, who + ": args: '" + it.key() + "' is not an input of the function");
  for (const SocketSpec& in : fn->inputs) {
    const std::string where = who + ": input '" + in.name + "'";
    if (!args.contains(in.name)) {
      if (in.type == "component" || is_node_list_type(in.type))
        return error(ErrorCode::kInvalidArgument, where + ": no component given");
      const auto d =
          std::find_if(fn->defaults.begin(), fn->defaults.end(), [&](const Param& p) { return p.name == in.name; });
      if (is_value_list(in.type)) lists[in.name] = {};
      else values[in.name] = d != fn->defaults.end() ? d->value : zero(in.type);
      continue;
    }
    const Json& a = args[in.name];
    const std::string made = in.type == "list:control" ? "$controls" : in.type == "list:joint" ? "$joints" : "$hooks";
    if (is_node_list_type(in.type) && a.is_object() && a.contains(made) && a[made].is_string()) {
      const graph::NodeId meta = find_component(g, ctx.root(), a[made].get<std::string>());
      if (!meta.is_valid()) return error(ErrorCode::kNotFound, where + ": component " + a[made].dump() + " is not built");
      auto list = component_nodes(ctx, meta, made.substr(1));
      if (!list) return list.status().with_context(where);
      nodes[in.name] = std::move(*list);
    } else if (is_node_list_type(in.type)) {
      return error(ErrorCode::kInvalidArgument, where + ": " + a.dump() + " names no component's " + made.substr(1));
    } else if (a.is_object() && a.contains("$component")) {
      const graph::NodeId meta = find_component(g, ctx.root(), a["$component"].get<std::string>());
      if (!meta.is_valid() || in.type != "component")
        return error(ErrorCode::kNotFound, where + ": component " + a["$component"].dump() + " is not built");
      components[in.name] = meta;
    } else if (a.is_object() && a.contains("$output") && a["$output"].is_array() && a["$output"].size() == 2) {
      const graph::NodeId from = find_component(g, ctx.root(), a["$output"][0].get<std::string>());
      const Json outputs = from.is_valid() ? Json::parse(meta_string(g, from, kOutputsAttr), nullptr, false) : Json();
      const std::string name = a["$output"][1].get<std::string>();
      const bool there = outputs.is_object() && outputs.contains(name);
      std::optional<ParamValue> v;
      std::optional<ValueList> items;
      if (there && is_value_list(in.type)) items = list_from_json(outputs[name], in.type);
      else if (there) v = value_from_json(outputs[name], in.type);
      if (!v && !items)
        return error(ErrorCode::kNotFound,
                     where + ": the output " + a["$output"].dump() + " is not there (did its call run?)");
      if (items) lists[in.name] = std::move(*items);
      else values[in.name] = std::move(*v);
    } else if (is_value_list(in.type)) {
      std::optional<ValueList> items = list_from_json(a, in.type);
      if (!items) return error(ErrorCode::kInvalidArgument, where + ": " + a.dump() + " is not a " + in.type);
      lists[in.name] = std::move(*items);
    } else {
      std::optional<ParamValue> v = value_from_json(a, in.type);
      if (!v) return error(ErrorCode::kInvalidArgument, where + ": " + a.dump() + " is not a " + in.type);
      values[in.name] = std::move(*v);
    }
  }
  FunctionCall call(ctx.scene(), ctx.definition(), ctx.root(), ctx.meta(), std::move(values), std::move(components),
                    std::move(nodes), std::move(lists));
  if (!fn->run) return error(ErrorCode::kInvalidArgument, who + ": the function has no body");
  if (Status s = fn->run(call); !s) return s.with_context(who);
  auto set = checked_outputs(*fn, call);
  if (!set) return set.status().with_context(who);
  Json out = Json::object();
  for (const SocketSpec& o : fn->outputs)
    out[o.name] = is_value_list(o.type) ? list_json(set->lists.at(o.name)) : output_json(set->values.at(o.name), o.type);
  if (fn->outputs.empty()) return Status::ok();
  return g.set_value(graph::Plug{ctx.meta(), g.node(ctx.meta())->type().attr_find(kOutputsAttr), -1},
                     graph::Value(out.dump()));
}

class CallClass final : public ComponentClass {
 public:
  std::string_view type() const override { return kCallType; }
  std::vector<Step> steps(const Component&) const override { return {Step{"run", "", "", run_call}}; }
  bool editable() const override { return false; }
};

}  // namespace

const ParamValue* FunctionCall::value(std::string_view input) const {
  const auto it = values_.find(std::string(input));
  return it == values_.end() ? nullptr : &it->second;
}

const Component* FunctionCall::component_definition(std::string_view input) const {
  const graph::NodeId meta = component(input);
  if (!meta.is_valid() || !scene_) return nullptr;
  return definition_->find_by_rig_id(meta_string(scene_->graph(), meta, "rigId"));
}

const ValueList* FunctionCall::list(std::string_view input) const {
  const auto it = lists_.find(std::string(input));
  return it == lists_.end() ? nullptr : &it->second;
}

const std::vector<graph::NodeId>* FunctionCall::nodes(std::string_view input) const {
  const auto it = nodes_.find(std::string(input));
  return it == nodes_.end() ? nullptr : &it->second;
}

graph::NodeId FunctionCall::component(std::string_view input) const {
  const auto it = components_.find(std::string(input));
  return it == components_.end() ? graph::NodeId{} : it->second;
}

const SocketSpec* BuildFunction::input(std::string_view name) const { return find_socket(inputs, name); }
const SocketSpec* BuildFunction::output(std::string_view name) const { return find_socket(outputs, name); }

Status FunctionRegistry::add(BuildFunction f) {
  const std::string who = "build function '" + f.id + "'" + (f.origin.empty() ? "" : " (" + f.origin + ")");
  if (f.id.empty()) return error(ErrorCode::kInvalidArgument, "a build function needs an id");
  if (!f.run) return error(ErrorCode::kInvalidArgument, who + ": no body to run");
  const bool pure = f.pure;
  const auto fits = [pure](const SocketSpec& s, bool input) {
    return is_value_type(s.type) || is_value_list(s.type) || (!pure && is_plugin_type(s.type)) ||
           (!pure && input && (s.type == "component" || is_node_list_type(s.type)));
  };
  if (Status s = check_sockets(who, f.inputs, f.outputs, f.defaults, fits,
                               "inputs: bool, int, number, string, vector, a list of one (list:number, ...), a "
                               "plugin's data type, component, list:control, list:joint or list:node; outputs: the "
                               "values, their lists and plugins' types");
      !s)
    return s;
  return insert(std::move(f), who);
}

FunctionRegistry& build_functions() {
  static FunctionRegistry registry;
  return registry;
}

Result<FunctionValues> run_pure(const BuildFunction& f, FunctionValues in) {
  fill_inputs(f.inputs, f.defaults, in);
  if (!f.run) return error(ErrorCode::kInvalidArgument, "the function has no body");
  FunctionCall call(std::move(in.values), std::move(in.lists));
  if (Status s = f.run(call); !s) return s;
  return checked_outputs(f, call);
}

std::optional<ParamValue> value_from_json(const nlohmann::ordered_json& j, std::string_view type) {
  if (type.empty()) {  // by the JSON's kind
    if (j.is_boolean()) type = "bool";
    else if (j.is_number_integer()) type = "int";
    else if (j.is_number()) type = "number";
    else if (j.is_string()) type = "string";
    else type = "vector";
  }
  if (is_plugin_type(type)) return j.dump();
  if (type == "bool" && j.is_boolean()) return j.get<bool>();
  if (type == "int" && j.is_number_integer()) return j.get<std::int64_t>();
  if (type == "number" && j.is_number()) return j.get<double>();
  if (type == "string" && j.is_string()) return j.get<std::string>();
  if (type == "vector" && j.is_array() && j.size() == 3 && j[0].is_number() && j[1].is_number() && j[2].is_number())
    return math::Vec3(j[0].get<double>(), j[1].get<double>(), j[2].get<double>());
  return std::nullopt;
}

std::optional<ValueList> list_from_json(const nlohmann::ordered_json& j, std::string_view list_type) {
  const std::string element = list_element(list_type);
  if (element.empty() || !j.is_array()) return std::nullopt;
  ValueList out;
  out.reserve(j.size());
  for (const Json& item : j) {
    std::optional<ParamValue> v = value_from_json(item, element);
    if (!v) return std::nullopt;
    out.push_back(std::move(*v));
  }
  return out;
}

NodeKind function_node_kind(const BuildFunction& f) {
  NodeKind k;
  k.id = "function:" + f.id;
  k.nice_name = f.nice_name.empty() ? f.id : f.nice_name;
  k.category = f.category.empty() ? (f.pure ? "Values" : "Functions") : f.category;
  k.help = f.help;
  if (!f.pure) k.inputs.push_back({"exec", "exec", "runs the function"});
  for (const SocketSpec& s : f.inputs) k.inputs.push_back(s);
  if (!f.pure) k.outputs.push_back({"then", "exec", "the next node"});
  for (const SocketSpec& s : f.outputs) k.outputs.push_back(s);
  return k;
}

// ---- flow kinds

const ParamValue* FlowCall::value(std::string_view input) const {
  const auto it = in_.values.find(std::string(input));
  return it == in_.values.end() ? nullptr : &it->second;
}

const ValueList* FlowCall::list(std::string_view input) const {
  const auto it = in_.lists.find(std::string(input));
  return it == in_.lists.end() ? nullptr : &it->second;
}

const SocketSpec* FlowKind::input(std::string_view name) const { return find_socket(inputs, name); }
const SocketSpec* FlowKind::output(std::string_view name) const { return find_socket(outputs, name); }

Status FlowKindRegistry::add(FlowKind k) {
  const std::string who = "node kind '" + k.id + "'" + (k.origin.empty() ? "" : " (" + k.origin + ")");
  if (k.id.empty()) return error(ErrorCode::kInvalidArgument, "a node kind needs an id");
  if (!k.run) return error(ErrorCode::kInvalidArgument, who + ": no body to run");
  if (k.exits.empty()) return error(ErrorCode::kInvalidArgument, who + ": no exits (exec outputs) to go on through");
  std::set<std::string> names;
  for (const SocketSpec& s : k.outputs) names.insert(s.name);
  for (const std::string& e : k.exits)
    if (e.empty() || e == "exec" || !names.insert(e).second)
      return error(ErrorCode::kInvalidArgument, who + ": exit '" + e + "' is empty, 'exec', or a second socket of its name");
  for (const std::string& r : k.repeats)
    if (std::find(k.exits.begin(), k.exits.end(), r) == k.exits.end())
      return error(ErrorCode::kInvalidArgument, who + ": repeat '" + r + "' is not one of its exits");
  const auto fits = [](const SocketSpec& s, bool) { return is_value_type(s.type) || is_value_list(s.type); };
  if (Status s = check_sockets(who, k.inputs, k.outputs, k.defaults, fits,
                               "bool, int, number, string, vector or a list of one (list:number, ...)");
      !s)
    return s;
  return insert(std::move(k), who);
}

FlowKindRegistry& flow_kinds() {
  static FlowKindRegistry registry;
  return registry;
}

Result<std::vector<FlowCall::Step>> run_flow(const FlowKind& k, FunctionValues in) {
  fill_inputs(k.inputs, k.defaults, in);
  if (!k.run) return error(ErrorCode::kInvalidArgument, "the node kind has no body");
  FlowCall call(std::move(in));
  if (Status s = k.run(call); !s) return s;
  std::vector<FlowCall::Step> steps;
  std::set<std::string> taken;
  for (const FlowCall::Step& step : call.steps()) {
    if (std::find(k.exits.begin(), k.exits.end(), step.exit) == k.exits.end())
      return error(ErrorCode::kInvalidArgument, "it went on through '" + step.exit + "', which is not one of its exits");
    const bool repeats = std::find(k.repeats.begin(), k.repeats.end(), step.exit) != k.repeats.end();
    if (!repeats && !taken.insert(step.exit).second)
      return error(ErrorCode::kInvalidArgument, "it went on through '" + step.exit + "' twice (it is not a repeat)");
    auto outputs = checked_outputs(k.outputs, step.outputs.values, step.outputs.lists);
    if (!outputs) return outputs.status();
    steps.push_back({step.exit, std::move(*outputs)});
  }
  return steps;
}

NodeKind flow_node_kind(const FlowKind& k) {
  NodeKind n;
  n.id = "flow:" + k.id;
  n.nice_name = k.nice_name.empty() ? k.id : k.nice_name;
  n.category = k.category.empty() ? "Flow" : k.category;
  n.help = k.help;
  n.inputs.push_back({"exec", "exec", "runs the node"});
  for (const SocketSpec& s : k.inputs) n.inputs.push_back(s);
  for (const std::string& e : k.exits) {
    const bool repeats = std::find(k.repeats.begin(), k.repeats.end(), e) != k.repeats.end();
    n.outputs.push_back({e, "exec", repeats ? "runs once per pass" : "runs at most once"});
  }
  for (const SocketSpec& s : k.outputs) n.outputs.push_back(s);
  return n;
}

Status add_call_component(ComponentFactory& factory) { return factory.add(std::make_shared<CallClass>()); }

}  // namespace rigel::rig
