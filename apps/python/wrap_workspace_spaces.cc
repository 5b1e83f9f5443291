// rigel.Workspace's spaces (rig/spaces.h, tools/spaces.h): list, add,
// switch at a frame, bake a range.

#include <optional>
#include <string>
#include <utility>

#include "wrap_workspace.h"

namespace rigel::python {

namespace {

py::object spaces_record(const WorkspaceRef& w, const rig::ControlSpaces& s) {
  py::list spaces;
  for (const rig::Space& space : s.spaces) {
    py::dict d;
    d["name"] = space.name;
    d["target"] = space.target.is_valid() ? py::cast(node_ref(w.scene, space.target)) : py::none();
    spaces.append(record(d));
  }
  py::dict d;
  d["control"] = node_ref(w.scene, s.control);
  d["spaces"] = spaces;
  d["current"] = s.spaces.empty() ? py::none() : py::cast(s.spaces[static_cast<std::size_t>(s.current)].name);
  return record(d);
}
}  // namespace

void def_space_tools(WorkspaceClass& cls) {
  cls.def(
         "spaces", [](const WorkspaceRef& w, const NodeArg& control) {
           return spaces_record(w, w.ws->spaces(node_arg(w, control, "control")));
         },
         py::arg("control"), "The control's spaces: a record (control, spaces [(name, target)], current).")
      .def(
          "add_space",
          [](const WorkspaceRef& w, const NodeArg& control, const std::string& name, const std::optional<NodeArg>& target) {
            const NodeId c = node_arg(w, control, "control");
            const NodeId t = target ? node_arg(w, *target, "target") : NodeId{};
            edit(w, [&](app::Workspace& ws) { return unwrap(ws.add_space(c, name, t)); });
            return spaces_record(w, w.ws->spaces(c));
          },
          py::arg("control"), py::arg("name"), py::arg("target") = py::none(),
          R"(Adds space `name` to a control, following `target` (a transform; None: the world), offset so that
following it now moves nothing; the first also makes space 0 "parent". Returns the control's spaces.)")
      .def(
          "switch_space",
          [](const WorkspaceRef& w, const NodeArg& control, const std::string& space, const std::optional<double>& frame,
             const std::optional<std::pair<double, double>>& frames) {
            const NodeId c = node_arg(w, control, "control");
            tools::SpaceSwitchOptions options;
            options.space = space;
            options.frame = frame;
            if (frames) {
              options.first = frames->first;
              options.last = frames->second;
            }
            const tools::SpaceSwitchReport r =
                edit(w, [&](app::Workspace& ws) { return unwrap(ws.switch_space(c, options)); });
            py::dict d;
            d["from_space"] = r.from;
            d["to_space"] = r.to;
            d["frames"] = r.frames;
            d["keys"] = r.keys;
            d["max_error"] = r.max_error;
            d["worst_frame"] = r.worst_frame;
            return record(d);
          },
          py::arg("control"), py::arg("space"), py::arg("frame") = py::none(), py::arg("frames") = py::none(),
          R"(Switches a control to another space at `frame` (default: the current frame), keying the space and a
compensation with step tangents so the control stays where it is and earlier frames are unchanged; or, with
frames=(first, last), bakes the range into the space, keying the control at every frame so its world motion
is kept. Returns a record (from_space, to_space, frames, keys, max_error, worst_frame).)");
}

}  // namespace rigel::python
