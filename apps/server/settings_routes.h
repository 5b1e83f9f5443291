#pragma once
// The JSON API's scene settings routes (settings_routes.cc; docs/SERVER.md):
// the playback range and named selection sets, both saved with the scene.
// Bad input is refused with api::ApiError (api_fields.h).

#include <vector>

#include <nlohmann/json.hpp>

#include "rigel/app/workspace.h"

namespace rigel::server::routes {

using Json = nlohmann::ordered_json;

// POST /api/playback-range {"first", "last"}: one undo step.
Json playback_range(app::Workspace& ws, const Json& body);
// GET /api/selection-sets: every set with its members (uuids and names).
Json selection_sets(const app::Workspace& ws);
// POST /api/selection-sets {"op": "save"|"remove"|"select", "name",
// "add"? (select)}; `members`: a save's, already resolved (the selection
// when the request named none).
Json selection_set(app::Workspace& ws, const Json& body, const std::vector<graph::NodeId>& members);

// GET /api/picker: the picker's groups (app::Workspace::picker).
Json picker(const app::Workspace& ws);

}  // namespace rigel::server::routes
