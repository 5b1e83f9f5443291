// Scene-level settings as nodes (scene_options.h): the playback range and
// selection sets.

#include "rigel/scene/scene_options.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace rigel::scene {

using graph::NodeId;
using graph::Plug;
using graph::ValueType;

namespace {

constexpr double kMaxFrame = 1e6;
constexpr const char* kPlaybackNodeName = "playbackOptions";

Status bad(const char* field, const std::string& message) {
  return Status(ErrorCode::kInvalidArgument, std::string(field) + ": " + message).with_field(field);
}

NodeId playback_node(const graph::Graph& g) {
  const NodeId id = g.find(kPlaybackNodeName);
  if (id.is_valid() && g.node(id)->type().name() == kPlaybackOptionsType) return id;
  for (NodeId n : g.nodes())
    if (g.node(n)->type().name() == kPlaybackOptionsType) return n;
  return NodeId();
}

NodeId set_node(const graph::Graph& g, const std::string& name) {
  const NodeId id = g.find(name);
  return id.is_valid() && g.node(id)->type().name() == kSelectionSetType ? id : NodeId();
}

}  // namespace

Status register_scene_option_types(graph::Registry& registry) {
  graph::NodeTypeSpec playback;
  playback.name = kPlaybackOptionsType;
  playback.description = "The scene's playback range (frames): what the timeline plays";
  playback.attrs = {graph::input_attr("minFrame", {ValueType::kDouble, false}, 0.0),
                    graph::input_attr("maxFrame", {ValueType::kDouble, false}, 100.0)};
  if (Status s = registry.add(std::move(playback)); !s) return s;
  graph::NodeTypeSpec set;
  set.name = kSelectionSetType;
  set.description = "A named selection set: the uuids of its members";
  set.attrs = {graph::input_attr("members", {ValueType::kString, true}, std::vector<std::string>{})};
  return registry.add(std::move(set));
}

std::optional<std::array<double, 2>> playback_range(const graph::Graph& graph) {
  const NodeId id = playback_node(graph);
  if (!id.is_valid()) return std::nullopt;
  const graph::Node& n = *graph.node(id);
  return std::array<double, 2>{std::get<double>(n.value(playback_attr::kMinFrame)),
                               std::get<double>(n.value(playback_attr::kMaxFrame))};
}

Status set_playback_range(graph::Graph& graph, double first, double last) {
  for (double f : {first, last})
    if (!std::isfinite(f) || std::abs(f) > kMaxFrame) return bad("range", "frames must be finite and within 1e6 of 0");
  if (last < first) return bad("range", "the last frame is before the first");
  graph::Transaction tx(graph, "set playback range");
  NodeId id = playback_node(graph);
  if (!id.is_valid()) {
    Result<NodeId> made = graph.create_node(kPlaybackOptionsType, kPlaybackNodeName);
    if (!made) {
      tx.rollback();
      return made.status();
    }
    id = *made;
  }
  for (auto [attr, v] : {std::pair{playback_attr::kMinFrame, first}, std::pair{playback_attr::kMaxFrame, last}})
    if (Status s = graph.set_value(Plug{id, attr, -1}, v); !s) {
      tx.rollback();
      return s;
    }
  return Status();
}

std::vector<SelectionSet> selection_sets(const graph::Graph& graph) {
  std::vector<SelectionSet> out;
  for (NodeId id : graph.nodes()) {
    const graph::Node& n = *graph.node(id);
    if (n.type().name() != kSelectionSetType) continue;
    SelectionSet set{n.name(), id, {}, {}};
    for (const std::string& text : std::get<std::vector<std::string>>(n.value(selection_set_attr::kMembers))) {
      const std::optional<graph::Uuid> uuid = graph::Uuid::parse(text);
      const NodeId m = uuid ? graph.find(*uuid) : NodeId();
      if (m.is_valid())
        set.members.push_back(m);
      else
        set.missing.push_back(text);
    }
    out.push_back(std::move(set));
  }
  std::sort(out.begin(), out.end(), [](const SelectionSet& a, const SelectionSet& b) { return a.name < b.name; });
  return out;
}

Result<NodeId> save_selection_set(graph::Graph& graph, const std::string& name, const std::vector<NodeId>& members) {
  if (!graph::Graph::is_valid_name(name) || name.find('.') != std::string::npos)
    return bad("name", "'" + name + "' is not a set name (no spaces, dots or brackets)");
  if (members.empty()) return bad("members", "a set needs at least one member");
  std::vector<std::string> uuids;
  for (NodeId m : members) {
    if (!graph.node(m)) return bad("members", "no such node (stale handle)");
    const std::string u = graph.node(m)->uuid().str();
    if (std::find(uuids.begin(), uuids.end(), u) == uuids.end()) uuids.push_back(u);
  }
  NodeId id = set_node(graph, name);
  if (!id.is_valid() && graph.find(name).is_valid())
    return bad("name", "'" + name + "' is the name of a node that is not a selection set");
  graph::Transaction tx(graph, "selection set " + name);
  if (!id.is_valid()) {
    Result<NodeId> made = graph.create_node(kSelectionSetType, name);
    if (!made) {
      tx.rollback();
      return made.status();
    }
    id = *made;
  }
  if (Status s = graph.set_value(Plug{id, selection_set_attr::kMembers, -1}, std::move(uuids)); !s) {
    tx.rollback();
    return s;
  }
  return id;
}

Status remove_selection_set(graph::Graph& graph, const std::string& name) {
  const NodeId id = set_node(graph, name);
  if (!id.is_valid())
    return Status(ErrorCode::kNotFound, "name: no selection set '" + name + "'").with_field("name");
  graph::Transaction tx(graph, "remove selection set " + name);
  if (Status s = graph.delete_node(id); !s) {
    tx.rollback();
    return s;
  }
  return Status();
}

}  // namespace rigel::scene
