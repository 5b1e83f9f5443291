#pragma once
// Scene-level settings an animator makes, kept as nodes so that they are
// saved with the scene (.rigel) and undone as every other edit (Maya keeps
// its playback range and its sets as nodes too):
//
// - playbackOptions (at most one, named "playbackOptions"): minFrame,
//   maxFrame: the playback range the timeline plays and the tools default
//   to. Without one the range is the keys' (Workspace's scene summary).
// - selectionSet (one per set, the node's name is the set's): members, the
//   uuids of the nodes in the set (uuids, so a member deleted and brought
//   back by undo is still a member; one deleted for good is reported as
//   missing, not an error).

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/graph/node_type.h"

namespace rigel::scene {

inline constexpr const char* kPlaybackOptionsType = "playbackOptions";
inline constexpr const char* kSelectionSetType = "selectionSet";

namespace playback_attr {
enum : graph::AttrIndex { kMinFrame = 0, kMaxFrame, kCount };
}
namespace selection_set_attr {
enum : graph::AttrIndex { kMembers = 0, kCount };
}

// Adds playbackOptions and selectionSet (register_scene_types calls it).
Status register_scene_option_types(graph::Registry& registry);

// The playback range set on the scene (frames), or none.
std::optional<std::array<double, 2>> playback_range(const graph::Graph& graph);
// Sets it (creating the playbackOptions node on first use). kInvalidArgument
// naming "range" for frames that are not finite, beyond 1e6 of 0, or a last
// before the first. One undo step.
Status set_playback_range(graph::Graph& graph, double first, double last);

struct SelectionSet {
  std::string name;
  graph::NodeId node;
  std::vector<graph::NodeId> members;  // the members the scene has, in set order
  std::vector<std::string> missing;    // uuids of members no longer in the scene
};

// Every selection set, by name.
std::vector<SelectionSet> selection_sets(const graph::Graph& graph);
// Creates set `name` holding `members`, or replaces the members of the set
// of that name. kInvalidArgument naming "name" for a name that is not a
// node name (Graph::is_valid_name, and no '.') or that another kind of
// node has; naming "members" for an invalid node
// or none at all. One undo step.
Result<graph::NodeId> save_selection_set(graph::Graph& graph, const std::string& name,
                                         const std::vector<graph::NodeId>& members);
// Removes set `name` (kNotFound naming "name" when there is none). One undo step.
Status remove_selection_set(graph::Graph& graph, const std::string& name);

}  // namespace rigel::scene
