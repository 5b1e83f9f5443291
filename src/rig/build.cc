#include "rigel/rig/build.h"

#include <algorithm>
#include <charconv>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

#include <nlohmann/json.hpp>

#include "rigel/io/scene_file.h"
#include "rigel/math/rotation.h"
#include "rigel/math/transform.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/ops/constraints/constraints.h"
#include "rigel/ops/constraints/nodes.h"
#include "rigel/ops/util/nodes.h"
#include "rigel/rig/component.h"
#include "rigel/rig/definition_io.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/shapes.h"
#include "rigel/scene/transform_types.h"

namespace rigel::rig {
namespace {

using Json = nlohmann::ordered_json;
using graph::Plug;
using graph::Uuid;
using graph::Value;
using math::Mat4;
namespace xform = scene::xform;

// A guide's values as a matrix: its place, or its offset from its joint.
Mat4 guide_values(const Guide& guide) {
  math::TransformParts parts;
  parts.translate = guide.translate;
  parts.rotate = math::to_radians(guide.rotate);
  parts.scale = guide.scale;
  return math::compose(parts);
}

constexpr const char* kRigStep = "rig";
constexpr const char* kMetaStep = "meta";

// ---- what a step did -----------------------------------------------------

struct PlugRef {
  Uuid node;
  std::string attr;
  int element = -1;
};

struct ValueChange {
  PlugRef plug;
  Value before;
};

struct ConnectionChange {
  PlugRef src, dst;
};

struct StepRecord {
  std::string step;
  std::vector<Uuid> created;
  std::vector<ValueChange> values;
  std::vector<ConnectionChange> made, broken;
  std::vector<std::pair<Uuid, std::string>> renamed;
};

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
// own; everything it does to other nodes is remembered with how it was.
class Recorder : public graph::Observer {
 public:
  Recorder(graph::Graph& g, StepRecord& record) : graph_(g), record_(record) { g.add_observer(this); }
  ~Recorder() override { graph_.remove_observer(this); }
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  const std::string& failure() const { return failure_; }

  void node_added(const graph::Graph& g, NodeId id) override {
    const Uuid& u = g.node(id)->uuid();
    record_.created.push_back(u);
    own_.insert(u);
  }
  void node_removed(const graph::Graph& g, NodeId id) override {
    const Uuid& u = g.node(id)->uuid();
    if (own_.erase(u)) {
      std::erase(record_.created, u);
    } else if (failure_.empty()) {
      failure_ = "a build step may not delete '" + g.node(id)->name() + "', which it did not make";
    }
  }
  void node_renamed(const graph::Graph& g, NodeId id, const std::string& old_name) override {
    const Uuid& u = g.node(id)->uuid();
    if (own_.count(u)) return;
    for (const auto& r : record_.renamed)
      if (r.first == u) return;
    record_.renamed.emplace_back(u, old_name);
  }
  void attribute_set(const graph::Graph& g, const Plug& plug, const Value& before) override {
    if (own_.count(g.node(plug.node)->uuid())) return;
    remember_value(g, plug, before);
  }
  void connection_made(const graph::Graph& g, const graph::Connection& c) override {
    const bool src_own = own_.count(g.node(c.src.node)->uuid()) > 0;
    const bool dst_own = own_.count(g.node(c.dst.node)->uuid()) > 0;
    if (dst_own) return;
    // The destination keeps what it pulls once the connection goes: remember
    // what it holds now.
    remember_value(g, Plug{c.dst.node, c.dst.attr, -1}, g.node(c.dst.node)->value(c.dst.attr));
    if (!src_own) record_.made.push_back(ConnectionChange{ref_of(g, c.src), ref_of(g, c.dst)});
  }
  void connection_broken(const graph::Graph& g, const graph::Connection& c) override {
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
  void tag_changed(const graph::Graph& g, NodeId id, const std::string& key) override {
    if (!own_.count(g.node(id)->uuid()) && failure_.empty())
      failure_ = "a build step may not tag '" + g.node(id)->name() + "' (" + key + "), which it did not make";
  }

 private:
  void remember_value(const graph::Graph& g, const Plug& plug, const Value& before) {
    const PlugRef r = ref_of(g, Plug{plug.node, plug.attr, -1});
    for (const ValueChange& v : record_.values)
      if (v.plug.node == r.node && v.plug.attr == r.attr) return;
    record_.values.push_back(ValueChange{r, before});
  }

  graph::Graph& graph_;
  StepRecord& record_;
  std::unordered_set<Uuid, graph::UuidHash> own_;
  std::string failure_;
};

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

// A component's own data, for telling what changed (children left out).
std::string signature(const Component& c) {
  std::ostringstream o;
  o.precision(17);
  o << c.type << '|' << c.name << '|' << side_name(c.side) << '|' << c.version << '|' << c.attach << '|';
  for (const Guide& g : c.guides)
    o << g.name << ',' << g.joint << ',' << g.translate.transpose() << ',' << g.rotate.transpose() << ','
      << g.scale.transpose() << ';';
  o << '|';
  for (const ControlStyle& s : c.controls) o << s.role << ',' << s.shape << ',' << s.color << ',' << s.size << ';';
  o << '|';
  for (const Param& p : c.params) {
    o << p.name << '=';
    std::visit(
        [&](const auto& v) {
          if constexpr (std::is_same_v<std::decay_t<decltype(v)>, math::Vec3>) o << v.transpose();
          else o << v;
        },
        p.value);
    o << ';';
  }
  o << '|';
  for (const Feature& f : c.features) {
    o << f.name << '=' << f.enabled << '[';
    for (const FeatureSwitch& s : f.switches) o << s.name << '=' << s.enabled << ',';
    o << ']';
  }
  return o.str();
}

std::string full_name_of(const Component& c) {
  return c.side == Side::kCenter ? c.name : c.name + "_" + side_name(c.side);
}

const Feature* find_feature(const std::vector<Feature>& list, std::string_view name) {
  for (const Feature& f : list)
    if (f.name == name) return &f;
  return nullptr;
}

bool step_enabled(const Definition& d, const Component* c, const std::string& feature, const std::string& sw) {
  if (feature.empty()) return true;
  const Feature* f = c ? find_feature(c->features, feature) : nullptr;
  if (!f) f = find_feature(d.features, feature);
  if (!f) return true;
  if (!f->enabled) return false;
  if (sw.empty()) return true;
  for (const FeatureSwitch& s : f->switches)
    if (s.name == sw) return s.enabled;
  return true;
}

// Where a component attaches: (component index or -1 for the rig, hook reference).
struct AttachTarget {
  int component = -1;
  std::string hook;
};

}  // namespace

// ---- Build ---------------------------------------------------------------

struct Build::Records {
  // (rigId or "" for the rig, step) -> what the step did
  std::map<std::pair<std::string, std::string>, StepRecord> done;
  // owner -> the buildRecord text its entries in `done` were read from or
  // written as: sync() re-parses an owner only when the scene's text differs
  // (parsing every record on every step made builds quadratic).
  std::map<std::string, std::string> text;
  void forget(const std::string& owner) {
    text.erase(owner);
    for (auto it = done.begin(); it != done.end();) it = it->first.first == owner ? done.erase(it) : std::next(it);
  }
  std::vector<int> parent;           // per component: index of its nesting parent, -1 for roots
  std::vector<AttachTarget> attach;  // per component
};

std::string PlannedStep::label() const { return step; }

Build::Build(scene::Scene& scene, Definition definition, const ComponentFactory& factory, BuildOptions options)
    : scene_(scene), definition_(std::move(definition)), factory_(factory), options_(options),
      records_(std::make_unique<Records>()) {}

Build::~Build() = default;

Result<std::unique_ptr<Build>> Build::open(scene::Scene& scene, Definition definition, const ComponentFactory& factory,
                                           BuildOptions options) {
  if (!scene.graph().registry().find(kMetaRootType))
    return error(ErrorCode::kUnsupported, "build: the scene's registry has no rig types (use rig::default_registry())");
  if (definition.name.empty() || !graph::Graph::is_valid_name(definition.name)) {
    const Diagnostic where{definition.source, definition.where,
                           definition.name.empty() ? "the rig has no name"
                                                   : "rig name '" + definition.name + "' is not usable in node names"};
    return error(ErrorCode::kInvalidArgument, "build: " + where.str());
  }
  std::unique_ptr<Build> b(new Build(scene, std::move(definition), factory, options));
  if (Status s = b->replan(); !s) return s;
  // Continue a build the scene already holds.
  if (Status s = b->sync(); !s) return s;
  return b;
}

Result<std::unique_ptr<Build>> Build::reopen(scene::Scene& scene, std::string_view rig_name,
                                             const ComponentFactory& factory, BuildOptions options) {
  const graph::Graph& g = scene.graph();
  NodeId root = find_rig(g, rig_name);
  if (!root.is_valid()) return error(ErrorCode::kNotFound, "the scene has no rig '" + std::string(rig_name) + "'");
  const std::string text = meta_string(g, root, "definition");
  const std::string source = g.node(root)->name() + ".definition";
  if (text.empty()) return error(ErrorCode::kParseError, source + ": empty");
  ParseResult parsed = parse_definition(text, Syntax::kJson, source, factory.schemas());
  if (!parsed.ok()) return error(ErrorCode::kParseError, parsed.errors.front().str());
  parsed.definition.source = meta_string(g, root, "definitionPath");
  return open(scene, std::move(parsed.definition), factory, options);
}

Status Build::sync() {
  graph::Graph& g = scene_.graph();
  position_ = 0;
  NodeId root = this->root();
  if (!root.is_valid()) {
    records_->done.clear();
    records_->text.clear();
    records_->text.clear();
    return Status::ok();
  }
  std::set<std::string> seen;
  auto load = [&](NodeId meta, const std::string& key) -> Status {
    const std::string& text = meta_string(g, meta, "buildRecord");
    seen.insert(key);
    auto known = records_->text.find(key);
    if (known != records_->text.end() && known->second == text) return Status::ok();
    records_->forget(key);
    if (text.empty()) return Status::ok();
    Json j = Json::parse(text, nullptr, false);
    if (j.is_discarded() || !j.is_array())
      return error(ErrorCode::kParseError, g.node(meta)->name() + ".buildRecord: not a build record");
    for (const Json& step : j) {
      Result<StepRecord> r = error(ErrorCode::kParseError, "bad step record");
      try {
        r = record_from_json(g, step);
      } catch (const Json::exception& e) {
        r = error(ErrorCode::kParseError, std::string("build record: ") + e.what());
      }
      if (!r) return r.status().with_context(g.node(meta)->name());
      records_->done[{key, r->step}] = std::move(*r);
    }
    records_->text[key] = text;
    return Status::ok();
  };
  if (Status s = load(root, ""); !s) return s;
  for (NodeId c : rig_components(g, root)) {
    const std::string id = meta_string(g, c, "rigId");
    if (!definition_.find_by_rig_id(id))
      return error(ErrorCode::kInvalidArgument,
                   "build: the scene's rig '" + definition_.name + "' has a component '" +
                       meta_string(g, c, "componentName") + "' (rigId " + id +
                       ") that this definition does not: it was built from another definition (use update)");
    if (Status s = load(c, id); !s) return s;
  }
  // Owners whose meta node is gone (undo, another Build) leave nothing.
  for (auto it = records_->done.begin(); it != records_->done.end();)
    it = seen.count(it->first.first) ? std::next(it) : records_->done.erase(it);
  for (auto it = records_->text.begin(); it != records_->text.end();)
    it = seen.count(it->first) ? std::next(it) : records_->text.erase(it);
  const auto& pos = g.node(root)->value(g.node(root)->type().attr_find("buildPosition"));
  position_ = static_cast<int>(
      std::clamp<std::int64_t>(std::get<std::int64_t>(pos), 0, static_cast<std::int64_t>(plan_.size())));
  const graph::AttrIndex edit = g.node(root)->type().attr_find("editMode");
  if (edit != graph::kNoAttr) options_.edit_mode = std::get<bool>(g.node(root)->value(edit));
  return Status::ok();
}

Status Build::replan() {
  const Definition& d = definition_;
  components_.clear();
  std::vector<int> parent;
  std::function<void(const Component&, int)> walk = [&](const Component& c, int p) {
    const int me = static_cast<int>(components_.size());
    components_.push_back(&c);
    parent.push_back(p);
    for (const Component& child : c.children) walk(child, me);
  };
  for (const Component& root : d.components) walk(root, -1);
  const int n = static_cast<int>(components_.size());

  // Classes, unique ids and names.
  std::set<std::string> ids, names;
  for (const Component* c : components_) {
    const std::string who = "component '" + full_name_of(*c) + "'";
    if (!factory_.find(c->type))
      return error(ErrorCode::kNotFound, "build: " + who + ": no component class for type '" + c->type + "'");
    if (c->rig_id.empty() || !ids.insert(c->rig_id).second)
      return error(ErrorCode::kInvalidArgument, "build: " + who + ": missing or duplicate rigId");
    if (!names.insert(full_name_of(*c)).second)
      return error(ErrorCode::kInvalidArgument, "build: two components are named '" + full_name_of(*c) + "'");
  }
  // Attach targets: "HOOK" of the parent, or "OTHER.HOOK" of another component.
  std::vector<AttachTarget> attach(n);
  auto find_component_index = [&](std::string_view key) {
    for (int i = 0; i < n; ++i)
      if (components_[i]->rig_id == key || full_name_of(*components_[i]) == key || components_[i]->name == key) return i;
    return -1;
  };
  for (int i = 0; i < n; ++i) {
    const Component& c = *components_[i];
    attach[i] = AttachTarget{parent[i], c.attach};
    if (const std::size_t dot = c.attach.find('.'); dot != std::string::npos) {
      const int other = find_component_index(std::string_view(c.attach).substr(0, dot));
      if (other >= 0) attach[i] = AttachTarget{other, c.attach.substr(dot + 1)};
    }
    if (attach[i].component == i)
      return error(ErrorCode::kCycle, "build: component '" + full_name_of(c) + "' attaches to itself");
    if (attach[i].component >= 0) {
      const Component& target = *components_[attach[i].component];
      const ComponentSchema* ts = factory_.schemas().find(target.type);
      if (!ts || !resolve_hook(ts->hook_names(target), attach[i].hook))
        return error(ErrorCode::kNotFound, "build: component '" + full_name_of(c) + "' attaches to hook '" +
                                               attach[i].hook + "', which '" + full_name_of(target) + "' does not have");
    }
  }
  // Order: parents and attach targets first, file order otherwise (Kahn).
  std::vector<int> order;
  std::vector<int> state(n, 0);
  std::vector<std::vector<int>> deps(n);
  for (int i = 0; i < n; ++i) {
    if (parent[i] >= 0) deps[i].push_back(parent[i]);
    if (attach[i].component >= 0 && attach[i].component != parent[i]) deps[i].push_back(attach[i].component);
  }
  std::vector<char> placed(n, 0);
  while (static_cast<int>(order.size()) < n) {
    bool progress = false;
    for (int i = 0; i < n; ++i) {
      if (placed[i]) continue;
      if (std::all_of(deps[i].begin(), deps[i].end(), [&](int d) { return placed[d] != 0; })) {
        placed[i] = 1;
        order.push_back(i);
        progress = true;
      }
    }
    if (!progress) {
      std::string names_in_cycle;
      for (int i = 0; i < n; ++i)
        if (!placed[i]) names_in_cycle += (names_in_cycle.empty() ? "" : ", ") + full_name_of(*components_[i]);
      return error(ErrorCode::kCycle, "build: components attach to each other in a cycle: " + names_in_cycle);
    }
  }
  std::vector<const Component*> ordered;
  std::vector<int> new_index(n);
  for (int k = 0; k < n; ++k) {
    new_index[order[k]] = k;
    ordered.push_back(components_[order[k]]);
  }
  records_->parent.assign(n, -1);
  records_->attach.assign(n, AttachTarget{});
  for (int i = 0; i < n; ++i) {
    records_->parent[new_index[i]] = parent[i] >= 0 ? new_index[parent[i]] : -1;
    records_->attach[new_index[i]] =
        AttachTarget{attach[i].component >= 0 ? new_index[attach[i].component] : -1, attach[i].hook};
  }
  components_ = std::move(ordered);

  // Steps.
  steps_.clear();
  plan_.clear();
  plan_.push_back(PlannedStep{-1, kRigStep, "", "", true});
  for (int i = 0; i < n; ++i) {
    const Component& c = *components_[i];
    steps_.push_back(factory_.find(c.type)->steps(c));
    std::set<std::string> step_names{kMetaStep};
    plan_.push_back(PlannedStep{i, kMetaStep, "", "", true});
    for (const Step& s : steps_.back()) {
      if (!step_names.insert(s.name).second)
        return error(ErrorCode::kInvalidArgument, "build: component type '" + c.type + "' has two steps named '" + s.name + "'");
      plan_.push_back(PlannedStep{i, s.name, s.feature, s.switch_name, step_enabled(definition_, &c, s.feature, s.switch_name)});
    }
  }
  return Status::ok();
}

NodeId Build::root() const { return find_rig(scene_.graph(), definition_.name); }

namespace {

std::string key_of(const Build& b, int component) {
  return component < 0 ? std::string() : b.components()[component]->rig_id;
}

// The meta node that keeps the records of a component (or the rig).
NodeId owner_meta(const graph::Graph& g, NodeId root, const std::string& key) {
  if (!root.is_valid()) return {};
  return key.empty() ? root : find_component(g, root, key);
}

}  // namespace

Status Build::save_state(const std::string& owner) {
  graph::Graph& g = scene_.graph();
  NodeId root = this->root();
  if (!root.is_valid()) return Status::ok();
  Json list = Json::array();
  for (const PlannedStep& p : plan_) {
    if (key_of(*this, p.component) != owner) continue;
    auto it = records_->done.find({owner, p.step});
    if (it != records_->done.end()) list.push_back(record_json(g, it->second));
  }
  NodeId meta = owner_meta(g, root, owner);
  if (owner.empty()) {
    // The definition as built: update, the Rig Manager and edit mode start from it.
    const graph::AttrIndex d = g.node(root)->type().attr_find("definition");
    if (Status s = g.set_value(Plug{root, d, -1}, Value(write_definition(definition_, Syntax::kJson))); !s) return s;
  }
  if (meta.is_valid()) {
    const graph::AttrIndex a = g.node(meta)->type().attr_find("buildRecord");
    std::string text = list.empty() ? std::string() : list.dump();
    if (Status s = g.set_value(Plug{meta, a, -1}, Value(text)); !s) return s;
    records_->text[owner] = std::move(text);
  }
  const graph::AttrIndex pos = g.node(root)->type().attr_find("buildPosition");
  return g.set_value(Plug{root, pos, -1}, Value(static_cast<std::int64_t>(position_)));
}

Status Build::construct(int index) {
  const PlannedStep& p = plan_[index];
  if (!p.enabled) return Status::ok();
  graph::Graph& g = scene_.graph();
  const std::string key = key_of(*this, p.component);
  const Component* comp = p.component >= 0 ? components_[p.component] : nullptr;

  // The manager is shared by every rig: made outside any record, removed by
  // remove() when no rig is left.
  if (!meta_manager(g).is_valid()) {
    if (Result<NodeId> m = g.create_node(kMetaManagerType, "metaManager"); !m) return m.status();
  }

  BuildContext ctx(scene_, definition_);
  ctx.edit_mode_ = options_.edit_mode;
  ctx.step_ = p.step;
  ctx.root_ = root();
  if (comp) {
    ctx.component_ = comp;
    ctx.schema_ = factory_.schemas().find(comp->type);
    ctx.meta_ = find_component(g, ctx.root_, comp->rig_id);
    const AttachTarget& at = records_->attach[p.component];
    if (at.component >= 0) {
      NodeId target_meta = find_component(g, ctx.root_, components_[at.component]->rig_id);
      const ComponentSchema* ts = factory_.schemas().find(components_[at.component]->type);
      const std::optional<int> hook = resolve_hook(ts->hook_names(*components_[at.component]), at.hook);
      for (NodeId m : meta_members(g, target_meta)) {
        const std::string* h = g.node(m)->tag_find(kTagHook);
        if (h && hook && *h == std::to_string(*hook)) ctx.attach_ = m;
      }
      if (!ctx.attach_.is_valid())
        return error(ErrorCode::kNotFound, "build " + full_name_of(*comp) + ": '" +
                                               full_name_of(*components_[at.component]) + "' published no hook '" +
                                               at.hook + "'");
    }
  }

  StepRecord record;
  record.step = p.step;
  Status status;
  {
    Recorder recorder(g, record);
    if (p.component < 0) {
      // The rig's own step: its metaRoot and groups.
      Result<NodeId> r = g.create_node(kMetaRootType, definition_.name + "_meta");
      if (!r) return r.status();
      auto set = [&](NodeId node, const char* attr, Value v) {
        return g.set_value(Plug{node, g.node(node)->type().attr_find(attr), -1}, std::move(v));
      };
      status = set(*r, "rigName", Value(definition_.name));
      if (status) status = set(*r, "version", Value(definition_.version));
      if (status) status = set(*r, "definitionPath", Value(definition_.source));
      if (status && options_.edit_mode) status = set(*r, "editMode", Value(true));
      if (status) {
        NodeId mgr = meta_manager(g);
        status = g.connect(Plug{mgr, g.node(mgr)->type().attr_find("metaRoots"), -1},
                           Plug{*r, g.node(*r)->type().attr_find(graph::kMetaParentAttr), -1});
      }
      ctx.root_ = *r;
      ctx.meta_ = *r;
      if (status) {
        Result<NodeId> top = ctx.create(scene::kTransformType, "top", -1, -1, NodeId{});
        Result<NodeId> controls = top ? ctx.create(scene::kTransformType, "controls", -1, -1, *top) : top;
        Result<NodeId> still = top ? ctx.create(scene::kTransformType, "noTransform", -1, -1, *top) : top;
        if (!top) status = top.status();
        else if (!controls) status = controls.status();
        else if (!still) status = still.status();
      }
    } else if (p.step == kMetaStep) {
      Result<NodeId> m = g.create_node(kMetaComponentType, definition_.name + "_" + full_name_of(*comp) + "_meta");
      if (!m) return m.status();
      auto set = [&](const char* attr, Value v) {
        return g.set_value(Plug{*m, g.node(*m)->type().attr_find(attr), -1}, std::move(v));
      };
      status = set("metaType", Value(comp->type));
      if (status) status = set("componentName", Value(full_name_of(*comp)));
      if (status) status = set("side", Value(std::string(side_name(comp->side))));
      if (status) status = set("version", Value(comp->version));
      if (status) status = set("rigId", Value(comp->rig_id));
      if (status) {
        const int parent = records_->parent[p.component];
        NodeId up = parent >= 0 ? find_component(g, ctx.root_, components_[parent]->rig_id) : ctx.root_;
        status = g.connect(Plug{up, g.node(up)->type().attr_find("metaChildren"), -1},
                           Plug{*m, g.node(*m)->type().attr_find(graph::kMetaParentAttr), -1});
      }
    } else {
      const std::vector<Step>& steps = steps_[p.component];
      auto it = std::find_if(steps.begin(), steps.end(), [&](const Step& s) { return s.name == p.step; });
      status = it->construct ? it->construct(ctx) : Status::ok();
    }
    if (status && !recorder.failure().empty()) status = error(ErrorCode::kInvalidArgument, recorder.failure());
  }
  if (!status) return status.with_context("build " + (comp ? full_name_of(*comp) + "/" : std::string()) + p.step);
  records_->done[{key, p.step}] = std::move(record);
  records_->text.erase(key);  // save_state() writes and remembers the new text
  return Status::ok();
}

Status Build::destruct(int index) {
  const PlannedStep& p = plan_[index];
  const std::string key = key_of(*this, p.component);
  auto it = records_->done.find({key, p.step});
  if (it == records_->done.end()) return Status::ok();  // passed over
  if (Status s = undo_record(scene_.graph(), it->second); !s) return s;
  records_->done.erase(it);
  records_->text.erase(key);
  return Status::ok();
}

Status Build::forward() {
  if (Status s = sync(); !s) return s;
  if (position_ >= static_cast<int>(plan_.size())) return error(ErrorCode::kInvalidArgument, "build: already at the end");
  graph::Graph& g = scene_.graph();
  g.begin_transaction("build " + definition_.name + ": " + plan_[position_].step);
  Status s = construct(position_);
  if (s) {
    ++position_;
    s = save_state(key_of(*this, plan_[position_ - 1].component));
    if (!s) --position_;
  }
  if (!s) {
    g.rollback_transaction();
    records_->done.erase({key_of(*this, plan_[position_].component), plan_[position_].step});
    records_->text.erase(key_of(*this, plan_[position_].component));
    return s;
  }
  g.commit_transaction();
  return Status::ok();
}

Status Build::back() {
  if (Status s = sync(); !s) return s;
  if (position_ <= 0) return error(ErrorCode::kInvalidArgument, "build: already at the start");
  graph::Graph& g = scene_.graph();
  g.begin_transaction("unbuild " + definition_.name + ": " + plan_[position_ - 1].step);
  Status s = destruct(position_ - 1);
  if (s) {
    --position_;
    s = save_state(key_of(*this, plan_[position_].component));
    if (s && position_ == 0 && list_rigs(g).empty()) {
      if (NodeId m = meta_manager(g); m.is_valid()) s = g.delete_node(m);
    }
  }
  if (!s) {
    g.rollback_transaction();
    return s;
  }
  g.commit_transaction();
  return Status::ok();
}

Status Build::go_to(int position) {
  if (position < 0 || position > static_cast<int>(plan_.size()))
    return error(ErrorCode::kInvalidArgument, "build: no step " + std::to_string(position) + " (the plan has " +
                                                  std::to_string(plan_.size()) + ")");
  while (position_ < position)
    if (Status s = forward(); !s) return s;
  while (position_ > position)
    if (Status s = back(); !s) return s;
  return Status::ok();
}

Status Build::remove() { return go_to(0); }

Status Build::set_edit_mode(bool on) {
  if (on == options_.edit_mode) return Status::ok();
  graph::Transaction tx(scene_.graph(), on ? "enter rig edit mode" : "leave rig edit mode");
  const int target = position_;
  Status s = go_to(0);
  if (s) {
    // With the metaRoot gone, the mode is ours to choose; the rig's own step
    // writes it on the new metaRoot.
    options_.edit_mode = on;
    s = go_to(target);
  }
  if (!s) {
    tx.rollback();
    options_.edit_mode = !on;
    (void)sync();
  }
  return s;
}

Status Build::set_feature(std::string_view feature, bool enabled, std::string_view switch_name) {
  Definition next = definition_;
  Feature* f = nullptr;
  for (Feature& x : next.features)
    if (x.name == feature) f = &x;
  if (!f) {
    next.features.push_back(Feature{std::string(feature), true, {}, {}});
    f = &next.features.back();
  }
  if (switch_name.empty()) {
    f->enabled = enabled;
  } else {
    FeatureSwitch* s = nullptr;
    for (FeatureSwitch& x : f->switches)
      if (x.name == switch_name) s = &x;
    if (!s) {
      f->switches.push_back(FeatureSwitch{std::string(switch_name), true, {}});
      s = &f->switches.back();
    }
    s->enabled = enabled;
  }
  // Rebuild from the first step whose state changes.
  std::vector<bool> before;
  for (const PlannedStep& p : plan_) before.push_back(p.enabled);
  int first = static_cast<int>(plan_.size());
  for (std::size_t i = 0; i < plan_.size(); ++i) {
    const Component* c = plan_[i].component >= 0 ? components_[plan_[i].component] : nullptr;
    if (step_enabled(next, c, plan_[i].feature, plan_[i].switch_name) != before[i]) {
      first = static_cast<int>(i);
      break;
    }
  }
  const int target = position_;
  if (first < position_)
    if (Status s = go_to(first); !s) return s;
  definition_ = std::move(next);
  if (Status s = replan(); !s) return s;
  if (Status s = go_to(target); !s) return s;
  if (!root().is_valid()) return Status::ok();
  graph::Transaction tx(scene_.graph(), "feature " + std::string(feature));
  return save_state("");
}

namespace {

bool is_control(const graph::Graph& g, NodeId id) {
  const graph::Node* n = g.node(id);
  return n && n->type().name() == scene::kControlType;
}

// Puts a free channel of `control` at its rest value (inside a transaction).
Status zero_channels(graph::Graph& g, NodeId control) {
  auto free = [&](graph::AttrIndex a) { return !g.source(Plug{control, a, -1}).has_value(); };
  Status s;
  if (free(xform::kTranslate)) s = g.set_value(Plug{control, xform::kTranslate, -1}, Value(math::Vec3(math::Vec3::Zero())));
  if (s && free(xform::kRotate)) s = g.set_value(Plug{control, xform::kRotate, -1}, Value(math::Vec3(math::Vec3::Zero())));
  if (s && free(xform::kRotateQuaternion))
    s = g.set_value(Plug{control, xform::kRotateQuaternion, -1}, Value(math::Quat(math::Quat::Identity())));
  if (s && free(xform::kScale)) s = g.set_value(Plug{control, xform::kScale, -1}, Value(math::Vec3(math::Vec3::Ones())));
  if (s && free(xform::kShear)) s = g.set_value(Plug{control, xform::kShear, -1}, Value(math::Vec3(math::Vec3::Zero())));
  return s;
}

// The rest pose a rebuild builds on, whatever the scene's time: every
// member of the components kept (and of the rig itself) loses its time
// curves (animation), each such attribute taking its default, and every
// control's free channels are zeroed. What
// was there comes back afterwards, bit for bit (restore()).
class RestPose {
 public:
  Status enter(graph::Graph& g, const std::vector<NodeId>& nodes) {
    for (NodeId m : nodes) {
      const graph::Node* n = g.node(m);
      if (!n) continue;
      std::vector<graph::Connection> inputs;
      for (const graph::Connection& c : n->inputs()) {
        // Time curves only: every other input is the build's own wiring (from
        // the rig or the character's joints).
        if (ops::anim::curve_kind(g, c.src.node) == ops::anim::CurveKind::kOther) continue;
        inputs.push_back(c);
      }
      for (const graph::Connection& c : inputs) {
        remember(g, m, c.dst.attr);
        held_.push_back(c);
        if (Status s = g.disconnect(c.src, c.dst); !s) return s;
      }
      for (const graph::Connection& c : inputs) {
        const graph::AttrSpec& spec = n->type().attr(c.dst.attr);
        Value rest = n->type().default_value(c.dst.attr);
        if (std::holds_alternative<std::monostate>(rest)) rest = graph::zero_value(spec.type);
        if (c.dst.element >= 0) {
          const graph::AttrType scalar{spec.type.value, false};
          if (Status s = g.set_value(Plug{m, c.dst.attr, c.dst.element}, graph::zero_value(scalar)); !s) return s;
        } else if (Status s = g.set_value(Plug{m, c.dst.attr, -1}, rest); !s) {
          return s;
        }
      }
      if (is_control(g, m)) {
        for (graph::AttrIndex a : {graph::AttrIndex{xform::kTranslate}, graph::AttrIndex{xform::kRotate},
                                   graph::AttrIndex{xform::kRotateQuaternion}, graph::AttrIndex{xform::kScale},
                                   graph::AttrIndex{xform::kShear}})
          remember(g, m, a);
        if (Status s = zero_channels(g, m); !s) return s;
      }
    }
    return Status::ok();
  }

  // Puts back what enter() changed on nodes that still exist.
  Status restore(graph::Graph& g) {
    for (const auto& [plug, value] : values_) {
      if (!g.node(plug.node) || g.source(plug)) continue;
      if (Status s = g.set_value(plug, value); !s) return s;
    }
    for (const graph::Connection& c : held_) {
      if (!g.node(c.src.node) || !g.node(c.dst.node) || g.source(c.dst)) continue;
      if (Status s = g.connect(c.src, c.dst); !s) return s;
    }
    return Status::ok();
  }

 private:
  void remember(const graph::Graph& g, NodeId node, graph::AttrIndex attr) {
    const Plug p{node, attr, -1};
    for (const auto& v : values_)
      if (v.first == p) return;
    values_.emplace_back(p, g.node(node)->value(attr));
  }

  std::vector<std::pair<Plug, Value>> values_;
  std::vector<graph::Connection> held_;
};

// An input of a rebuilt control from outside the rig (an animation curve,
// say), remembered by (rigId, role, index, attribute) to re-attach it to the
// new control, never by name.
struct Kept {
  std::string rig_id, role, index, attr;
  std::int32_t element = -1;   // an array element (fingerCurl[k])
  std::int8_t component = -1;  // x, y, z of a double3 (a curve per component)
  Plug src;
};

// A keyed control of a rebuilt component and where it was in the world at
// each of its key times (--keep-keys world).
struct KeyedControl {
  std::string rig_id, role, index;
  std::vector<double> times;
  std::vector<Mat4> worlds;
};

// The control of component `rig_id` with `role` and `index`, or invalid.
NodeId member_with(const graph::Graph& g, NodeId root, const std::string& rig_id, const std::string& role,
                   const std::string& index) {
  const NodeId meta = find_component(g, root, rig_id);
  if (!meta.is_valid()) return {};
  for (NodeId m : meta_members(g, meta)) {
    const graph::Node& n = *g.node(m);
    const std::string* r = n.tag_find(kTagRole);
    const std::string* i = n.tag_find(kTagIndex);
    if (r && *r == role && (i ? *i : std::string()) == index) return m;
  }
  return {};
}

std::string frame_label(const graph::Graph& g, double t) {
  std::ostringstream out;
  out << "frame " << t * g.fps();
  return out.str();
}

// The controls that `kept` holds time curves for, with the world matrix of
// each at each of its key times (the scene's time is restored).
std::vector<KeyedControl> keyed_controls(scene::Scene& scene, NodeId root, const std::vector<Kept>& kept) {
  graph::Graph& g = scene.graph();
  std::vector<KeyedControl> out;
  for (const Kept& k : kept) {
    if (ops::anim::curve_kind(g, k.src.node) == ops::anim::CurveKind::kOther) continue;
    auto it = std::find_if(out.begin(), out.end(), [&](const KeyedControl& c) {
      return c.rig_id == k.rig_id && c.role == k.role && c.index == k.index;
    });
    if (it == out.end()) it = out.insert(out.end(), KeyedControl{k.rig_id, k.role, k.index, {}, {}});
    for (double t : ops::anim::curve_key_times(g, k.src.node)) it->times.push_back(t);
  }
  std::vector<NodeId> nodes;
  std::vector<double> all;
  for (KeyedControl& c : out) {
    std::sort(c.times.begin(), c.times.end());
    std::vector<double> unique;
    for (double t : c.times)
      if (unique.empty() || t - unique.back() > ops::anim::kKeyTimeTolerance) unique.push_back(t);
    c.times = std::move(unique);
    c.worlds.resize(c.times.size());
    nodes.push_back(member_with(g, root, c.rig_id, c.role, c.index));
    all.insert(all.end(), c.times.begin(), c.times.end());
  }
  // One pass over time, every control at once.
  std::sort(all.begin(), all.end());
  all.erase(std::unique(all.begin(), all.end()), all.end());
  const double now = g.time();
  for (double t : all) {
    g.set_time(t);
    for (std::size_t i = 0; i < out.size(); ++i) {
      auto at = std::find(out[i].times.begin(), out[i].times.end(), t);
      if (at != out[i].times.end() && scene.is_transform(nodes[i]))
        out[i].worlds[static_cast<std::size_t>(at - out[i].times.begin())] = scene.world_matrix(nodes[i]);
    }
  }
  g.set_time(now);
  return out;
}

bool same_value(const Value& a, const Value& b) {
  if (const auto* q = std::get_if<math::Quat>(&a)) return std::abs(std::abs(q->dot(std::get<math::Quat>(b))) - 1.0) < 1e-14;
  return (std::get<math::Vec3>(a) - std::get<math::Vec3>(b)).cwiseAbs().maxCoeff() < 1e-10;
}

// A control whose world matrix is this close to where it was is in place.
constexpr double kInPlace = 1e-9;

// Writes keys on the new controls so each `keyed` control is where it was
// at each of its key times (Build::KeepKeys::kWorld); parents first, so a
// child reads its parent's converted pose.
Status restore_world_keys(scene::Scene& scene, NodeId root, const std::vector<KeyedControl>& keyed) {
  graph::Graph& g = scene.graph();
  struct Item {
    const KeyedControl* control;
    NodeId node;
    int depth;
  };
  std::vector<Item> items;
  for (const KeyedControl& c : keyed) {
    const NodeId node = member_with(g, root, c.rig_id, c.role, c.index);
    if (scene.is_transform(node) && !c.times.empty()) items.push_back(Item{&c, node, scene.depth(node)});
  }
  std::stable_sort(items.begin(), items.end(), [](const Item& a, const Item& b) { return a.depth < b.depth; });
  const double now = g.time();
  Status s;
  for (const Item& item : items) {
    const KeyedControl& c = *item.control;
    const std::string name = g.node(item.node)->name();
    // Where the kept keys already put the control where it was (its rest
    // did not change), they stay as they are, bit for bit.
    bool in_place = true;
    for (std::size_t i = 0; i < c.times.size() && in_place; ++i) {
      g.set_time(c.times[i]);
      in_place = (scene.world_matrix(item.node) - c.worlds[i]).cwiseAbs().maxCoeff() <= kInPlace;
    }
    if (in_place) continue;
    std::vector<scene::Scene::LocalChannels> need;
    for (std::size_t i = 0; i < c.times.size() && s; ++i) {
      g.set_time(c.times[i]);
      Result<scene::Scene::LocalChannels> ch = scene.channels_for_world(item.node, c.worlds[i]);
      if (!ch) s = ch.status().with_context("keep world positions of '" + name + "' at " + frame_label(g, c.times[i]));
      else need.push_back(std::move(*ch));
    }
    if (!s) break;
    // Euler keys continuous: each angle within 180 degrees of the one before.
    if (need[0].rotation_attr == xform::kRotate) {
      for (std::size_t i = 1; i < need.size(); ++i) {
        auto& r = std::get<math::Vec3>(need[i].rotation);
        const auto& p = std::get<math::Vec3>(need[i - 1].rotation);
        for (int k = 0; k < 3; ++k) r[k] += 360.0 * std::round((p[k] - r[k]) / 360.0);
      }
    }
    const graph::Node& n = *g.node(item.node);
    for (graph::AttrIndex attr : {graph::AttrIndex{xform::kTranslate}, need[0].rotation_attr,
                                  graph::AttrIndex{xform::kScale}, graph::AttrIndex{xform::kShear}}) {
      std::vector<Value> values;
      for (const auto& ch : need) {
        if (attr == xform::kTranslate) values.push_back(ch.translate);
        else if (attr == xform::kScale) values.push_back(ch.scale);
        else if (attr == xform::kShear) values.push_back(ch.shear);
        else values.push_back(ch.rotation);
      }
      bool keyed_attr = false;
      for (const graph::Connection& conn : n.inputs()) keyed_attr = keyed_attr || conn.dst.attr == attr;
      // A channel that already holds what is needed at every time is left alone.
      bool holds = true;
      for (std::size_t i = 0; i < values.size() && holds; ++i) {
        g.set_time(c.times[i]);
        holds = same_value(g.evaluate(item.node, attr), values[i]);
      }
      if (holds) continue;
      bool constant = true;
      for (const Value& v : values) constant = constant && same_value(v, values[0]);
      if (!keyed_attr && constant) {
        // A free channel that keeps one value stays free.
        if (!same_value(n.value(attr), values[0])) s = g.set_value(Plug{item.node, attr, -1}, values[0]);
      } else {
        // All of a channel's keys in one pass (linear in the keys: a long
        // shot's update does not copy the key arrays once per key).
        std::vector<math::Vec3> vectors;
        std::vector<math::Quat> quats;
        for (const Value& v : values) {
          if (const auto* q = std::get_if<math::Quat>(&v)) quats.push_back(*q);
          else vectors.push_back(std::get<math::Vec3>(v));
        }
        s = quats.empty() ? ops::anim::write_channel_keys(g, item.node, attr, c.times, vectors, true)
                          : ops::anim::write_channel_keys(g, item.node, attr, c.times, quats, true);
      }
      if (!s) break;
    }
    if (!s) break;
    for (std::size_t i = 0; i < c.times.size() && s; ++i) {
      g.set_time(c.times[i]);
      const Mat4 world = scene.world_matrix(item.node);
      const double miss = (world - c.worlds[i]).cwiseAbs().maxCoeff();
      if (!(miss <= 1e-6)) {
        std::ostringstream out;
        out << "keep world positions: '" << name << "' misses its place at " << frame_label(g, c.times[i]) << " by "
            << miss;
        s = error(ErrorCode::kInvalidArgument, out.str());
      }
    }
    if (!s) break;
  }
  g.set_time(now);
  return s;
}

}  // namespace

Result<std::vector<std::string>> Build::rebuild_changed(Definition next, Rebuild when, KeepKeys keep) {
  if (Status s = sync(); !s) return s;
  if (position_ != static_cast<int>(plan_.size()))
    return error(ErrorCode::kInvalidArgument, "rebuild: the build is not complete (step " + std::to_string(position_) +
                                                  " of " + std::to_string(plan_.size()) + ")");
  if (next.name != definition_.name)
    return error(ErrorCode::kInvalidArgument, "rebuild: the rig is '" + definition_.name + "', not '" + next.name + "'");
  struct Old {
    std::string signature, version, parent;
  };
  std::map<std::string, Old> old;
  for (std::size_t i = 0; i < components_.size(); ++i) {
    const int p = records_->parent[i];
    old[components_[i]->rig_id] = Old{signature(*components_[i]), components_[i]->version,
                                      p >= 0 ? components_[p]->rig_id : ""};
  }
  const Definition old_def = definition_;
  std::vector<std::string> old_ids;
  for (const Component* c : components_) old_ids.push_back(c->rig_id);
  const std::vector<PlannedStep> old_plan = plan_;

  definition_ = std::move(next);
  if (Status s = replan(); !s) {
    definition_ = old_def;
    (void)replan();
    return s;
  }
  std::set<std::string> dirty;
  for (std::size_t i = 0; i < components_.size(); ++i) {
    const Component& c = *components_[i];
    const int p = records_->parent[i];
    const std::string parent_id = p >= 0 ? components_[p]->rig_id : "";
    auto it = old.find(c.rig_id);
    const bool changed = it == old.end() || it->second.parent != parent_id ||
                         (when == Rebuild::kAll) ||
                         (when == Rebuild::kChanged && it->second.signature != signature(c)) ||
                         (when == Rebuild::kNewerVersion && compare_versions(it->second.version, c.version) != 0);
    if (changed) dirty.insert(c.rig_id);
  }
  // What hangs from a dirty component is dirty too (its hooks are made again).
  for (bool grew = true; grew;) {
    grew = false;
    for (std::size_t i = 0; i < components_.size(); ++i) {
      if (dirty.count(components_[i]->rig_id)) continue;
      const int p = records_->parent[i];
      const int a = records_->attach[i].component;
      if ((p >= 0 && dirty.count(components_[p]->rig_id)) || (a >= 0 && dirty.count(components_[a]->rig_id))) {
        dirty.insert(components_[i]->rig_id);
        grew = true;
      }
    }
  }
  std::set<std::string> removed;
  for (const std::string& id : old_ids) {
    bool present = false;
    for (const Component* c : components_) present = present || c->rig_id == id;
    if (!present) removed.insert(id);
  }
  graph::Graph& g = scene_.graph();
  NodeId root = this->root();

  // Animation on the controls of what is rebuilt: curves and other inputs
  // from outside the rig, remembered by (rigId, role, index, attribute) so
  // they re-attach to the new controls, never by name.
  std::vector<Kept> kept;
  for (const std::string& id : old_ids) {
    if (!dirty.count(id) && !removed.count(id)) continue;
    NodeId meta = find_component(g, root, id);
    for (NodeId m : meta_members(g, meta)) {
      const graph::Node& n = *g.node(m);
      const std::string* role = n.tag_find(kTagRole);
      if (!role) continue;
      const std::string* index = n.tag_find(kTagIndex);
      for (const graph::Connection& c : n.inputs()) {
        if (n.type().attr(c.dst.attr).name == graph::kMetaParentAttr || c.dst.attr == xform::kParentMatrix) continue;
        if (rig_of(g, c.src.node) == root) continue;  // the rig's own wiring is rebuilt
        kept.push_back(Kept{id, *role, index ? *index : "", n.type().attr(c.dst.attr).name, c.dst.element, c.dst.component,
                              c.src});
      }
    }
  }

  // --keep-keys world: where each keyed control is at each of its key times.
  std::vector<KeyedControl> keyed;
  if (keep == KeepKeys::kWorld) keyed = keyed_controls(scene_, root, kept);

  g.begin_transaction("update " + definition_.name);
  Status s;
  std::set<std::string> owners;
  for (const Kept& k : kept) {
    // The source keeps going; only its link to the old control goes.
    std::optional<graph::Connection> link;
    for (const graph::Connection& c : g.node(k.src.node)->outputs()) {
      const graph::Node& d = *g.node(c.dst.node);
      if (c.src.attr == k.src.attr && c.src.element == k.src.element && d.type().attr(c.dst.attr).name == k.attr &&
          c.dst.element == k.element && c.dst.component == k.component &&
          rig_of(g, c.dst.node) == root && component_of(g, c.dst.node) == find_component(g, root, k.rig_id)) {
        link = c;  // a copy: disconnecting changes the list
        break;
      }
    }
    if (link) s = g.disconnect(link->src, link->dst);
    if (!s) break;
  }
  // Build on the rest pose, not on the pose at the scene's time.
  RestPose rest;
  if (s) {
    std::vector<NodeId> still = meta_members(g, root);
    for (const std::string& id : old_ids) {
      if (dirty.count(id) || removed.count(id)) continue;
      for (NodeId m : meta_members(g, find_component(g, root, id))) still.push_back(m);
    }
    s = rest.enter(g, still);
  }
  // Destruct, newest first, the old steps of dirty and removed components.
  for (int i = static_cast<int>(old_plan.size()) - 1; i >= 0 && s; --i) {
    if (old_plan[i].component < 0) continue;
    const std::string& id = old_ids[old_plan[i].component];
    if (!dirty.count(id) && !removed.count(id)) continue;
    auto it = records_->done.find({id, old_plan[i].step});
    if (it == records_->done.end()) continue;
    s = undo_record(g, it->second);
    records_->done.erase(it);
    records_->text.erase(id);
  }
  // Construct theirs in the new plan's order.
  for (std::size_t i = 0; i < plan_.size() && s; ++i) {
    if (plan_[i].component < 0) continue;
    const std::string& id = components_[plan_[i].component]->rig_id;
    if (!dirty.count(id)) continue;
    s = construct(static_cast<int>(i));
    owners.insert(id);
  }
  position_ = static_cast<int>(plan_.size());
  // Re-attach what was kept, where the new rig has the same control.
  for (const Kept& k : kept) {
    if (!s) break;
    NodeId meta = find_component(g, root, k.rig_id);
    if (!meta.is_valid()) continue;  // the component is gone
    for (NodeId m : meta_members(g, meta)) {
      const graph::Node& n = *g.node(m);
      const std::string* role = n.tag_find(kTagRole);
      const std::string* index = n.tag_find(kTagIndex);
      if (!role || *role != k.role || (index ? *index : std::string()) != k.index) continue;
      const graph::AttrIndex a = n.type().attr_find(k.attr);
      const Plug dst{m, a, k.element, k.component};
      if (a == graph::kNoAttr || g.source(dst)) break;
      s = g.connect(k.src, dst);
      break;
    }
  }
  if (s) s = rest.restore(g);
  if (s && !keyed.empty()) s = restore_world_keys(scene_, root, keyed);
  if (s) s = g.set_value(Plug{root, g.node(root)->type().attr_find("version"), -1}, Value(definition_.version));
  for (const Component* c : components_) {
    if (!s || dirty.count(c->rig_id)) continue;
    NodeId meta = find_component(g, root, c->rig_id);
    if (meta_string(g, meta, "version") != c->version)
      s = g.set_value(Plug{meta, g.node(meta)->type().attr_find("version"), -1}, Value(c->version));
  }
  for (const std::string& owner : owners)
    if (s) s = save_state(owner);
  if (s) s = save_state("");
  if (!s) {
    g.rollback_transaction();
    definition_ = old_def;
    (void)replan();
    records_->done.clear();
    return s.with_context("update " + definition_.name);
  }
  g.commit_transaction();
  std::vector<std::string> out;
  for (const Component* c : components_)
    if (dirty.count(c->rig_id)) out.push_back(c->rig_id);
  for (const std::string& id : removed) out.push_back(id);
  return out;
}

// ---- rig edit mode --------------------------------------------------------

std::string next_version(std::string_view version) {
  std::size_t end = version.size();
  std::size_t begin = end;
  while (begin > 0 && version[begin - 1] >= '0' && version[begin - 1] <= '9') --begin;
  if (begin == end) return std::string(version) + (version.empty() ? "1" : ".1");
  std::string digits(version.substr(begin));
  // Add one to the decimal digits (any length).
  int carry = 1;
  for (std::size_t i = digits.size(); i-- > 0 && carry;) {
    const int d = digits[i] - '0' + carry;
    digits[i] = static_cast<char>('0' + d % 10);
    carry = d / 10;
  }
  if (carry) digits.insert(digits.begin(), '1');
  return std::string(version.substr(0, begin)) + digits;
}

namespace {

// A guide that stands at `world`: values, or the offset from its joint at
// `joint_world` (rotation in XYZ degrees; shear is dropped).
void place_guide(Guide& guide, const Mat4& world, const std::optional<Mat4>& joint_world) {
  const Mat4 m = joint_world ? Mat4(math::affine_inverse(*joint_world) * world) : world;
  const math::TransformParts parts = math::decompose_to_parts(m, math::RotateOrder::kXYZ);
  // Rounded to 1e-10 (of a metre, a degree): a turn of 90 degrees is written
  // 90, not 90.00000000000001, and clean files diff cleanly.
  auto clean = [](math::Vec3 v) {
    for (int k = 0; k < 3; ++k) v[k] = std::round(v[k] * 1e10) / 1e10 + 0.0;  // + 0.0: no -0
    return v;
  };
  guide.translate = clean(parts.translate);
  guide.rotate = clean(math::to_degrees(parts.rotate));
  guide.scale = clean(parts.scale);
}

}  // namespace

// A control stands at its guide when its rest is the guide's place within this.
constexpr double kAtGuide = 1e-7;

Result<Edits> Build::edits() {
  if (Status s = sync(); !s) return s;
  const NodeId root = this->root();
  if (!root.is_valid() || position_ != static_cast<int>(plan_.size()))
    return error(ErrorCode::kInvalidArgument, "edit " + definition_.name + ": the rig is not fully built");
  if (!options_.edit_mode)
    return error(ErrorCode::kInvalidArgument, "edit " + definition_.name +
                                                  ": the rig is not in edit mode (build it in edit mode: rigel build --edit-mode)");
  graph::Graph& g = scene_.graph();
  struct Made {
    std::size_t component;
    int guide;
    NodeId node;
    Mat4 now, rest;
  };
  std::vector<Made> controls;
  std::vector<NodeId> all;
  for (std::size_t i = 0; i < components_.size(); ++i) {
    const ComponentClass* cls = factory_.find(components_[i]->type);
    if (cls && !cls->editable()) continue;
    const NodeId meta = find_component(g, root, components_[i]->rig_id);
    for (NodeId m : meta_members(g, meta)) {
      if (!is_control(g, m)) continue;
      const std::string* tag = g.node(m)->tag_find(kTagGuide);
      int guide = -1;
      if (tag) std::from_chars(tag->data(), tag->data() + tag->size(), guide);
      controls.push_back(Made{i, guide, m, scene_.world_matrix(m), Mat4::Identity()});
      all.push_back(m);
    }
  }
  // Rest poses: every control zeroed, then rolled back. The joints' rest too.
  std::map<std::pair<std::size_t, int>, Mat4> joint_rest;
  g.begin_transaction("edit: rest pose");
  Status s;
  for (NodeId m : all)
    if (s) s = zero_channels(g, m);
  if (s) {
    for (Made& c : controls) c.rest = scene_.world_matrix(c.node);
    for (std::size_t i = 0; i < components_.size(); ++i)
      for (std::size_t k = 0; k < components_[i]->guides.size(); ++k) {
        const std::string& joint = components_[i]->guides[k].joint;
        const NodeId j = joint.empty() ? NodeId{} : g.find(joint);
        if (scene_.is_transform(j)) joint_rest[{i, static_cast<int>(k)}] = scene_.world_matrix(j);
      }
  }
  g.rollback_transaction();
  if (!s) return s.with_context("edit " + definition_.name);

  Edits out;
  out.definition = definition_;
  // Components by rigId in the copy (components_ points into definition_).
  std::map<std::pair<std::size_t, int>, const Made*> mover;
  for (const Made& c : controls) {
    if (math::is_near(c.now, c.rest, 1e-9)) continue;
    bool at_guide = c.guide >= 0 && c.guide < static_cast<int>(components_[c.component]->guides.size());
    if (at_guide) {
      // Only a control that stands at its guide stands for it.
      const Guide& guide = components_[c.component]->guides[static_cast<std::size_t>(c.guide)];
      auto jr = joint_rest.find({c.component, c.guide});
      if (!guide.joint.empty() && jr == joint_rest.end()) {
        at_guide = false;
      } else {
        const Mat4 place = guide.joint.empty() ? guide_values(guide) : Mat4(jr->second * guide_values(guide));
        at_guide = math::is_near(c.rest, place, kAtGuide);
      }
    }
    if (!at_guide) {
      out.ignored.push_back(g.node(c.node)->name());
      continue;
    }
    auto [it, fresh] = mover.emplace(std::make_pair(c.component, c.guide), &c);
    if (fresh) continue;
    // Two moved controls of one guide must agree on the move.
    const Mat4 a = c.now * math::affine_inverse(c.rest);
    const Mat4 b = it->second->now * math::affine_inverse(it->second->rest);
    if (!math::is_near(a, b, 1e-9))
      return error(ErrorCode::kInvalidArgument, "edit " + definition_.name + ": '" + g.node(it->second->node)->name() +
                                                    "' and '" + g.node(c.node)->name() + "' both stand for guide " +
                                                    std::to_string(c.guide) + " of " + full_name_of(*components_[c.component]) +
                                                    " and were moved differently; move one of them");
  }
  std::set<std::size_t> changed;
  for (const auto& [key, c] : mover) {
    const Component& before = *components_[key.first];
    Component* after = out.definition.find_by_rig_id(before.rig_id);
    if (!after) continue;
    Guide& guide = after->guides[static_cast<std::size_t>(key.second)];
    auto jr = joint_rest.find(key);
    const std::optional<Mat4> joint = jr == joint_rest.end() ? std::nullopt : std::optional<Mat4>(jr->second);
    const Mat4 was = joint ? Mat4(*joint * guide_values(guide)) : guide_values(guide);
    place_guide(guide, c->now * math::affine_inverse(c->rest) * was, joint);
    changed.insert(key.first);
  }
  for (std::size_t i : changed) {
    Component* after = out.definition.find_by_rig_id(components_[i]->rig_id);
    after->version = next_version(after->version);
    out.changed.push_back(after->rig_id);
  }
  if (!changed.empty()) out.definition.version = next_version(out.definition.version);
  return out;
}

Result<Edits> Build::commit_edits(const std::string& definition_path, bool leave_edit_mode) {
  Result<Edits> e = edits();
  if (!e) return e;
  graph::Graph& g = scene_.graph();
  const Definition before = definition_;
  graph::Transaction tx(g, "commit rig edits " + definition_.name);
  Status s;
  if (!e->changed.empty()) {
    Result<std::vector<std::string>> rebuilt = rebuild_changed(e->definition, Rebuild::kChanged);
    if (!rebuilt) s = rebuilt.status();
    if (s && !definition_path.empty()) {
      definition_.source = definition_path;
      const NodeId root = this->root();
      s = g.set_value(Plug{root, g.node(root)->type().attr_find("definitionPath"), -1}, Value(definition_path));
    }
  }
  if (s && leave_edit_mode) s = set_edit_mode(false);
  if (!s) {
    tx.rollback();
    definition_ = before;
    (void)replan();
    (void)sync();
    return s;
  }
  return e;
}

// ---- BuildContext --------------------------------------------------------

std::string BuildContext::full_name() const { return component_ ? full_name_of(*component_) : std::string(); }

namespace {
const Param* find_param(const Component& c, std::string_view name) { return c.param(name); }
}  // namespace

bool BuildContext::param_bool(std::string_view name) const {
  const Param* p = find_param(*component_, name);
  if (p && std::holds_alternative<bool>(p->value)) return std::get<bool>(p->value);
  const ParamSpec* s = schema_->param(name);
  return s && std::holds_alternative<bool>(s->default_value) ? std::get<bool>(s->default_value) : false;
}

std::int64_t BuildContext::param_int(std::string_view name) const {
  const Param* p = find_param(*component_, name);
  if (p && std::holds_alternative<std::int64_t>(p->value)) return std::get<std::int64_t>(p->value);
  const ParamSpec* s = schema_->param(name);
  return s && std::holds_alternative<std::int64_t>(s->default_value) ? std::get<std::int64_t>(s->default_value) : 0;
}

double BuildContext::param_double(std::string_view name) const {
  const Param* p = find_param(*component_, name);
  if (p && std::holds_alternative<double>(p->value)) return std::get<double>(p->value);
  if (p && std::holds_alternative<std::int64_t>(p->value)) return static_cast<double>(std::get<std::int64_t>(p->value));
  const ParamSpec* s = schema_->param(name);
  return s && std::holds_alternative<double>(s->default_value) ? std::get<double>(s->default_value) : 0.0;
}

std::string BuildContext::param_string(std::string_view name) const {
  const Param* p = find_param(*component_, name);
  if (p && std::holds_alternative<std::string>(p->value)) return std::get<std::string>(p->value);
  const ParamSpec* s = schema_->param(name);
  return s && std::holds_alternative<std::string>(s->default_value) ? std::get<std::string>(s->default_value)
                                                                     : std::string();
}

ControlStyle BuildContext::control_style(std::string_view role) const {
  ControlStyle out;
  out.role = std::string(role);
  if (const ControlSpec* s = schema_ ? schema_->control(role) : nullptr) {
    out.shape = s->shape;
    out.color = s->color;
    out.size = s->size;
  } else {
    out.shape = "circle";
    out.color = "yellow";
  }
  if (const ControlStyle* c = component_ ? component_->control(role) : nullptr) {
    if (!c->shape.empty()) out.shape = c->shape;
    if (!c->color.empty()) out.color = c->color;
    out.size = c->size;
  }
  return out;
}

Result<NodeId> BuildContext::guide_joint(int i) {
  if (i < 0 || i >= guide_count())
    return error(ErrorCode::kNotFound, full_name() + ": no guide " + std::to_string(i));
  const Guide& guide = component_->guides[i];
  if (guide.joint.empty())
    return error(ErrorCode::kNotFound, full_name() + ": guide " + std::to_string(i) + " names no joint");
  NodeId id = graph().find(guide.joint);
  if (!id.is_valid())
    return error(ErrorCode::kNotFound, full_name() + ": guide " + std::to_string(i) + ": the scene has no node '" +
                                           guide.joint + "'");
  return id;
}

Result<Mat4> BuildContext::guide_world(int i) {
  if (i < 0 || i >= guide_count()) return error(ErrorCode::kNotFound, full_name() + ": no guide " + std::to_string(i));
  const Guide& guide = component_->guides[i];
  if (!guide.joint.empty()) {
    Result<NodeId> j = guide_joint(i);
    if (!j) return j.status();
    if (!scene_.is_transform(*j))
      return error(ErrorCode::kInvalidArgument, full_name() + ": guide " + std::to_string(i) + ": '" + guide.joint +
                                                    "' is not a transform");
    return Mat4(scene_.world_matrix(*j) * guide_values(guide));  // the values: an offset in the joint's space
  }
  return guide_values(guide);
}

Result<NodeId> BuildContext::create(std::string_view type, std::string_view role, int index, int guide, NodeId parent) {
  std::string name = rig_name();
  if (component_) name += "_" + full_name();
  name += "_" + std::string(role);
  if (index >= 0) name += std::to_string(index);
  Result<NodeId> id = parent.is_valid() ? scene_.create(type, name, parent) : graph().create_node(type, name);
  if (!id) return id.status();
  Status s = link(*id, role, index, guide);
  if (!s) return s;
  return id;
}

Status BuildContext::link(NodeId id, std::string_view role, int index, int guide) {
  graph::Graph& g = graph();
  if (!g.node(id)) return error(ErrorCode::kNotFound, full_name() + ": link " + std::string(role) + ": no such node");
  Status s = g.set_tag(id, kTagRole, std::string(role));
  if (s && index >= 0) s = g.set_tag(id, kTagIndex, std::to_string(index));
  if (s) s = g.set_tag(id, kTagStep, step_);
  if (s && guide >= 0) s = g.set_tag(id, kTagGuide, std::to_string(guide));
  if (s && meta_.is_valid())
    s = g.connect(Plug{meta_, g.node(meta_)->type().attr_find("members"), -1},
                  Plug{id, g.node(id)->type().attr_find(graph::kMetaParentAttr), -1});
  return s;
}

namespace {
Status place_zeroed(scene::Scene& scene, NodeId id, const Mat4& world, NodeId parent) {
  const Mat4 parent_world = parent.is_valid() ? scene.world_matrix(parent) : Mat4(Mat4::Identity());
  const Mat4 offset = math::affine_inverse(parent_world) * world;
  return scene.graph().set_value(Plug{id, xform::kOffsetParentMatrix, -1}, Value(offset));
}
}  // namespace

Result<NodeId> BuildContext::create_group(std::string_view role, int index, const Mat4& world, NodeId parent) {
  Result<NodeId> id = create(scene::kTransformType, role, index, -1, parent);
  if (!id) return id;
  if (Status s = place_zeroed(scene_, *id, world, parent); !s) return s;
  return id;
}

Result<NodeId> BuildContext::create_control(std::string_view role, int index, int guide, const Mat4& world,
                                            NodeId parent) {
  Result<NodeId> id = create(scene::kControlType, role, index, guide, parent);
  if (!id) return id;
  if (Status s = place_zeroed(scene_, *id, world, parent); !s) return s;
  const ControlStyle style = control_style(role);
  if (Status s = scene::apply_control_shape(graph(), *id, style.shape, style.size, style.color); !s)
    return s.with_context(full_name() + " control '" + std::string(role) + "'");
  return id;
}

Status BuildContext::drive(NodeId driver, NodeId driven) {
  ConstraintSpec spec;
  spec.role = "drive";
  spec.space_role = "parentSpace";
  spec.targets = {driver};
  spec.channels = {"translate", "rotate", "scale"};
  return constrain(spec, driven, static_cast<int>(nodes("drive").size())).status();
}

Result<NodeId> BuildContext::constrain(const ConstraintSpec& spec, NodeId driven, int index) {
  graph::Graph& g = graph();
  const graph::Node* d = g.node(driven);
  const std::string where = full_name() + ": " + spec.role;
  if (!d || !scene_.is_transform(driven))
    return error(ErrorCode::kInvalidArgument, where + ": the driven is not a transform");
  if (spec.targets.empty()) return error(ErrorCode::kInvalidArgument, where + ": no target");
  auto plug = [&](NodeId n, const char* attr, int element = -1) {
    return Plug{n, g.node(n)->type().attr_find(attr), element};
  };
  const std::string name = d->name();
  Result<NodeId> c = create(spec.type, spec.role, index);
  if (!c) return c.status();
  const Mat4 driven_world = scene_.world_matrix(driven);
  std::vector<Mat4> offsets;
  Status s;
  for (std::size_t i = 0; s && i < spec.targets.size(); ++i) {
    s = g.connect(Plug{spec.targets[i], xform::kWorldMatrix, -1}, plug(*c, "targetWorldMatrix", static_cast<int>(i)));
    offsets.push_back(spec.maintain_offset
                          ? ops::constraints::compute_offset(scene_.world_matrix(spec.targets[i]), driven_world)
                          : Mat4(Mat4::Identity()));
  }
  if (s && spec.maintain_offset) s = g.set_value(plug(*c, "targetOffset"), Value(offsets));
  if (s && !spec.weights.empty()) s = g.set_value(plug(*c, "targetWeight"), Value(spec.weights));
  if (s && spec.space != ConstraintSpec::Space::kIdentity) {
    const NodeId space = spec.space == ConstraintSpec::Space::kParent ? g.parent(driven) : spec.space_node;
    Result<NodeId> inv =
        create(ops::util::kInverseMatrixType, spec.space_role.empty() ? spec.role + "Space" : spec.space_role, index);
    if (!inv) return inv.status();
    if (space.is_valid()) s = g.connect(Plug{space, xform::kWorldMatrix, -1}, plug(*inv, "inputMatrix"));
    if (s) s = g.set_value(plug(*inv, "offsetMatrix"), d->value(xform::kOffsetParentMatrix));
    if (s) s = g.connect(plug(*inv, "outputMatrix"), plug(*c, "parentInverseMatrix"));
  }
  // Euler channels in the driven's order, past its joint orient; rest values
  // are what the driven holds now.
  if (s) s = g.set_value(plug(*c, "rotateOrder"), d->value(xform::kRotateOrder));
  if (s && d->type().name() == scene::kJointType)
    s = g.set_value(plug(*c, "jointOrient"), d->value(scene::joint_attr::kJointOrient));
  if (s) s = g.set_value(plug(*c, "restTranslate"), d->value(xform::kTranslate));
  if (s) s = g.set_value(plug(*c, "restRotate"), d->value(xform::kRotate));
  if (s) s = g.set_value(plug(*c, "restScale"), d->value(xform::kScale));
  if (s && xform::is_quaternion_mode(*d))
    s = g.set_value(Plug{driven, xform::kRotateMode, -1}, Value(xform::kEulerMode));
  for (const char* ch : spec.channels) {
    if (!s) break;
    const Plug dst = plug(driven, ch);
    if (g.source(dst)) s = g.disconnect_input(dst);
    if (s) s = g.connect(plug(*c, ch), dst);
  }
  if (!s) return s.with_context(where + " on " + name);
  return c;
}

std::vector<NodeId> BuildContext::nodes(std::string_view role) const {
  std::vector<std::pair<int, NodeId>> hits;
  if (!meta_.is_valid()) return {};
  const graph::Graph& g = scene_.graph();
  for (NodeId m : meta_members(g, meta_)) {
    const graph::Node& n = *g.node(m);
    const std::string* r = n.tag_find(kTagRole);
    if (!r || *r != role) continue;
    const std::string* i = n.tag_find(kTagIndex);
    int index = 0;
    if (i) std::from_chars(i->data(), i->data() + i->size(), index);
    hits.emplace_back(index, m);
  }
  std::stable_sort(hits.begin(), hits.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<NodeId> out;
  for (const auto& h : hits) out.push_back(h.second);
  return out;
}

NodeId BuildContext::node(std::string_view role, int index) const {
  std::vector<NodeId> all = nodes(role);
  return index >= 0 && index < static_cast<int>(all.size()) ? all[index] : NodeId{};
}

Status BuildContext::publish_hook(int index, NodeId node) {
  graph::Graph& g = graph();
  if (!g.node(node)) return error(ErrorCode::kNotFound, "publish_hook: no such node");
  if (meta_parent(g, node) != meta_)
    return error(ErrorCode::kInvalidArgument, "publish_hook: " + g.node(node)->name() + " was not made by " + full_name());
  return g.set_tag(node, kTagHook, std::to_string(index));
}

NodeId BuildContext::attach_node() const { return attach_.is_valid() ? attach_ : rig_group("controls"); }

NodeId BuildContext::rig_group(std::string_view role) const {
  if (!root_.is_valid()) return {};
  const graph::Graph& g = scene_.graph();
  for (NodeId m : meta_members(g, root_)) {
    const std::string* r = g.node(m)->tag_find(kTagRole);
    if (r && *r == role) return m;
  }
  return {};
}

// ---- ComponentFactory ----------------------------------------------------

Status ComponentFactory::add(std::shared_ptr<const ComponentClass> component_class) {
  const std::string type(component_class->type());
  if (!schemas_->find(type)) return error(ErrorCode::kNotFound, "component class '" + type + "' has no schema");
  if (find(type)) return error(ErrorCode::kAlreadyExists, "component type '" + type + "' already has a class");
  classes_.push_back(std::move(component_class));
  return Status::ok();
}

const ComponentClass* ComponentFactory::find(std::string_view type) const {
  for (const auto& c : classes_)
    if (c->type() == type) return c.get();
  return nullptr;
}

Result<const ComponentClass*> ComponentFactory::class_of(const graph::Graph& graph, NodeId meta) const {
  const graph::Node* n = graph.node(meta);
  if (!n || n->type().name() != kMetaComponentType)
    return error(ErrorCode::kNotFound, "class_of: not a metaComponent node");
  const std::string type = meta_string(graph, meta, "metaType");
  const ComponentClass* c = find(type);
  if (!c) return error(ErrorCode::kUnsupported, n->name() + ": no component class for metaType '" + type + "'");
  return c;
}

std::vector<std::string> ComponentFactory::types() const {
  std::vector<std::string> out;
  for (const auto& c : classes_) out.emplace_back(c->type());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace rigel::rig
