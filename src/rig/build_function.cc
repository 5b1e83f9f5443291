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
      values[in.name] = d != fn->defaults.end() ? d->value : zero(in.type);
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
      std::optional<ParamValue> v;
      if (outputs.is_object() && outputs.contains(name)) v = value_from_json(outputs[name], in.type);
      if (!v)
        return error(ErrorCode::kNotFound,
                     where + ": the output " + a["$output"].dump() + " is not there (did its call run?)");
      values[in.name] = std::move(*v);
    } else {
      std::optional<ParamValue> v = value_from_json(a, in.type);
      if (!v) return error(ErrorCode::kInvalidArgument, where + ": " + a.dump() + " is not a " + in.type);
      values[in.name] = std::move(*v);
    }
  }
  FunctionCall call(ctx.scene(), ctx.definition(), ctx.root(), ctx.meta(), std::move(values), std::move(components),
                    std::move(nodes));
  if (!fn->run) return error(ErrorCode::kInvalidArgument, who + ": the function has no body");
  if (Status s = fn->run(call); !s) return s.with_context(who);
  Json out = Json::object();
  for (const auto& [name, value] : call.outputs()) {
    const SocketSpec* o = fn->output(name);
    if (!o)
      return error(ErrorCode::kInvalidArgument,
                   who + ": the function set '" + name + "', which is not one of its outputs");
    if (!fits_type(value, o->type))
      return error(ErrorCode::kInvalidArgument, who + ": output '" + name + "' is not a " + o->type);
  }
  for (const SocketSpec& o : fn->outputs) {
    const auto it = call.outputs().find(o.name);
    out[o.name] = output_json(it != call.outputs().end() ? it->second : zero(o.type), o.type);
  }
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
  for (const auto* list : {&f.inputs, &f.outputs}) {
    std::set<std::string> names;
    for (const SocketSpec& s : *list) {
      if (s.name.empty() || !names.insert(s.name).second)
        return error(ErrorCode::kInvalidArgument, who + ": an empty or repeated socket name '" + s.name + "'");
      const bool ok = is_value_type(s.type) || (!f.pure && is_plugin_type(s.type)) ||
                      (!f.pure && list == &f.inputs && (s.type == "component" || is_node_list_type(s.type)));
      if (!ok)
        return error(ErrorCode::kInvalidArgument,
                     who + ": socket '" + s.name + "' has type '" + s.type +
                         "' (inputs: bool, int, number, string, vector, a plugin's data type, component, "
                         "list:control, list:joint or list:node; outputs: the values and plugins' types)");
    }
  }
  for (const Param& d : f.defaults) {
    const SocketSpec* in = f.input(d.name);
    if (!in || !is_value_type(in->type) || !fits_type(d.value, in->type))
      return error(ErrorCode::kInvalidArgument,
                   who + ": the default of '" + d.name + "' is not one of its value inputs' type");
  }
  std::lock_guard lock(mutex_);
  for (const BuildFunction& other : functions_)
    if (other.id == f.id)
      return error(ErrorCode::kAlreadyExists, who + ": the id is taken by " +
                                                  (other.origin.empty() ? std::string("another function") : other.origin));
  functions_.push_back(std::move(f));
  return Status::ok();
}

std::size_t FunctionRegistry::remove_origin(std::string_view origin) {
  std::lock_guard lock(mutex_);
  const std::size_t before = functions_.size();
  std::erase_if(functions_, [&](const BuildFunction& f) { return f.origin == origin; });
  return before - functions_.size();
}

bool FunctionRegistry::remove(std::string_view id) {
  std::lock_guard lock(mutex_);
  return std::erase_if(functions_, [&](const BuildFunction& f) { return f.id == id; }) > 0;
}

std::optional<BuildFunction> FunctionRegistry::find(std::string_view id) const {
  std::lock_guard lock(mutex_);
  for (const BuildFunction& f : functions_)
    if (f.id == id) return f;
  return std::nullopt;
}

std::vector<BuildFunction> FunctionRegistry::functions() const {
  std::lock_guard lock(mutex_);
  return functions_;
}

FunctionRegistry& build_functions() {
  static FunctionRegistry registry;
  return registry;
}

Result<std::map<std::string, ParamValue>> run_pure(const BuildFunction& f, std::map<std::string, ParamValue> values) {
  for (const SocketSpec& in : f.inputs) {
    if (values.count(in.name)) continue;
    const auto d = std::find_if(f.defaults.begin(), f.defaults.end(), [&](const Param& p) { return p.name == in.name; });
    values[in.name] = d != f.defaults.end() ? d->value : zero(in.type);
  }
  if (!f.run) return error(ErrorCode::kInvalidArgument, "the function has no body");
  FunctionCall call(std::move(values));
  if (Status s = f.run(call); !s) return s;
  std::map<std::string, ParamValue> out;
  for (const auto& [name, value] : call.outputs()) {
    const SocketSpec* o = f.output(name);
    if (!o) return error(ErrorCode::kInvalidArgument, "it set '" + name + "', which is not one of its outputs");
    if (!fits_type(value, o->type)) return error(ErrorCode::kInvalidArgument, "output '" + name + "' is not a " + o->type);
    out[name] = value;
  }
  for (const SocketSpec& o : f.outputs) out.try_emplace(o.name, zero(o.type));
  return out;
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

Status add_call_component(ComponentFactory& factory) { return factory.add(std::make_shared<CallClass>()); }

}  // namespace rigel::rig
