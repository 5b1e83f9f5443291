// Ephemeral rigs (docs/EPHEMERAL.md): setup, relations, the posing session
// (modes, select, drag, release) and keys.

#include <cctype>

#include "common.h"
#include "rigel/ephemeral/keying.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/ephemeral/session.h"

namespace rigel::python {
namespace {

namespace eph = ephemeral;

eph::Mode mode_from(const std::string& name) {
  if (std::optional<eph::Mode> mode = eph::mode_from_name(name)) return *mode;
  std::string modes;
  for (int i = 0; i < eph::kModeCount; ++i) modes += std::string(i ? ", " : "") + eph::mode_name(static_cast<eph::Mode>(i));
  raise(ErrorCode::kInvalidArgument, "mode '" + name + "': unknown mode; modes: " + modes);
}

eph::RelationKind kind_from(const std::string& name) {
  if (std::optional<eph::RelationKind> kind = eph::relation_kind_from_name(name)) return *kind;
  raise(ErrorCode::kInvalidArgument, "relation kind '" + name + "': expected forward, inverse, pair or magnet");
}

NodeId rig_arg(const SceneRef& s, const NodeArg& arg) {
  const NodeId id = resolve(s, arg);
  if (s->graph().node(id)->type().name() != eph::kRigType)
    raise(ErrorCode::kInvalidArgument, "'" + s->graph().node(id)->name() + "' is not an ephemeralRig node");
  return id;
}

// The session and the scene it observes (kept alive; the session goes first).
struct SessionRef {
  SceneRef scene;
  std::unique_ptr<eph::Session> session;
};

py::list relation_list(const SceneRef& s, const std::vector<eph::Relation>& relations) {
  py::list out;
  for (const eph::Relation& r : relations)
    out.append(py::make_tuple(eph::relation_kind_name(r.kind), node_ref(s, r.from), node_ref(s, r.to)));
  return out;
}

// The options' one range check (SessionOptions::validate), its message naming
// the Python argument: magnet_fraction, not magnetFraction.
void check_options(const eph::SessionOptions& options) {
  const Status s = options.validate();
  if (s) return;
  std::string arg;
  for (char c : s.field()) {
    if (std::isupper(static_cast<unsigned char>(c))) arg += '_', arg += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    else arg += c;
  }
  std::string message = s.message();
  if (message.rfind(s.field() + ": ", 0) == 0) message = arg + ": " + message.substr(s.field().size() + 2);
  raise(s.code(), message);
}

}  // namespace

void bind_ephemeral(py::module_& m) {
  m.def(
      "setup_ephemeral",
      [](const SceneRef& s, std::optional<std::vector<NodeArg>> joints, const std::string& control_suffix,
         const std::string& rig_name, bool keep_animation, double shape_radius) {
        eph::SetupOptions options;
        if (joints) options.joints = resolve_all(s, *joints);
        options.control_suffix = control_suffix;
        options.rig_name = rig_name;
        options.keep_animation = keep_animation;
        options.shape_radius = shape_radius;
        eph::SetupResult r = unwrap(eph::setup_ephemeral(*s, options));
        py::dict d;
        d["rig"] = node_ref(s, r.rig);
        d["joints"] = node_list(s, r.joints);
        d["controls"] = node_list(s, r.controls);
        return record(d);
      },
      py::arg("scene"), py::arg("joints") = py::none(), py::arg("control_suffix") = "_ctrl",
      py::arg("rig_name") = "ephemeralRig", py::arg("keep_animation") = true, py::arg("shape_radius") = 0.0,
      R"(Builds an ephemeral rig: one control per joint (all joints, or `joints`), mirroring the
hierarchy and driving the joint's channels. One undo step. Returns (rig, joints, controls).)");
  m.def(
      "ephemeral_rigs", [](const SceneRef& s) { return node_list(s, eph::rigs_find(s->graph())); }, py::arg("scene"),
      "Every ephemeralRig node.");
  m.def(
      "ephemeral_controls",
      [](const SceneRef& s, const NodeArg& rig) { return node_list(s, eph::rig_controls(s->graph(), rig_arg(s, rig))); },
      py::arg("scene"), py::arg("rig"), "The controls of an ephemeral rig.");
  m.def(
      "control_of", [](const SceneRef& s, const NodeArg& n) { return node_or_none(s, eph::control_of(s->graph(), resolve(s, n))); },
      py::arg("scene"), py::arg("node"), "The ephemeral control standing for a control or joint, or None.");
  m.def(
      "relations",
      [](const SceneRef& s, const NodeArg& rig) { return relation_list(s, unwrap(eph::relations(s->graph(), rig_arg(s, rig)))); },
      py::arg("scene"), py::arg("rig"), "The rig's relations as (kind, from, to).");
  m.def(
      "relation_add",
      [](const SceneRef& s, const NodeArg& rig, const std::string& kind, const NodeArg& from, const NodeArg& to) {
        check(eph::relation_add(s->graph(), rig_arg(s, rig), eph::Relation{kind_from(kind), resolve(s, from), resolve(s, to)}));
      },
      py::arg("scene"), py::arg("rig"), py::arg("kind"), py::arg("source"), py::arg("target"));
  m.def(
      "relation_remove",
      [](const SceneRef& s, const NodeArg& rig, const std::string& kind, const NodeArg& from, const NodeArg& to) {
        check(eph::relation_remove(s->graph(), rig_arg(s, rig), eph::Relation{kind_from(kind), resolve(s, from), resolve(s, to)}));
      },
      py::arg("scene"), py::arg("rig"), py::arg("kind"), py::arg("source"), py::arg("target"));

  // ---- keys ------------------------------------------------------------------------------
  m.def(
      "set_key", [](const SceneRef& s, const std::vector<NodeArg>& controls) { check(eph::set_key(s->graph(), resolve_all(s, controls))); },
      py::arg("scene"), py::arg("controls"),
      "Keys the keying set of `controls` (their characters, with scope 'character') at the scene's time.");
  m.def(
      "delete_key",
      [](const SceneRef& s, const std::vector<NodeArg>& controls) { check(eph::delete_key(s->graph(), resolve_all(s, controls))); },
      py::arg("scene"), py::arg("controls"), "Removes the keying set's keys at the scene's time.");
  m.def(
      "key_times",
      [](const SceneRef& s, const std::vector<NodeArg>& controls) { return eph::key_times(s->graph(), resolve_all(s, controls)); },
      py::arg("scene"), py::arg("controls"), "Sorted key times in seconds (frames: t * scene.fps).");
  m.def(
      "keying_set",
      [](const SceneRef& s, const std::vector<NodeArg>& controls) {
        return node_list(s, eph::keying_set(s->graph(), resolve_all(s, controls)));
      },
      py::arg("scene"), py::arg("controls"), "What a key on `controls` keys.");
  m.def(
      "has_key", [](const SceneRef& s, const NodeArg& c) { return eph::has_key_now(s->graph(), resolve(s, c)); },
      py::arg("scene"), py::arg("control"), "Whether the control has a key at the scene's time.");
  m.def(
      "is_keyed", [](const SceneRef& s, const NodeArg& c) { return eph::is_keyed(s->graph(), resolve(s, c)); },
      py::arg("scene"), py::arg("control"));
  m.def(
      "key_scope",
      [](const SceneRef& s, const NodeArg& rig) { return std::string(eph::key_scope_name(eph::key_scope(s->graph(), rig_arg(s, rig)))); },
      py::arg("scene"), py::arg("rig"), "'character' or 'controls'.");
  m.def(
      "set_key_scope",
      [](const SceneRef& s, const NodeArg& rig, const std::string& scope) {
        const std::optional<eph::KeyScope> k = eph::key_scope_from_name(scope);
        if (!k) raise(ErrorCode::kInvalidArgument, "key scope '" + scope + "': expected 'character' or 'controls'");
        check(eph::set_key_scope(s->graph(), rig_arg(s, rig), *k));
      },
      py::arg("scene"), py::arg("rig"), py::arg("scope"));

  // ---- Session -------------------------------------------------------------------------------
  py::class_<SessionRef>(m, "Session", R"(The ephemeral posing session (seed 000's master node): a mode, the
grabbed controls (the scene's selection) and, while dragging, a plan. All
drags between a selection and release() are one undo step.)")
      .def(py::init([](const SceneRef& s, const std::string& mode, double magnet_fraction, double magnet_min_weight,
                       double magnet_radius, int max_chain, bool auto_key) {
             eph::SessionOptions options;
             options.magnet_fraction = magnet_fraction;
             options.magnet_min_weight = magnet_min_weight;
             options.magnet_radius = magnet_radius;
             options.max_chain = max_chain;
             options.auto_key = auto_key;
             check_options(options);
             const eph::Mode m = mode_from(mode);
             SessionRef r{s, std::make_unique<eph::Session>(*s, options)};
             r.session->set_mode(m);
             return r;
           }),
           py::arg("scene"), py::arg("mode") = "forward", py::arg("magnet_fraction") = 0.65,
           py::arg("magnet_min_weight") = 0.01, py::arg("magnet_radius") = 1.0, py::arg("max_chain") = 0,
           py::arg("auto_key") = false)
      .def_static(
          "modes",
          [] {
            std::vector<std::string> out;
            for (int i = 0; i < eph::kModeCount; ++i) out.emplace_back(eph::mode_name(static_cast<eph::Mode>(i)));
            return out;
          },
          "Mode names.")
      .def_property_readonly("scene", [](const SessionRef& r) { return r.scene; })
      .def_property(
          "mode", [](const SessionRef& r) { return std::string(eph::mode_name(r.session->mode())); },
          [](const SessionRef& r, const std::string& name) { r.session->set_mode(mode_from(name)); },
          "forward, suspended, pseudo-inverse, pseudo-inverse-length, inverse, magnet, magnet-radius, body.")
      .def_property(
          "auto_key", [](const SessionRef& r) { return r.session->options().auto_key; },
          [](const SessionRef& r, bool on) {
            eph::SessionOptions o = r.session->options();
            o.auto_key = on;
            r.session->set_options(o);
          })
      .def(
          "select",
          [](const SessionRef& r, const std::vector<NodeArg>& controls) { r.session->select(resolve_all(r.scene, controls)); },
          py::arg("controls"), "Grabs controls (joints stand for their controls); drops the plan.")
      .def_property_readonly(
          "grabbed", [](const SessionRef& r) { return node_list(r.scene, r.session->grabbed()); },
          "The grabbed controls, hierarchy order.")
      .def(
          "drag",
          [](const SessionRef& r, py::object translate, py::object rotate, py::object scale) {
            eph::Delta delta;
            if (!translate.is_none()) delta.translate = vec3_from_python(translate, "drag translate");
            if (!rotate.is_none()) delta.rotate = rotation_from_python(rotate, "drag rotate");
            if (!scale.is_none()) delta.scale = vec3_from_python(scale, "drag scale");
            check(r.session->drag(delta));
          },
          py::arg("translate") = py::none(), py::arg("rotate") = py::none(), py::arg("scale") = py::none(),
          R"(Moves the grabbed controls by a world-space delta: translate (x, y, z); rotate as degrees
(x, y, z), XYZ order, about each control's pivot, or a quaternion (x, y, z, w); scale (body mode).)")
      .def(
          "drag_to",
          [](const SessionRef& r, const NodeArg& control, py::object world) {
            check(r.session->drag_to(resolve(r.scene, control), matrix_from_python(world, "drag_to world")));
          },
          py::arg("control"), py::arg("world"), "Moves so that a grabbed control reaches a world matrix.")
      .def(
          "release", [](const SessionRef& r) { r.session->release(); }, "Ends the gesture (drops the plan).")
      .def_property_readonly("has_plan", [](const SessionRef& r) { return r.session->has_plan(); })
      .def_property_readonly("plans_built", [](const SessionRef& r) { return r.session->plans_built(); })
      .def(
          "plan",
          [](const SessionRef& r) {
            const eph::Plan* plan = unwrap(r.session->plan());
            py::list out;
            for (const eph::PlanEntry& e : plan->entries) {
              py::dict d;
              d["control"] = node_ref(r.scene, e.control);
              d["role"] = eph::role_name(e.role);
              d["driver"] = e.driver < 0 ? py::object(py::none())
                                         : py::cast(node_ref(r.scene, plan->entries[static_cast<std::size_t>(e.driver)].control));
              d["weight"] = e.weight;
              out.append(record(d));
            }
            return out;
          },
          "Builds the plan if needed: each control that moves with its role, driver and weight.")
      .def_property(
          "body_pivot",
          [](const SessionRef& r) -> py::object {
            const std::optional<math::Mat4> p = r.session->body_pivot();
            return p ? py::object(matrix_to_python(*p)) : py::object(py::none());
          },
          [](const SessionRef& r, py::object world) {
            if (world.is_none()) {
              r.session->clear_body_pivot();
            } else {
              r.session->set_body_pivot(matrix_from_python(world, "body_pivot"));
            }
          },
          "Body mode's pivot (world matrix), or None: the first grabbed control.");
}

}  // namespace rigel::python
