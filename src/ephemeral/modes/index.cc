// The index of every rig's controls: their hierarchy (controls and the
// joints they drive) and their relations, as the planners walk them.
#include <unordered_map>

#include "modes.h"
#include "rigel/ephemeral/keying.h"

namespace rigel::ephemeral::modes {

int Index::find(const Graph& graph, NodeId id) const {
  auto it = by_index.find(id.index);
  if (it == by_index.end() || !graph.node(id)) return -1;
  const Ctrl& c = ctrls[it->second];
  if (c.id == id) return it->second;
  // A joint driven by this control.
  for (const graph::Connection& conn : graph.node(c.id)->outputs())
    if (conn.dst.node == id) return it->second;
  return -1;
}

Status index_build(scene::Scene& scene, Index& index) {
  Graph& graph = scene.graph();
  std::unordered_map<std::uint32_t, int> order;
  {
    std::vector<NodeId> h = scene.hierarchy();
    for (std::size_t i = 0; i < h.size(); ++i) order[h[i].index] = static_cast<int>(i);
  }
  std::vector<NodeId> rigs = rigs_find(graph);
  for (std::size_t r = 0; r < rigs.size(); ++r) {
    index.rig_members.emplace_back();
    for (NodeId c : rig_controls(graph, rigs[r])) {
      if (index.by_index.count(c.index)) continue;  // listed by an earlier rig
      Index::Ctrl ctrl;
      ctrl.id = c;
      ctrl.rig = static_cast<int>(r);
      auto it = order.find(c.index);
      ctrl.order = it == order.end() ? 0 : it->second;
      const int k = static_cast<int>(index.ctrls.size());
      index.by_index[c.index] = k;
      index.rig_members.back().push_back(k);
      index.ctrls.push_back(std::move(ctrl));
    }
  }
  for (Index::Ctrl& c : index.ctrls) {
    NodeId p = graph.parent(c.id);
    auto it = p.is_valid() ? index.by_index.find(p.index) : index.by_index.end();
    if (it != index.by_index.end() && index.ctrls[it->second].id == p) {
      c.parent = it->second;
    }
    // Joints this control drives map to it (selecting a joint grabs its control).
    for (const graph::Connection& conn : graph.node(c.id)->outputs())
      if (conn.src.attr == xform::kTranslate) index.by_index.emplace(conn.dst.node.index, index.by_index[c.id.index]);
  }
  // A control whose parent is a joint driven by a control (the root of a
  // second character rigged under the first one's joints) moves with that
  // control: it is its parent for the plan, so it is carried once and kept
  // in place when the plan leaves it out.
  for (std::size_t k = 0; k < index.ctrls.size(); ++k) {
    Index::Ctrl& c = index.ctrls[k];
    if (c.parent >= 0) continue;
    const NodeId p = graph.parent(c.id);
    const int driver = p.is_valid() ? index.find(graph, p) : -1;
    if (driver >= 0 && driver != static_cast<int>(k) && index.ctrls[driver].id != p) {
      c.parent = driver;
      c.parent_via_joint = true;
    }
  }
  for (std::size_t k = 0; k < index.ctrls.size(); ++k)
    if (index.ctrls[k].parent >= 0) index.ctrls[index.ctrls[k].parent].children.push_back(static_cast<int>(k));
  std::vector<Relation> all;
  for (NodeId rig : rigs) {
    Result<std::vector<Relation>> rel = relations(graph, rig);
    if (!rel) return rel.status();
    all.insert(all.end(), rel->begin(), rel->end());
  }
  for (const Relation& r : carrier_relations(graph)) all.push_back(r);
  // Merged characters (keying.h) move together in body mode.
  index.rig_group.resize(rigs.size());
  for (std::size_t r = 0; r < rigs.size(); ++r)
    for (NodeId m : merged_rigs(graph, rigs[r]))
      for (std::size_t q = 0; q < rigs.size(); ++q)
        if (rigs[q] == m) index.rig_group[r].push_back(static_cast<int>(q));
  for (const Relation& r : all) {
    int f = index.find(graph, r.from), t = index.find(graph, r.to);
    if (f < 0 || t < 0 || index.ctrls[f].id != r.from || index.ctrls[t].id != r.to) continue;
    index.ctrls[f].out.push_back(Index::Edge{t, r.kind});
    if (r.kind == RelationKind::kForward) ++index.ctrls[f].forward_out;
  }
  return Status::ok();
}

}  // namespace rigel::ephemeral::modes
