// Ephemeral rigs (docs/EPHEMERAL.md) as module functions: setup, the rigs
// and controls of a scene, and the relations between controls.

#include "common.h"
#include "rigel/ephemeral/rig.h"

namespace rigel::python {

namespace eph = ephemeral;

NodeId ephemeral_rig(const SceneRef& s, const NodeArg& arg) {
  const NodeId id = resolve(s, arg);
  if (s->graph().node(id)->type().name() != eph::kRigType)
    raise(ErrorCode::kInvalidArgument, "'" + s->graph().node(id)->name() + "' is not an ephemeralRig node");
  return id;
}

namespace {

eph::RelationKind kind_from(const std::string& name) {
  if (std::optional<eph::RelationKind> kind = eph::relation_kind_from_name(name)) return *kind;
  raise(ErrorCode::kInvalidArgument, "relation kind '" + name + "': expected forward, inverse, pair or magnet");
}

py::list relation_list(const SceneRef& s, const std::vector<eph::Relation>& relations) {
  py::list out;
  for (const eph::Relation& r : relations)
    out.append(py::make_tuple(eph::relation_kind_name(r.kind), node_ref(s, r.from), node_ref(s, r.to)));
  return out;
}

}  // namespace

void wrap_ephemeral(py::module_& m) {
  m.def(
      "setup_ephemeral",
      [](const SceneRef& s, std::optional<std::vector<NodeArg>> joints, const std::string& control_suffix,
         const std::string& rig_name, bool keep_animation, double shape_radius, bool size_from_bones) {
        eph::SetupOptions options;
        if (joints) options.joints = resolve_all(s, *joints);
        options.control_suffix = control_suffix;
        options.rig_name = rig_name;
        options.keep_animation = keep_animation;
        options.shape_radius = shape_radius;
        options.size_from_bones = size_from_bones;
        eph::SetupResult r = unwrap(eph::setup_ephemeral(*s, options));
        py::dict d;
        d["rig"] = node_ref(s, r.rig);
        d["joints"] = node_list(s, r.joints);
        d["controls"] = node_list(s, r.controls);
        return record(d);
      },
      py::arg("scene"), py::arg("joints") = py::none(), py::arg("control_suffix") = "_ctrl",
      py::arg("rig_name") = "ephemeralRig", py::arg("keep_animation") = true, py::arg("shape_radius") = 0.0, py::arg("size_from_bones") = false,
      R"(Builds an ephemeral rig: one control per joint (all joints, or `joints`), mirroring the
hierarchy and driving the joint's channels. One undo step. Returns (rig, joints, controls).)");
  m.def(
      "ephemeral_rigs", [](const SceneRef& s) { return node_list(s, eph::rigs_find(s->graph())); }, py::arg("scene"),
      "Every ephemeralRig node.");
  m.def(
      "ephemeral_controls",
      [](const SceneRef& s, const NodeArg& rig) { return node_list(s, eph::rig_controls(s->graph(), ephemeral_rig(s, rig))); },
      py::arg("scene"), py::arg("rig"), "The controls of an ephemeral rig.");
  m.def(
      "control_of", [](const SceneRef& s, const NodeArg& n) { return node_or_none(s, eph::control_of(s->graph(), resolve(s, n))); },
      py::arg("scene"), py::arg("node"), "The ephemeral control standing for a control or joint, or None.");
  m.def(
      "relations",
      [](const SceneRef& s, const NodeArg& rig) {
        return relation_list(s, unwrap(eph::relations(s->graph(), ephemeral_rig(s, rig))));
      },
      py::arg("scene"), py::arg("rig"), "The rig's relations as (kind, from, to).");
  m.def(
      "relation_add",
      [](const SceneRef& s, const NodeArg& rig, const std::string& kind, const NodeArg& from, const NodeArg& to) {
        check(eph::relation_add(s->graph(), ephemeral_rig(s, rig), eph::Relation{kind_from(kind), resolve(s, from), resolve(s, to)}));
      },
      py::arg("scene"), py::arg("rig"), py::arg("kind"), py::arg("source"), py::arg("target"));
  m.def(
      "relation_remove",
      [](const SceneRef& s, const NodeArg& rig, const std::string& kind, const NodeArg& from, const NodeArg& to) {
        check(eph::relation_remove(s->graph(), ephemeral_rig(s, rig),
                                   eph::Relation{kind_from(kind), resolve(s, from), resolve(s, to)}));
      },
      py::arg("scene"), py::arg("rig"), py::arg("kind"), py::arg("source"), py::arg("target"));
}

}  // namespace rigel::python
