// Build graphs (build_graph.h): the data types, the node kinds, the model's
// lookups, and the graph of a definition.
#include "rigel/rig/build_graph.h"

#include "rigel/rig/build_function.h"

#include <algorithm>
#include <map>

#include <nlohmann/json.hpp>
#include <cctype>
#include <functional>
#include <limits>
#include <regex>
#include <string>
#include <set>

namespace rigel::rig {
namespace {

bool is_colour(std::string_view c) {
  return c.size() == 7 && c[0] == '#' &&
         std::all_of(c.begin() + 1, c.end(), [](char h) { return std::isxdigit(static_cast<unsigned char>(h)) != 0; });
}

const SocketSpec* find_socket(const std::vector<SocketSpec>& list, std::string_view name) {
  for (const SocketSpec& s : list)
    if (s.name == name) return &s;
  return nullptr;
}

}  // namespace

// ---- data types -----------------------------------------------------------------

Status DataTypeRegistry::add(DataType type) {
  const std::string who = "data type '" + type.name + "'" + (type.origin.empty() ? "" : " (" + type.origin + ")");
  if (type.name.empty()) return error(ErrorCode::kInvalidArgument, "a data type needs a name");
  if (!is_colour(type.color))
    return error(ErrorCode::kInvalidArgument, who + ": colour '" + type.color + "' is not #rrggbb");
  std::lock_guard lock(mutex_);
  for (const DataType& t : types_)
    if (t.name == type.name)
      return error(ErrorCode::kAlreadyExists,
                   who + " is already registered, by " + (t.origin.empty() ? std::string("rigel") : t.origin));
  types_.push_back(std::move(type));
  return Status::ok();
}

std::size_t DataTypeRegistry::remove_origin(std::string_view origin) {
  std::lock_guard lock(mutex_);
  const std::size_t before = types_.size();
  std::erase_if(types_, [&](const DataType& t) { return !origin.empty() && t.origin == origin; });
  return before - types_.size();
}

const DataType* DataTypeRegistry::find(std::string_view name) const {
  std::lock_guard lock(mutex_);
  for (const DataType& t : types_)
    if (t.name == name) return &t;
  return nullptr;
}

std::vector<DataType> DataTypeRegistry::types() const {
  std::lock_guard lock(mutex_);
  return {types_.begin(), types_.end()};
}

bool DataTypeRegistry::can_link(std::string_view from, std::string_view to) {
  return from == to || (from == "int" && to == "number");
}

namespace {
DataTypeRegistry& process_data_types() {
  static DataTypeRegistry registry;
  static const bool filled = [] {
    DataTypeRegistry& r = registry;
    const auto add = [&](std::string name, std::string color, std::optional<ParamType> value, std::string help) {
      DataType t;
      t.name = std::move(name);
      t.color = std::move(color);
      t.value_type = value;
      t.help = std::move(help);
      (void)r.add(std::move(t));
    };
    add("exec", "#ffffff", std::nullopt, "orders the build: a node runs after the node whose exec output feeds it");
    add("bool", "#c0392b", ParamType::kBool, "true or false");
    add("int", "#1abc9c", ParamType::kInt, "a whole number");
    add("number", "#7fd857", ParamType::kDouble, "a real number");
    add("string", "#e056fd", ParamType::kString, "text");
    add("vector", "#f5c542", ParamType::kVec3, "three numbers [x, y, z]");
    add("component", "#4aa3ff", std::nullopt, "a component the build made (a component node's output)");
    // What a component node's build makes, for function nodes to take.
    add("list:control", "#ff9f43", std::nullopt, "the controls a component the build made has, in build order");
    add("list:joint", "#dfe6e9", std::nullopt, "the joints a component the build made drives (its guides' joints)");
    add("list:node", "#a29bfe", std::nullopt, "the hooks a component the build made publishes, by index");
    // A list's colour is its element's, darker, so the two read as kin.
    for (const char* element : {"bool", "int", "number", "string", "vector"}) {
      std::string color = r.find(element)->color;
      for (std::size_t k = 1; k < color.size(); k += 2) {
        const int v = std::stoi(color.substr(k, 2), nullptr, 16) * 2 / 3;
        static constexpr char kHex[] = "0123456789abcdef";
        color[k] = kHex[v / 16];
        color[k + 1] = kHex[v % 16];
      }
      add(std::string("list:") + element, color, std::nullopt,
           std::string("a list of ") + element + " values (a for-each node runs its body once per item)");
    }
    return true;
  }();
  (void)filled;
  return registry;
}
}  // namespace

const DataTypeRegistry& builtin_data_types() { return process_data_types(); }

Status register_data_type(DataType type) {
  if (type.origin.empty())
    return error(ErrorCode::kInvalidArgument, "data type '" + type.name + "': a plugin's type names its origin");
  if (type.name.find_first_of(":$") != std::string::npos)
    return error(ErrorCode::kInvalidArgument, "data type '" + type.name + "' (" + type.origin +
                                                  "): a name with ':' or '$' is the built-in families' (list:TYPE)");
  return process_data_types().add(std::move(type));
}

std::size_t unregister_data_types(std::string_view origin) { return process_data_types().remove_origin(origin); }

bool is_plugin_type(std::string_view type) {
  const DataType* t = builtin_data_types().find(type);
  return t && !t->origin.empty();
}


std::string list_element(std::string_view type) {
  constexpr std::string_view kList = "list:";
  if (type.substr(0, kList.size()) != kList) return "";
  const DataType* t = builtin_data_types().find(type.substr(kList.size()));
  return t && t->value_type ? t->name : "";
}

bool holds_values(std::string_view type) {
  const DataType* t = builtin_data_types().find(type);
  return t && (t->value_type || !list_element(type).empty());
}

bool list_fits(const ValueList& list, std::string_view list_type) {
  const DataType* t = builtin_data_types().find(list_element(list_type));
  return t && std::all_of(list.begin(), list.end(), [&](const ParamValue& v) { return value_fits(v, *t->value_type); });
}

const char* data_type_of(ParamType type) {
  switch (type) {
    case ParamType::kBool: return "bool";
    case ParamType::kInt: return "int";
    case ParamType::kDouble: return "number";
    case ParamType::kVec3: return "vector";
    case ParamType::kString:
    case ParamType::kEnum: return "string";
  }
  return "string";
}

bool value_fits(const ParamValue& v, ParamType t) {
  switch (t) {
    case ParamType::kBool: return std::holds_alternative<bool>(v);
    case ParamType::kInt: return std::holds_alternative<std::int64_t>(v);
    case ParamType::kDouble: return std::holds_alternative<double>(v) || std::holds_alternative<std::int64_t>(v);
    case ParamType::kString:
    case ParamType::kEnum: return std::holds_alternative<std::string>(v);
    case ParamType::kVec3: return std::holds_alternative<math::Vec3>(v);
  }
  return false;
}

ParamValue zero_value(ParamType t) {
  switch (t) {
    case ParamType::kBool: return false;
    case ParamType::kInt: return std::int64_t{0};
    case ParamType::kDouble: return 0.0;
    case ParamType::kVec3: return math::Vec3(math::Vec3::Zero());
    case ParamType::kString:
    case ParamType::kEnum: return std::string();
  }
  return std::string();
}

// ---- node kinds -----------------------------------------------------------------

const SocketSpec* NodeKind::input(std::string_view name) const { return find_socket(inputs, name); }
const SocketSpec* NodeKind::output(std::string_view name) const { return find_socket(outputs, name); }
bool NodeKind::has_exec() const {
  const auto exec = [](const SocketSpec& s) { return s.type == "exec"; };
  return std::any_of(inputs.begin(), inputs.end(), exec) || std::any_of(outputs.begin(), outputs.end(), exec);
}

Status NodeKindRegistry::add(NodeKind kind, const DataTypeRegistry& types) {
  if (kind.id.empty()) return error(ErrorCode::kInvalidArgument, "a node kind needs an id");
  if (find(kind.id)) return error(ErrorCode::kAlreadyExists, "node kind '" + kind.id + "' is already registered");
  for (const auto* list : {&kind.inputs, &kind.outputs}) {
    std::set<std::string> names;
    for (const SocketSpec& s : *list) {
      if (!names.insert(s.name).second)
        return error(ErrorCode::kInvalidArgument, "node kind '" + kind.id + "' has two sockets named '" + s.name + "'");
      if (s.type != kVariableType && !types.find(s.type))
        return error(ErrorCode::kInvalidArgument,
                     "node kind '" + kind.id + "' socket '" + s.name + "': unknown data type '" + s.type + "'");
    }
  }
  kinds_.push_back(std::move(kind));
  return Status::ok();
}

const NodeKind* NodeKindRegistry::find(std::string_view id) const {
  for (const NodeKind& k : kinds_)
    if (k.id == id) return &k;
  return nullptr;
}

NodeKindRegistry builtin_node_kinds(const SchemaRegistry& schemas) {
  NodeKindRegistry r;
  const auto add = [&](NodeKind k) { (void)r.add(std::move(k)); };
  add({"start", "Start", "Flow", {}, {{"then", "exec", "the first node of the build"}}, "where the build begins"});
  for (const std::string& type : schemas.types()) {
    const ComponentSchema& schema = *schemas.find(type);
    NodeKind k;
    k.id = "component:" + type;
    k.nice_name = type;
    k.category = "Components";
    k.help = schema.help;
    k.inputs = {{"exec", "exec", "builds the component"},
                {"parent", "component", "the component it hangs from (none: a root)"},
                {"name", "string", "its name"},
                {"side", "string", "C, L or R"},
                {"attach", "string", "the parent's hook it attaches to, or OTHER.HOOK (empty: hook 0)"}};
    for (const ParamSpec& p : schema.params) k.inputs.push_back({p.name, data_type_of(p.type), p.help});
    k.outputs = {{"then", "exec", "the next node"},
                 {"component", "component", "the component, for its children"},
                 {"controls", "list:control", "its controls, for a function node"},
                 {"joints", "list:joint", "the joints it drives (its guides' joints), for a function node"},
                 {"hooks", "list:node", "the hooks it publishes, by index, for a function node"}};
    add(std::move(k));
  }
  for (const DataType& t : builtin_data_types().types()) {
    if (!holds_values(t.name)) continue;
    add({"constant:" + t.name, t.name, "Constants", {}, {{"value", t.name, "the node's value"}}, "a " + t.name + " value"});
  }
  add({"variable:get", "Get", "Variables", {}, {{"value", kVariableType, "the variable's value when it is read"}},
       "reads a graph variable"});
  add({"variable:set", "Set", "Variables", {{"exec", "exec", ""}, {"value", kVariableType, "the new value"}},
       {{"then", "exec", ""}}, "writes a graph variable: nodes after it read the new value"});
  add({"branch", "Branch", "Flow", {{"exec", "exec", ""}, {"condition", "bool", "which way to go"}},
       {{"true", "exec", "runs when the condition is true"}, {"false", "exec", "runs when it is false"}},
       "goes on one way or the other"});
  for (const DataType& t : builtin_data_types().types()) {
    const std::string element = list_element(t.name);
    if (element.empty()) continue;
    add({"forEach:" + element, "For each " + element, "Flow",
         {{"exec", "exec", ""}, {"list", t.name, "the items, in order"}},
         {{"body", "exec", "runs once per item"},
          {"element", element, "the item the body runs for"},
          {"index", "int", "its index in the list, from 0"},
          {"completed", "exec", "runs after the last item"}},
         "runs its body once per item of a list: a component node in the body builds one component per item "
         "(give each its own name or side, from the element)"});
  }
  for (const BuildFunction& f : build_functions().functions()) add(function_node_kind(f));
  for (const FlowKind& f : flow_kinds().kinds()) add(flow_node_kind(f));
  return r;
}

NodeKind subgraph_node_kind(const std::string& path, const BuildGraph& sub) {
  NodeKind k;
  k.id = "graph:" + path;
  k.nice_name = sub.rig.name.empty() ? path : sub.rig.name;
  k.category = "Graphs";
  k.help = "runs the build graph " + path + ": its variables are the inputs and outputs";
  k.inputs = {{"exec", "exec", "runs the graph"}};
  k.outputs = {{"then", "exec", "the next node, after the graph's chain"}};
  for (const GraphVariable& v : sub.variables) {
    k.inputs.push_back({v.name, v.type, "the graph's variable (unlinked: its value in the graph)"});
    k.outputs.push_back({v.name, v.type, "the variable as the graph's chain leaves it"});
  }
  return k;
}

// ---- the model ------------------------------------------------------------------

const Param* GraphNode::value(std::string_view name) const {
  for (const Param& p : values)
    if (p.name == name) return &p;
  return nullptr;
}

const GraphNode* BuildGraph::find(std::string_view id) const {
  for (const GraphNode& n : nodes)
    if (n.id == id) return &n;
  return nullptr;
}

const GraphVariable* BuildGraph::variable(std::string_view name) const {
  for (const GraphVariable& v : variables)
    if (v.name == name) return &v;
  return nullptr;
}

bool is_build_graph_path(const std::filesystem::path& path) {
  const std::string name = path.filename().string();
  constexpr std::string_view kSuffix = ".build.json";
  return name.size() > kSuffix.size() && name.compare(name.size() - kSuffix.size(), kSuffix.size(), kSuffix) == 0;
}

// ---- the graph of a definition --------------------------------------------------

BuildGraph convert_definition(const Definition& definition) {
  BuildGraph g;
  g.rig = definition;
  g.rig.components.clear();
  g.source = definition.source;
  constexpr double kColumn = 260.0, kRow = 160.0;
  GraphNode start;
  start.id = start.kind = "start";
  start.position = std::pair{0.0, 0.0};
  g.nodes.push_back(std::move(start));
  std::set<std::string> ids{"start"};
  std::string previous = "start";
  std::string previous_output = "then";
  int column = 1;
  std::map<std::string, std::string> node_of;  // rigId -> node id
  std::vector<const Component*> calls;
  // Depth first, parents before children: the order the build runs them.
  std::function<void(const Component&, const std::string&, int)> walk = [&](const Component& c,
                                                                           const std::string& parent, int depth) {
    if (c.type == kCallType) {  // a function node's: after the components, as the build runs them
      calls.push_back(&c);
      return;
    }
    const std::string base = c.full_name().empty() ? c.type : c.full_name();
    std::string id = base;
    for (int k = 2; !ids.insert(id).second; ++k) id = base + "_" + std::to_string(k);
    GraphNode n;
    n.id = id;
    n.kind = "component:" + c.type;
    n.position = c.gui_location ? *c.gui_location : std::pair{kColumn * column, kRow * depth};
    n.component = c;
    n.component.children.clear();
    n.where = c.where;
    g.nodes.push_back(std::move(n));
    node_of[c.rig_id] = id;
    g.links.push_back(GraphLink{{previous, previous_output}, {id, "exec"}, {}});
    if (!parent.empty()) g.links.push_back(GraphLink{{parent, "component"}, {id, "parent"}, {}});
    previous = id;
    previous_output = "then";
    ++column;
    for (const Component& child : c.children) walk(child, id, depth + 1);
  };
  for (const Component& root : definition.components) walk(root, "", 0);
  // Each call back as its function node: its args' values as the node's,
  // its references to components and calls as links.
  for (const Component* c : calls) {
    const Param* function = c->param("function");
    const Param* args = c->param("args");
    const std::string base = c->name.empty() ? "call" : c->name;
    std::string id = base;
    for (int k = 2; !ids.insert(id).second; ++k) id = base + "_" + std::to_string(k);
    GraphNode n;
    n.id = id;
    n.kind = "function:" + (function ? std::get<std::string>(function->value) : std::string());
    n.rig_id = c->rig_id;
    n.position = c->gui_location ? *c->gui_location : std::pair{kColumn * column++, 0.0};
    n.where = c->where;
    const auto parsed = args ? nlohmann::ordered_json::parse(std::get<std::string>(args->value), nullptr, false)
                             : nlohmann::ordered_json::object();
    const std::optional<BuildFunction> fn = build_functions().find(n.kind.substr(std::string_view("function:").size()));
    for (auto it = parsed.begin(); parsed.is_object() && it != parsed.end(); ++it) {
      const auto& a = it.value();
      const auto from = [&](const std::string& rig_id, const std::string& output) {
        const auto node = node_of.find(rig_id);
        if (node != node_of.end()) g.links.push_back(GraphLink{{node->second, output}, {id, it.key()}, {}});
      };
      if (a.is_object() && a.size() == 1 && a.begin().value().is_string() && a.begin().key().starts_with("$")) {
        const std::string what = a.begin().key().substr(1);
        from(a.begin().value().get<std::string>(), what);
      } else if (a.is_object() && a.contains("$output") && a["$output"].is_array() && a["$output"].size() == 2) {
        from(a["$output"][0].get<std::string>(), a["$output"][1].get<std::string>());
      } else {
        const SocketSpec* in = fn ? fn->input(it.key()) : nullptr;
        if (in && !list_element(in->type).empty()) {
          if (auto items = list_from_json(a, in->type)) n.lists[it.key()] = std::move(*items);
        } else if (auto v = value_from_json(a, in ? std::string_view(in->type) : std::string_view())) {
          n.values.push_back(Param{it.key(), std::move(*v), {}});
        }
      }
    }
    g.nodes.push_back(std::move(n));
    node_of[c->rig_id] = id;
    g.links.push_back(GraphLink{{previous, previous_output}, {id, "exec"}, {}});
    previous = id;
    previous_output = "then";
  }
  return g;
}

// ---- places -------------------------------------------------------------------

GraphPlace place_of(const BuildGraph& graph, const Diagnostic& d) {
  // What the message names, in the compiler's words (build_graph_compile.cc).
  static const std::regex link_re(R"(^link '[^']*' -> '([^'.]+)\.([^']+)')");
  static const std::regex two_re(R"(^(?:exec output|input) '([^'.]+)\.([^']+)' has two links)");
  static const std::regex node_re(R"(^node '([^']+)')");
  static const std::regex socket_re(R"(^node '[^']+': (?:input '([^']+)'|'([^']+)' is not a data input|the value of '([^']+)'))");
  std::smatch m;
  GraphPlace place;
  // A problem in a sub-graph's file: the graph:PATH node it runs in, when
  // the message names a node of it ("node 'arm/ik'"); else none of this
  // graph's.
  if (!d.file.empty() && d.file != graph.source) {
    if (!std::regex_search(d.message, m, node_re)) return place;
    const std::string named = m[1].str();
    const std::string use = named.substr(0, named.find('/'));
    if (named.find('/') != std::string::npos && graph.find(use)) place.node = use;
    return place;
  }
  if (std::regex_search(d.message, m, link_re) || std::regex_search(d.message, m, two_re)) return {m[1].str(), m[2].str()};
  if (std::regex_search(d.message, m, node_re)) {
    place.node = m[1].str();
    if (std::smatch s; std::regex_search(d.message, s, socket_re))
      for (std::size_t i = 1; i < s.size(); ++i)
        if (s[i].matched) place.socket = s[i].str();
  }
  const int line = d.where.line;
  if (line <= 0) return place;
  // The block (node, link or variable) that holds the place: the last one
  // starting at or before it, by line and column (a file may be one line).
  using At = std::pair<int, int>;
  const auto at = [](const SourceLocation& w) { return At{w.line, w.column}; };
  const At here{line, d.where.column > 0 ? d.where.column : std::numeric_limits<int>::max()};
  const GraphNode* in = nullptr;
  const GraphLink* on = nullptr;
  At best{0, 0};
  const auto consider = [&](const SourceLocation& w) {
    if (w.line <= 0 || at(w) > here || at(w) < best) return false;
    best = at(w);
    in = nullptr;
    on = nullptr;
    return true;
  };
  for (const GraphNode& n : graph.nodes)
    if (consider(n.where)) in = &n;
  for (const GraphLink& l : graph.links)
    if (consider(l.where)) on = &l;
  for (const GraphVariable& v : graph.variables) consider(v.where);
  if (on) return place.node.empty() && on->where.line == line ? GraphPlace{on->to.node, on->to.socket} : place;
  if (!in || (!place.node.empty() && place.node != in->id)) return place;
  place.node = in->id;
  // The input whose value starts on the place's line, last at or before it.
  if (place.socket.empty()) {
    At socket_at{0, 0};
    for (const std::vector<Param>* params : {&in->values, &in->component.params})
      for (const Param& p : *params)
        if (p.where.line == line && at(p.where) <= here && at(p.where) >= socket_at) {
          socket_at = at(p.where);
          place.socket = p.name;
        }
  }
  return place;
}

}  // namespace rigel::rig
