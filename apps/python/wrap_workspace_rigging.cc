// rigel.Workspace's rigger actions (app::Workspace::control_look, shapes,
// locators, align, mirror_joints; tools/rigging.h): Python values in, app
// calls, records out.

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "wrap_workspace.h"

namespace rigel::python {

namespace {

using Point = std::array<double, 3>;

std::vector<NodeId> nodes_or_selection(const WorkspaceRef& w, const std::optional<std::vector<NodeArg>>& nodes,
                                       const std::string& field) {
  if (!nodes) return w.ws->selection();
  std::vector<NodeId> out;
  for (std::size_t i = 0; i < nodes->size(); ++i) out.push_back(node_arg(w, (*nodes)[i], field + "[" + std::to_string(i) + "]"));
  return out;
}

py::tuple point(const math::Vec3& p) { return py::make_tuple(p.x(), p.y(), p.z()); }

}  // namespace

void def_rigging(WorkspaceClass& cls) {
  cls.def(
         "control_look",
         [](const WorkspaceRef& w, const NodeArg& control) {
           const tools::ControlLook look = unwrap(w.ws->control_look(node_arg(w, control, "control")));
           py::list points;
           for (const math::Vec3& p : look.points) points.append(point(p));
           py::dict d;
           d["points"] = points;
           d["closed"] = look.closed;
           d["color"] = point(look.color);
           return record(d);
         },
         py::arg("control"),
         "A control's shape and colour (what copy takes): a record of points (in its local space), closed and "
         "color (linear RGB 0..1).")
      .def(
          "paste_control_look",
          [](const WorkspaceRef& w, const std::vector<Point>& points, bool closed, const Point& color,
             const std::optional<std::vector<NodeArg>>& controls, bool shape, bool paste_color) {
            tools::ControlLook look;
            for (const Point& p : points) look.points.emplace_back(p[0], p[1], p[2]);
            look.closed = closed;
            look.color = math::Vec3(color[0], color[1], color[2]);
            const std::vector<NodeId> ids = nodes_or_selection(w, controls, "controls");
            edit(w, [&](app::Workspace& ws) { check(ws.paste_control_look(ids, look, {shape, paste_color})); });
          },
          py::arg("points"), py::arg("closed") = true, py::arg("color") = Point{1, 1, 0},
          py::arg("controls") = py::none(), py::arg("shape") = true, py::arg("paste_color") = true,
          "Pastes a look (control_look's points, closed and color) onto controls (default: the selection): the "
          "shape, the colour or both. One undo step.")
      .def(
          "mirror_control_shape",
          [](const WorkspaceRef& w, const std::optional<std::vector<NodeArg>>& controls) {
            const std::vector<NodeId> ids = nodes_or_selection(w, controls, "controls");
            edit(w, [&](app::Workspace& ws) { check(ws.edit_control_shape(ids, tools::ShapeEdit::kMirror)); });
          },
          py::arg("controls") = py::none(),
          "Mirrors each control's shape over its local YZ plane (x -> -x), in place. One undo step.")
      .def(
          "flip_control_shape",
          [](const WorkspaceRef& w, const std::optional<std::vector<NodeArg>>& controls) {
            const std::vector<NodeId> ids = nodes_or_selection(w, controls, "controls");
            edit(w, [&](app::Workspace& ws) { check(ws.edit_control_shape(ids, tools::ShapeEdit::kFlip)); });
          },
          py::arg("controls") = py::none(),
          "Flips each control's shape over, a half turn about its local Y (x -> -x, z -> -z). One undo step.")
      .def(
          "mirror_shape_to_opposite",
          [](const WorkspaceRef& w, const std::optional<std::vector<NodeArg>>& controls) {
            const std::vector<NodeId> ids = nodes_or_selection(w, controls, "controls");
            const auto pairs = edit(w, [&](app::Workspace& ws) { return unwrap(ws.mirror_shape_to_opposite(ids)); });
            py::list out;
            for (const tools::MirroredShape& p : pairs) out.append(py::make_tuple(node_ref(w.scene, p.from), node_ref(w.scene, p.to)));
            return out;
          },
          py::arg("controls") = py::none(),
          "Copies each control's shape onto the control on the other side, as its mirror image in the world; "
          "returns (from, to) pairs. One undo step.")
      .def(
          "create_locators",
          [](const WorkspaceRef& w, const std::optional<std::vector<NodeArg>>& nodes, double size) {
            const std::vector<NodeId> ids = nodes_or_selection(w, nodes, "nodes");
            return node_list(w.scene, edit(w, [&](app::Workspace& ws) { return unwrap(ws.create_locators(ids, size)); }));
          },
          py::arg("nodes") = py::none(), py::arg("size") = 0.1,
          "A locator (a control drawn as a cross, named <node>_loc) at each node's world position and rotation "
          "(default: the selection's); returns them. One undo step.")
      .def(
          "align",
          [](const WorkspaceRef& w, const std::vector<NodeArg>& nodes, const NodeArg& target, bool position, bool rotation) {
            const std::vector<NodeId> ids = nodes_or_selection(w, nodes, "nodes");
            const NodeId to = node_arg(w, target, "target");
            return node_list(w.scene, edit(w, [&](app::Workspace& ws) { return unwrap(ws.align(ids, to, position, rotation)); }));
          },
          py::arg("nodes"), py::arg("target"), py::arg("position") = true, py::arg("rotation") = true,
          "Matches the nodes' world position and/or rotation to the target's (an ephemeral control through the "
          "session in the current mode); returns the nodes moved. One undo step.")
      .def(
          "mirror_joints",
          [](const WorkspaceRef& w, const std::optional<std::vector<NodeArg>>& joints, bool update) {
            const std::vector<NodeId> ids = nodes_or_selection(w, joints, "joints");
            tools::MirrorJointsOptions options;
            options.update_existing = update;
            const auto report = edit(w, [&](app::Workspace& ws) { return unwrap(ws.mirror_joints(ids, options)); });
            py::dict d;
            d["created"] = node_list(w.scene, report.created);
            d["updated"] = node_list(w.scene, report.updated);
            return record(d);
          },
          py::arg("joints") = py::none(), py::arg("update") = false,
          "Mirrors joint hierarchies to the other side with their sides renamed (an ephemeral control stands for "
          "its joint); with update, joints that exist are moved onto the mirror. A record of created and updated. "
          "One undo step.");
}

}  // namespace rigel::python
