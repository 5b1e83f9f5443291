// Running a build graph's exec chain (build_graph_compiler.h): values
// flowing along links, component and function nodes making components and
// calls, for-each bodies once per item, sub-graphs by a compiler of their
// own.
#include <algorithm>

#include <nlohmann/json.hpp>

#include "build_graph_compiler.h"
#include "definition_io_internal.h"
#include "rigel/rig/build_function.h"
#include "rigel/rig/templates.h"

namespace rigel::rig::detail {

// The value reaching input `socket` of node `n`; nullopt when it is not
// linked (the node's own value holds) or the error was reported.
std::optional<Flow> Compiler::input(std::size_t n, const std::string& socket) {
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
    if (src.kind.rfind("forEach:", 0) == 0) return l.from.socket == "index" ? loop_.at(s).second : loop_.at(s).first;
    if (subgraph_of_.count(s)) {
      Flow f = outputs_of_.at(s).at(l.from.socket);
      if (f.value) f.value = as_type(*f.value, type);
      return f;
    }
    if (src.kind.rfind("function:", 0) == 0) return runtime_flow(ran_.at(s).call, l.from.socket);
    if (src.kind.rfind("flow:", 0) == 0) {
      const FunctionValues& out = flow_out_.at(s);
      if (const auto items = out.lists.find(l.from.socket); items != out.lists.end()) return list_flow(items->second);
      return value_flow(as_type(out.values.at(l.from.socket), type));
    }
    Flow f = ran_.at(s);
    if (l.from.socket != "component") f.output = l.from.socket;  // a component's controls, joints or hooks
    return f;
  }
  if (src.kind == "variable:get") {
    Flow f = variables_.at(src.variable);
    if (f.value) f.value = as_type(*f.value, type);
    return f;
  }
  if (src.kind.rfind("function:", 0) == 0) return pure_output(s, l.from.socket, type);
  // A constant.
  const std::string& own = kind_of_[s]->outputs.front().type;
  if (!list_element(own).empty()) {
    const auto items = src.lists.find("value");
    return list_flow(items == src.lists.end() ? ValueList{} : items->second);
  }
  const Param* v = src.value("value");
  const DataType* t = builtin_data_types().find(own);
  return value_flow(as_type(v ? v->value : zero_value(*t->value_type), type));
}

// Output `output` of pure function node `n`, run now on its inputs (read
// as any node's, so in a for-each body once per item); nullopt with the
// problem reported.
std::optional<Flow> Compiler::pure_output(std::size_t n, const std::string& output, const std::string& type) {
  const GraphNode& node = g_.nodes[n];
  const std::string id = node.kind.substr(std::string_view("function:").size());
  const std::optional<BuildFunction> fn = build_functions().find(id);
  if (!fn || !fn->pure) {
    fail(n, "build function '" + id + "' is not registered as a pure function");
    return std::nullopt;
  }
  FunctionValues in;
  if (!known_values(n, fn->inputs, in)) return std::nullopt;
  auto out = run_pure(*fn, std::move(in));
  if (!out) {
    fail(n, "function " + id + (fn->origin.empty() ? "" : " (" + fn->origin + ")") + ": " + out.status().message());
    return std::nullopt;
  }
  if (const auto items = out->lists.find(output); items != out->lists.end()) return list_flow(items->second);
  return value_flow(as_type(out->values.at(output), type));
}

// The values of inputs `sockets` of node `n` (linked, else its own; the
// rest are the function's or flow kind's defaults); false with the
// problem reported.
bool Compiler::known_values(std::size_t n, const std::vector<SocketSpec>& sockets, FunctionValues& in) {
  const GraphNode& node = g_.nodes[n];
  for (const SocketSpec& s : sockets) {
    if (!list_element(s.type).empty()) {
      std::optional<ValueList> items = list_input(n, s.name);
      if (!items) return false;
      in.lists[s.name] = std::move(*items);
      continue;
    }
    std::optional<Flow> f = known_input(n, s.name);
    if (failed()) return false;
    if (f && f->value) in.values[s.name] = as_type(*f->value, s.type);
    else if (const Param* p = node.value(s.name)) in.values[s.name] = as_type(p->value, s.type);
  }
  return true;
}

// An input the node needs before the build: nullopt (with the error)
// when it reads a function's output, which only the build makes.
std::optional<Flow> Compiler::known_input(std::size_t n, const std::string& socket) {
  std::optional<Flow> f = input(n, socket);
  if (f && f->runtime()) {
    fail(n, "input '" + socket + "' reads a value the build makes (output '" + f->output +
                "' of a function node): only function nodes take those (a value known before the build is a "
                "constant's, a variable's or a pure function's)");
    return std::nullopt;
  }
  return f;
}

// An input's value as a value of its type: linked, else the node's own,
// else the type's zero.
std::optional<ParamValue> Compiler::value_input(std::size_t n, const std::string& socket) {
  if (auto f = known_input(n, socket)) return f->value;
  if (failed()) return std::nullopt;
  if (const Param* p = g_.nodes[n].value(socket)) return as_type(p->value, socket_type(n, *kind_of_[n]->input(socket)));
  const DataType* t = builtin_data_types().find(socket_type(n, *kind_of_[n]->input(socket)));
  return zero_value(*t->value_type);
}

// A list input's items: linked (a list constant, a list variable's get,
// ...), else the node's own, else none; nullopt with the error reported.
std::optional<ValueList> Compiler::list_input(std::size_t n, const std::string& socket) {
  if (auto f = known_input(n, socket)) {
    if (f->items) return f->items;
    fail(n, "input '" + socket + "' needs a list");
    return std::nullopt;
  }
  if (failed()) return std::nullopt;
  const auto own = g_.nodes[n].lists.find(socket);
  return own == g_.nodes[n].lists.end() ? ValueList{} : own->second;
}

bool Compiler::run_chain(const std::map<std::string, Flow>& inputs) {
  for (const GraphVariable& v : g_.variables) {
    const auto given = inputs.find(v.name);
    if (given != inputs.end()) variables_[v.name] = given->second;
    else if (v.type == "component") variables_[v.name] = Flow{};  // none
    else if (list_element(v.type).empty()) variables_[v.name] = value_flow(as_type(v.value, v.type));
    else variables_[v.name] = list_flow(v.items);
  }
  std::size_t n = 0;
  while (g_.nodes[n].kind != "start") ++n;
  ran_[n] = Flow{};
  path_ = {n};
  return walk(n, "then");
}

// Runs the chain from exec output `next` of node `n` until it ends (a
// for-each's body: until the body's last node). False on an error.
bool Compiler::walk(std::size_t n, std::string next) {
  const std::size_t base = path_.size();
  bool ok = true;
  while (ok) {
    const auto link = exec_next_.find({n, next});
    if (link == exec_next_.end()) break;
    const std::size_t m = index_.at(g_.links[link->second].to.node);
    if (std::find(path_.begin(), path_.end(), m) != path_.end()) {
      std::string cycle;
      for (auto it = std::find(path_.begin(), path_.end(), m); it != path_.end(); ++it) cycle += path_of(*it) + " -> ";
      fail(m, "exec links form a cycle: " + cycle + path_of(m));
      ok = false;
      break;
    }
    n = m;
    path_.push_back(n);
    run_log_.push_back(n);
    if (++run_.runs > kMaxRuns) {
      fail(n, "the exec chain runs more than " + std::to_string(kMaxRuns) +
                  " nodes and items (for-each bodies multiply them): the limit");
      ok = false;
      break;
    }
    run_.out.order.push_back(path_of(n));
    next = "then";
    ok = run_node(n, next);
  }
  path_.resize(base);
  return ok && !failed();
}

// Runs one node of the chain; `next` becomes the exec output it goes on
// through. False on an error.
bool Compiler::run_node(std::size_t n, std::string& next) {
  const GraphNode& node = g_.nodes[n];
  if (node.kind == "variable:set") {
    // A set may hold a function's output, for later function nodes.
    std::optional<Flow> f;
    if (!list_element(g_.variable(node.variable)->type).empty()) {
      auto items = list_input(n, "value");
      if (!items) return false;
      f = list_flow(std::move(*items));
    } else {
      f = input(n, "value");
      if (failed()) return false;
      if (!f && g_.variable(node.variable)->type == "component") {
        f = Flow{};  // none
      } else if (!f) {
        auto v = value_input(n, "value");
        if (!v) return false;
        f = value_flow(*v);
      }
    }
    variables_[node.variable] = *f;
    ran_[n] = Flow{};
  } else if (node.kind == "branch") {
    auto c = value_input(n, "condition");
    if (!c) return false;
    next = std::get<bool>(*c) ? "true" : "false";
    ran_[n] = Flow{};
  } else if (node.kind.rfind("forEach:", 0) == 0) {
    next = "completed";
    return run_loop(n);
  } else if (node.kind.rfind("component:", 0) == 0) {
    return make_component(n);
  } else if (node.kind.rfind("function:", 0) == 0) {
    return make_call(n);
  } else if (node.kind.rfind("flow:", 0) == 0) {
    return run_flow_node(n, next);
  } else if (subgraph_of_.count(n)) {
    return run_subgraph(n);
  }
  return true;
}

// A for-each: its body once per item, the item and its index on its
// outputs, each iteration's components and calls told apart by the
// iteration's key (the indices of the loops it is in).
bool Compiler::run_loop(std::size_t n) {
  std::optional<ValueList> items = list_input(n, "list");
  if (!items) return false;
  const std::string element = list_element(kind_of_[n]->input("list")->type);
  ran_[n] = Flow{};
  for (std::size_t i = 0; i < items->size(); ++i) {
    // An item counts as a node run, so empty bodies cannot loop for minutes.
    if (++run_.runs > kMaxRuns) {
      fail(n, "the exec chain runs more than " + std::to_string(kMaxRuns) +
                  " nodes and items (for-each bodies multiply them): the limit");
      return false;
    }
    loop_[n] = {value_flow(as_type((*items)[i], element)), value_flow(static_cast<std::int64_t>(i))};
    run_.keys.push_back(i);
    const std::size_t mark = run_log_.size();
    const bool ok = walk(n, "body");
    run_.keys.pop_back();
    if (!ok) return false;
    // The next item's body reads its own nodes' outputs, never this one's;
    // after the last, nodes after the loop read the last item's.
    if (i + 1 < items->size())
      for (std::size_t k = mark; k < run_log_.size(); ++k) ran_.erase(run_log_[k]);
  }
  return true;
}

// A plugin's flow node: its body says which exits to go on through, in
// order; each pass but the last (or a repeat) runs as a body does, a
// repeat's passes keyed as a for-each's items; the last, if it does not
// repeat, goes on in place (`next`).
bool Compiler::run_flow_node(std::size_t n, std::string& next) {
  const std::string id = g_.nodes[n].kind.substr(std::string_view("flow:").size());
  const std::optional<FlowKind> kind = flow_kinds().find(id);
  if (!kind) {
    fail(n, "node kind 'flow:" + id + "' is not registered (is the plugin that registers it loaded?)");
    return false;
  }
  FunctionValues in;
  if (!known_values(n, kind->inputs, in)) return false;
  auto steps = run_flow(*kind, std::move(in));
  if (!steps) {
    fail(n, "node kind " + id + (kind->origin.empty() ? "" : " (" + kind->origin + ")") + ": " + steps.status().message());
    return false;
  }
  ran_[n] = Flow{};
  next.clear();  // no exit taken: the chain ends here
  std::map<std::string, std::size_t> passes;
  for (std::size_t k = 0; k < steps->size(); ++k) {
    const FlowCall::Step& step = (*steps)[k];
    flow_out_[n] = step.outputs;
    const bool repeats = std::find(kind->repeats.begin(), kind->repeats.end(), step.exit) != kind->repeats.end();
    if (!repeats && k + 1 == steps->size()) {
      next = step.exit;
      return true;
    }
    if (++run_.runs > kMaxRuns) {
      fail(n, "the exec chain runs more than " + std::to_string(kMaxRuns) +
                  " nodes and items (for-each bodies multiply them): the limit");
      return false;
    }
    if (repeats) run_.keys.push_back(passes[step.exit]++);
    const std::size_t mark = run_log_.size();
    const bool ok = walk(n, step.exit);
    if (repeats) run_.keys.pop_back();
    if (!ok) return false;
    // A later pass through the same exit reads its own nodes' outputs.
    const bool again = std::any_of(steps->begin() + static_cast<std::ptrdiff_t>(k) + 1, steps->end(),
                                   [&](const FlowCall::Step& s) { return s.exit == step.exit; });
    if (again)
      for (std::size_t r = mark; r < run_log_.size(); ++r) ran_.erase(run_log_[r]);
  }
  return true;
}

// The key of the iteration the chain is in: "" outside for-each bodies,
// else "[i]" per loop ("[1][0]").
std::string Compiler::iteration_key() const {
  std::string key;
  for (std::size_t i : run_.keys) key += "[" + std::to_string(i) + "]";
  return key;
}

// A component's or call's rigId: its own (or one made from the node's
// id); in a for-each body or a sub-graph, one made from that, the path of
// the sub-graph nodes it is in and the iteration's key, so each item and
// each use of a sub-graph has its own.
std::string Compiler::rig_id_of(const std::string& own, std::size_t node) const {
  if (run_.keys.empty() && prefix_.empty()) return own.empty() ? derived_rig_id(run_.rig, g_.nodes[node].id) : own;
  return derived_rig_id(run_.rig, prefix_ + (own.empty() ? g_.nodes[node].id : own) + iteration_key());
}

// The node of the top graph that `node` runs in: itself, or the sub-graph
// node around it.
std::string Compiler::top_node(std::size_t node) const {
  return prefix_.empty() ? g_.nodes[node].id : prefix_.substr(0, prefix_.find('/'));
}

// Refuses the graph past kMaxMade components and calls.
bool Compiler::within_limit(std::size_t n) {
  if (run_.made.size() + run_.calls.size() < kMaxMade) return true;
  fail(n, "the graph makes more than " + std::to_string(kMaxMade) +
              " components and calls (for-each bodies multiply them): the limit");
  return false;
}

bool Compiler::make_component(std::size_t n) {
  const GraphNode& node = g_.nodes[n];
  Component c = node.component;
  c.children.clear();
  if (c.where.line == 0) c.where = node.where;
  if (!within_limit(n)) return false;
  c.rig_id = rig_id_of(c.rig_id, n);
  int parent = -1;
  if (auto p = input(n, "parent")) parent = p->component;
  else if (failed()) return false;
  const auto text = [&](const char* socket, std::string& into) {
    if (auto f = known_input(n, socket)) into = std::get<std::string>(*f->value);
    return !failed();
  };
  std::string side;
  if (!text("name", c.name) || !text("side", side) || !text("attach", c.attach)) return false;
  if (!side.empty()) {
    const auto s = side_from_name(side);
    if (!s) {
      fail(n, "input 'side': '" + side + "' is not C, L or R");
      return false;
    }
    // Drawn for one side and given the other: built mirrored (its guides'
    // joints and rotations, its attach), as a mirrored template is.
    const bool opposite = (c.side == Side::kLeft && *s == Side::kRight) || (c.side == Side::kRight && *s == Side::kLeft);
    if (opposite) {
      MirrorOptions keep;
      keep.keep_ids = true;
      c = mirror_component(c, keep);
    }
    c.side = *s;
  }
  const ComponentSchema* schema = run_.schemas.find(c.type);
  for (const ParamSpec& spec : schema ? schema->params : std::vector<ParamSpec>{}) {
    auto f = known_input(n, spec.name);
    if (!f) {
      if (failed()) return false;
      continue;
    }
    ParamValue v = as_type(*f->value, data_type_of(spec.type));
    auto it = std::find_if(c.params.begin(), c.params.end(), [&](const Param& p) { return p.name == spec.name; });
    if (it != c.params.end()) it->value = std::move(v);
    else c.params.push_back(Param{spec.name, std::move(v), node.where});
  }
  const int depth = parent >= 0 ? run_.depth[static_cast<std::size_t>(parent)] + 1 : 1;
  if (depth > static_cast<int>(kMaxComponentDepth)) {
    fail(n, "components nest deeper than " + std::to_string(kMaxComponentDepth) + " levels (the limit)");
    return false;
  }
  Flow made;
  made.component = static_cast<int>(run_.made.size());
  ran_[n] = made;
  run_.out.rig_ids.emplace_back(top_node(n), c.rig_id);
  run_.made.push_back(std::move(c));
  run_.parent.push_back(parent);
  run_.depth.push_back(depth);
  run_.made_by.push_back(CompileRun::Maker{path_of(n), g_.source, node.where});
  return true;
}

namespace {

// A list's items as a call's argument: a JSON array of values of the
// list type's element type.
nlohmann::ordered_json items_json(const ValueList& items, const std::string& list_type) {
  const std::string element = list_element(list_type);
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const ParamValue& v : items) out.push_back(param_value_json(element.empty() ? v : as_type(v, element)));
  return out;
}

}  // namespace

// A function node: a `call` component, a root built after the
// components, that builds after every component or call it reads.
bool Compiler::make_call(std::size_t n) {
  const GraphNode& node = g_.nodes[n];
  const std::string id = node.kind.substr(std::string_view("function:").size());
  const std::optional<BuildFunction> fn = build_functions().find(id);
  if (!fn) {
    fail(n, "build function '" + id + "' is not registered");
    return false;
  }
  Component c;
  c.type = kCallType;
  if (!within_limit(n)) return false;
  c.name = path_of(n);
  std::replace(c.name.begin(), c.name.end(), '/', '_');
  for (std::size_t i : run_.keys) c.name += "_" + std::to_string(i);
  c.rig_id = rig_id_of(node.rig_id, n);
  c.where = node.where;
  nlohmann::ordered_json args = nlohmann::ordered_json::object();
  for (const SocketSpec& in : fn->inputs) {
    std::optional<Flow> f = input(n, in.name);
    if (failed()) return false;
    if (!f) {
      if (in.type == "component") {
        fail(n, "input '" + in.name + "' needs a link from a component node's 'component' output");
        return false;
      }
      if (in.type.rfind("list:", 0) == 0 && list_element(in.type).empty()) {
        fail(n, "input '" + in.name + "' needs a link from a component node's " +
                    (in.type == "list:control" ? "'controls'" : in.type == "list:joint" ? "'joints'" : "'hooks'") +
                    " output");
        return false;
      }
      if (const Param* p = node.value(in.name)) args[in.name] = param_value_json(as_type(p->value, in.type));
      if (const auto own = node.lists.find(in.name); own != node.lists.end()) args[in.name] = items_json(own->second, in.type);
      continue;
    }
    std::string from;
    if (f->runtime()) {
      args[in.name] = {{"$output", {f->call, f->output}}};
      from = f->call;
    } else if (f->component >= 0) {
      // {"$component": rigId}, or its {"$controls" | "$joints" | "$hooks": rigId}.
      from = run_.made[static_cast<std::size_t>(f->component)].rig_id;
      args[in.name] = {{"$" + (f->output.empty() ? std::string("component") : f->output), from}};
    } else if (f->items) {
      args[in.name] = items_json(*f->items, in.type);
    } else if (!f->value) {
      fail(n, "input '" + in.name + "' reads no component (a component variable no node has set)");
      return false;
    } else {
      args[in.name] = param_value_json(as_type(*f->value, in.type));
    }
    if (!from.empty() && std::find(c.after.begin(), c.after.end(), from) == c.after.end()) c.after.push_back(from);
  }
  c.params = {Param{"function", id, node.where}, Param{"args", args.dump(), node.where}};
  ran_[n] = runtime_flow(c.rig_id, {});
  run_.out.rig_ids.emplace_back(top_node(n), c.rig_id);
  run_.calls.push_back(std::move(c));
  return true;
}

// A graph:PATH node: its graph run by a compiler of its own, its variables
// taking the node's inputs (linked, else the node's own values, else the
// graph's), its outputs the variables as its chain leaves them.
bool Compiler::run_subgraph(std::size_t n) {
  const BuildGraph& sub = *subgraph_of_.at(n);
  std::map<std::string, Flow> inputs;
  for (const GraphVariable& v : sub.variables) {
    std::optional<Flow> f = input(n, v.name);
    if (failed()) return false;
    if (!f) f = own_value(n, v);
    if (failed()) return false;
    if (f) inputs[v.name] = std::move(*f);
  }
  Compiler inner(sub, run_, path_of(n) + "/");
  if (!inner.check() || !inner.run_chain(inputs)) return false;
  outputs_of_[n] = inner.variables();
  ran_[n] = Flow{};
  return true;
}

// The value a graph:PATH node holds for its input `v` (a variable of the
// sub-graph), as `v`'s type: the file gives a number, a string, a bool or
// an array, which is a vector or a list by the variable's type; nullopt
// when it holds none (the sub-graph's own value holds) or it does not fit
// (reported).
std::optional<Flow> Compiler::own_value(std::size_t n, const GraphVariable& v) {
  const GraphNode& node = g_.nodes[n];
  const Param* p = node.value(v.name);
  const auto list = node.lists.find(v.name);
  if (!p && list == node.lists.end()) return std::nullopt;
  // What the file gave: one value, or an array (read as a vector when it
  // is three numbers).
  ValueList items;
  bool array = list != node.lists.end();
  if (array) {
    items = list->second;
  } else if (const auto* xyz = std::get_if<math::Vec3>(&p->value)) {
    array = true;
    items = {xyz->x(), xyz->y(), xyz->z()};
  }
  const std::string element = list_element(v.type);
  const DataType* t = builtin_data_types().find(v.type);
  if (!element.empty() && array) {
    for (ParamValue& item : items) item = as_type(item, element);
    if (list_fits(items, v.type)) return list_flow(std::move(items));
  } else if (v.type == "vector" && array && items.size() == 3 && list_fits(items, "list:number")) {
    const auto x = [&](std::size_t k) { return std::get<double>(as_type(items[k], "number")); };
    return value_flow(math::Vec3(x(0), x(1), x(2)));
  } else if (p && t && t->value_type && value_fits(p->value, *t->value_type)) {
    return value_flow(as_type(p->value, v.type));
  }
  fail(n, "the value of '" + v.name + "' is not a " + v.type);
  return std::nullopt;
}

}  // namespace rigel::rig::detail
