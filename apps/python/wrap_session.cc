// rigel.Session: the ephemeral posing session (docs/EPHEMERAL.md): modes,
// options, select, drag, release, the plan and body mode's pivot.

#include "common.h"
#include "rigel/ephemeral/session.h"

namespace rigel::python {
namespace {

namespace eph = ephemeral;

// The session and the scene it observes (kept alive; the session goes first).
struct SessionRef {
  SceneRef scene;
  std::unique_ptr<eph::Session> session;
};

using SessionClass = py::class_<SessionRef>;

SessionRef make_session(const SceneRef& s, const std::string& mode, double magnet_fraction, double magnet_min_weight,
                        double magnet_radius, int max_chain, bool auto_key) {
  eph::SessionOptions options;
  options.magnet_fraction = magnet_fraction;
  options.magnet_min_weight = magnet_min_weight;
  options.magnet_radius = magnet_radius;
  options.max_chain = max_chain;
  options.auto_key = auto_key;
  check(options.validate());  // the field in Python's spelling (module.cc): magnet_fraction
  const eph::Mode m = mode_from(mode);
  SessionRef r{s, std::make_unique<eph::Session>(*s, options)};
  r.session->set_mode(m);
  return r;
}

void def_state(SessionClass& cls) {
  cls.def(py::init(&make_session), py::arg("scene"), py::arg("mode") = "forward", py::arg("magnet_fraction") = 0.65,
          py::arg("magnet_min_weight") = 0.01, py::arg("magnet_radius") = 1.0, py::arg("max_chain") = 0,
          py::arg("auto_key") = false)
      .def_static("modes", &mode_names, "Mode names.")
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
          });
}

void def_posing(SessionClass& cls) {
  cls.def(
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
          "release", [](const SessionRef& r) { r.session->release(); }, "Ends the gesture (drops the plan).");
}

void def_plan(SessionClass& cls) {
  cls.def_property_readonly("has_plan", [](const SessionRef& r) { return r.session->has_plan(); })
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

}  // namespace

void wrap_session(py::module_& m) {
  SessionClass cls(m, "Session", R"(The ephemeral posing session (seed 000's master node): a mode, the
grabbed controls (the scene's selection) and, while dragging, a plan. All
drags between a selection and release() are one undo step.)");
  def_state(cls);
  def_posing(cls);
  def_plan(cls);
}

}  // namespace rigel::python
