// The `.build.json` file of a build graph (build_graph.h, docs/BUILD_GRAPH.md):
// read with every problem at file:line:column, written as diffable JSON.
// The rig's settings and each component node's component are in the
// `.rig.json` syntax and go through its reader and writer
// (DefinitionJsonParts), so the two files never disagree.
#include <algorithm>

#include "definition_io_internal.h"
#include "rigel/io/diffable_json.h"
#include "rigel/io/scene_file.h"
#include "rigel/rig/build_function.h"
#include "rigel/rig/build_graph.h"

namespace rigel::rig {
namespace {

using Json = nlohmann::ordered_json;
using detail::DefinitionJsonParts;

constexpr int kFormat = 1;

std::string child(const std::string& path, std::string_view key) {
  std::string out = path + "/";
  for (char c : key) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}
std::string child(const std::string& path, std::size_t index) { return path + "/" + std::to_string(index); }

// "node.socket" (a socket name has no dot; a node id may).
std::optional<SocketRef> socket_ref(const std::string& text) {
  const std::size_t dot = text.rfind('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == text.size()) return std::nullopt;
  return SocketRef{text.substr(0, dot), text.substr(dot + 1)};
}

class Reader {
 public:
  Reader(std::string_view text, BuildGraphParse& out, const SchemaRegistry& schemas)
      : parts_(text, out.graph.source, schemas, out.errors), out_(out), schemas_(schemas) {}

  void document(const Json& root) {
    if (!root.is_object() || !root.contains("buildGraph") || !root["buildGraph"].is_object()) {
      parts_.error("", "the file must hold an object {\"buildGraph\": {...}}");
      return;
    }
    parts_.check_keys(root, "", {"buildGraph"}, "the file");
    const Json& g = root["buildGraph"];
    const std::string path = "/buildGraph";
    parts_.check_keys(g, path, {"format", "rig", "variables", "nodes", "links"}, "the build graph");
    if (!g.contains("format") || !g["format"].is_number_integer() || g["format"].get<std::int64_t>() != kFormat)
      parts_.error(g.contains("format") ? child(path, "format") : path,
                   "'format' must be " + std::to_string(kFormat) + " (the build graph format this rigel reads)");
    if (g.contains("rig")) {
      const Json& rig = g["rig"];
      if (rig.is_object() && rig.contains("components"))
        parts_.key_error(child(child(path, "rig"), "components"),
                         "a build graph's rig holds no components: they are the graph's component nodes");
      Json settings = rig;
      if (settings.is_object()) settings.erase("components");
      parts_.read_rig(settings, child(path, "rig"), out_.graph.rig);
    }
    array(g, path, "variables", [&](const Json& v, const std::string& p) { variable(v, p); });
    array(g, path, "nodes", [&](const Json& n, const std::string& p) { node(n, p); });
    array(g, path, "links", [&](const Json& l, const std::string& p) { link(l, p); });
  }

 private:
  template <typename F>
  void array(const Json& object, const std::string& path, const char* key, F&& f) {
    if (!object.contains(key)) return;
    const Json& a = object[key];
    if (!a.is_array()) {
      parts_.error(child(path, key), std::string("'") + key + "' must be an array");
      return;
    }
    for (std::size_t i = 0; i < a.size(); ++i) f(a[i], child(child(path, key), i));
  }

  bool string_member(const Json& object, const std::string& path, const char* key, std::string& out, bool required) {
    if (!object.contains(key)) {
      if (required) parts_.error(path, std::string("missing '") + key + "'");
      return false;
    }
    if (!object[key].is_string()) {
      parts_.error(child(path, key), std::string("'") + key + "' must be a string");
      return false;
    }
    out = object[key].get<std::string>();
    return true;
  }

  // A value typed as data type `type` ("" = by its JSON kind).
  std::optional<ParamValue> typed_value(const std::string& name, const Json& v, const std::string& path,
                                        const std::string& type) {
    const DataType* t = builtin_data_types().find(type);
    ParamSpec spec;
    spec.name = name;
    if (t && t->value_type) spec.type = *t->value_type;
    return parts_.read_value(name, v, path, t && t->value_type ? &spec : nullptr);
  }

  // A list of data type `type` (list:T): an array of T values.
  std::optional<ValueList> typed_list(const std::string& name, const Json& v, const std::string& path,
                                      const std::string& type) {
    if (!v.is_array()) {
      parts_.error(path, "'" + name + "' is a " + type + ": an array of " + list_element(type) + " values");
      return std::nullopt;
    }
    ValueList items;
    bool ok = true;
    const DataType* element = builtin_data_types().find(list_element(type));
    for (std::size_t i = 0; i < v.size(); ++i) {
      auto item = typed_value(name, v[i], child(path, i), element->name);
      if (item && !value_fits(*item, *element->value_type)) {
        parts_.error(child(path, i), "'" + name + "': item " + std::to_string(i) + " is not a " + element->name);
        item.reset();
      }
      if (item) items.push_back(std::move(*item));
      else ok = false;
    }
    return ok ? std::optional<ValueList>(std::move(items)) : std::nullopt;
  }

  void variable(const Json& v, const std::string& path) {
    if (!v.is_object()) {
      parts_.error(path, "a variable must be an object {\"name\", \"type\", \"value\"}");
      return;
    }
    parts_.check_keys(v, path, {"name", "type", "value"}, "a variable");
    GraphVariable var;
    var.where = parts_.at(path);
    string_member(v, path, "name", var.name, true);
    string_member(v, path, "type", var.type, true);
    if (var.type == "component") {
      if (v.contains("value") && !v["value"].is_null())
        parts_.error(child(path, "value"), "variable '" + var.name + "': a component variable's value is null (none)");
    } else if (v.contains("value") && !list_element(var.type).empty()) {
      if (auto items = typed_list(var.name, v["value"], child(path, "value"), var.type)) var.items = std::move(*items);
    } else if (v.contains("value")) {
      if (auto value = typed_value(var.name, v["value"], child(path, "value"), var.type)) var.value = std::move(*value);
    } else {
      parts_.error(path, "variable '" + var.name + "': missing 'value'");
    }
    out_.graph.variables.push_back(std::move(var));
  }

  void node(const Json& n, const std::string& path) {
    if (!n.is_object()) {
      parts_.error(path, "a node must be an object {\"id\", \"kind\", ...}");
      return;
    }
    parts_.check_keys(n, path, {"id", "kind", "position", "component", "value", "values", "variable", "rigId"}, "a node");
    GraphNode node;
    node.where = parts_.at(path);
    string_member(n, path, "id", node.id, true);
    string_member(n, path, "kind", node.kind, true);
    if (n.contains("position")) {
      const Json& p = n["position"];
      if (p.is_array() && p.size() == 2 && p[0].is_number() && p[1].is_number())
        node.position = std::pair{p[0].get<double>(), p[1].get<double>()};
      else
        parts_.error(child(path, "position"), "'position' must be [x, y]");
    }
    string_member(n, path, "variable", node.variable, false);
    string_member(n, path, "rigId", node.rig_id, false);
    const bool component = node.kind.rfind("component:", 0) == 0;
    if (component) {
      const std::string type = node.kind.substr(std::string_view("component:").size());
      if (!n.contains("component") || !n["component"].is_object()) {
        parts_.error(n.contains("component") ? child(path, "component") : path,
                     "node '" + node.id + "': a component node holds its component {\"name\", \"side\", ...}");
      } else {
        Json c = n["component"];
        if (c.contains("children"))
          parts_.key_error(child(child(path, "component"), "children"),
                           "node '" + node.id + "': a component node holds one component; nest with a 'parent' link");
        c.erase("children");
        if (!c.contains("type")) c["type"] = type;
        std::vector<Component> read;
        parts_.read_component(c, child(path, "component"), read);
        if (!read.empty()) node.component = std::move(read.front());
        if (node.component.type != type)
          parts_.error(child(child(path, "component"), "type"), "node '" + node.id + "': its component's type '" +
                                                                    node.component.type + "' is not its kind's '" +
                                                                    type + "'");
      }
    } else if (n.contains("component")) {
      parts_.key_error(child(path, "component"), "node '" + node.id + "': only component nodes hold a component");
    }
    if (n.contains("value")) {
      const std::string type = node.kind.rfind("constant:", 0) == 0 ? node.kind.substr(9) : "";
      if (!list_element(type).empty()) {
        if (auto items = typed_list("value", n["value"], child(path, "value"), type)) node.lists["value"] = std::move(*items);
      } else if (auto v = typed_value("value", n["value"], child(path, "value"), type)) {
        node.values.push_back(Param{"value", std::move(*v), parts_.at(child(path, "value"))});
      }
    }
    if (n.contains("values")) {
      const Json& values = n["values"];
      if (!values.is_object()) {
        parts_.error(child(path, "values"), "'values' must be an object {INPUT: VALUE}");
      } else {
        for (auto it = values.begin(); it != values.end(); ++it) {
          const std::string p = child(child(path, "values"), it.key());
          const std::string type = input_type(node, it.key());
          // A sub-graph's input, or one of a kind no one registered (the
          // compile names it): the file does not say the type.
          const bool untyped_list = (node.kind.rfind("graph:", 0) == 0 || type.empty()) && it.value().is_array() &&
                                    !(it.value().size() == 3 && std::all_of(it.value().begin(), it.value().end(),
                                                                            [](const Json& x) { return x.is_number(); }));
          if (untyped_list) {
            // Typed when it runs, or refused with its node's kind.
            ValueList items;
            for (std::size_t k = 0; k < it.value().size(); ++k)
              if (auto item = typed_value(it.key(), it.value()[k], child(p, k), "")) items.push_back(std::move(*item));
            node.lists[it.key()] = std::move(items);
          } else if (!list_element(type).empty()) {
            if (auto items = typed_list(it.key(), it.value(), p, type)) node.lists[it.key()] = std::move(*items);
          } else if (auto v = typed_value(it.key(), it.value(), p, type)) {
            node.values.push_back(Param{it.key(), std::move(*v), parts_.at(p)});
          }
        }
      }
    }
    out_.graph.nodes.push_back(std::move(node));
  }

  // The data type of a node's input, where the file alone says it.
  std::string input_type(const GraphNode& node, const std::string& input) const {
    if (node.kind == "variable:set" && input == "value") {
      const GraphVariable* v = out_.graph.variable(node.variable);
      return v ? v->type : "";
    }
    if (node.kind == "branch" && input == "condition") return "bool";
    if (node.kind.rfind("forEach:", 0) == 0 && input == "list") return "list:" + node.kind.substr(8);
    if (node.kind.rfind("function:", 0) == 0)
      if (const auto f = build_functions().find(node.kind.substr(9)))
        if (const SocketSpec* in = f->input(input)) return in->type;
    if (node.kind.rfind("flow:", 0) == 0)
      if (const auto f = flow_kinds().find(node.kind.substr(5)))
        if (const SocketSpec* in = f->input(input)) return in->type;
    return "";
  }

  void link(const Json& l, const std::string& path) {
    if (!l.is_object()) {
      parts_.error(path, "a link must be an object {\"from\": \"NODE.OUTPUT\", \"to\": \"NODE.INPUT\"}");
      return;
    }
    parts_.check_keys(l, path, {"from", "to"}, "a link");
    GraphLink link;
    link.where = parts_.at(path);
    std::string from, to;
    const bool has_from = string_member(l, path, "from", from, true);
    const bool has_to = string_member(l, path, "to", to, true);
    const auto from_ref = socket_ref(from), to_ref = socket_ref(to);
    if (has_from && !from_ref) parts_.error(child(path, "from"), "'from' must be NODE.OUTPUT, not '" + from + "'");
    if (has_to && !to_ref) parts_.error(child(path, "to"), "'to' must be NODE.INPUT, not '" + to + "'");
    if (!from_ref || !to_ref) return;
    link.from = *from_ref;
    link.to = *to_ref;
    out_.graph.links.push_back(std::move(link));
  }

  DefinitionJsonParts parts_;
  BuildGraphParse& out_;
  const SchemaRegistry& schemas_;
};

Json value_json(const ParamValue& v) { return detail::param_value_json(v); }
Json list_json(const ValueList& items) {
  Json a = Json::array();
  for (const ParamValue& v : items) a.push_back(value_json(v));
  return a;
}

}  // namespace

BuildGraphParse parse_build_graph(std::string_view text, const std::string& source, const SchemaRegistry& schemas) {
  BuildGraphParse out;
  out.graph.source = source;
  out.graph.rig.source = source;
  std::optional<Json> root = DefinitionJsonParts::parse(text, source, out.errors);
  if (!root) return out;
  Reader(text, out, schemas).document(*root);
  return out;
}

std::string write_build_graph(const BuildGraph& graph) {
  Json g = Json::object();
  g["format"] = kFormat;
  g["rig"] = DefinitionJsonParts::rig_json(graph.rig);
  if (!graph.variables.empty()) {
    Json a = Json::array();
    for (const GraphVariable& v : graph.variables)
      a.push_back(Json{{"name", v.name},
                       {"type", v.type},
                       {"value", v.type == "component"        ? Json(nullptr)
                                 : list_element(v.type).empty() ? value_json(v.value)
                                                                : list_json(v.items)}});
    g["variables"] = std::move(a);
  }
  Json nodes = Json::array();
  for (const GraphNode& n : graph.nodes) {
    Json j = Json::object();
    j["id"] = n.id;
    j["kind"] = n.kind;
    if (n.position) j["position"] = Json::array({n.position->first, n.position->second});
    if (!n.variable.empty()) j["variable"] = n.variable;
    if (!n.rig_id.empty()) j["rigId"] = n.rig_id;
    if (n.kind.rfind("component:", 0) == 0) {
      Component c = n.component;
      c.children.clear();
      j["component"] = DefinitionJsonParts::component_json(c);
    }
    Json values = Json::object();
    for (const Param& p : n.values) {
      if (p.name == "value" && n.kind.rfind("constant:", 0) == 0) j["value"] = value_json(p.value);
      else values[p.name] = value_json(p.value);
    }
    for (const auto& [name, items] : n.lists) {
      if (name == "value" && n.kind.rfind("constant:", 0) == 0) j["value"] = list_json(items);
      else values[name] = list_json(items);
    }
    if (!values.empty()) j["values"] = std::move(values);
    nodes.push_back(std::move(j));
  }
  g["nodes"] = std::move(nodes);
  Json links = Json::array();
  for (const GraphLink& l : graph.links)
    links.push_back(Json{{"from", l.from.node + "." + l.from.socket}, {"to", l.to.node + "." + l.to.socket}});
  g["links"] = std::move(links);
  Json root = Json::object();
  root["buildGraph"] = std::move(g);
  return io::diffable_json(root, {.inline_flat_objects_in_arrays = true, .scalar = DefinitionJsonParts::scalar_text});
}

Status save_build_graph(const BuildGraph& graph, const std::filesystem::path& path) {
  if (!is_build_graph_path(path))
    return error(ErrorCode::kInvalidArgument, path.string() + ": a build graph's file name ends in .build.json");
  return io::write_file_atomic(path, write_build_graph(graph));
}

nlohmann::ordered_json graph_palette_json(const NodeKindRegistry& kinds, const SchemaRegistry& schemas) {
  using Json = nlohmann::ordered_json;
  Json types = Json::array();
  for (const DataType& t : builtin_data_types().types())
    types.push_back(Json{{"name", t.name},
                         {"color", t.color},
                         {"value", holds_values(t.name)},
                         {"variable", holds_values(t.name) || t.name == "component"},
                         {"element", list_element(t.name)},
                         {"help", t.help}});
  const auto sockets = [](const std::vector<SocketSpec>& specs, const auto& default_of, bool inputs) {
    Json list = Json::array();
    for (const SocketSpec& s : specs) {
      Json j{{"name", s.name}, {"type", s.type}, {"help", s.help}};
      if (std::optional<ParamValue> d = default_of(s)) j["default"] = detail::param_value_json(*d);
      else if (inputs && !list_element(s.type).empty()) j["default"] = Json::array();
      list.push_back(std::move(j));
    }
    return list;
  };
  Json list = Json::array();
  for (const NodeKind& k : kinds.kinds()) {
    // A call is a function node's component: the palette offers the functions.
    if (k.id == std::string("component:") + kCallType) continue;
    const ComponentSchema* schema =
        k.id.rfind("component:", 0) == 0 ? schemas.find(std::string_view(k.id).substr(std::string_view("component:").size())) : nullptr;
    std::vector<Param> defaults;
    if (k.id.rfind("function:", 0) == 0)
      if (auto f = build_functions().find(k.id.substr(std::string_view("function:").size()))) defaults = f->defaults;
    if (k.id.rfind("flow:", 0) == 0)
      if (auto f = flow_kinds().find(k.id.substr(std::string_view("flow:").size()))) defaults = f->defaults;
    const auto default_of = [&](const SocketSpec& s) -> std::optional<ParamValue> {
      if (schema)
        for (const ParamSpec& p : schema->params)
          if (p.name == s.name) return p.default_value;
      for (const Param& p : defaults)
        if (p.name == s.name) return p.value;
      const DataType* t = builtin_data_types().find(s.type);
      if (!t || !t->value_type) return std::nullopt;
      return zero_value(*t->value_type);
    };
    const auto none = [](const SocketSpec&) -> std::optional<ParamValue> { return std::nullopt; };
    list.push_back(Json{{"id", k.id},
                        {"niceName", k.nice_name},
                        {"category", k.category},
                        {"help", k.help},
                        {"inputs", sockets(k.inputs, default_of, true)},
                        {"outputs", sockets(k.outputs, none, false)}});
  }
  return Json{{"types", std::move(types)}, {"kinds", std::move(list)}};
}

}  // namespace rigel::rig
