// rigel.Workspace's pose library (app::Workspace::save_pose, apply_pose,
// list_poses, remove_pose; tools/poses.h): Python values in, records out.

#include <optional>
#include <string>
#include <vector>

#include "wrap_workspace.h"

namespace rigel::python {
namespace {

std::vector<NodeId> nodes_arg(const WorkspaceRef& w, const std::optional<std::vector<NodeArg>>& nodes) {
  std::vector<NodeId> out;
  if (!nodes) return out;
  for (std::size_t i = 0; i < nodes->size(); ++i)
    out.push_back(node_arg(w, (*nodes)[i], "controls[" + std::to_string(i) + "]"));
  return out;
}

}  // namespace

void def_poses(WorkspaceClass& cls) {
  cls.def(
         "save_pose",
         [](const WorkspaceRef& w, const std::string& library, const std::string& name, const std::optional<std::string>& rig,
            const std::optional<std::vector<NodeArg>>& controls) {
           const std::vector<NodeId> ids = nodes_arg(w, controls);
           const tools::SavedPose saved = unwrap(w.ws->save_pose(library, name, rig.value_or(""), ids));
           py::dict d;
           d["name"] = name;
           d["path"] = saved.path.string();
           d["entries"] = saved.entries;
           return record(d);
         },
         py::arg("library"), py::arg("name"), py::arg("rig") = py::none(), py::arg("controls") = py::none(),
         R"(Saves a named pose as LIBRARY/NAME.pose.json (diffable JSON): the whole of rig `rig` (default: the
scene's only rig), or `controls` (controls, components or rigs). Each entry is found again by its
component's rigId and its role and index, never by names. Returns a record (name, path, entries).)")
      .def(
          "apply_pose",
          [](const WorkspaceRef& w, const std::string& library, const std::string& name, const std::optional<std::string>& rig,
             const std::optional<std::vector<NodeArg>>& controls, bool mirror, const std::string& plane, double fraction,
             bool key) {
            if (plane != "yz" && plane != "xy" && plane != "xz")
              raise(Status(ErrorCode::kInvalidArgument, "plane: expected 'yz', 'xy' or 'xz', got '" + plane + "'")
                        .with_field("plane"));
            tools::ApplyPoseOptions options;
            options.controls = nodes_arg(w, controls);
            options.mirrored = mirror;
            options.plane = plane == "yz" ? tools::MirrorPlane::kYZ : plane == "xy" ? tools::MirrorPlane::kXY
                                                                                    : tools::MirrorPlane::kXZ;
            options.fraction = fraction;
            options.key = key;
            const tools::ApplyPoseReport r = edit(
                w, [&](app::Workspace& ws) { return unwrap(ws.apply_pose(library, name, rig.value_or(""), options)); });
            py::dict d;
            d["set"] = node_list(w.scene, r.set);
            d["channels"] = r.channels;
            d["keyed"] = r.keyed;
            d["unpaired"] = r.unpaired;
            d["skipped"] = r.skipped;
            return record(d);
          },
          py::arg("library"), py::arg("name"), py::arg("rig") = py::none(), py::arg("controls") = py::none(),
          py::arg("mirror") = false, py::arg("plane") = "yz", py::arg("fraction") = 1.0, py::arg("key") = false,
          R"(Applies a saved pose now to rig `rig` (default: the pose's rig, or the scene's only one): all of it or
only `controls`; mirror=True puts each entry on its pair on the other side; `fraction` (0..1) blends from
the current pose (rotations by slerp); key=True keys the channels (keyed channels are keyed anyway). A
pose of another rig is refused naming the missing rigId and role. One undo step. Returns a record (set,
channels, keyed, unpaired, skipped).)")
      .def(
          "list_poses",
          [](const WorkspaceRef& w, const std::string& library) {
            py::list out;
            for (const tools::PoseInfo& p : unwrap(w.ws->list_poses(library))) {
              py::dict d;
              d["name"] = p.name;
              d["rig"] = p.rig;
              d["entries"] = p.entries;
              d["thumbnail"] = p.thumbnail;
              d["error"] = p.error.empty() ? py::object(py::none()) : py::object(py::str(p.error));
              out.append(record(d));
            }
            return out;
          },
          py::arg("library"), R"(The library's poses by name: records (name, rig, entries, thumbnail: whether NAME.pose.svg is beside it, error: why a file cannot be read, or None).)")
      .def(
          "pose_thumbnail",
          [](const WorkspaceRef& w, const std::string& library, const std::string& name) {
            return unwrap(w.ws->pose_thumbnail(library, name));
          },
          py::arg("library"), py::arg("name"),
          R"(The SVG text of a saved pose's thumbnail (the skeletons in the pose, from the front; NotFoundError when there is none).)")
      .def(
          "remove_pose",
          [](const WorkspaceRef& w, const std::string& library, const std::string& name) {
            if (Status s = w.ws->remove_pose(library, name); !s) raise(s);
          },
          py::arg("library"), py::arg("name"), R"(Deletes LIBRARY/NAME.pose.json and its thumbnail (NotFoundError when there is none).)");
}

}  // namespace rigel::python
