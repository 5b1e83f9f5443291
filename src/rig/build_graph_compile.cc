// Compiling a build graph to a rig definition (build_graph.h): check the
// nodes, links and variables, run the exec chain once from start with
// values flowing along it, and nest the components it made.
#include <algorithm>
#include <cstdio>
#include <functional>
#include <map>
#include <set>

#include <nlohmann/json.hpp>

#include "definition_io_internal.h"
#include "rigel/rig/build_function.h"
#include "rigel/rig/build_graph.h"

namespace rigel::rig {
namespace {

// What a data socket holds while the chain runs: a value, a component the
// chain made (its index in the order made), or an output of a function
// node, which only the build makes (the call's rigId and the output).
struct Flow {
  std::optional<ParamValue> value;
  int component = -1;
  std::string call, output;
  bool runtime() const { return !call.empty(); }
};

// A rigId for a node that has none: made from the rig's name and the
// node's id (FNV-1a, 128 bits, shaped as a UUID v4), so it stays as long
// as they do.
std::string derived_rig_id(const std::string& rig, const std::string& node) {
  std::uint64_t h[2] = {14695981039346656037ull, 1099511628211ull * 31};
  for (int k = 0; k < 2; ++k)
    for (char ch : rig + '\0' + node) {
      h[k] ^= static_cast<unsigned char>(ch);
      h[k] *= 1099511628211ull;
      h[k] ^= h[k] >> (29 + k);
    }
  char text[37];
  std::snprintf(text, sizeof text, "%08x-%04x-4%03x-%04x-%012llx", static_cast<unsigned>(h[0] >> 32),
                static_cast<unsigned>((h[0] >> 16) & 0xffff), static_cast<unsigned>(h[0] & 0xfff),
                static_cast<unsigned>(0x8000 | ((h[1] >> 48) & 0x3fff)),
                static_cast<unsigned long long>(h[1] & 0xffffffffffffull));
  return text;
}

// A value of data type `type` as it goes into a socket of that type (an
// int into a number becomes a double).
ParamValue as_type(const ParamValue& v, std::string_view type) {
  if (type == "number")
    if (const auto* i = std::get_if<std::int64_t>(&v)) return static_cast<double>(*i);
  return v;
}

class Compiler {
 public:
  Compiler(const BuildGraph& graph, const SchemaRegistry& schemas, BuildGraphCompile& out)
      : g_(graph), schemas_(schemas), kinds_(builtin_node_kinds(schemas)), out_(out) {}

  void run() {
    check_variables();
    check_nodes();
    check_links();
    if (!out_.errors.empty()) return;
    check_data_cycles();
    if (!out_.errors.empty()) return;
    check_reachable();
    if (!out_.errors.empty()) return;
    run_chain();
    if (!out_.errors.empty()) return;
    assemble();
    if (!out_.errors.empty()) return;
    for (Diagnostic& d : validate(out_.definition, schemas_)) out_.errors.push_back(std::move(d));
  }

 private:
  void fail(SourceLocation where, std::string message) { out_.errors.push_back({g_.source, where, std::move(message)}); }
  void fail(std::size_t node, std::string message) {
    fail(g_.nodes[node].where, "node '" + g_.nodes[node].id + "': " + std::move(message));
  }
  static std::string name(const SocketRef& s) { return "'" + s.node + "." + s.socket + "'"; }

  // The data type of a socket of node `n` ("" when it has none).
  std::string socket_type(std::size_t n, const SocketSpec& s) const {
    if (s.type != kVariableType) return s.type;
    const GraphVariable* v = g_.variable(g_.nodes[n].variable);
    return v ? v->type : "";
  }

  void check_variables() {
    std::set<std::string> names;
    for (const GraphVariable& v : g_.variables) {
      const std::string who = "variable '" + v.name + "': ";
      if (v.name.empty()) fail(v.where, "a variable needs a name");
      else if (!names.insert(v.name).second) fail(v.where, who + "a second variable of that name");
      const DataType* t = builtin_data_types().find(v.type);
      if (!t || !t->value_type) {
        fail(v.where, who + "type '" + v.type + "' is not one a variable holds (bool, int, number, string, vector)");
        continue;
      }
      if (!value_fits(v.value, *t->value_type)) fail(v.where, who + "its value is not a " + v.type);
    }
  }

  void check_nodes() {
    kind_of_.assign(g_.nodes.size(), nullptr);
    int starts = 0;
    for (std::size_t i = 0; i < g_.nodes.size(); ++i) {
      const GraphNode& n = g_.nodes[i];
      if (n.id.empty()) {
        fail(n.where, "a node needs an id");
        continue;
      }
      if (!index_.emplace(n.id, i).second) fail(i, "a second node has this id");
      const NodeKind* kind = kinds_.find(n.kind);
      if (!kind) {
        fail(i, "unknown node kind '" + n.kind + "'");
        continue;
      }
      kind_of_[i] = kind;
      if (n.kind == "start" && ++starts > 1) fail(i, "a second start node (a graph has one)");
      if (n.kind.rfind("variable:", 0) == 0 && !g_.variable(n.variable))
        fail(i, "variable '" + n.variable + "' is not one of the graph's variables");
      for (const Param& p : n.values) {
        const bool constant = n.kind.rfind("constant:", 0) == 0 && p.name == "value";
        const SocketSpec* in = kind->input(p.name);
        if (!constant && (!in || in->type == "exec")) {
          fail(p.where, "node '" + n.id + "': '" + p.name + "' is not a data input of " + n.kind);
          continue;
        }
        const std::string type = constant ? kind->outputs.front().type : socket_type(i, *in);
        const DataType* t = builtin_data_types().find(type);
        if (t && t->value_type && !value_fits(p.value, *t->value_type))
          fail(p.where, "node '" + n.id + "': the value of '" + p.name + "' is not a " + type);
      }
    }
    if (starts == 0) fail(SourceLocation{}, "the graph has no start node: the build begins at one");
  }

  void check_links() {
    for (std::size_t i = 0; i < g_.links.size(); ++i) {
      const GraphLink& l = g_.links[i];
      const std::string what = "link " + name(l.from) + " -> " + name(l.to) + ": ";
      const auto from = index_.find(l.from.node), to = index_.find(l.to.node);
      if (from == index_.end() || to == index_.end()) {
        fail(l.where, what + "no node '" + (from == index_.end() ? l.from.node : l.to.node) + "'");
        continue;
      }
      const NodeKind* fk = kind_of_[from->second];
      const NodeKind* tk = kind_of_[to->second];
      if (!fk || !tk) continue;  // reported with the node
      const SocketSpec* out = fk->output(l.from.socket);
      const SocketSpec* in = tk->input(l.to.socket);
      if (!out) {
        fail(l.where, what + g_.nodes[from->second].kind + " has no output '" + l.from.socket + "'");
        continue;
      }
      if (!in) {
        fail(l.where, what + g_.nodes[to->second].kind + " has no input '" + l.to.socket + "'");
        continue;
      }
      const std::string ft = socket_type(from->second, *out), tt = socket_type(to->second, *in);
      if ((ft == "exec") != (tt == "exec") || !DataTypeRegistry::can_link(ft, tt)) {
        fail(l.where, what + "a " + ft + " output cannot feed a " + tt + " input");
        continue;
      }
      if (ft == "exec") {
        const auto [it, fresh] = exec_next_.emplace(std::pair{from->second, l.from.socket}, i);
        if (!fresh)
          fail(l.where, "exec output " + name(l.from) + " has two links (to " + name(g_.links[it->second].to) +
                            " and " + name(l.to) + "): it runs one next node");
      } else {
        const auto [it, fresh] = feeds_.emplace(std::pair{to->second, l.to.socket}, i);
        if (!fresh)
          fail(l.where, "input " + name(l.to) + " has two links (from " + name(g_.links[it->second].from) + " and " +
                            name(l.from) + ")");
      }
    }
  }

  void check_data_cycles() {
    std::vector<std::vector<std::size_t>> next(g_.nodes.size());
    for (const auto& [to, link] : feeds_) next[index_.at(g_.links[link].from.node)].push_back(to.first);
    std::vector<int> state(g_.nodes.size(), 0);  // 0 new, 1 on the path, 2 done
    std::vector<std::size_t> path;
    // Iterative depth-first search: a long chain must not overflow the stack.
    for (std::size_t root = 0; root < g_.nodes.size(); ++root) {
      if (state[root]) continue;
      std::vector<std::pair<std::size_t, std::size_t>> stack{{root, 0}};
      state[root] = 1;
      path = {root};
      while (!stack.empty()) {
        auto& [n, k] = stack.back();
        if (k < next[n].size()) {
          const std::size_t m = next[n][k++];
          if (state[m] == 1) {
            std::string cycle;
            for (auto it = std::find(path.begin(), path.end(), m); it != path.end(); ++it) cycle += g_.nodes[*it].id + " -> ";
            fail(g_.nodes[m].where, "data links form a cycle: " + cycle + g_.nodes[m].id);
            return;
          }
          if (state[m] == 0) {
            state[m] = 1;
            stack.emplace_back(m, 0);
            path.push_back(m);
          }
        } else {
          state[n] = 2;
          stack.pop_back();
          path.pop_back();
        }
      }
    }
  }

  // Every node with exec sockets must be reachable from start through exec
  // links (either way of a branch).
  void check_reachable() {
    std::vector<char> seen(g_.nodes.size(), 0);
    std::vector<std::size_t> work;
    for (std::size_t i = 0; i < g_.nodes.size(); ++i)
      if (g_.nodes[i].kind == "start") work.push_back(i);
    while (!work.empty()) {
      const std::size_t n = work.back();
      work.pop_back();
      if (seen[n]) continue;
      seen[n] = 1;
      for (const SocketSpec& s : kind_of_[n]->outputs) {
        const auto it = exec_next_.find({n, s.name});
        if (it != exec_next_.end()) work.push_back(index_.at(g_.links[it->second].to.node));
      }
    }
    for (std::size_t i = 0; i < g_.nodes.size(); ++i)
      if (!seen[i] && kind_of_[i]->has_exec())
        fail(i, "not on the exec chain from start: link an exec output to its 'exec' input");
  }

  // The value reaching input `socket` of node `n`; nullopt when it is not
  // linked (the node's own value holds) or the error was reported.
  std::optional<Flow> input(std::size_t n, const std::string& socket) {
    const auto it = feeds_.find({n, socket});
    if (it == feeds_.end()) return std::nullopt;
    const GraphLink& l = g_.links[it->second];
    const std::size_t s = index_.at(l.from.node);
    const GraphNode& src = g_.nodes[s];
    const SocketSpec& in = *kind_of_[n]->input(socket);
    const std::string type = socket_type(n, in);
    if (kind_of_[s]->has_exec()) {
      if (!ran_.count(s)) {
        fail(n, "input '" + socket + "' reads " + name(l.from) + ", but '" + src.id +
                    "' has not run by then (it runs later on the exec chain, or on a branch not taken)");
        return std::nullopt;
      }
      if (src.kind.rfind("function:", 0) == 0) return Flow{std::nullopt, -1, ran_.at(s).call, l.from.socket};
      return ran_.at(s);
    }
    if (src.kind == "variable:get") {
      Flow f = variables_.at(src.variable);
      if (f.value) f.value = as_type(*f.value, type);
      return f;
    }
    // A constant.
    const Param* v = src.value("value");
    const DataType* t = builtin_data_types().find(kind_of_[s]->outputs.front().type);
    return Flow{as_type(v ? v->value : zero_value(*t->value_type), type), -1, {}, {}};
  }

  // An input the node needs before the build: nullopt (with the error)
  // when it reads a function's output, which only the build makes.
  std::optional<Flow> known_input(std::size_t n, const std::string& socket) {
    std::optional<Flow> f = input(n, socket);
    if (f && f->runtime()) {
      fail(n, "input '" + socket + "' reads a value the build makes (output '" + f->output +
                  "' of a function node): only function nodes take those");
      return std::nullopt;
    }
    return f;
  }

  // An input's value as a value of its type: linked, else the node's own,
  // else the type's zero.
  std::optional<ParamValue> value_input(std::size_t n, const std::string& socket) {
    if (auto f = known_input(n, socket)) return f->value;
    if (!out_.errors.empty()) return std::nullopt;
    if (const Param* p = g_.nodes[n].value(socket)) return as_type(p->value, socket_type(n, *kind_of_[n]->input(socket)));
    const DataType* t = builtin_data_types().find(socket_type(n, *kind_of_[n]->input(socket)));
    return zero_value(*t->value_type);
  }

  void run_chain() {
    for (const GraphVariable& v : g_.variables) variables_[v.name] = Flow{as_type(v.value, v.type), -1, {}, {}};
    std::size_t n = 0;
    while (g_.nodes[n].kind != "start") ++n;
    std::string next = "then";
    std::vector<std::size_t> chain{n};
    ran_[n] = Flow{};
    while (true) {
      const auto link = exec_next_.find({n, next});
      if (link == exec_next_.end()) return;
      const std::size_t m = index_.at(g_.links[link->second].to.node);
      if (ran_.count(m)) {
        std::string cycle;
        for (auto it = std::find(chain.begin(), chain.end(), m); it != chain.end(); ++it) cycle += g_.nodes[*it].id + " -> ";
        fail(m, "exec links form a cycle: " + cycle + g_.nodes[m].id);
        return;
      }
      n = m;
      chain.push_back(n);
      out_.order.push_back(g_.nodes[n].id);
      next = "then";
      const GraphNode& node = g_.nodes[n];
      if (node.kind == "variable:set") {
        // A set may hold a function's output, for later function nodes.
        std::optional<Flow> f = input(n, "value");
        if (!out_.errors.empty()) return;
        if (!f) {
          auto v = value_input(n, "value");
          if (!v) return;
          f = Flow{*v, -1, {}, {}};
        }
        variables_[node.variable] = *f;
        ran_[n] = Flow{};
      } else if (node.kind == "branch") {
        auto c = value_input(n, "condition");
        if (!c) return;
        next = std::get<bool>(*c) ? "true" : "false";
        ran_[n] = Flow{};
      } else if (node.kind.rfind("component:", 0) == 0) {
        if (!make_component(n)) return;
      } else if (node.kind.rfind("function:", 0) == 0) {
        if (!make_call(n)) return;
      }
    }
  }

  bool make_component(std::size_t n) {
    const GraphNode& node = g_.nodes[n];
    Component c = node.component;
    c.children.clear();
    if (c.where.line == 0) c.where = node.where;
    if (c.rig_id.empty()) c.rig_id = derived_rig_id(g_.rig.name, node.id);
    int parent = -1;
    if (auto p = input(n, "parent")) parent = p->component;
    else if (!out_.errors.empty()) return false;
    const auto text = [&](const char* socket, std::string& into) {
      if (auto f = known_input(n, socket)) into = std::get<std::string>(*f->value);
      return out_.errors.empty();
    };
    std::string side;
    if (!text("name", c.name) || !text("side", side) || !text("attach", c.attach)) return false;
    if (!side.empty()) {
      const auto s = side_from_name(side);
      if (!s) {
        fail(n, "input 'side': '" + side + "' is not C, L or R");
        return false;
      }
      c.side = *s;
    }
    const ComponentSchema* schema = schemas_.find(c.type);
    for (const ParamSpec& spec : schema ? schema->params : std::vector<ParamSpec>{}) {
      auto f = known_input(n, spec.name);
      if (!f) {
        if (!out_.errors.empty()) return false;
        continue;
      }
      ParamValue v = as_type(*f->value, data_type_of(spec.type));
      auto it = std::find_if(c.params.begin(), c.params.end(), [&](const Param& p) { return p.name == spec.name; });
      if (it != c.params.end()) it->value = std::move(v);
      else c.params.push_back(Param{spec.name, std::move(v), node.where});
    }
    const int depth = parent >= 0 ? depth_[static_cast<std::size_t>(parent)] + 1 : 1;
    if (depth > static_cast<int>(kMaxComponentDepth)) {
      fail(n, "components nest deeper than " + std::to_string(kMaxComponentDepth) + " levels (the limit)");
      return false;
    }
    ran_[n] = Flow{std::nullopt, static_cast<int>(made_.size()), {}, {}};
    out_.rig_ids.emplace_back(node.id, c.rig_id);
    made_.push_back(std::move(c));
    parent_.push_back(parent);
    depth_.push_back(depth);
    made_by_.push_back(n);
    return true;
  }

  // A function node: a `call` component, a root built after the
  // components, that builds after every component or call it reads.
  bool make_call(std::size_t n) {
    const GraphNode& node = g_.nodes[n];
    const std::string id = node.kind.substr(std::string_view("function:").size());
    const std::optional<BuildFunction> fn = build_functions().find(id);
    if (!fn) {
      fail(n, "build function '" + id + "' is not registered");
      return false;
    }
    Component c;
    c.type = kCallType;
    c.name = node.id;
    c.rig_id = node.rig_id.empty() ? derived_rig_id(g_.rig.name, node.id) : node.rig_id;
    c.where = node.where;
    nlohmann::ordered_json args = nlohmann::ordered_json::object();
    for (const SocketSpec& in : fn->inputs) {
      std::optional<Flow> f = input(n, in.name);
      if (!out_.errors.empty()) return false;
      if (!f) {
        if (in.type == "component") {
          fail(n, "input '" + in.name + "' needs a link from a component node's 'component' output");
          return false;
        }
        if (const Param* p = node.value(in.name)) args[in.name] = detail::param_value_json(as_type(p->value, in.type));
        continue;
      }
      std::string from;
      if (f->runtime()) {
        args[in.name] = {{"$output", {f->call, f->output}}};
        from = f->call;
      } else if (f->component >= 0) {
        from = made_[static_cast<std::size_t>(f->component)].rig_id;
        args[in.name] = {{"$component", from}};
      } else {
        args[in.name] = detail::param_value_json(as_type(*f->value, in.type));
      }
      if (!from.empty() && std::find(c.after.begin(), c.after.end(), from) == c.after.end()) c.after.push_back(from);
    }
    c.params = {Param{"function", id, node.where}, Param{"args", args.dump(), node.where}};
    ran_[n] = Flow{std::nullopt, -1, c.rig_id, {}};
    out_.rig_ids.emplace_back(node.id, c.rig_id);
    calls_.push_back(std::move(c));
    return true;
  }

  // Nests the components made (children in the order made), the calls
  // after them, and warns when the build's depth-first order is not the
  // chain's.
  void assemble() {
    std::vector<std::vector<int>> children(made_.size());
    std::vector<int> roots;
    for (std::size_t i = 0; i < made_.size(); ++i)
      (parent_[i] >= 0 ? children[static_cast<std::size_t>(parent_[i])] : roots).push_back(static_cast<int>(i));
    std::vector<int> depth_first;
    std::function<Component(int)> nest = [&](int i) {
      depth_first.push_back(i);
      Component c = made_[static_cast<std::size_t>(i)];
      for (int k : children[static_cast<std::size_t>(i)]) c.children.push_back(nest(k));
      return c;
    };
    out_.definition = g_.rig;
    out_.definition.components.clear();
    out_.definition.source = g_.source;
    for (int r : roots) out_.definition.components.push_back(nest(r));
    for (Component& c : calls_) out_.definition.components.push_back(std::move(c));
    for (std::size_t k = 0; k < depth_first.size(); ++k) {
      if (depth_first[k] == static_cast<int>(k)) continue;
      const std::size_t n = made_by_[static_cast<std::size_t>(depth_first[k])];
      out_.warnings.push_back({g_.source, g_.nodes[n].where,
                               "node '" + g_.nodes[n].id + "': builds before '" +
                                   g_.nodes[made_by_[k]].id +
                                   "', not after it as the chain says: a build runs depth first (a component's "
                                   "children right after it)"});
      break;
    }
  }

  const BuildGraph& g_;
  const SchemaRegistry& schemas_;
  NodeKindRegistry kinds_;
  BuildGraphCompile& out_;
  std::vector<const NodeKind*> kind_of_;
  std::map<std::string, std::size_t> index_;
  std::map<std::pair<std::size_t, std::string>, std::size_t> exec_next_;  // (node, exec output) -> link
  std::map<std::pair<std::size_t, std::string>, std::size_t> feeds_;      // (node, data input) -> link
  std::map<std::size_t, Flow> ran_;                                       // nodes run, with their output
  std::map<std::string, Flow> variables_;
  std::vector<Component> made_, calls_;
  std::vector<int> parent_, depth_;
  std::vector<std::size_t> made_by_;
};

}  // namespace

BuildGraphCompile compile_build_graph(const BuildGraph& graph, const SchemaRegistry& schemas) {
  BuildGraphCompile out;
  Compiler(graph, schemas, out).run();
  return out;
}

}  // namespace rigel::rig
