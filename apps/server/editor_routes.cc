// The JSON API's rig editor routes (editor_routes.h).

#include "editor_routes.h"

#include <string>
#include <utility>
#include <vector>

#include "api_fields.h"
#include "rigel/app/graphs.h"
#include "rigel/rig/build_graph.h"
#include "rigel/rig/definition_io.h"
#include "rigel/rig/manager.h"

namespace rigel::server::routes {

using namespace api;
namespace fs = std::filesystem;

namespace {

Json graph_problems_json(const std::vector<app::GraphProblem>& problems) {
  Json list = Json::array();
  for (const app::GraphProblem& p : problems) {
    Json j{{"where", p.diagnostic.str()}, {"message", p.diagnostic.message}};
    if (!p.place.node.empty()) j["node"] = p.place.node;
    if (!p.place.socket.empty()) j["socket"] = p.place.socket;
    list.push_back(std::move(j));
  }
  return list;
}

Json rig_ids_json(const std::vector<std::pair<std::string, std::string>>& ids) {
  Json out = Json::object();
  for (const auto& [node, rig_id] : ids) out[rig_id] = node;
  return out;
}

Json graph_json(const rig::BuildGraph& graph) { return Json::parse(rig::write_build_graph(graph)); }

// The request's definition (the .rig.json object), parsed and checked.
app::CheckedDefinition request_definition(const app::Workspace& ws, const Json& body) {
  const Json& def = need(body, "definition");
  if (!def.is_object()) refuse(400, "definition: expected the .rig.json object", "definition");
  return ws.check_definition(def.dump(2), rig::Syntax::kJson, "definition");
}

// The request's graph (the .build.json object), read and compiled.
app::CheckedGraph request_graph(const app::Workspace& ws, const Json& body) {
  const Json& graph = need(body, "graph");
  if (!graph.is_object()) refuse(400, "graph: expected the .build.json object", "graph");
  return ws.check_graph(graph.dump(2), "graph");
}

}  // namespace

// ---- definitions ---------------------------------------------------------------

Json definition_open(app::Workspace& ws, const std::map<std::string, std::string>& query) {
  auto it = query.find("rig");
  if (it == query.end()) refuse(400, "missing query 'rig'", "rig");
  const rig::Definition def = take(ws.definition(it->second));
  return Json{{"rig", it->second},
              {"path", def.source},
              {"definition", Json::parse(rig::write_definition(def, rig::Syntax::kJson))}};
}

Json components(const app::Workspace& ws) {
  Json list = Json::array();
  for (const std::string& t : ws.component_types())
    list.push_back(rig::component_schema_json(*ws.factory().schemas().find(t)));
  return Json{{"components", std::move(list)}};
}

Json definition_validate(const app::Workspace& ws, const Json& body) {
  const app::CheckedDefinition c = request_definition(ws, body);
  return Json{{"ok", c.problems.empty()}, {"problems", problems_json(c.problems)}};
}

Json definition_build(app::Workspace& ws, const Json& body) {
  app::CheckedDefinition c = request_definition(ws, body);
  if (!c.problems.empty()) refuse(400, "definition: " + c.problems.front().str(), "definition");
  const app::BuildReport r = take(ws.build_definition(std::move(c.definition)));
  return Json{{"rig", r.rig}, {"rebuilt", names_json(r.rebuilt)}};
}

Json definition_save(app::Workspace& ws, const Json& body) {
  const fs::path path = take(ws.resolve_path(as_string(need(body, "path"), "path"), "path"));
  if (!rig::syntax_of(path))
    refuse(400, "path: '" + as_string(need(body, "path"), "path") + "' is neither .rig.xml nor .rig.json", "path");
  app::CheckedDefinition c = request_definition(ws, body);
  if (!c.problems.empty()) refuse(400, "definition: " + c.problems.front().str(), "definition");
  const app::SavedDefinition saved = take(ws.save_definition(std::move(c.definition), path));
  return Json{{"path", saved.path.string()}, {"version", saved.version}};
}

// ---- build graphs ---------------------------------------------------------------

Json graph_palette(const app::Workspace& ws) {
  return rig::graph_palette_json(ws.graph_kinds(), ws.factory().schemas());
}

Json graph_files(const app::Workspace& ws) {
  Json files = Json::array();
  for (const auto& f : take(ws.graph_files())) files.push_back(f.generic_string());
  return Json{{"files", std::move(files)}};
}

Json graph_open(app::Workspace& ws, const std::map<std::string, std::string>& query) {
  const auto path = query.find("path");
  const auto rig = query.find("rig");
  if ((path == query.end()) == (rig == query.end())) refuse(400, "name one of the queries 'path' or 'rig'", "path");
  if (path != query.end()) {
    const rig::BuildGraph g = take(ws.open_graph(take(ws.resolve_path(path->second, "path"))));
    return Json{{"path", path->second}, {"graph", graph_json(g)}};
  }
  const app::RigGraph g = take(ws.rig_graph(rig->second));
  std::string shown = g.path.string();
  if (!g.path.empty() && !ws.root().empty()) {
    const fs::path rel = g.path.lexically_relative(ws.root());
    if (!rel.empty() && *rel.begin() != "..") shown = rel.generic_string();
  }
  return Json{{"path", shown}, {"graph", graph_json(g.graph)}, {"converted", g.converted}};
}

Json graph_validate(const app::Workspace& ws, const Json& body) {
  const app::CheckedGraph c = request_graph(ws, body);
  return Json{{"ok", c.ok()},
              {"problems", graph_problems_json(c.problems)},
              {"warnings", graph_problems_json(c.warnings)},
              {"order", names_json(c.order)},
              {"rigIds", rig_ids_json(c.rig_ids)}};
}

Json graph_build(app::Workspace& ws, const Json& body) {
  app::CheckedGraph c = request_graph(ws, body);
  if (!c.parsed) refuse(400, "graph: " + c.problems.front().diagnostic.str(), "graph");
  const app::GraphBuildReport r = take(ws.build_graph(std::move(c.graph)));
  return Json{{"rig", r.rig}, {"rebuilt", names_json(r.rebuilt)}, {"rigIds", rig_ids_json(r.rig_ids)}};
}

Json graph_save(app::Workspace& ws, const Json& body) {
  const std::string asked = as_string(need(body, "path"), "path");
  const fs::path path = take(ws.resolve_path(asked, "path"));
  app::CheckedGraph c = request_graph(ws, body);
  if (!c.parsed) refuse(400, "graph: " + c.problems.front().diagnostic.str(), "graph");
  const app::SavedGraph saved = take(ws.save_graph(std::move(c.graph), path));
  return Json{{"path", asked},
              {"version", saved.version},
              {"problems", graph_problems_json(saved.problems)}};
}

}  // namespace rigel::server::routes
