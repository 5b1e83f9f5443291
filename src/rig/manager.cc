// The Rig Manager's operations (manager.h).

#include "rigel/rig/manager.h"

#include <functional>
#include <set>
#include <sstream>

#include "definition_io_internal.h"
#include "rigel/rig/definition_io.h"
#include "rigel/rig/meta.h"

namespace rigel::rig {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

std::int64_t meta_int(const graph::Graph& g, NodeId meta, std::string_view attr) {
  const graph::Node* n = g.node(meta);
  if (!n) return 0;
  const graph::AttrIndex a = n->type().attr_find(attr);
  if (a == graph::kNoAttr) return 0;
  const graph::Value& v = n->value(a);
  if (const auto* i = std::get_if<std::int64_t>(&v)) return *i;
  if (const auto* b = std::get_if<bool>(&v)) return *b ? 1 : 0;
  return 0;
}

}  // namespace

Json component_schema_json(const ComponentSchema& s) {
  Json j = Json::object();
  j["type"] = s.type;
  j["help"] = s.help;
  Json params = Json::array();
  for (const ParamSpec& p : s.params) {
    Json e = Json::object();
    e["name"] = p.name;
    e["type"] = param_type_name(p.type);
    e["default"] = detail::param_value_json(p.default_value);
    if (p.min) e["min"] = *p.min;
    if (p.max) e["max"] = *p.max;
    if (!p.choices.empty()) e["choices"] = p.choices;
    e["help"] = p.help;
    params.push_back(std::move(e));
  }
  j["params"] = std::move(params);
  j["guides"] = Json{{"min", s.guides.min}, {"max", s.guides.max}, {"names", s.guides.names}, {"help", s.guides.help}};
  Json controls = Json::array();
  for (const ControlSpec& c : s.controls)
    controls.push_back(Json{{"role", c.role}, {"shape", c.shape}, {"color", c.color}, {"size", c.size}, {"help", c.help}});
  j["controls"] = std::move(controls);
  j["hooks"] = s.hooks;
  j["features"] = s.features;
  j["rootOnly"] = s.root_only;
  j["needsParent"] = s.needs_parent;
  return j;
}

Result<Definition> read_definition(const fs::path& path, const SchemaRegistry& schemas) {
  std::vector<Diagnostic> problems = check_definition(path, schemas);
  ParseResult parsed;
  if (problems.empty()) {
    parsed = load_definition(path, schemas);
    problems = parsed.errors;
  }
  if (!problems.empty()) {
    std::ostringstream o;
    for (std::size_t i = 0; i < problems.size(); ++i) o << (i ? "\n" : "") << problems[i].str();
    return error(ErrorCode::kInvalidArgument, o.str());
  }
  // Absolute: the scene keeps it relative to its own file (io/scene_file.h).
  std::error_code ec;
  const fs::path absolute = fs::absolute(path, ec);
  parsed.definition.source = ec ? path.string() : absolute.lexically_normal().string();
  return std::move(parsed.definition);
}

const char* component_state_name(ComponentState::Kind kind) {
  switch (kind) {
    case ComponentState::Kind::kCurrent: return "current";
    case ComponentState::Kind::kChanged: return "changed";
    case ComponentState::Kind::kRemoved: return "removed";
    case ComponentState::Kind::kAdded: return "added";
  }
  return "current";
}

namespace {

// Compares the built rig `root` with `def` (or, without one, lists the
// built components only).
void compare(const graph::Graph& g, NodeId root, const Definition* def, RigState& out) {
  std::set<std::string> built;
  for (NodeId c : rig_components(g, root)) {
    ComponentState st;
    st.rig_id = meta_string(g, c, "rigId");
    st.name = meta_string(g, c, "componentName");
    st.type = meta_string(g, c, "metaType");
    st.version = meta_string(g, c, "version");
    built.insert(st.rig_id);
    if (def) {
      if (const Component* d = def->find_by_rig_id(st.rig_id)) {
        st.definition_version = d->version;
        if (compare_versions(st.version, d->version) != 0) st.kind = ComponentState::Kind::kChanged;
      } else {
        st.kind = ComponentState::Kind::kRemoved;
      }
    }
    out.components.push_back(std::move(st));
  }
  if (!def) return;
  std::function<void(const Component&)> walk = [&](const Component& c) {
    if (!built.count(c.rig_id)) {
      ComponentState st;
      st.rig_id = c.rig_id;
      st.name = c.full_name();
      st.type = c.type;
      st.definition_version = c.version;
      st.kind = ComponentState::Kind::kAdded;
      out.components.push_back(std::move(st));
    }
    for (const Component& child : c.children) walk(child);
  };
  for (const Component& c : def->components) walk(c);
  out.out_of_date = compare_versions(out.version, def->version) != 0;
  for (const ComponentState& c : out.components) out.out_of_date = out.out_of_date || c.out_of_date();
}

}  // namespace

Result<RigState> rig_state(const graph::Graph& g, std::string_view rig_name, const SchemaRegistry& schemas) {
  const NodeId root = find_rig(g, rig_name);
  if (!root.is_valid()) return error(ErrorCode::kNotFound, "no rig '" + std::string(rig_name) + "'");
  RigState out;
  out.rig = meta_string(g, root, "rigName");
  out.version = meta_string(g, root, "version");
  out.definition = meta_string(g, root, "definitionPath");
  if (out.definition.empty()) {
    out.problem = "no definition path";
    compare(g, root, nullptr, out);
    return out;
  }
  Result<Definition> def = read_definition(out.definition, schemas);
  if (!def) {
    const std::string& m = def.status().message();
    out.problem = m.substr(0, m.find('\n'));
    compare(g, root, nullptr, out);
    return out;
  }
  out.definition_found = true;
  out.definition_version = def->version;
  compare(g, root, &*def, out);
  return out;
}

Json rigs_report(const graph::Graph& g) {
  Json list = Json::array();
  for (NodeId root : list_rigs(g)) {
    const std::string name = meta_string(g, root, "rigName");
    Result<RigState> state = rig_state(g, name);
    if (!state) continue;
    auto version_or_null = [](const std::string& v) { return v.empty() ? Json(nullptr) : Json(v); };
    Json comps = Json::array();
    Json added = Json::array();
    for (const ComponentState& c : state->components) {
      if (c.kind == ComponentState::Kind::kAdded) {
        added.push_back(Json{{"name", c.name},
                             {"type", c.type},
                             {"definitionVersion", c.definition_version},
                             {"rigId", c.rig_id},
                             {"state", component_state_name(c.kind)},
                             {"outOfDate", true}});
        continue;
      }
      const NodeId meta = find_component(g, root, c.rig_id);
      const NodeId parent = meta_parent(g, meta);
      comps.push_back(Json{{"name", c.name},
                           {"type", c.type},
                           {"version", c.version},
                           {"rigId", c.rig_id},
                           {"parent", parent == root ? "" : meta_string(g, parent, "componentName")},
                           {"nodes", meta_members(g, meta).size()},
                           {"definitionVersion", version_or_null(c.definition_version)},
                           {"state", component_state_name(c.kind)},
                           {"outOfDate", c.out_of_date()}});
    }
    list.push_back(Json{{"name", state->rig},
                        {"version", state->version},
                        {"definition", state->definition},
                        {"definitionFound", state->definition_found},
                        {"definitionProblem", state->definition_found ? Json(nullptr) : Json(state->problem)},
                        {"definitionVersion", version_or_null(state->definition_version)},
                        {"outOfDate", state->out_of_date},
                        {"editMode", meta_int(g, root, "editMode") != 0},
                        {"buildPosition", meta_int(g, root, "buildPosition")},
                        {"components", comps},
                        {"added", added}});
  }
  return list;
}

std::vector<Diagnostic> check_guide_joints(const Definition& d, const scene::Scene& scene) {
  std::vector<Diagnostic> out;
  const graph::Graph& g = scene.graph();
  std::vector<const Component*> stack;
  for (auto it = d.components.rbegin(); it != d.components.rend(); ++it) stack.push_back(&*it);
  while (!stack.empty()) {
    const Component& c = *stack.back();
    stack.pop_back();
    for (std::size_t i = 0; i < c.guides.size(); ++i) {
      const Guide& guide = c.guides[i];
      if (guide.joint.empty()) continue;
      const NodeId id = g.find(guide.joint);
      std::string what;
      if (!id.is_valid()) what = "the character has no joint '" + guide.joint + "'";
      else if (!scene.is_transform(id)) what = "'" + guide.joint + "' is not a joint or transform";
      else continue;
      out.push_back({d.source, guide.where,
                     "component '" + c.name + "' (" + c.type + (c.side == Side::kCenter ? "" : std::string(", ") + side_name(c.side)) +
                         "): guide " + std::to_string(i) + (guide.name.empty() ? "" : " (" + guide.name + ")") + ": " + what});
    }
    for (auto it = c.children.rbegin(); it != c.children.rend(); ++it) stack.push_back(&*it);
  }
  return out;
}

Result<AddedRig> add_rig(scene::Scene& scene, const fs::path& path, const ComponentFactory& factory,
                         BuildOptions options, const std::function<void(int, int)>& progress) {
  auto def = read_definition(path, factory.schemas());
  if (!def) return def.status();
  if (find_rig(scene.graph(), def->name).is_valid())
    return error(ErrorCode::kAlreadyExists, path.string() + ": the scene already has a rig '" + def->name + "'");
  if (std::vector<Diagnostic> missing = check_guide_joints(*def, scene); !missing.empty()) {
    std::ostringstream o;
    for (std::size_t i = 0; i < missing.size(); ++i) o << (i ? "\n" : "") << missing[i].str();
    return error(ErrorCode::kNotFound, o.str());
  }
  AddedRig added{def->name, def->version, 0, {}};
  auto build = Build::open(scene, std::move(*def), factory, options);
  if (!build) return build.status().with_context(path.string());
  const int total = static_cast<int>((*build)->plan().size());
  graph::Graph& g = scene.graph();
  g.begin_transaction("add rig " + added.name);
  for (int i = (*build)->position(); i < total; ++i) {
    if (Status s = (*build)->forward(); !s) {
      g.rollback_transaction();
      return s.with_context(path.string());
    }
    if (progress) progress(i + 1, total);
  }
  g.commit_transaction();
  added.steps = total;
  for (const Component* c : (*build)->components()) added.components.push_back(c->full_name());
  return added;
}

Result<UpdateReport> update_rig(scene::Scene& scene, std::string_view rig_name, const ComponentFactory& factory,
                                const fs::path& definition_path, bool force, Build::KeepKeys keep) {
  graph::Graph& g = scene.graph();
  NodeId root = find_rig(g, rig_name);
  if (!root.is_valid()) return error(ErrorCode::kNotFound, "no rig '" + std::string(rig_name) + "'");
  UpdateReport report;
  report.rig = std::string(rig_name);
  report.definition = definition_path.empty() ? meta_string(g, root, "definitionPath") : definition_path.string();
  if (report.definition.empty())
    return error(ErrorCode::kNotFound, report.rig + ": no definition path; give one");
  auto def = read_definition(report.definition, factory.schemas());
  if (!def) return def.status().with_context("rig " + report.rig + ": definition");
  report.from = meta_string(g, root, "version");
  report.to = def->version;
  if (def->name != report.rig)
    return error(ErrorCode::kInvalidArgument,
                 report.definition + ": defines rig '" + def->name + "', not '" + report.rig + "'");
  // Up to date: the rig's version and every component's agree, and the
  // definition has the same components.
  bool same = compare_versions(report.from, report.to) == 0;
  std::set<std::string> built;
  for (NodeId c : rig_components(g, root)) {
    const std::string id = meta_string(g, c, "rigId");
    built.insert(id);
    const Component* d = def->find_by_rig_id(id);
    same = same && d && compare_versions(meta_string(g, c, "version"), d->version) == 0;
  }
  std::function<void(const Component&)> walk = [&](const Component& c) {
    same = same && built.count(c.rig_id) > 0;
    for (const Component& child : c.children) walk(child);
  };
  for (const Component& c : def->components) walk(c);
  // ... and the same data to import (Definition::data).
  if (same) {
    const ParseResult built_def = parse_definition(meta_string(g, root, "definition"), Syntax::kJson, "", factory.schemas());
    auto entries = [](const Definition& d) {
      std::vector<std::pair<std::string, std::string>> out;
      for (const DataImport& x : d.data) out.emplace_back(x.kind, x.file);
      return out;
    };
    same = built_def.ok() && entries(built_def.definition) == entries(*def);
  }
  if (same && !force) return report;
  auto build = Build::reopen(scene, report.rig, factory);
  if (!build) return build.status();
  const Definition kept = *def;
  graph::Transaction tx(g, "update " + report.rig);
  auto rebuilt = (*build)->rebuild_changed(std::move(*def), force ? Build::Rebuild::kAll : Build::Rebuild::kNewerVersion,
                                           keep);
  if (!rebuilt) {
    tx.rollback();
    return rebuilt.status();
  }
  // Updated from another file: the rig now follows that one.
  if (!definition_path.empty()) {
    const NodeId r = find_rig(g, report.rig);
    if (Status s = g.set_value(graph::Plug{r, g.node(r)->type().attr_find("definitionPath"), -1}, graph::Value(kept.source));
        !s) {
      tx.rollback();
      return s;
    }
    report.definition = kept.source;
  }
  report.updated = true;
  for (const std::string& id : *rebuilt) {
    const Component* c = kept.find_by_rig_id(id);
    report.rebuilt.push_back(c ? c->full_name() : id);
  }
  return report;
}

}  // namespace rigel::rig
