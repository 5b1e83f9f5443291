// rigel.Workspace's scene settings (app::Workspace::playback_range,
// selection sets, the picker, motion trails and ghosts): Python values in, app calls, records out.

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "wrap_workspace.h"

namespace rigel::python {

void def_scene_settings(WorkspaceClass& cls) {
  cls.def_property_readonly(
         "playback_range",
         [](const WorkspaceRef& w) -> py::object {
           const auto r = w.ws->playback_range();
           return r ? py::object(py::make_tuple((*r)[0], (*r)[1])) : py::object(py::none());
         },
         "The playback range (first, last) in frames the animator set, saved with the scene; None until set.")
      .def(
          "set_playback_range",
          [](const WorkspaceRef& w, double first, double last) {
            edit(w, [&](app::Workspace& ws) { check(ws.set_playback_range(first, last)); });
          },
          py::arg("first"), py::arg("last"),
          "Sets the playback range (frames; InvalidArgumentError naming \"range\" for a last before the first). "
          "One undo step.")
      .def(
          "selection_sets",
          [](const WorkspaceRef& w) {
            py::list out;
            for (const scene::SelectionSet& s : w.ws->selection_sets()) {
              py::dict d;
              d["name"] = s.name;
              d["members"] = node_list(w.scene, s.members);
              d["missing"] = s.missing;
              out.append(record(d));
            }
            return out;
          },
          "The named selection sets saved with the scene, by name: records (name, members, missing: the uuids of "
          "members no longer in the scene).")
      .def(
          "save_selection_set",
          [](const WorkspaceRef& w, const std::string& name, const std::optional<std::vector<NodeArg>>& members) {
            const std::vector<NodeId> ids = members ? key_nodes_arg(w, members) : std::vector<NodeId>{};
            edit(w, [&](app::Workspace& ws) { unwrap(ws.save_selection_set(name, ids)); });
          },
          py::arg("name"), py::arg("members") = py::none(),
          "Saves selection set `name` with `members` (default: the selection), replacing the members of a set of "
          "that name. One undo step.")
      .def(
          "remove_selection_set",
          [](const WorkspaceRef& w, const std::string& name) {
            edit(w, [&](app::Workspace& ws) { check(ws.remove_selection_set(name)); });
          },
          py::arg("name"), "Removes selection set `name` (NotFoundError naming \"name\"). One undo step.")
      .def(
          "select_set",
          [](const WorkspaceRef& w, const std::string& name, bool add) {
            return node_list(w.scene, edit(w, [&](app::Workspace& ws) { return unwrap(ws.select_set(name, add)); }));
          },
          py::arg("name"), py::arg("add") = false,
          "Selects the members of selection set `name` (or adds them); returns the selection.")
      .def(
          "picker",
          [](const WorkspaceRef& w) {
            py::list out;
            for (const app::PickerGroup& p : w.ws->picker()) {
              py::list controls;
              for (const app::PickerGroup::Entry& e : p.controls) controls.append(py::make_tuple(node_ref(w.scene, e.control), e.label));
              py::dict d;
              d["rig"] = p.rig;
              d["name"] = p.name;
              d["part"] = p.part;
              d["side"] = std::string(1, p.side);
              d["controls"] = controls;
              out.append(record(d));
            }
            return out;
          },
          "The picker: every control in groups (a built rig's components, an ephemeral rig's regions) by rig, body "
          "part (head, arm, hand, torso, leg, tail, root, other) and side (R, C, L): records (rig, name, part, side, "
          "controls: [(node, label)]).")
      .def(
          "motion_trails",
          [](const WorkspaceRef& w, double first, double last, const std::optional<std::vector<NodeArg>>& controls,
             double step) {
            const std::vector<NodeId> ids = controls ? key_nodes_arg(w, controls) : std::vector<NodeId>{};
            py::list out;
            for (const tools::MotionTrail& t : unwrap(w.ws->motion_trails(ids, first, last, step))) {
              py::list points;
              for (const math::Vec3& p : t.points) points.append(py::make_tuple(p.x(), p.y(), p.z()));
              py::dict d;
              d["node"] = node_ref(w.scene, t.node);
              d["frames"] = t.frames;
              d["points"] = points;
              d["keys"] = t.key_frames;
              out.append(record(d));
            }
            return out;
          },
          py::arg("first"), py::arg("last"), py::arg("controls") = py::none(), py::arg("step") = 1.0,
          "Motion trails of `controls` (default: the selection) over frames first..last every `step` frames (and "
          "at their keys): records (node, frames, points: world positions, keys: the key frames). Changes nothing.")
      .def(
          "ghosts",
          [](const WorkspaceRef& w, const std::optional<std::vector<double>>& frames, int before, int after, double step,
             bool at_keys) {
            app::GhostOptions o;
            if (frames) o.frames = *frames;
            o.before = before;
            o.after = after;
            o.step = step;
            o.at_keys = at_keys;
            const app::Ghosts g = unwrap(w.ws->ghosts(o));
            py::list poses;
            for (const auto& frame : g.points) {
              py::list points;
              for (const math::Vec3& p : frame) points.append(py::make_tuple(p.x(), p.y(), p.z()));
              poses.append(points);
            }
            py::dict d;
            d["joints"] = node_list(w.scene, g.joints);
            d["parents"] = g.parents;
            d["frames"] = g.frames;
            d["points"] = poses;
            return record(d);
          },
          py::arg("frames") = py::none(), py::arg("before") = 0, py::arg("after") = 0, py::arg("step") = 1.0,
          py::arg("at_keys") = false,
          "Ghosts of the skeleton: every joint's world position at `frames`, or at `before` and `after` frames "
          "`step` apart around the current one, or at the selection's keys: a record (joints, parents: an index "
          "into joints or -1, frames, points[frame][joint]). Changes nothing.");
}

}  // namespace rigel::python
