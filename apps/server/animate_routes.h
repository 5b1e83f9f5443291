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
// GET /api/spaces?control=C and POST /api/space (add or switch).
Json spaces(app::Workspace& ws, const std::string& control);
Json space(app::Workspace& ws, const Json& body);
// The pose library: POST /api/poses/save, /api/poses/apply, /api/poses/remove
// (bodies) and GET /api/poses (`query`: the request's library as
// {"library": ...}).
Json poses_save(app::Workspace& ws, const Json& body);
Json poses_apply(app::Workspace& ws, const Json& body);
Json poses_list(app::Workspace& ws, const Json& query);
Json poses_remove(app::Workspace& ws, const Json& body);

}  // namespace rigel::server::routes
