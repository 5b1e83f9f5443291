// The component types builds know, their schemas and the check of a
// definition file, as module functions.

#include "rig_common.h"

namespace rigel::python {

void wrap_schemas(py::module_& m) {
  m.def(
      "check_definition", [](const std::string& path) { return rig::check_definition(path, schemas()); }, py::arg("path"),
      "Everything `rigel validate` reports for a file: a list of Diagnostic, sorted by place (empty: valid).");
  m.def(
      "component_types", [] { return factory().types(); }, "The component types rigel can build.");
  m.def(
      "component_schema", [](const std::string& type) { return schema_info(schema_of(type)); }, py::arg("type"),
      "A component type's schema: help, params (type, default, min, max, choices, help), guides, controls, hooks, ...");
  m.def("new_rig_id", &rig::new_rig_id, "A fresh rigId (UUID v4).");
}

}  // namespace rigel::python
