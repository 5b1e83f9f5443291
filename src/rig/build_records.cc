// What a step did (build_internal.h): the recorder that watches a
// construct, its record as JSON on a meta node, and the exact undo of it.
#include <algorithm>
#include <optional>
#include <string>

#include "build_internal.h"
#include "rigel/io/scene_file.h"

namespace rigel::rig::detail {
namespace {

using graph::Plug;
using graph::Uuid;
using graph::Value;

PlugRef ref_of(const graph::Graph& g, const Plug& p) {
  const graph::Node& n = *g.node(p.node);
  return PlugRef{n.uuid(), n.type().attr(p.attr).name, p.element};
}

Result<Plug> plug_of(const graph::Graph& g, const PlugRef& r) {
  NodeId id = g.find(r.node);
  if (!id.is_valid()) return error(ErrorCode::kNotFound, "build record: node " + r.node.str() + " is gone");
  const graph::AttrIndex a = g.node(id)->type().attr_find(r.attr);
  if (a == graph::kNoAttr) return error(ErrorCode::kNotFound, "build record: no attribute " + r.attr);
  return Plug{id, a, r.element};
}

Json plug_json(const PlugRef& r) {
  Json j = Json::array({r.node.str(), r.attr});
  if (r.element >= 0) j.push_back(r.element);
  return j;
}

Result<PlugRef> plug_from_json(const Json& j) {
  if (!j.is_array() || j.size() < 2 || !j[0].is_string() || !j[1].is_string())
    return error(ErrorCode::kParseError, "build record: bad plug " + j.dump());
  auto u = Uuid::parse(j[0].get<std::string>());
  if (!u) return error(ErrorCode::kParseError, "build record: bad uuid " + j[0].dump());
  PlugRef r{*u, j[1].get<std::string>(), -1};
  if (j.size() > 2 && j[2].is_number_integer()) r.element = j[2].get<int>();
  return r;
}

}  // namespace

Json record_json(const graph::Graph& g, const StepRecord& r) {
  Json j;
  j["step"] = r.step;
  Json created = Json::array();
  for (const Uuid& u : r.created) created.push_back(u.str());
  j["created"] = created;
  Json values = Json::array();
  for (const ValueChange& v : r.values) {
    NodeId id = g.find(v.plug.node);
    if (!id.is_valid()) continue;  // deleted by the user since: nothing to restore
    const graph::AttrSpec& spec = g.node(id)->type().attr(g.node(id)->type().attr_find(v.plug.attr));
    values.push_back(Json::array({plug_json(v.plug), io::attribute_to_json(v.before, spec)}));
  }
  j["values"] = values;
  for (const char* key : {"made", "broken"}) {
    Json list = Json::array();
    for (const ConnectionChange& c : (std::string(key) == "made" ? r.made : r.broken))
      list.push_back(Json::array({plug_json(c.src), plug_json(c.dst)}));
    j[key] = list;
  }
  Json renamed = Json::array();
  for (const auto& [u, name] : r.renamed) renamed.push_back(Json::array({u.str(), name}));
  j["renamed"] = renamed;
  return j;
}

Result<StepRecord> record_from_json(const graph::Graph& g, const Json& j) {
  StepRecord r;
  if (!j.is_object() || !j.contains("step")) return error(ErrorCode::kParseError, "build record: not a step record");
  r.step = j["step"].get<std::string>();
  for (const Json& u : j.value("created", Json::array())) {
    auto id = Uuid::parse(u.get<std::string>());
    if (!id) return error(ErrorCode::kParseError, "build record: bad uuid " + u.dump());
    r.created.push_back(*id);
  }
  for (const Json& v : j.value("values", Json::array())) {
    Result<PlugRef> p = plug_from_json(v.at(0));
    if (!p) return p.status();
    NodeId id = g.find(p->node);
    if (!id.is_valid()) continue;  // a node the user deleted since: nothing to restore
    const graph::AttrIndex a = g.node(id)->type().attr_find(p->attr);
    if (a == graph::kNoAttr) return error(ErrorCode::kParseError, "build record: no attribute " + p->attr);
    Result<Value> value = io::attribute_from_json(v.at(1), g.node(id)->type().attr(a));
    if (!value) return value.status().with_context("build record");
    r.values.push_back(ValueChange{*p, std::move(*value)});
  }
  for (const char* key : {"made", "broken"}) {
    for (const Json& c : j.value(key, Json::array())) {
      Result<PlugRef> s = plug_from_json(c.at(0)), d = plug_from_json(c.at(1));
      if (!s) return s.status();
      if (!d) return d.status();
      (std::string(key) == "made" ? r.made : r.broken).push_back(ConnectionChange{*s, *d});
    }
  }
  for (const Json& n : j.value("renamed", Json::array())) {
    auto id = Uuid::parse(n.at(0).get<std::string>());
    if (!id) return error(ErrorCode::kParseError, "build record: bad uuid");
    r.renamed.emplace_back(*id, n.at(1).get<std::string>());
  }
  return r;
}

// Watches the graph while a construct runs. Nodes made by this step are its

Recorder::Recorder(graph::Graph& g, StepRecord& record) : graph_(g), record_(record) { g.add_observer(this); }

Recorder::~Recorder() { graph_.remove_observer(this); }

void Recorder::node_added(const graph::Graph& g, NodeId id) {
  const Uuid& u = g.node(id)->uuid();
  record_.created.push_back(u);
  own_.insert(u);
}

void Recorder::node_removed(const graph::Graph& g, NodeId id) {
  const Uuid& u = g.node(id)->uuid();
  if (own_.erase(u)) {
    std::erase(record_.created, u);
  } else if (failure_.empty()) {
    failure_ = "a build step may not delete '" + g.node(id)->name() + "', which it did not make";
  }
}

void Recorder::node_renamed(const graph::Graph& g, NodeId id, const std::string& old_name) {
  const Uuid& u = g.node(id)->uuid();
  if (own_.count(u)) return;
  for (const auto& r : record_.renamed)
    if (r.first == u) return;
  record_.renamed.emplace_back(u, old_name);
}

void Recorder::attribute_set(const graph::Graph& g, const Plug& plug, const Value& before) {
  if (own_.count(g.node(plug.node)->uuid())) return;
  remember_value(g, plug, before);
}

void Recorder::connection_made(const graph::Graph& g, const graph::Connection& c) {
  const bool src_own = own_.count(g.node(c.src.node)->uuid()) > 0;
  const bool dst_own = own_.count(g.node(c.dst.node)->uuid()) > 0;
  if (dst_own) return;
  // The destination keeps what it pulls once the connection goes: remember
  // what it holds now.
  remember_value(g, Plug{c.dst.node, c.dst.attr, -1}, g.node(c.dst.node)->value(c.dst.attr));
  if (!src_own) record_.made.push_back(ConnectionChange{ref_of(g, c.src), ref_of(g, c.dst)});
}

void Recorder::connection_broken(const graph::Graph& g, const graph::Connection& c) {
  const graph::Node* s = g.node(c.src.node);
  const graph::Node* d = g.node(c.dst.node);
  if (!s || !d || own_.count(s->uuid()) || own_.count(d->uuid())) return;
  const PlugRef src = ref_of(g, c.src), dst = ref_of(g, c.dst);
  // Made by this step and broken again: forget it.
  for (auto it = record_.made.begin(); it != record_.made.end(); ++it) {
    if (it->src.node == src.node && it->src.attr == src.attr && it->src.element == src.element &&
        it->dst.node == dst.node && it->dst.attr == dst.attr && it->dst.element == dst.element) {
      record_.made.erase(it);
      return;
    }
  }
  record_.broken.push_back(ConnectionChange{src, dst});
}

void Recorder::tag_changed(const graph::Graph& g, NodeId id, const std::string& key) {
  if (!own_.count(g.node(id)->uuid()) && failure_.empty())
    failure_ = "a build step may not tag '" + g.node(id)->name() + "' (" + key + "), which it did not make";
}

void Recorder::remember_value(const graph::Graph& g, const Plug& plug, const Value& before) {
  const PlugRef r = ref_of(g, Plug{plug.node, plug.attr, -1});
  for (const ValueChange& v : record_.values)
    if (v.plug.node == r.node && v.plug.attr == r.attr) return;
  record_.values.push_back(ValueChange{r, before});
}

// Undoes what a step did, newest first.
Status undo_record(graph::Graph& g, const StepRecord& r) {
  for (auto it = r.created.rbegin(); it != r.created.rend(); ++it) {
    NodeId id = g.find(*it);
    if (!id.is_valid()) continue;
    if (Status s = g.delete_node(id); !s) return s.with_context("destruct " + r.step);
  }
  for (auto it = r.made.rbegin(); it != r.made.rend(); ++it) {
    Result<Plug> s = plug_of(g, it->src), d = plug_of(g, it->dst);
    if (!s || !d) continue;
    std::optional<Plug> now = g.source(*d);
    if (now && now->node == s->node && now->attr == s->attr && now->element == s->element)
      if (Status st = g.disconnect(*s, *d); !st) return st.with_context("destruct " + r.step);
  }
  for (auto it = r.broken.rbegin(); it != r.broken.rend(); ++it) {
    Result<Plug> s = plug_of(g, it->src), d = plug_of(g, it->dst);
    if (!s || !d || g.source(*d)) continue;
    if (Status st = g.connect(*s, *d); !st) return st.with_context("destruct " + r.step);
  }
  for (auto it = r.values.rbegin(); it != r.values.rend(); ++it) {
    Result<Plug> p = plug_of(g, it->plug);
    if (!p) continue;
    bool connected = false;
    for (const graph::Connection& c : g.node(p->node)->inputs())
      if (c.dst.attr == p->attr) connected = true;
    if (connected) continue;
    if (Status st = g.set_value(*p, it->before); !st) return st.with_context("destruct " + r.step);
  }
  for (auto it = r.renamed.rbegin(); it != r.renamed.rend(); ++it) {
    NodeId id = g.find(it->first);
    if (id.is_valid() && g.node(id)->name() != it->second)
      if (Status st = g.rename(id, it->second); !st) return st.with_context("destruct " + r.step);
  }
  return Status::ok();
}

}  // namespace rigel::rig::detail
