// The JSON API's motion trails and ghosts (trail_routes.h): each reads its
// query and calls the app layer.

#include "trail_routes.h"

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "api_fields.h"

namespace rigel::server::routes {

using namespace api;

Json trails(app::Workspace& ws, const std::vector<graph::NodeId>& controls,
            const std::map<std::string, std::string>& query) {
  const std::optional<double> first = query_number(query, "first");
  const std::optional<double> last = query_number(query, "last");
  if (!first) refuse(400, "missing query 'first'", "first");
  if (!last) refuse(400, "missing query 'last'", "last");
  const double step = query_number(query, "step").value_or(1.0);
  Json out = Json::array();
  for (const tools::MotionTrail& t : take(ws.motion_trails(controls, *first, *last, step))) {
    Json points = Json::array();
    for (const math::Vec3& p : t.points) points.push_back(vec_json(p));
    const graph::Node* n = ws.graph().node(t.node);
    out.push_back(Json{{"control", n->uuid().str()},
                       {"name", n->name()},
                       {"frames", t.frames},
                       {"points", points},
                       {"keys", t.key_frames}});
  }
  return Json{{"revision", ws.revision()}, {"trails", out}};
}

Json ghosts(app::Workspace& ws, const std::map<std::string, std::string>& query) {
  app::GhostOptions options;
  if (auto it = query.find("frames"); it != query.end()) {
    std::size_t from = 0, i = 0;
    while (from <= it->second.size()) {
      const std::size_t comma = std::min(it->second.find(',', from), it->second.size());
      options.frames.push_back(query_text_number(it->second.substr(from, comma - from), "frames[" + std::to_string(i++) + "]"));
      from = comma + 1;
    }
  }
  auto count = [&](const char* key) {
    const std::optional<double> v = query_number(query, key);
    if (v && (*v != std::floor(*v) || std::abs(*v) > 1000)) refuse(400, std::string(key) + ": expected a whole number", key);
    return v ? static_cast<int>(*v) : 0;
  };
  options.before = count("before");
  options.after = count("after");
  options.step = query_number(query, "step").value_or(1.0);
  options.at_keys = query_number(query, "keys").value_or(0) != 0;
  const app::Ghosts g = take(ws.ghosts(options));
  Json joints = Json::array();
  for (graph::NodeId id : g.joints) joints.push_back(ws.graph().node(id)->uuid().str());
  Json frames = Json::array();
  for (std::size_t f = 0; f < g.frames.size(); ++f) {
    Json points = Json::array();
    for (const math::Vec3& p : g.points[f]) points.push_back(vec_json(p));
    frames.push_back(Json{{"frame", g.frames[f]}, {"points", points}});
  }
  return Json{{"revision", ws.revision()}, {"joints", joints}, {"parents", g.parents}, {"frames", frames}};
}

}  // namespace rigel::server::routes
