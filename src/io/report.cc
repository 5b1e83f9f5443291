#include "rigel/io/report.h"

#include <map>

#include "rigel/math/transform.h"

namespace rigel::io {

using Json = nlohmann::ordered_json;
using graph::NodeId;

nlohmann::ordered_json inspect_report(scene::Scene& scene) {
  graph::Graph& g = scene.graph();
  Json report;
  report["fps"] = g.fps();
  report["time"] = g.time();
  report["frame"] = scene.frame();
  report["node_count"] = g.node_count();
  std::map<std::string, int> counts;
  for (NodeId id : g.nodes()) ++counts[g.node(id)->type().name()];
  report["types"] = counts;
  Json roots = Json::array();
  for (NodeId id : scene.roots()) roots.push_back(g.node(id)->name());
  report["roots"] = std::move(roots);
  Json nodes = Json::array();
  for (NodeId id : g.nodes()) {
    const graph::Node& n = *g.node(id);
    Json jn;
    jn["name"] = n.name();
    jn["type"] = n.type().name();
    jn["uuid"] = n.uuid().str();
    if (NodeId p = g.parent(id); p.is_valid()) jn["parent"] = g.node(p)->name();
    Json kids = Json::array();
    for (NodeId c : g.children(id)) kids.push_back(g.node(c)->name());
    jn["children"] = std::move(kids);
    jn["tags"] = n.tags();
    nodes.push_back(std::move(jn));
  }
  report["nodes"] = std::move(nodes);
  Json connections = Json::array();
  for (const graph::Connection& c : g.connections()) {
    if (g.parent(c.dst.node) == c.src.node && c.dst.attr == g.node(c.dst.node)->type().parent_input()) continue;
    connections.push_back(Json{{"src", g.plug_name(c.src)}, {"dst", g.plug_name(c.dst)}});
  }
  report["connections"] = std::move(connections);
  return report;
}

nlohmann::ordered_json eval_report(scene::Scene& scene) {
  graph::Graph& g = scene.graph();
  g.evaluate_all();
  Json report;
  report["frame"] = scene.frame();
  report["time"] = g.time();
  Json nodes = Json::object();
  for (NodeId id : scene.hierarchy()) {
    math::Decomposed d = math::decompose(scene.world_matrix(id));
    const math::Quat& q = d.rotation;
    nodes[g.node(id)->name()] = Json{{"t", {d.translate.x(), d.translate.y(), d.translate.z()}},
                                     {"q", {q.x(), q.y(), q.z(), q.w()}},
                                     {"s", {d.scale.x(), d.scale.y(), d.scale.z()}}};
  }
  report["nodes"] = std::move(nodes);
  return report;
}

}  // namespace rigel::io
