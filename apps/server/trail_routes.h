#pragma once
// The JSON API's motion trails and ghosts (trail_routes.cc; docs/SERVER.md):
// GET /api/trails and GET /api/ghosts, computed on the server from the
// evaluated graph. Bad input is refused with api::ApiError (api_fields.h).

#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rigel/app/workspace.h"

namespace rigel::server::routes {

using Json = nlohmann::ordered_json;

// The trails of `controls` (already resolved: the selection when the
// request named none); `query`: first, last (frames, required), step.
Json trails(app::Workspace& ws, const std::vector<graph::NodeId>& controls,
            const std::map<std::string, std::string>& query);
// `query`: frames=A,B,C; or before=N&after=N&step=S; or keys=1.
Json ghosts(app::Workspace& ws, const std::map<std::string, std::string>& query);

}  // namespace rigel::server::routes
