// rigel.Diagnostic: one problem of a rig definition, with its place
// (file:line:column).

#include "rig_common.h"

namespace rigel::python {

void wrap_diagnostic(py::module_& m) {
  py::class_<rig::Diagnostic>(m, "Diagnostic", "One problem of a rig definition, with its place.")
      .def_readonly("file", &rig::Diagnostic::file)
      .def_property_readonly("line", [](const rig::Diagnostic& d) { return d.where.line; })
      .def_property_readonly("column", [](const rig::Diagnostic& d) { return d.where.column; })
      .def_readonly("message", &rig::Diagnostic::message)
      .def("__str__", &rig::Diagnostic::str)
      .def("__repr__", [](const rig::Diagnostic& d) { return "<rigel.Diagnostic " + d.str() + ">"; });
}

}  // namespace rigel::python
