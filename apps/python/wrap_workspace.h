#pragma once
// What rigel.Workspace's wrap files share (wrap_workspace.cc: the class and
// most methods; wrap_workspace_tools.cc: transfer, move keys and channel
// values; wrap_workspace_spaces.cc: spaces; wrap_workspace_poses.cc: the pose
// library; wrap_workspace_curves.cc: the graph editor;
// wrap_workspace_settings.cc: playback range and selection sets;
// wrap_workspace_rigging.cc: rigger actions; wrap_workspace_graphs.cc:
// build graphs).

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common.h"
#include "rigel/app/workspace.h"

namespace rigel::python {

// The workspace and the scene it works on (shared with the Scene objects
// Python holds; the workspace goes first).
struct WorkspaceRef {
  SceneRef scene;
  std::unique_ptr<app::Workspace> ws;
};

using WorkspaceClass = py::class_<WorkspaceRef>;

// One mutating call, run as the server runs a request: the rigs at step 0
// that the call leaves no way to redo are dropped after it.
template <typename F>
auto edit(const WorkspaceRef& w, F&& call) {
  struct Prune {
    app::Workspace& ws;
    std::vector<std::uint64_t> undone;
    ~Prune() { ws.drop_unbuilt(undone); }
  } prune{*w.ws, w.ws->unbuilt_undone()};
  return call(*w.ws);
}

// A node given as a Node or a name, uuid or rig address.
NodeId node_arg(const WorkspaceRef& w, const NodeArg& arg, const std::string& field);

// Channel keys: one record per keyed plug (plug name, times, frames, values).
py::list plug_keys_list(const WorkspaceRef& w, const std::vector<tools::PlugKeys>& keys);
// Any nodes with keyable channels (default: the selection): controls (a
// joint stands for its ephemeral control) or others, such as a fkIkSwitch.
std::vector<NodeId> key_nodes_arg(const WorkspaceRef& w, const std::optional<std::vector<NodeArg>>& nodes);

// Workspace.transfer_keys, move_channel_keys, set_channel_values.
void def_transfer_and_values(WorkspaceClass& cls);
// Workspace.spaces, add_space, switch_space.
void def_space_tools(WorkspaceClass& cls);
// Workspace.save_pose, apply_pose, list_poses, remove_pose.
void def_poses(WorkspaceClass& cls);
// Workspace.curves, edit_curve_keys, insert_curve_keys, delete_curve_keys.
void def_curves(WorkspaceClass& cls);
// Workspace.playback_range, set_playback_range, selection_sets, save_selection_set,
// remove_selection_set, select_set.
void def_scene_settings(WorkspaceClass& cls);
// Workspace.control_look, paste_control_look, mirror_control_shape,
// flip_control_shape, mirror_shape_to_opposite, create_locators, align,
// mirror_joints.
void def_rigging(WorkspaceClass& cls);
// Workspace.export_skin_weights, import_skin_weights, export_control_shapes,
// import_control_shapes, export_blend_shapes, import_blend_shapes
// (wrap_pipeline.cc).
void def_data(WorkspaceClass& cls);
// Workspace.check_graph, build_graph, save_graph, rig_graph, graph_files
// (wrap_workspace_graphs.cc).
void def_graphs(WorkspaceClass& cls);

}  // namespace rigel::python
