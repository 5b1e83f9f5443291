// The workspace's scene settings: the playback range and selection sets
// (workspace.h, scene/scene_options.h).

#include <string>
#include <vector>

#include "rigel/app/workspace.h"
#include "rigel/scene/scene_options.h"

namespace rigel::app {

std::optional<std::array<double, 2>> Workspace::playback_range() const { return scene::playback_range(graph()); }

Status Workspace::set_playback_range(double first, double last) {
  if (Status s = scene::set_playback_range(graph(), first, last); !s) return s;
  bump_revision();
  return Status();
}

std::vector<scene::SelectionSet> Workspace::selection_sets() const { return scene::selection_sets(graph()); }

Result<NodeId> Workspace::save_selection_set(const std::string& name, const std::vector<NodeId>& members) {
  Result<NodeId> id = scene::save_selection_set(graph(), name, members.empty() ? selection() : members);
  if (!id) return id.status().field() == "members" && members.empty()
                      ? Status(ErrorCode::kInvalidArgument, "members: nothing is selected and no members given")
                            .with_field("members")
                      : id.status();
  bump_revision();
  return id;
}

Status Workspace::remove_selection_set(const std::string& name) {
  if (Status s = scene::remove_selection_set(graph(), name); !s) return s;
  bump_revision();
  return Status();
}

Result<std::vector<NodeId>> Workspace::select_set(const std::string& name, bool add) {
  for (const scene::SelectionSet& set : selection_sets()) {
    if (set.name != name) continue;
    select(set.members, add);
    return selection();
  }
  return Status(ErrorCode::kNotFound, "name: no selection set '" + name + "'").with_field("name");
}

}  // namespace rigel::app
