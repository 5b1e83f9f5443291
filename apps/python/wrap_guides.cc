// mGear guide templates from Python (app/guide_import.h):
// rigel.import_guides, what `rigel import-guides` runs. Paths in, the
// report out as plain Python data.

#include <string>

#include "common.h"
#include "rigel/app/guide_import.h"

namespace rigel::python {

void wrap_guides(py::module_& m) {
  m.def(
      "import_guides",
      [](const std::string& file, const std::string& output, const std::string& skeleton) {
        auto imported = unwrap(app::import_guides_file(file, output, skeleton));
        nlohmann::ordered_json report = tools::mgear_report_json(imported.imported);
        report["definition"] = imported.definition.string();
        report["skeleton"] = imported.skeleton.string();
        return py::module_::import("json").attr("loads")(report.dump());
      },
      py::arg("file"), py::arg("output"), py::arg("skeleton") = "",
      "Imports an mGear guide template (.sgt) as a rig definition (output: NAME.rig.xml or NAME.rig.json) and the "
      "skeleton its guides imply (skeleton: .glb or .gltf; default NAME.glb beside the definition), as `rigel "
      "import-guides` does. Returns the report: {rig, components: [{mgear, mgearType, rigel, rigelType, problem, "
      "guides, unmappedParams, unmappedGuides, notes}], unmapped, joints, definition, skeleton}; components that "
      "could not be mapped are listed in `unmapped`, a malformed template raises.");
}

}  // namespace rigel::python
