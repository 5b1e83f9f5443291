#pragma once
// The JSON API's animator-tool routes (animate_routes.cc): each takes the
// request body and answers with JSON, refusing bad input with api::ApiError
// (api_fields.h), as workspace.cc's routes do.

#include <nlohmann/json.hpp>

#include "rigel/app/workspace.h"

namespace rigel::server::routes {

using Json = nlohmann::ordered_json;

// POST /api/export, /api/match, /api/mirror, /api/bind-pose, /api/tween,
// /api/transfer, /api/channel-values.
Json export_scene(app::Workspace& ws, const Json& body);
Json match(app::Workspace& ws, const Json& body);
Json mirror(app::Workspace& ws, const Json& body);
Json bind_pose(app::Workspace& ws, const Json& body);
Json tween(app::Workspace& ws, const Json& body);
Json transfer(app::Workspace& ws, const Json& body);
Json channel_values(app::Workspace& ws, const Json& body);

}  // namespace rigel::server::routes
