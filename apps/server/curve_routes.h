#pragma once
// The JSON API's graph editor routes (curve_routes.cc; docs/SERVER.md):
// GET /api/curves and POST /api/curve-keys. Bad input is refused with
// api::ApiError (api_fields.h), as workspace.cc's routes do.

#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rigel/app/workspace.h"

namespace rigel::server::routes {

using Json = nlohmann::ordered_json;

// The curves of `controls` (already resolved: the selection when the
// request named none); `query`: the request's first, last, step (frames)
// and euler (0/1, default 1).
Json curves(app::Workspace& ws, const std::vector<graph::NodeId>& controls,
            const std::map<std::string, std::string>& query);
// {"op": "edit"|"insert"|"delete", "keys": [{"curve": PLUG, "frame": F,
// "toFrame"?, "value"?, "component"?, "inTangent"?, "outTangent"?,
// "tangent"?, "inSlope"?, "outSlope"?}, ...]}: one undo step.
Json curve_keys(app::Workspace& ws, const Json& body);

}  // namespace rigel::server::routes
