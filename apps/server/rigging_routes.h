#pragma once
// The JSON API's rigger-action routes (rigging_routes.cc; seed 004's shape,
// transform and joint actions, app::Workspace's rigger actions): each reads
// its request's fields, calls the app layer and answers with JSON.

#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "rigel/app/workspace.h"

namespace rigel::server::routes {

using Json = nlohmann::ordered_json;

// GET /api/shape?control=C: the control's look {"control", "name",
// "points", "closed", "color"} (what the page copies).
Json shape(const app::Workspace& ws, const std::map<std::string, std::string>& query);
// GET /api/poses/thumbnail?library=L&name=N: the SVG text.
std::string pose_thumbnail(const app::Workspace& ws, const std::map<std::string, std::string>& query);
// POST /api/shape {"op": "paste"|"mirror"|"flip"|"opposite", "controls"?
// (the selection by default), "shape"? (paste: {"points", "closed",
// "color"}), "parts"? (paste: ["shape", "color"] by default)}.
Json shape_edit(app::Workspace& ws, const Json& body);
// POST /api/align {"nodes"? (the selection), "target", "position"?,
// "rotation"? (both true by default)}: the nodes matched to the target.
Json align(app::Workspace& ws, const Json& body);
// POST /api/locators {"nodes"? (the selection), "size"?}.
Json locators(app::Workspace& ws, const Json& body);
// POST /api/mirror-joints {"joints"? (the selection), "update"?}.
Json mirror_joints(app::Workspace& ws, const Json& body);
// The data managers: POST /api/data/export {"kind":
// "weights"|"shapes"|"blendshapes"|"driven_poses"|"correctives", "file",
// "rig"? (shapes)} and POST /api/data/import {"kind", "file", "rig"?,
// "rename"? {old: new}, "nearest"?, "mirror"? (weights)}, files inside the root.
Json data_export(app::Workspace& ws, const Json& body);
Json data_import(app::Workspace& ws, const Json& body);
// Set-driven keys: GET /api/driven-keys {"drivenPoses": {"drivers":
// [{"driver", "curves": [{"node", "driven", "at": [...], "values":
// [...]}]}]}, "correctives": {...}}; POST /api/driven-keys {"op": "set",
// "driver", "at"?, "driven": {channel: value or null}, "tangent"?} or
// {"op": "remove", "driven": [channel, ...]}, or {"op": "reader", "joint",
// "axis"?} (a pose reader: {"reader", "angle", "rotate"} plugs).
Json driven_keys(app::Workspace& ws);
Json driven_key_edit(app::Workspace& ws, const Json& body);

}  // namespace rigel::server::routes
