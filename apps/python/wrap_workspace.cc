// rigel.Workspace: the service layer (app::Workspace, ARCHITECTURE.md
// "app") from Python: a scene, its posing session and its rigs, and
// everything a user can do to them, as the CLI and the server do it. This
// file (and wrap_workspace_poses.cc) converts Python values into app calls and app answers into Python
// values; every rule and range check is app's (its errors name the
// argument in Python's spelling: module.cc).

#include <filesystem>

#include "common.h"
#include "wrap_workspace.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/app/workspace.h"
#include "rigel/ephemeral/component.h"
#include "rigel/tools/data_files.h"

namespace rigel::python {

NodeId node_arg(const WorkspaceRef& w, const NodeArg& arg, const std::string& field) {
  if (std::holds_alternative<NodeRef>(arg)) return resolve(w.scene, arg);
  return unwrap(w.ws->node(std::get<std::string>(arg), field));
}

namespace {

namespace fs = std::filesystem;
namespace eph = ephemeral;
using DefinitionRef = std::shared_ptr<rig::Definition>;

using SceneArg = std::variant<SceneRef, std::string>;

WorkspaceRef make_workspace(const SceneArg& scene, const std::optional<std::string>& root) {
  WorkspaceRef w;
  fs::path scene_path, character;
  if (const std::string* path = std::get_if<std::string>(&scene)) {
    w.scene = open_any(*path);
    // Only a .rigel file is where save() writes; a character (.glb, .bvh)
    // is what the scene was opened from (as `rigel serve` does).
    if (app::is_scene_file(*path)) scene_path = *path;
    character = fs::absolute(*path).lexically_normal();
  } else {
    w.scene = std::get<SceneRef>(scene);
  }
  w.ws = std::make_unique<app::Workspace>(w.scene, scene_path, root ? fs::path(*root) : fs::path(), tools::components());
  if (!character.empty()) w.ws->set_character(character);
  return w;
}

// ---- arguments -----------------------------------------------------------------

NodeId control_arg(const WorkspaceRef& w, const NodeArg& arg, const std::string& field) {
  if (std::holds_alternative<NodeRef>(arg)) return unwrap(w.ws->control_of(resolve(w.scene, arg), field));
  return unwrap(w.ws->control(std::get<std::string>(arg), field));
}

std::vector<NodeId> controls_arg(const WorkspaceRef& w, const std::vector<NodeArg>& args, const std::string& field) {
  std::vector<NodeId> out;
  for (std::size_t i = 0; i < args.size(); ++i) out.push_back(control_arg(w, args[i], field + "[" + std::to_string(i) + "]"));
  return out;
}

// The controls given, or the selection when none are.
std::vector<NodeId> controls_or_selection(const WorkspaceRef& w, const std::optional<std::vector<NodeArg>>& controls) {
  return controls ? controls_arg(w, *controls, "controls") : w.ws->selection();
}

fs::path path_arg(const WorkspaceRef& w, const std::optional<std::string>& path, const std::string& field) {
  return path ? unwrap(w.ws->resolve_path(*path, field)) : fs::path();
}

// A rotation: `rotate` a quaternion (x, y, z, w), or `euler` degrees (x, y, z;
// app::rotation_from_euler_degrees); none given: unset.
std::optional<math::Quat> rotation_arg(py::object rotate, py::object euler) {
  if (!rotate.is_none() && !euler.is_none())
    raise(Status(ErrorCode::kInvalidArgument, "euler: give rotate or euler, not both").with_field("euler"));
  if (!rotate.is_none()) return quat_from_python(rotate, "rotate");
  if (!euler.is_none()) return app::rotation_from_euler_degrees(vec3_from_python(euler, "euler"));
  return std::nullopt;
}

// ---- answers -------------------------------------------------------------------

py::object trs_record(const SceneRef& s, const app::Trs& t) {
  py::dict d;
  d["node"] = node_ref(s, t.node);
  d["translate"] = vec3_to_python(t.translate);
  d["rotate"] = quat_to_python(t.rotate);
  d["scale"] = vec3_to_python(t.scale);
  return record(d);
}

py::list trs_list(const SceneRef& s, const std::vector<app::Trs>& values) {
  py::list out;
  for (const app::Trs& t : values) out.append(trs_record(s, t));
  return out;
}

py::object drag_record(const SceneRef& s, const app::DragReport& r) {
  py::dict d;
  d["dragged"] = node_list(s, r.dragged);
  d["moved"] = trs_list(s, r.moved);
  d["moved_controls"] = trs_list(s, r.moved_controls);
  d["notes"] = r.notes;
  return record(d);
}

py::object keys_record(const SceneRef& s, const app::KeyReport& k) {
  py::dict d;
  d["scope"] = k.scope.empty() ? py::object(py::none()) : py::object(py::str(k.scope));
  d["set"] = node_list(s, k.set);
  d["times"] = k.times;
  d["frames"] = k.frames;
  return record(d);
}

}  // namespace

// Channel keys: one record per keyed plug (plug name, times, frames, values).
py::list plug_keys_list(const WorkspaceRef& w, const std::vector<tools::PlugKeys>& keys) {
  py::list out;
  const double fps = w.ws->graph().fps();
  for (const tools::PlugKeys& k : keys) {
    py::dict d;
    d["plug"] = k.name;
    d["times"] = k.times;
    std::vector<double> frames;
    for (double t : k.times) frames.push_back(app::key_frame(t, fps));
    d["frames"] = frames;
    py::list values;
    for (const graph::Value& v : k.values) values.append(to_python(v));
    d["values"] = values;
    d["in_tangents"] = k.in_tangents;
    d["out_tangents"] = k.out_tangents;
    out.append(record(d));
  }
  return out;
}

// Any nodes with keyable channels: controls (a joint stands for its
// ephemeral control) or others, such as a limb's fkIkSwitch.
std::vector<NodeId> key_nodes_arg(const WorkspaceRef& w, const std::optional<std::vector<NodeArg>>& nodes) {
  if (!nodes) return w.ws->selection();
  std::vector<NodeId> out;
  for (std::size_t i = 0; i < nodes->size(); ++i) {
    out.push_back(w.ws->key_target(node_arg(w, (*nodes)[i], "controls[" + std::to_string(i) + "]")));
  }
  return out;
}

namespace {

py::object summary_record(const SceneRef& s, const app::SceneSummary& x) {
  py::dict scopes;
  for (const auto& [rig, scope] : x.key_scopes) scopes[py::str(rig)] = scope;
  py::dict d;
  d["fps"] = x.fps;
  d["frame"] = x.frame;
  d["time"] = x.time;
  d["range"] = py::make_tuple(x.range[0], x.range[1]);
  d["playback_range"] = x.playback ? py::object(py::make_tuple((*x.playback)[0], (*x.playback)[1])) : py::object(py::none());
  d["mode"] = eph::mode_name(x.mode);
  d["auto_key"] = x.auto_key;
  d["key_scopes"] = scopes;
  d["can_undo"] = x.can_undo;
  d["can_redo"] = x.can_redo;
  d["undo_label"] = x.undo_label;
  d["redo_label"] = x.redo_label;
  d["selection"] = node_list(s, x.selection);
  return record(d);
}

py::list features_list(const std::vector<app::FeatureState>& features) {
  py::list out;
  for (const app::FeatureState& f : features) {
    py::dict d;
    d["feature"] = f.feature;
    d["switch"] = f.switch_name;
    d["enabled"] = f.enabled;
    out.append(record(d));
  }
  return out;
}

py::object rig_entry_record(const app::RigEntry& e) {
  py::dict d;
  d["name"] = e.name;
  d["unbuilt"] = e.unbuilt;
  d["steps"] = e.steps;
  d["features"] = features_list(e.features);
  d["version"] = e.version;
  d["definition"] = e.definition;
  d["definition_version"] = e.definition_version ? py::object(py::str(*e.definition_version)) : py::object(py::none());
  d["edit_mode"] = e.edit_mode;
  return record(d);
}

py::object path_or_none(const fs::path& p) { return p.empty() ? py::object(py::none()) : py::object(py::str(p.string())); }

// ---- methods -------------------------------------------------------------------

void def_state(WorkspaceClass& cls) {
  cls.def(py::init(&make_workspace), py::arg("scene"), py::arg("root") = py::none(),
          R"(A workspace on a Scene, or on a file opened as rigel.open does (a .rigel file is where
save() writes). `root`: the folder every path argument is relative to and confined in (None:
paths as given).)")
      .def_property_readonly("scene", [](const WorkspaceRef& w) { return w.scene; }, "The Scene it works on.")
      .def_property_readonly(
          "scene_path", [](const WorkspaceRef& w) { return path_or_none(w.ws->scene_path()); },
          "Where save() without a path writes, or None.")
      .def_property_readonly(
          "root", [](const WorkspaceRef& w) { return path_or_none(w.ws->root()); }, "The folder paths are confined in, or None.")
      .def_property_readonly(
          "character", [](const WorkspaceRef& w) { return path_or_none(w.ws->character()); },
          "The file the scene was opened from, or None.")
      .def_property_readonly(
          "revision", [](const WorkspaceRef& w) { return w.ws->revision(); },
          "Counts changes: every call that changes the scene, the session or the rigs increments it.")
      .def(
          "save",
          [](const WorkspaceRef& w, const std::optional<std::string>& path) {
            const fs::path p = path_arg(w, path, "path");
            return edit(w, [&](app::Workspace& ws) { return unwrap(ws.save(p)).string(); });
          },
          py::arg("path") = py::none(),
          "Saves the scene atomically at `path` (or scene_path); it becomes scene_path. Returns the path.");
}

void def_reports(WorkspaceClass& cls) {
  cls.def(
         "node", [](const WorkspaceRef& w, const std::string& ref) { return node_ref(w.scene, unwrap(w.ws->node(ref, "ref"))); },
         py::arg("ref"), "A node by name or UUID.")
      .def(
          "control", [](const WorkspaceRef& w, const NodeArg& ref) { return node_ref(w.scene, control_arg(w, ref, "ref")); },
          py::arg("ref"), "A control, or the ephemeral control of a joint.")
      .def(
          "is_control", [](const WorkspaceRef& w, const NodeArg& node) { return w.ws->is_control(node_arg(w, node, "node")); },
          py::arg("node"))
      .def(
          "all_controls", [](const WorkspaceRef& w) { return node_list(w.scene, w.ws->all_controls()); },
          "Every control: the ephemeral rigs' (rig by rig), then the built rigs', hierarchy order.")
      .def_property_readonly(
          "selection", [](const WorkspaceRef& w) { return node_list(w.scene, w.ws->selection()); }, "The selected nodes.")
      .def(
          "nodes",
          [](const WorkspaceRef& w) {
            py::list out;
            for (const app::NodeEntry& e : w.ws->nodes()) {
              py::dict d;
              d["node"] = node_ref(w.scene, e.node);
              d["parent"] = node_or_none(w.scene, e.parent);
              out.append(record(d));
            }
            return out;
          },
          "The hierarchy: (node, parent or None) records, parents first.")
      .def(
          "controls",
          [](const WorkspaceRef& w) {
            py::list out;
            for (const app::ControlEntry& c : w.ws->controls()) {
              py::list points;
              for (const math::Vec3& p : c.points) points.append(vec3_to_python(p));
              py::dict d;
              d["node"] = node_ref(w.scene, c.node);
              d["rig"] = c.rig;
              d["ephemeral"] = c.ephemeral;
              d["group"] = c.group;
              d["points"] = points;
              d["closed"] = c.closed;
              d["color"] = vec3_to_python(c.color);
              out.append(record(d));
            }
            return out;
          },
          "Every control with its rig, whether it is ephemeral, and its shape (points, closed, color).")
      .def(
          "summary", [](const WorkspaceRef& w) { return summary_record(w.scene, w.ws->summary()); },
          "fps, frame, time, range (first and last keyed frame), mode, auto_key, key_scopes {rig: scope}, "
          "can_undo, can_redo, undo_label, redo_label, selection.")
      .def(
          "pose",
          [](const WorkspaceRef& w, const std::string& space) {
            if (space != "local" && space != "world")
              raise(Status(ErrorCode::kInvalidArgument, "space: expected 'local' or 'world', got '" + space + "'").with_field("space"));
            return trs_list(w.scene, w.ws->pose(space == "world" ? app::Space::kWorld : app::Space::kLocal));
          },
          py::arg("space") = "local",
          "Every transform's (node, translate, rotate (x, y, z, w), scale): local (offsetParentMatrix * matrix) or "
          "world, hierarchy order.");
}

py::dict options_dict(const eph::SessionOptions& o) {
  py::dict d;
  d["magnet_fraction"] = o.magnet_fraction;
  d["magnet_min_weight"] = o.magnet_min_weight;
  d["magnet_radius"] = o.magnet_radius;
  d["max_chain"] = o.max_chain;
  d["auto_key"] = o.auto_key;
  d["fabrik_iterations"] = o.fabrik_iterations;
  d["fabrik_tolerance"] = o.fabrik_tolerance;
  return d;
}

void set_options(const WorkspaceRef& w, std::optional<double> magnet_fraction, std::optional<double> magnet_min_weight,
                 std::optional<double> magnet_radius, std::optional<int> max_chain, std::optional<bool> auto_key,
                 std::optional<int> fabrik_iterations, std::optional<double> fabrik_tolerance) {
  eph::SessionOptions o = w.ws->session().options();
  if (magnet_fraction) o.magnet_fraction = *magnet_fraction;
  if (magnet_min_weight) o.magnet_min_weight = *magnet_min_weight;
  if (magnet_radius) o.magnet_radius = *magnet_radius;
  if (max_chain) o.max_chain = *max_chain;
  if (auto_key) o.auto_key = *auto_key;
  if (fabrik_iterations) o.fabrik_iterations = *fabrik_iterations;
  if (fabrik_tolerance) o.fabrik_tolerance = *fabrik_tolerance;
  edit(w, [&](app::Workspace& ws) { check(ws.set_options(o)); });
}

void def_posing(WorkspaceClass& cls) {
  cls.def(
         "select",
         [](const WorkspaceRef& w, const std::vector<NodeArg>& controls, bool add) {
           std::vector<NodeId> ids = controls_arg(w, controls, "controls");
           edit(w, [&](app::Workspace& ws) { ws.select(std::move(ids), add); });
         },
         py::arg("controls"), py::arg("add") = false,
         "Selects controls (a joint stands for its ephemeral control), or adds them to the selection.")
      .def_property(
          "mode", [](const WorkspaceRef& w) { return std::string(eph::mode_name(w.ws->session().mode())); },
          [](const WorkspaceRef& w, const std::string& mode) {
            const eph::Mode m = mode_from(mode);
            edit(w, [&](app::Workspace& ws) { ws.set_mode(m); });
          },
          "The posing mode: forward, suspended, pseudo-inverse, pseudo-inverse-length, inverse, magnet, magnet-radius, body.")
      .def_property_readonly(
          "options", [](const WorkspaceRef& w) { return options_dict(w.ws->session().options()); }, "The posing options (dict).")
      .def("set_options", &set_options, py::kw_only(), py::arg("magnet_fraction") = py::none(),
           py::arg("magnet_min_weight") = py::none(), py::arg("magnet_radius") = py::none(), py::arg("max_chain") = py::none(),
           py::arg("auto_key") = py::none(), py::arg("fabrik_iterations") = py::none(), py::arg("fabrik_tolerance") = py::none(),
           "Changes the options given (the others keep their values); the session takes them once checked.")
      .def(
          "set_body_pivot",
          [](const WorkspaceRef& w, const NodeArg& control, py::object at) {
            const NodeId c = control_arg(w, control, "control");
            std::optional<math::Vec3> point;
            if (!at.is_none()) point = vec3_from_python(at, "at");
            w.ws->set_body_pivot(c, point);
          },
          py::arg("control"), py::arg("at") = py::none(),
          "Body mode's pivot: at `control` (its world position and axes), or at the world point `at`, world axes.")
      .def(
          "drag",
          [](const WorkspaceRef& w, py::object translate, py::object rotate, py::object scale, py::object euler) {
            eph::Delta delta;
            if (!translate.is_none()) delta.translate = vec3_from_python(translate, "translate");
            if (std::optional<math::Quat> q = rotation_arg(rotate, euler)) delta.rotate = *q;
            if (!scale.is_none()) delta.scale = vec3_from_python(scale, "scale");
            return drag_record(w.scene, edit(w, [&](app::Workspace& ws) { return unwrap(ws.drag(delta)); }));
          },
          py::arg("translate") = py::none(), py::arg("rotate") = py::none(), py::arg("scale") = py::none(), py::kw_only(),
          py::arg("euler") = py::none(),
          R"(Moves the selected controls by a world delta: translate (x, y, z); rotate a quaternion
(x, y, z, w) or euler=(x, y, z) degrees (x first: R = Rz Ry Rx), about each control's pivot; scale
(body mode). Ephemeral rigs' controls move in the mode, built rigs' as they are. Returns
(dragged, moved, moved_controls (world), notes).)")
      .def(
          "drag_to",
          [](const WorkspaceRef& w, const NodeArg& control, py::object translate, py::object rotate, py::object euler) {
            const NodeId c = control_arg(w, control, "control");
            std::optional<math::Vec3> t;
            if (!translate.is_none()) t = vec3_from_python(translate, "translate");
            const std::optional<math::Quat> q = rotation_arg(rotate, euler);
            return drag_record(w.scene, edit(w, [&](app::Workspace& ws) { return unwrap(ws.drag_to(c, t, q)); }));
          },
          py::arg("control"), py::arg("translate") = py::none(), py::arg("rotate") = py::none(), py::kw_only(),
          py::arg("euler") = py::none(),
          R"(Drags `control` so that its world translation and rotation (a quaternion, or euler= degrees)
become these (None: unchanged); selects it when it is not. Returns what drag() returns.)")
      .def(
          "release", [](const WorkspaceRef& w) { edit(w, [](app::Workspace& ws) { ws.release(); }); },
          "Ends the gesture: the next drag is a new undo step.")
      .def(
          "undo", [](const WorkspaceRef& w) { return unwrap(w.ws->undo()); },
          "Undoes one step and returns its label; StateError when there is nothing to undo.")
      .def(
          "redo", [](const WorkspaceRef& w) { return unwrap(w.ws->redo()); },
          "Redoes one step and returns its label; StateError when there is nothing to redo.");
}

void def_time_and_keys(WorkspaceClass& cls) {
  auto set_frame = [](const WorkspaceRef& w, double frame) { edit(w, [&](app::Workspace& ws) { check(ws.set_frame(frame)); }); };
  auto set_time = [](const WorkspaceRef& w, double time) { edit(w, [&](app::Workspace& ws) { check(ws.set_time(time)); }); };
  cls.def("set_frame", set_frame, py::arg("frame"), "Moves the current time to a frame (at most 1e6 either side of 0).")
      .def("set_time", set_time, py::arg("time"), "Moves the current time to `time` seconds.")
      .def_property(
          "frame", [](const WorkspaceRef& w) { return w.ws->scene().frame(); }, set_frame, "The current time in frames.")
      .def_property(
          "time", [](const WorkspaceRef& w) { return w.ws->graph().time(); }, set_time, "The current time in seconds.")
      .def(
          "keys",
          [](const WorkspaceRef& w, const std::optional<std::vector<NodeArg>>& controls) {
            return keys_record(w.scene, w.ws->keys(controls_or_selection(w, controls)));
          },
          py::arg("controls") = py::none(),
          "The keys of controls (default: the selection): scope, set (the keying set), times (seconds), frames.")
      .def(
          "set_key",
          [](const WorkspaceRef& w, const std::optional<std::vector<NodeArg>>& controls) {
            const std::vector<NodeId> ids = controls_or_selection(w, controls);
            return keys_record(w.scene, edit(w, [&](app::Workspace& ws) { return unwrap(ws.set_key(ids)); }));
          },
          py::arg("controls") = py::none(), "Keys the controls' keying set (default: the selection's) now; returns keys().")
      .def(
          "delete_key",
          [](const WorkspaceRef& w, const std::optional<std::vector<NodeArg>>& controls) {
            const std::vector<NodeId> ids = controls_or_selection(w, controls);
            return keys_record(w.scene, edit(w, [&](app::Workspace& ws) { return unwrap(ws.delete_key(ids)); }));
          },
          py::arg("controls") = py::none(), "Deletes the keying set's keys now; returns keys().")
      .def(
          "set_channel_keys",
          [](const WorkspaceRef& w, const std::optional<std::vector<NodeArg>>& controls,
             const std::vector<std::string>& attrs, std::optional<double> value, const std::optional<std::string>& tangent,
             const std::optional<std::string>& in_tangent, const std::optional<std::string>& out_tangent) {
            const std::vector<NodeId> ids = key_nodes_arg(w, controls);
            tools::Tangents tangents;
            auto type = [](const std::optional<std::string>& name, const char* field) -> std::optional<ops::anim::TangentType> {
              if (!name) return std::nullopt;
              auto t = ops::anim::tangent_type_from_name(*name);
              if (!t) raise(Status(ErrorCode::kInvalidArgument, std::string(field) + ": '" + *name + "' is not a tangent type").with_field(field));
              return t;
            };
            if (auto both = type(tangent, "tangent")) tangents.in = tangents.out = both;
            if (auto in = type(in_tangent, "in_tangent")) tangents.in = in;
            if (auto out = type(out_tangent, "out_tangent")) tangents.out = out;
            return plug_keys_list(
                w, edit(w, [&](app::Workspace& ws) { return unwrap(ws.set_channel_keys(ids, attrs, value, tangents)); }));
          },
          py::arg("controls") = py::none(), py::arg("attrs") = std::vector<std::string>{}, py::arg("value") = py::none(),
          py::arg("tangent") = py::none(), py::arg("in_tangent") = py::none(), py::arg("out_tangent") = py::none(),
          R"(Keys any rig's controls and switches now (default: the selection). Without `attrs` every keyable
channel of their keying group (a built rig's whole character, an ephemeral rig's keying set); with
`attrs` (e.g. ["fkIk"]) those channels of the nodes given. `value` keys a scalar channel at that value;
`tangent` (or `in_tangent` / `out_tangent`) gives the keys that tangent type (auto, spline, linear,
flat, step, stepNext, clamped, plateau, fixed).
Returns the channels' keys: records (plug, times, frames, values).)")
      .def(
          "delete_channel_keys",
          [](const WorkspaceRef& w, const std::optional<std::vector<NodeArg>>& controls, const std::vector<std::string>& attrs) {
            const std::vector<NodeId> ids = key_nodes_arg(w, controls);
            return plug_keys_list(w, edit(w, [&](app::Workspace& ws) { return unwrap(ws.delete_channel_keys(ids, attrs)); }));
          },
          py::arg("controls") = py::none(), py::arg("attrs") = std::vector<std::string>{},
          "Deletes the channels' keys now (as set_channel_keys chooses them); NotFoundError when none has one.")
      .def(
          "channel_keys",
          [](const WorkspaceRef& w, const std::optional<std::vector<NodeArg>>& controls, const std::vector<std::string>& attrs) {
            return plug_keys_list(w, unwrap(w.ws->channel_keys(key_nodes_arg(w, controls), attrs)));
          },
          py::arg("controls") = py::none(), py::arg("attrs") = std::vector<std::string>{},
          "The keys of the nodes' own channels (those named, or every keyable one): records (plug, times, frames, values).");
}

// The animator tools (tools/: tween, FK/IK match, mirror, bind pose).
void def_animator_tools(WorkspaceClass& cls) {
  cls.def(
          "tween",
          [](const WorkspaceRef& w, const std::optional<std::vector<NodeArg>>& controls, const std::vector<std::string>& attrs,
             double fraction, bool key) {
            const std::vector<NodeId> ids = key_nodes_arg(w, controls);
            return plug_keys_list(w, edit(w, [&](app::Workspace& ws) { return unwrap(ws.tween(ids, attrs, fraction, key)); }));
          },
          py::arg("controls") = py::none(), py::arg("attrs") = std::vector<std::string>{}, py::arg("fraction") = 0.5,
          py::arg("key") = true,
          R"(Tween / breakdown now: the channels set_channel_keys would key (default: the selection's keying group),
each set between its previous and next key by `fraction` (0: the previous, 1: the next, beyond: overshoot;
rotations by quaternion slerp), keyed (key=False: only keys already there change). Returns the channels'
keys as records.)")
      .def(
          "match",
          [](const WorkspaceRef& w, const std::string& rig, const std::string& component, const std::string& to,
             const std::optional<std::pair<double, double>>& frames, bool key) {
            if (to != "fk" && to != "ik") raise(ErrorCode::kInvalidArgument, "to: expected 'fk' or 'ik', got '" + to + "'");
            tools::MatchOptions options;
            options.to = to == "fk" ? rig::components::MatchSide::kFk : rig::components::MatchSide::kIk;
            if (frames) {
              options.first = frames->first;
              options.last = frames->second;
            }
            options.key = key;
            const tools::MatchReport r = edit(w, [&](app::Workspace& ws) { return unwrap(ws.match(rig, component, options)); });
            py::dict d;
            d["frames"] = r.frames;
            d["keys"] = r.keys;
            py::list controls;
            for (NodeId c : r.controls) controls.append(node_ref(w.scene, c));
            d["controls"] = controls;
            d["max_error"] = r.max_error;
            d["worst_frame"] = r.worst_frame;
            return record(d);
          },
          py::arg("rig"), py::arg("component"), py::arg("to"), py::arg("frames") = py::none(), py::arg("key") = true,
          R"(FK/IK match and bake of a limb (`component`: its name or rigId): to="fk" keys its FK controls (and
a foot's FK toe) to the IK pose, to="ik" its ik and pole controls (and a foot's toe tap) to the FK pose,
at the current frame or at every frame of `frames` (first, last), and keys the switch to that side with
step tangents at the range's ends. key=False sets one frame without keying. Returns a record (frames,
keys, controls, max_error: the largest driven-joint difference between the sides afterwards, worst_frame).)")
      .def(
          "mirror",
          [](const WorkspaceRef& w, const std::optional<std::vector<NodeArg>>& controls, bool all, bool flip,
             const std::string& side, const std::string& plane, const std::optional<std::pair<double, double>>& frames,
             bool key) {
            if (side != "L" && side != "R") raise(ErrorCode::kInvalidArgument, "side: expected 'L' or 'R', got '" + side + "'");
            if (plane != "yz" && plane != "xy" && plane != "xz")
              raise(ErrorCode::kInvalidArgument, "plane: expected 'yz', 'xy' or 'xz', got '" + plane + "'");
            tools::MirrorOptions options;
            if (controls) options.controls = key_nodes_arg(w, controls);
            else if (!all) options.controls = w.ws->selection();
            options.all = all;
            options.flip = flip;
            options.from = side[0];
            options.plane = plane == "yz" ? tools::MirrorPlane::kYZ : plane == "xy" ? tools::MirrorPlane::kXY
                                                                                    : tools::MirrorPlane::kXZ;
            if (frames) {
              options.first = frames->first;
              options.last = frames->second;
            }
            options.key = key;
            const tools::MirrorReport r = edit(w, [&](app::Workspace& ws) { return unwrap(ws.mirror(options)); });
            py::dict d;
            d["frames"] = r.frames;
            d["keys"] = r.keys;
            py::list set;
            for (NodeId n : r.set) set.append(node_ref(w.scene, n));
            d["set"] = set;
            return record(d);
          },
          py::arg("controls") = py::none(), py::arg("all") = false, py::arg("flip") = false, py::arg("side") = "L",
          py::arg("plane") = "yz", py::arg("frames") = py::none(), py::arg("key") = true,
          R"(Mirrors built rigs' controls (default: the selection) onto their pairs on the other side, or with
flip=True swaps both sides (centre controls mirror in place); all=True takes every control of their rigs
(every rig without controls) from `side`, switches and foot values too. Pairs come from the components
(type and name, other side), never node names. At the current frame, or keyed at every frame of `frames`.
Returns a record (frames, keys, set: the nodes it set).)")
      .def(
          "reset_bind_pose",
          [](const WorkspaceRef& w, const std::optional<std::vector<NodeArg>>& nodes, bool key) {
            std::vector<NodeId> ids;
            if (nodes) {
              for (const NodeArg& n : *nodes) ids.push_back(resolve(w.scene, n));
            } else {
              ids = w.ws->selection();
            }
            const tools::BindPoseReport r = edit(w, [&](app::Workspace& ws) { return unwrap(ws.reset_bind_pose(ids, key)); });
            py::dict d;
            d["channels"] = r.channels;
            py::list set;
            for (NodeId n : r.set) set.append(node_ref(w.scene, n));
            d["set"] = set;
            return record(d);
          },
          py::arg("nodes") = py::none(), py::arg("key") = false,
          R"(Resets controls, components (scene.resolve("hero:arm_L")) or rigs (scene.resolve("hero:")), default the
selection, to their bind pose now: controls to their rest as built, switches and foot values to theirs; keyed
when key=True. Returns a record (channels, set).)");
}


py::object step_record(const app::StepReport& r) {
  py::dict d;
  d["rig"] = r.rig;
  d["position"] = r.position;
  d["steps"] = r.steps;
  d["step"] = r.step;
  d["rig_id"] = r.rig_id;
  return record(d);
}

py::object feature_record(const app::FeatureReport& r) {
  py::dict d;
  d["rig"] = r.rig;
  d["features"] = features_list(r.features);
  d["position"] = r.position;
  d["steps"] = r.steps;
  return record(d);
}

py::object commit_record(app::CommitReport r) {
  py::dict d;
  d["rig"] = r.rig;
  d["version"] = r.version;
  d["definition"] = std::make_shared<rig::Definition>(std::move(r.definition));
  d["changed"] = r.changed;
  d["ignored"] = r.ignored;
  d["definition_path"] = path_or_none(r.definition_path);
  d["edit_mode"] = r.edit_mode;
  return record(d);
}

py::object added_record(const rig::AddedRig& r) {
  py::dict d;
  d["name"] = r.name;
  d["version"] = r.version;
  d["steps"] = r.steps;
  d["components"] = r.components;
  return record(d);
}

py::object update_record(const rig::UpdateReport& r) {
  py::dict d;
  d["rig"] = r.rig;
  d["from_version"] = r.from;
  d["to_version"] = r.to;
  d["definition"] = r.definition;
  d["updated"] = r.updated;
  d["rebuilt"] = r.rebuilt;
  return record(d);
}

void def_rigs(WorkspaceClass& cls) {
  cls.def(
         "rigs",
         [](const WorkspaceRef& w) {
           py::list out;
           for (const app::RigEntry& e : w.ws->rigs()) out.append(rig_entry_record(e));
           return out;
         },
         "The rigs: the scene's, then those stepped back to step 0 (unbuilt): name, unbuilt, steps, features, "
         "version, definition, definition_version, edit_mode.")
      .def(
          "add_rig",
          [](const WorkspaceRef& w, const std::string& definition, bool edit_mode, const std::string& naming_template) {
            const fs::path p = unwrap(w.ws->resolve_path(definition, "definition"));
            rig::BuildOptions options;
            options.edit_mode = edit_mode;
            options.naming_template = naming_template;
            return added_record(edit(w, [&](app::Workspace& ws) { return unwrap(ws.add_rig(p, options)); }));
          },
          py::arg("definition"), py::arg("edit_mode") = false, py::arg("naming_template") = "",
          "Builds a definition file (`rigel build`), its nodes named by `naming_template` (the setting naming.template; \"\": the default): name, version, steps, components.")
      .def(
          "update_rig",
          [](const WorkspaceRef& w, const std::string& name, const std::optional<std::string>& definition, bool force,
             const std::string& keep_keys) {
            const fs::path p = path_arg(w, definition, "definition");
            const rig::Build::KeepKeys keep = keep_keys_from_name(keep_keys);
            return update_record(edit(w, [&](app::Workspace& ws) { return unwrap(ws.update_rig(name, p, force, keep)); }));
          },
          py::arg("rig"), py::arg("definition") = py::none(), py::arg("force") = false, py::arg("keep_keys") = "local",
          "`rigel update`: rebuilds the components whose version changed (all with force): rig, from_version, "
          "to_version, definition, updated, rebuilt.")
      .def(
          "remove_rig", [](const WorkspaceRef& w, const std::string& name) { edit(w, [&](app::Workspace& ws) { check(ws.remove_rig(name)); }); },
          py::arg("rig"), "Removes a rig: exactly what its metadata network links to.")
      .def(
          "step_rig",
          [](const WorkspaceRef& w, const std::string& name, std::optional<int> to, int by) {
            return step_record(edit(w, [&](app::Workspace& ws) { return unwrap(ws.step_rig(name, to, by)); }));
          },
          py::arg("rig"), py::arg("to") = py::none(), py::arg("by") = 0,
          "Moves the rig's build to step `to`, or `by` steps (clamped): rig, position, steps, step (its label).")
      .def(
          "set_feature",
          [](const WorkspaceRef& w, const std::string& name, const std::string& feature, bool enabled, const std::string& switch_name) {
            return feature_record(edit(w, [&](app::Workspace& ws) { return unwrap(ws.set_feature(name, feature, switch_name, enabled)); }));
          },
          py::arg("rig"), py::arg("feature"), py::arg("enabled") = true, py::arg("switch") = "",
          "Enables or disables a feature (or one switch of it) of the rig's steps: rig, features, position, steps.")
      .def(
          "set_edit_mode",
          [](const WorkspaceRef& w, const std::string& name, bool on) {
            return edit(w, [&](app::Workspace& ws) { return unwrap(ws.set_edit_mode(name, on)); });
          },
          py::arg("rig"), py::arg("on") = true, "Rig edit mode on or off; returns whether it is on.")
      .def(
          "commit_edits",
          [](const WorkspaceRef& w, const std::string& name, const std::optional<std::string>& definition_out, bool keep_editing) {
            const fs::path out = path_arg(w, definition_out, "definitionOut");
            return commit_record(edit(w, [&](app::Workspace& ws) { return unwrap(ws.commit_edits(name, out, keep_editing)); }));
          },
          py::arg("rig"), py::arg("definition_out") = py::none(), py::arg("keep_editing") = false,
          R"(Commits the guides moved in edit mode to the definition, saved at definition_out (default:
the rig's definition file), and leaves edit mode unless keep_editing: rig, version, definition,
changed, ignored, definition_path, edit_mode.)");
}

void def_definitions(WorkspaceClass& cls) {
  cls.def(
         "definition",
         [](const WorkspaceRef& w, const std::string& name) { return std::make_shared<rig::Definition>(unwrap(w.ws->definition(name))); },
         py::arg("rig"), "The rig's definition as built (a copy).")
      .def(
          "component_types", [](const WorkspaceRef& w) { return w.ws->component_types(); }, "The component types builds know.")
      .def(
          "check_definition",
          [](const WorkspaceRef& w, const std::string& text, const std::string& syntax, const std::string& source) {
            app::CheckedDefinition c = w.ws->check_definition(text, syntax_from_name(syntax), source);
            py::dict d;
            d["definition"] = std::make_shared<rig::Definition>(std::move(c.definition));
            d["problems"] = c.problems;
            return record(d);
          },
          py::arg("text"), py::arg("syntax") = "xml", py::arg("source") = "<string>",
          "Parses and validates definition text: (definition, problems: [Diagnostic]; empty when it can build).")
      .def(
          "build_definition",
          [](const WorkspaceRef& w, const DefinitionRef& definition) {
            app::BuildReport r = edit(w, [&](app::Workspace& ws) { return unwrap(ws.build_definition(*definition)); });
            py::dict d;
            d["rig"] = r.rig;
            d["rebuilt"] = r.rebuilt;
            return record(d);
          },
          py::arg("definition"),
          "Builds the definition, or live-rebuilds the components that changed when the scene has its rig (one undo "
          "step): rig, rebuilt (rigIds).")
      .def(
          "save_definition",
          [](const WorkspaceRef& w, const DefinitionRef& definition, const std::string& path) {
            const fs::path p = unwrap(w.ws->resolve_path(path, "path"));
            app::SavedDefinition saved = unwrap(w.ws->save_definition(*definition, p));
            py::dict d;
            d["path"] = saved.path.string();
            d["version"] = saved.version;
            return record(d);
          },
          py::arg("definition"), py::arg("path"),
          "Saves the definition (.rig.xml or .rig.json); over a file with other content the version moves to the "
          "next one: path, version.");
}

}  // namespace

void wrap_workspace(py::module_& m) {
  WorkspaceClass cls(m, "Workspace", R"(The service layer every driver shares (app::Workspace): a scene, its posing
session and its rigs, and what a user can do to them: select, pose (ephemeral and
built rigs), keys, time, undo, saves, rigs (add, update, remove, step, features, edit
mode, commit), definitions (check, build or live rebuild, versioned save) and
reports. What `rigel pose`, `rigel ephemeral key` and `rigel serve` do, they do
through it. Errors name the argument at fault (`e.field`); StateError: the scene
cannot do it in its state.)");
  def_state(cls);
  def_reports(cls);
  def_posing(cls);
  def_time_and_keys(cls);
  def_animator_tools(cls);
  def_transfer_and_values(cls);
  def_curves(cls);
  def_scene_settings(cls);
  def_rigging(cls);
  def_data(cls);
  def_graphs(cls);
  def_space_tools(cls);
  def_poses(cls);
  def_rigs(cls);
  def_definitions(cls);
}

}  // namespace rigel::python
