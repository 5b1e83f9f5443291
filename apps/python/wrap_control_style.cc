// rigel.ControlStyle: the look of one control role of a component.

#include "rig_common.h"

namespace rigel::python {

void wrap_control_style(py::module_& m) {
  py::class_<rig::ControlStyle>(m, "ControlStyle", "The look of one control role (shape, colour, size).")
      .def(py::init([](const std::string& role, const std::string& shape, const std::string& color, double size) {
             return rig::ControlStyle{role, shape, color, size, {}};
           }),
           py::arg("role"), py::arg("shape") = "", py::arg("color") = "", py::arg("size") = 1.0)
      .def_readwrite("role", &rig::ControlStyle::role)
      .def_readwrite("shape", &rig::ControlStyle::shape)
      .def_readwrite("color", &rig::ControlStyle::color)
      .def_readwrite("size", &rig::ControlStyle::size)
      .def("__repr__", [](const rig::ControlStyle& s) { return "<rigel.ControlStyle role='" + s.role + "'>"; });
}

}  // namespace rigel::python
