// The Rig Manager's operations (manager.h).

#include "rigel/rig/manager.h"

#include <sstream>

#include "definition_io_internal.h"
#include "rigel/rig/definition_io.h"
#include "rigel/rig/meta.h"

namespace rigel::rig {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

std::string full_name(const Component& c) {
  return c.side == Side::kCenter ? c.name : c.name + "_" + side_name(c.side);
}

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
  parsed.definition.source = path.string();
  return std::move(parsed.definition);
}

Json rigs_report(const graph::Graph& g) {
  Json list = Json::array();
  for (NodeId root : list_rigs(g)) {
    const std::string path = meta_string(g, root, "definitionPath");
    const std::string version = meta_string(g, root, "version");
    // The Rig Manager's red button: the definition on disk has another version.
    Json on_disk = nullptr;
    std::error_code ec;
    if (!path.empty() && fs::exists(path, ec)) {
      ParseResult p = load_definition(path);
      if (p.ok()) on_disk = p.definition.version;
    }
    Json comps = Json::array();
    for (NodeId c : rig_components(g, root)) {
      NodeId parent = meta_parent(g, c);
      comps.push_back(Json{{"name", meta_string(g, c, "componentName")},
                           {"type", meta_string(g, c, "metaType")},
                           {"version", meta_string(g, c, "version")},
                           {"rigId", meta_string(g, c, "rigId")},
                           {"parent", parent == root ? "" : meta_string(g, parent, "componentName")},
                           {"nodes", meta_members(g, c).size()}});
    }
    list.push_back(Json{{"name", meta_string(g, root, "rigName")},
                        {"version", version},
                        {"definition", path},
                        {"definitionVersion", on_disk},
                        {"outOfDate", on_disk.is_string() && on_disk.get<std::string>() != version},
                        {"editMode", meta_int(g, root, "editMode") != 0},
                        {"buildPosition", meta_int(g, root, "buildPosition")},
                        {"components", comps}});
  }
  return list;
}

Result<AddedRig> add_rig(scene::Scene& scene, const fs::path& path, const ComponentFactory& factory,
                         BuildOptions options, const std::function<void(int, int)>& progress) {
  auto def = read_definition(path, factory.schemas());
  if (!def) return def.status();
  if (find_rig(scene.graph(), def->name).is_valid())
    return error(ErrorCode::kAlreadyExists, path.string() + ": the scene already has a rig '" + def->name + "'");
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
  for (const Component* c : (*build)->components()) added.components.push_back(full_name(*c));
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
  if (!def) return def.status();
  report.from = meta_string(g, root, "version");
  report.to = def->version;
  if (def->name != report.rig)
    return error(ErrorCode::kInvalidArgument,
                 report.definition + ": defines rig '" + def->name + "', not '" + report.rig + "'");
  if (compare_versions(report.from, report.to) == 0 && !force) return report;
  auto build = Build::reopen(scene, report.rig, factory);
  if (!build) return build.status();
  const Definition kept = *def;
  auto rebuilt = (*build)->rebuild_changed(std::move(*def), force ? Build::Rebuild::kAll : Build::Rebuild::kNewerVersion,
                                           keep);
  if (!rebuilt) return rebuilt.status();
  report.updated = true;
  for (const std::string& id : *rebuilt) {
    const Component* c = kept.find_by_rig_id(id);
    report.rebuilt.push_back(c ? full_name(*c) : id);
  }
  return report;
}

}  // namespace rigel::rig
