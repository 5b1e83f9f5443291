// rigel.Workspace's graph editor (app::Workspace::curves, edit_curve_keys,
// insert_curve_keys, delete_curve_keys): Python values in, app calls,
// records out. Frames throughout, as every Workspace method.

#include <optional>
#include <string>
#include <vector>

#include "rigel/ops/anim/channel_keys.h"
#include "wrap_workspace.h"

namespace rigel::python {

namespace {

std::optional<ops::anim::TangentType> tangent_arg(const std::optional<std::string>& name, const char* field) {
  if (!name) return std::nullopt;
  auto type = ops::anim::tangent_type_from_name(*name);
  if (!type)
    raise(Status(ErrorCode::kInvalidArgument,
                        std::string(field) + ": '" + *name +
                            "' is not a tangent type (auto, spline, linear, flat, step, stepNext, clamped, plateau, fixed)")
                     .with_field(field));
  return type;
}

std::vector<tools::CurveKeyRef> key_refs(const std::vector<std::pair<std::string, double>>& keys) {
  std::vector<tools::CurveKeyRef> refs;
  for (const auto& [curve, frame] : keys) refs.push_back(tools::CurveKeyRef{curve, frame});
  return refs;
}

py::object curve_record(const tools::CurveView& v) {  // in frames (Workspace::curves)
  py::dict d;
  d["plug"] = v.name;
  d["curve"] = v.curve;
  d["kind"] = v.kind;
  d["component"] = v.component;
  d["label"] = v.label;
  d["editable"] = v.editable;
  d["frames"] = v.key_times;
  d["values"] = v.key_values;
  d["in_tangents"] = v.in_tangents;
  d["out_tangents"] = v.out_tangents;
  d["in_slopes"] = v.in_slopes;
  d["out_slopes"] = v.out_slopes;
  d["sample_frames"] = v.sample_times;
  d["sample_values"] = v.sample_values;
  return record(d);
}

}  // namespace

void def_curves(WorkspaceClass& cls) {
  cls.def(
         "curves",
         [](const WorkspaceRef& w, const std::optional<std::vector<NodeArg>>& controls, std::optional<double> first,
            std::optional<double> last, std::optional<double> step, bool euler) {
           const std::vector<NodeId> ids = key_nodes_arg(w, controls);
           tools::CurveViewOptions options;
           options.first = first;
           options.last = last;
           options.step = step;
           options.quat_as_euler = euler;
           py::list out;
           for (const tools::CurveView& v : unwrap(w.ws->curves(ids, options))) out.append(curve_record(v));
           return out;
         },
         py::arg("controls") = py::none(), py::arg("first") = py::none(), py::arg("last") = py::none(),
         py::arg("step") = py::none(), py::arg("euler") = true,
         R"(The animation curves of the channels the channel box shows for `controls` (default: the
selection), as the graph editor draws them: per curve a record (plug: the name edits take, curve: the
curve node, kind: "curve", "vectorTrack" or "rotationTrack", component, label, editable, frames, values,
in_tangents, out_tangents, in_slopes, out_slopes: per frame, sample_frames, sample_values). Samples
every `step` frames (default 1) from `first` to `last` (default: over the keys). A glTF rotation track
shows as unwrapped Euler angles in degrees, or with euler=False as its x y z w components.)")
      .def(
          "edit_curve_keys",
          [](const WorkspaceRef& w, const std::string& curve, const std::vector<double>& frames,
             std::optional<double> to_frame, std::optional<double> value, int component,
             const std::optional<std::string>& tangent, const std::optional<std::string>& in_tangent,
             const std::optional<std::string>& out_tangent, std::optional<double> in_slope,
             std::optional<double> out_slope) {
            std::vector<tools::CurveKeyEdit> edits;
            for (double f : frames) {
              tools::CurveKeyEdit e;
              e.key = {curve, f};
              e.to_time = to_frame;
              e.value = value;
              e.component = component;
              if (auto both = tangent_arg(tangent, "tangent")) e.in_type = e.out_type = both;
              if (auto in = tangent_arg(in_tangent, "in_tangent")) e.in_type = in;
              if (auto out = tangent_arg(out_tangent, "out_tangent")) e.out_type = out;
              e.in_slope = in_slope;
              e.out_slope = out_slope;
              edits.push_back(std::move(e));
            }
            return edit(w, [&](app::Workspace& ws) { return unwrap(ws.edit_curve_keys(std::move(edits))); });
          },
          py::arg("curve"), py::arg("frames"), py::kw_only(), py::arg("to_frame") = py::none(),
          py::arg("value") = py::none(), py::arg("component") = -1, py::arg("tangent") = py::none(),
          py::arg("in_tangent") = py::none(), py::arg("out_tangent") = py::none(), py::arg("in_slope") = py::none(),
          py::arg("out_slope") = py::none(),
          R"(Edits the keys of curve `curve` (a plug name from curves()) at `frames` (a key a hair off a
frame is that frame's key): moved to `to_frame`, given `value` (a vector track's `component`), tangent
types ("auto", "spline", "linear", "flat", "step", "stepNext", "clamped", "plateau", "fixed"; `tangent`
both sides) or slopes per frame (the side becomes fixed). All or nothing, one undo step; returns the
number of keys changed.)")
      .def(
          "insert_curve_keys",
          [](const WorkspaceRef& w, const std::vector<std::pair<std::string, double>>& keys) {
            return edit(w, [&](app::Workspace& ws) { return unwrap(ws.insert_curve_keys(key_refs(keys))); });
          },
          py::arg("keys"),
          R"(Inserts a key on each (curve, frame) with the value the curve has there (the pose does not
change). One undo step; returns the number of keys made.)")
      .def(
          "delete_curve_keys",
          [](const WorkspaceRef& w, const std::vector<std::pair<std::string, double>>& keys) {
            return edit(w, [&](app::Workspace& ws) { return unwrap(ws.delete_curve_keys(key_refs(keys))); });
          },
          py::arg("keys"),
          R"(Deletes the keys (curve, frame); a curve left without keys goes and its channel keeps its
value. One undo step; returns the number of keys deleted.)");
}

}  // namespace rigel::python
