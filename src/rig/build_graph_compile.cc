// Compiling a build graph to a rig definition (build_graph.h): check the
// nodes, links and variables (here), run the exec chain once from start
// with values flowing along it (build_graph_run.cc), and nest the
// components it made (here). A graph:PATH node's file is read and checked
// here, once per file, its own sub-graphs with it (a file that includes
// itself, by any path, is refused).
#include <algorithm>
#include <cstdio>
#include <functional>
#include <set>

#include "build_graph_compiler.h"

namespace rigel::rig {
namespace detail {

Flow value_flow(ParamValue v) {
  Flow f;
  f.value = std::move(v);
  return f;
}

Flow list_flow(ValueList items) {
  Flow f;
  f.items = std::move(items);
  return f;
}

Flow runtime_flow(std::string call, std::string output) {
  Flow f;
  f.call = std::move(call);
  f.output = std::move(output);
  return f;
}

ParamValue as_type(const ParamValue& v, std::string_view type) {
  if (type == "number")
    if (const auto* i = std::get_if<std::int64_t>(&v)) return static_cast<double>(*i);
  return v;
}

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

namespace {

// Why a graph:PATH node's path cannot be read ("" when it can): it must be
// a relative path to a .build.json file, inside the graph's folder.
std::string subgraph_path_problem(const std::string& path) {
  const std::filesystem::path p(path);
  if (!is_build_graph_path(p)) return "not a .build.json file";
  if (p.is_absolute() || p.has_root_name() || p.has_root_directory())
    return "a sub-graph's path is relative to the graph's folder";
  for (const auto& part : p)
    if (part == "..") return "a sub-graph's path stays inside the graph's folder (no '..')";
  return "";
}

}  // namespace

Compiler::Compiler(const BuildGraph& graph, CompileRun& run, std::string prefix)
    : g_(graph), run_(run), prefix_(std::move(prefix)) {}

bool Compiler::check() {
  check_variables();
  check_nodes();
  check_links();
  if (failed()) return false;
  check_data_cycles();
  if (failed()) return false;
  check_reachable();
  return !failed();
}

// The data type of a socket of node `n` ("" when it has none).
std::string Compiler::socket_type(std::size_t n, const SocketSpec& s) const {
  if (s.type != kVariableType) return s.type;
  const GraphVariable* v = g_.variable(g_.nodes[n].variable);
  return v ? v->type : "";
}

void Compiler::check_variables() {
  std::set<std::string> names;
  for (const GraphVariable& v : g_.variables) {
    const std::string who = "variable '" + v.name + "': ";
    if (v.name.empty()) fail(v.where, "a variable needs a name");
    else if (!names.insert(v.name).second) fail(v.where, who + "a second variable of that name");
    const DataType* t = builtin_data_types().find(v.type);
    if (v.type == "component") continue;  // none until a set gives it one
    if (!holds_values(v.type)) {
      fail(v.where, who + "type '" + v.type +
                        "' is not one a variable holds (bool, int, number, string, vector, component, or list:TYPE)");
      continue;
    }
    if (t->value_type ? !value_fits(v.value, *t->value_type) : !list_fits(v.items, v.type))
      fail(v.where, who + "its value is not a " + v.type);
  }
}

void Compiler::check_nodes() {
  kind_of_.assign(g_.nodes.size(), nullptr);
  int starts = 0;
  for (std::size_t i = 0; i < g_.nodes.size(); ++i) {
    const GraphNode& n = g_.nodes[i];
    if (n.id.empty()) {
      fail(n.where, "a node needs an id");
      continue;
    }
    if (!index_.emplace(n.id, i).second) fail(i, "a second node has this id");
    const NodeKind* kind = n.kind.rfind("graph:", 0) == 0 ? subgraph_kind(i) : run_.kinds.find(n.kind);
    if (!kind && n.kind.rfind("graph:", 0) == 0) continue;  // reported
    if (!kind) {
      const bool plugin = n.kind.rfind("function:", 0) == 0 || n.kind.rfind("flow:", 0) == 0;
      fail(i, "unknown node kind '" + n.kind + "'" +
                  (plugin ? " (is the plugin that registers it loaded? Python plugins load in `python3 -m rigel graph` "
                            "and rigel.serve, not in the rigel binary)"
                          : ""));
      continue;
    }
    kind_of_[i] = kind;
    if (n.kind == "start" && ++starts > 1) fail(i, "a second start node (a graph has one)");
    if (n.kind.rfind("variable:", 0) == 0 && !g_.variable(n.variable))
      fail(i, "variable '" + n.variable + "' is not one of the graph's variables");
    check_values(i, *kind);
  }
  if (starts == 0) fail(SourceLocation{}, "the graph has no start node: the build begins at one");
}

// The values a node holds for its inputs: each of an input it has, of the
// input's type (one value, or a list for a list input).
void Compiler::check_values(std::size_t i, const NodeKind& kind_ref) {
  const GraphNode& n = g_.nodes[i];
  const NodeKind* kind = &kind_ref;
  for (const Param& p : n.values) {
    const bool constant = n.kind.rfind("constant:", 0) == 0 && p.name == "value";
    const SocketSpec* in = kind->input(p.name);
    if (!constant && (!in || in->type == "exec")) {
      fail(p.where, "node '" + path_of(i) + "': '" + p.name + "' is not a data input of " + n.kind);
      continue;
    }
    if (subgraph_of_.count(i)) continue;  // typed when it runs (the file does not say the type)
    const std::string type = constant ? kind->outputs.front().type : socket_type(i, *in);
    const DataType* t = builtin_data_types().find(type);
    if (t && t->value_type && !value_fits(p.value, *t->value_type))
      fail(p.where, "node '" + path_of(i) + "': the value of '" + p.name + "' is not a " + type);
    else if (!t || !t->value_type)
      fail(p.where, "node '" + path_of(i) + "': '" + p.name + "' takes a " + type + ", not one value");
  }
  for (const auto& [name, items] : n.lists) {
    const bool constant = n.kind.rfind("constant:", 0) == 0 && name == "value";
    const SocketSpec* in = kind->input(name);
    const std::string type = constant ? kind->outputs.front().type : in ? socket_type(i, *in) : "";
    if (subgraph_of_.count(i) && in) continue;  // typed when it runs
    if (list_element(type).empty())
      fail(n.where, "node '" + path_of(i) + "': '" + name + "' is not a list input of " + n.kind);
    else if (!list_fits(items, type))
      fail(n.where, "node '" + path_of(i) + "': the value of '" + name + "' is not a " + type);
  }
}

// The kind of graph:PATH node `i`: its file read (once per run) and
// checked, relative to the graph's folder; nullptr with the problem
// reported.
const NodeKind* Compiler::subgraph_kind(std::size_t i) {
  const GraphNode& n = g_.nodes[i];
  const std::string path = n.kind.substr(std::string_view("graph:").size());
  const std::string problem = subgraph_path_problem(path);
  if (!problem.empty()) {
    fail(i, "sub-graph '" + path + "': " + problem);
    return nullptr;
  }
  const std::filesystem::path folder =
      !g_.folder.empty() ? g_.folder : std::filesystem::path(g_.source).parent_path();
  const std::string file = (folder / path).lexically_normal().string();
  if (std::find(run_.files.begin(), run_.files.end(), file) != run_.files.end()) {
    std::string chain;
    for (const std::string& f : run_.files) chain += f + " -> ";
    fail(i, "sub-graphs include each other: " + chain + file);
    return nullptr;
  }
  if (run_.files.size() >= kMaxSubgraphDepth) {
    fail(i, "sub-graphs nest deeper than " + std::to_string(kMaxSubgraphDepth) + " levels (the limit)");
    return nullptr;
  }
  auto& loaded = run_.loaded[file];
  if (!loaded) {
    BuildGraphParse p = load_build_graph(file, run_.schemas);
    if (!p.ok()) {
      fail(i, "sub-graph '" + path + "' cannot be read: " + p.errors.front().str());
      for (std::size_t k = 1; k < p.errors.size(); ++k) run_.out.errors.push_back(std::move(p.errors[k]));
      run_.loaded.erase(file);
      return nullptr;
    }
    p.graph.folder = std::filesystem::path(file).parent_path();
    loaded = std::make_shared<const BuildGraph>(std::move(p.graph));
    // Checked once, with the files that include it on the stack.
    run_.files.push_back(file);
    Compiler inner(*loaded, run_, path_of(i) + "/");
    const bool ok = inner.check();
    run_.files.pop_back();
    if (!ok) return nullptr;
  }
  subgraph_of_[i] = loaded;
  return &subgraph_kinds_.try_emplace(n.kind, subgraph_node_kind(path, *loaded)).first->second;
}

void Compiler::check_links() {
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

void Compiler::check_data_cycles() {
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
void Compiler::check_reachable() {
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

// Nests the components made (children in the order made), the calls
// after them, and warns when the build's depth-first order is not the
// chain's.
void Compiler::assemble() {
  std::vector<std::vector<int>> children(run_.made.size());
  std::vector<int> roots;
  for (std::size_t i = 0; i < run_.made.size(); ++i)
    (run_.parent[i] >= 0 ? children[static_cast<std::size_t>(run_.parent[i])] : roots).push_back(static_cast<int>(i));
  std::vector<int> depth_first;
  std::function<Component(int)> nest = [&](int i) {
    depth_first.push_back(i);
    Component c = run_.made[static_cast<std::size_t>(i)];
    for (int k : children[static_cast<std::size_t>(i)]) c.children.push_back(nest(k));
    return c;
  };
  run_.out.definition = g_.rig;
  run_.out.definition.components.clear();
  run_.out.definition.source = g_.source;
  for (int r : roots) run_.out.definition.components.push_back(nest(r));
  for (Component& c : run_.calls) run_.out.definition.components.push_back(std::move(c));
  for (std::size_t k = 0; k < depth_first.size(); ++k) {
    if (depth_first[k] == static_cast<int>(k)) continue;
    const CompileRun::Maker& early = run_.made_by[static_cast<std::size_t>(depth_first[k])];
    run_.out.warnings.push_back({early.source, early.where,
                                 "node '" + early.node + "': builds before '" + run_.made_by[k].node +
                                     "', not after it as the chain says: a build runs depth first (a "
                                     "component's children right after it)"});
    break;
  }
}

}  // namespace detail

BuildGraphCompile compile_build_graph(const BuildGraph& graph, const SchemaRegistry& schemas) {
  BuildGraphCompile out;
  detail::CompileRun run(schemas, out);
  run.rig = graph.rig.name;
  if (!graph.source.empty()) {
    const std::filesystem::path folder =
        !graph.folder.empty() ? graph.folder : std::filesystem::path(graph.source).parent_path();
    run.files.push_back((folder / std::filesystem::path(graph.source).filename()).lexically_normal().string());
  }
  detail::Compiler top(graph, run, "");
  if (!top.check() || !top.run_chain()) return out;
  top.assemble();
  if (!out.ok()) return out;
  for (Diagnostic& d : validate(out.definition, schemas)) out.errors.push_back(std::move(d));
  return out;
}

}  // namespace rigel::rig
