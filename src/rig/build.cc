// Opening a build and keeping its state on the scene (build.h): the
// position, the definition as built and each owner's step records live on
// the rig's meta nodes, and sync() reads them back.
#include "rigel/rig/build.h"

#include <algorithm>
#include <set>
#include <string>

#include "build_internal.h"
#include "rigel/rig/component.h"
#include "rigel/rig/definition_io.h"
#include "rigel/rig/meta.h"

namespace rigel::rig {

using namespace detail;

namespace {

// The meta node that keeps the records of a component (or the rig).
NodeId owner_meta(const graph::Graph& g, NodeId root, const std::string& key) {
  if (!root.is_valid()) return {};
  return key.empty() ? root : find_component(g, root, key);
}

}  // namespace

std::string detail::key_of(const Build& b, int component) {
  return component < 0 ? std::string() : b.components()[component]->rig_id;
}

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
  // The names the rig was built with, for every later step and rebuild.
  const graph::AttrIndex naming = g.node(root)->type().attr_find("namingTemplate");
  if (naming != graph::kNoAttr) {
    const std::string& t = std::get<std::string>(g.node(root)->value(naming));
    if (!t.empty()) options_.naming_template = t;
  }
  return Status::ok();
}


NodeId Build::root() const { return find_rig(scene_.graph(), definition_.name); }

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

}  // namespace rigel::rig
