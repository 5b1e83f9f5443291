#pragma once
// The JSON API's rig editor routes (editor_routes.cc): the web app's
// definition editor and build-graph editor over app::Workspace's
// definitions and build graphs. A definition travels as its `.rig.json`
// object, a graph as its `.build.json` object; a graph's problem names the
// node and socket it is about.

#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "rigel/app/workspace.h"

namespace rigel::server::routes {

using Json = nlohmann::ordered_json;

// GET /api/definition?rig=NAME: {"rig", "path", "definition"} (the
// .rig.json form of the rig's definition as built).
Json definition_open(app::Workspace& ws, const std::map<std::string, std::string>& query);
// GET /api/components: {"components": [component_schema_json, ...]}.
Json components(const app::Workspace& ws);
// POST /api/definition/validate {"definition"}: {"ok", "problems"}.
Json definition_validate(const app::Workspace& ws, const Json& body);
// POST /api/definition/build {"definition"}: {"rig", "rebuilt"} (builds the
// rig, or live-rebuilds what changed when the scene has it).
Json definition_build(app::Workspace& ws, const Json& body);
// POST /api/definition/save {"definition", "path"}: {"path", "version"}.
Json definition_save(app::Workspace& ws, const Json& body);

// GET /api/graph/palette: rig::graph_palette_json of the kinds a graph can
// hold now.
Json graph_palette(const app::Workspace& ws);
// GET /api/graph/files: {"files": [path relative to the root, ...]}.
Json graph_files(const app::Workspace& ws);
// GET /api/graph?path=P: {"path", "graph"}; GET /api/graph?rig=NAME:
// {"path" ("" when converted), "graph", "converted"}.
Json graph_open(app::Workspace& ws, const std::map<std::string, std::string>& query);
// POST /api/graph/validate {"graph"}: {"ok", "problems": [{"where",
// "message", "node"?, "socket"?}], "warnings", "order", "rigIds"}.
Json graph_validate(const app::Workspace& ws, const Json& body);
// POST /api/graph/build {"graph"}: {"rig", "rebuilt", "rigIds"} (one undo step).
Json graph_build(app::Workspace& ws, const Json& body);
// POST /api/graph/save {"graph", "path"}: {"path", "version", "problems"}.
Json graph_save(app::Workspace& ws, const Json& body);

}  // namespace rigel::server::routes
