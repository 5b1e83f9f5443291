// The JSON API's scene settings routes (settings_routes.h): each reads its
// request's fields and calls the app layer.

#include "settings_routes.h"

#include <string>
#include <vector>

#include "api_fields.h"

namespace rigel::server::routes {

using namespace api;


Json playback_range(app::Workspace& ws, const Json& body) {
  const double first = as_number(need(body, "first"), "first");
  const double last = as_number(need(body, "last"), "last");
  check(ws.set_playback_range(first, last));
  const auto range = ws.playback_range();
  return Json{{"revision", ws.revision()}, {"playbackRange", Json::array({(*range)[0], (*range)[1]})}};
}

Json selection_sets(const app::Workspace& ws) {
  Json sets = Json::array();
  for (const scene::SelectionSet& s : ws.selection_sets())
    sets.push_back(Json{{"name", s.name}, {"members", node_refs_json(ws, s.members)}, {"missing", s.missing}});
  return Json{{"revision", ws.revision()}, {"sets", sets}};
}

Json selection_set(app::Workspace& ws, const Json& body, const std::vector<graph::NodeId>& members) {
  const std::string op = as_string(need(body, "op"), "op");
  const std::string name = as_string(need(body, "name"), "name");
  if (op == "save") {
    take(ws.save_selection_set(name, members));
  } else if (op == "remove") {
    check(ws.remove_selection_set(name));
  } else if (op == "select") {
    const Json* add = opt(body, "add");
    take(ws.select_set(name, add && as_bool(*add, "add")));
  } else {
    refuse(400, "op: expected \"save\", \"remove\" or \"select\", got \"" + op + "\"", "op");
  }
  Json out = selection_sets(ws);
  Json selection = Json::array();
  for (graph::NodeId id : ws.selection()) selection.push_back(ws.graph().node(id)->uuid().str());
  out["selection"] = selection;
  return out;
}

Json picker(const app::Workspace& ws) {
  Json groups = Json::array();
  for (const app::PickerGroup& p : ws.picker()) {
    Json controls = Json::array();
    for (const app::PickerGroup::Entry& e : p.controls) {
      const graph::Node* n = ws.graph().node(e.control);
      controls.push_back(Json{{"uuid", n->uuid().str()}, {"name", n->name()}, {"label", e.label}});
    }
    groups.push_back(Json{{"rig", p.rig},
                          {"name", p.name},
                          {"part", p.part},
                          {"side", std::string(1, p.side)},
                          {"controls", controls}});
  }
  return Json{{"revision", ws.revision()}, {"groups", groups}};
}

}  // namespace rigel::server::routes
