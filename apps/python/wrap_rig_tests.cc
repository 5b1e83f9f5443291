// Rig regression tests from Python (app/rig_checks.h, tools/rig_tests.h):
// rigel.record_rig_tests and rigel.check_rig, what `rigel check record` and
// `rigel check` run. Paths in, records out.

#include <string>
#include <vector>

#include "common.h"
#include "rigel/app/rig_checks.h"
#include "rigel/tools/data_files.h"

namespace rigel::python {

void wrap_rig_tests(py::module_& m) {
  m.def(
      "record_rig_tests",
      [](const std::string& file, const std::string& output, const std::string& character, const std::string& rig,
         const std::vector<double>& frames) {
        tools::RecordRigTestsOptions options;
        options.frames = frames;
        auto recorded = unwrap(app::record_rig_tests_file(file, output, character, rig, options, tools::components()));
        py::list poses;
        for (const tools::RigTestPose& p : recorded.tests.poses) {
          py::dict d;
          d["name"] = p.name;
          d["frame"] = p.frame;
          d["controls"] = p.pose.entries.size();
          d["moved"] = p.joints.size();
          poses.append(record(d));
        }
        py::dict d;
        d["rig"] = recorded.tests.rig;
        d["output"] = recorded.output.string();
        d["joints"] = recorded.tests.base.size();
        d["poses"] = poses;
        return record(d);
      },
      py::arg("file"), py::arg("output") = "", py::arg("character") = "", py::arg("rig") = "",
      py::arg("frames") = std::vector<double>{},
      "Records a rig's regression poses with every joint's world matrix under them (`rigel check record`): file "
      "is a definition (built onto character, else its geometry) or a scene (.rigel, its rig `rig`); output "
      "defaults to NAME.rigtest.json beside a definition. Without frames: rest, one pose per component and all; "
      "with frames: the controls' values at each frame as the scene plays. Returns record(rig, output, joints, "
      "poses: [record(name, frame, controls, moved)]).");
  m.def(
      "check_rig",
      [](const std::string& file, const std::string& tests, const std::string& character, const std::string& rig,
         double tolerance) {
        auto checked = unwrap(app::check_rig_tests_file(file, tests, character, rig, tolerance, tools::components()));
        py::list mismatches;
        for (const tools::RigTestMismatch& x : checked.report.mismatches) {
          py::dict d;
          d["pose"] = x.pose;
          d["joint"] = x.joint;
          d["error"] = x.error;
          d["problem"] = x.problem;
          mismatches.append(record(d));
        }
        py::dict d;
        d["rig"] = checked.rig;
        d["tests"] = checked.tests.string();
        d["ok"] = checked.report.ok();
        d["poses"] = checked.report.poses;
        d["joints"] = checked.report.joints;
        d["max_error"] = checked.report.max_error;
        d["mismatches"] = mismatches;
        return record(d);
      },
      py::arg("file"), py::arg("tests") = "", py::arg("character") = "", py::arg("rig") = "",
      py::arg("tolerance") = 1e-6,
      "Checks a rig against its regression poses (`rigel check`): tests defaults to NAME.rigtest.json beside a "
      "definition. Returns record(rig, tests, ok, poses, joints, max_error, mismatches: [record(pose, joint, "
      "error, problem)]); a file that cannot be read or built raises.");
}

}  // namespace rigel::python
