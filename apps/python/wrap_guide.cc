// rigel.Guide: where one joint or control of a component goes.

#include "rig_common.h"

namespace rigel::python {

void wrap_guide(py::module_& m) {
  py::class_<rig::Guide>(m, "Guide", R"(Where one joint or control of a component goes: a character joint
(`joint`; translate/rotate/scale are then an offset in its space) or values
(metres, degrees XYZ). Component.guides returns copies: assign the list back.)")
      .def(py::init([](const std::string& name, const std::string& joint, py::object translate, py::object rotate,
                       py::object scale) {
             rig::Guide g;
             g.name = name;
             g.joint = joint;
             if (!translate.is_none()) g.translate = vec3_from_python(translate, "Guide.translate");
             if (!rotate.is_none()) g.rotate = vec3_from_python(rotate, "Guide.rotate");
             if (!scale.is_none()) g.scale = vec3_from_python(scale, "Guide.scale");
             return g;
           }),
           py::arg("name") = "", py::arg("joint") = "", py::arg("translate") = py::none(), py::arg("rotate") = py::none(),
           py::arg("scale") = py::none())
      .def_readwrite("name", &rig::Guide::name)
      .def_readwrite("joint", &rig::Guide::joint)
      .def_property(
          "translate", [](const rig::Guide& g) { return vec3_to_python(g.translate); },
          [](rig::Guide& g, py::object v) { g.translate = vec3_from_python(v, "Guide.translate"); })
      .def_property(
          "rotate", [](const rig::Guide& g) { return vec3_to_python(g.rotate); },
          [](rig::Guide& g, py::object v) { g.rotate = vec3_from_python(v, "Guide.rotate"); })
      .def_property(
          "scale", [](const rig::Guide& g) { return vec3_to_python(g.scale); },
          [](rig::Guide& g, py::object v) { g.scale = vec3_from_python(v, "Guide.scale"); })
      .def_property_readonly("line", [](const rig::Guide& g) { return g.where.line; })
      .def("__repr__", [](const rig::Guide& g) {
        return "<rigel.Guide name='" + g.name + "' joint='" + g.joint + "'>";
      });
}

}  // namespace rigel::python
