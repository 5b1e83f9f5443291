// rigel.RigBuild: the procedural build of a definition on a scene
// (rig::Build, seed 003): its plan, stepping, features, updates and edit mode.

#include "rig_common.h"
#include "rigel/rig/build.h"

namespace rigel::python {
namespace {

struct BuildRef {
  SceneRef scene;  // kept alive: the build refers to it
  std::unique_ptr<rig::Build> build;
};

using DefinitionArg = std::variant<DefinitionRef, std::string>;

rig::Definition definition_of(const DefinitionArg& arg) {
  rig::Definition def = std::holds_alternative<std::string>(arg) ? *load_definition(std::get<std::string>(arg))
                                                                  : *std::get<DefinitionRef>(arg);
  check_valid(def);
  return def;
}

rig::Build::Rebuild rebuild_from(const std::string& when) {
  if (when == "changed") return rig::Build::Rebuild::kChanged;
  if (when == "newer-version") return rig::Build::Rebuild::kNewerVersion;
  if (when == "all") return rig::Build::Rebuild::kAll;
  raise(ErrorCode::kInvalidArgument, "when '" + when + "': expected 'changed', 'newer-version' or 'all'");
}

py::object edits_record(rig::Edits edits) {
  py::dict d;
  d["definition"] = std::make_shared<rig::Definition>(std::move(edits.definition));
  d["changed"] = edits.changed;
  d["ignored"] = edits.ignored;
  return record(d);
}

using BuildClass = py::class_<BuildRef>;

void def_state(BuildClass& cls) {
  cls
      .def_static(
          "open",
          [](const SceneRef& s, const DefinitionArg& definition, bool edit_mode) {
            rig::BuildOptions options;
            options.edit_mode = edit_mode;
            return BuildRef{s, unwrap(rig::Build::open(*s, definition_of(definition), factory(), options))};
          },
          py::arg("scene"), py::arg("definition"), py::arg("edit_mode") = false,
          "Plans a Definition (or a definition file) for `scene`; continues a rig of that name the scene holds.")
      .def_static(
          "reopen",
          [](const SceneRef& s, const std::string& rig_name, bool edit_mode) {
            rig::BuildOptions options;
            options.edit_mode = edit_mode;
            return BuildRef{s, unwrap(rig::Build::reopen(*s, rig_name, factory(), options))};
          },
          py::arg("scene"), py::arg("rig"), py::arg("edit_mode") = false,
          "Continues the scene's rig `rig` from the definition it was built from.")
      .def_property_readonly("scene", [](const BuildRef& b) { return b.scene; })
      .def_property_readonly(
          "definition", [](const BuildRef& b) { return std::make_shared<rig::Definition>(b.build->definition()); },
          "A copy of the definition being built.")
      .def_property_readonly("position", [](const BuildRef& b) { return b.build->position(); }, "Steps done.")
      .def_property_readonly("step_count", [](const BuildRef& b) { return b.build->plan().size(); })
      .def("__len__", [](const BuildRef& b) { return b.build->plan().size(); })
      .def_property_readonly(
          "plan",
          [](const BuildRef& b) {
            py::list out;
            for (const rig::PlannedStep& p : b.build->plan()) {
              // PlannedStep::label() gives the step name only, though its
              // comment promises "arm_L/controls": composed here.
              const std::string component =
                  p.component < 0 ? std::string() : b.build->components()[static_cast<std::size_t>(p.component)]->full_name();
              py::dict d;
              d["label"] = component.empty() ? p.step : component + "/" + p.step;
              d["component"] = component;
              d["step"] = p.step;
              d["feature"] = p.feature;
              d["switch"] = p.switch_name;
              d["enabled"] = p.enabled;
              out.append(record(d));
            }
            return out;
          },
          "The steps in order: label ('arm_L/controls'), component, step, feature, switch, enabled.")
      .def_property_readonly(
          "components",
          [](const BuildRef& b) {
            py::list out;
            for (const rig::Component* c : b.build->components()) {
              py::dict d;
              d["name"] = c->name;
              d["side"] = rig::side_name(c->side);
              d["full_name"] = c->full_name();
              d["type"] = c->type;
              d["rig_id"] = c->rig_id;
              out.append(record(d));
            }
            return out;
          },
          "The components in build order.")
      .def_property_readonly(
          "root", [](const BuildRef& b) { return node_or_none(b.scene, b.build->root()); }, "The metaRoot, or None.")
      .def_property_readonly("edit_mode", [](const BuildRef& b) { return b.build->edit_mode(); });
}

void def_steps(BuildClass& cls) {
  cls
      .def(
          "forward", [](const BuildRef& b) { check(b.build->forward()); }, "Constructs the next step.")
      .def(
          "back", [](const BuildRef& b) { check(b.build->back()); }, "Destructs the last step done.")
      .def(
          "go_to", [](const BuildRef& b, int position) { check(b.build->go_to(position)); }, py::arg("position"))
      .def(
          "build_all", [](const BuildRef& b) { check(b.build->build_all()); }, "Constructs every remaining step.")
      .def(
          "remove", [](const BuildRef& b) { check(b.build->remove()); }, "Destructs everything the rig built.")
      .def(
          "set_feature",
          [](const BuildRef& b, const std::string& feature, bool enabled, const std::string& switch_name) {
            check(b.build->set_feature(feature, enabled, switch_name));
          },
          py::arg("feature"), py::arg("enabled"), py::arg("switch") = "")
      .def(
          "rebuild_changed",
          [](const BuildRef& b, const DefinitionArg& definition, const std::string& when, const std::string& keep_keys) {
            return unwrap(b.build->rebuild_changed(definition_of(definition), rebuild_from(when), keep_keys_from_name(keep_keys)));
          },
          py::arg("definition"), py::arg("when") = "changed", py::arg("keep_keys") = "local",
          R"(Update: rebuilds only the components that changed (when='changed'), whose version changed
('newer-version', `rigel update`) or all ('all'); keep_keys 'local' or 'world'. Returns the rigIds rebuilt.)")
      .def(
          "edits", [](const BuildRef& b) { return edits_record(unwrap(b.build->edits())); },
          "Rig edit mode: (definition, changed, ignored) with guides moved as the controls were.")
      .def(
          "commit_edits",
          [](const BuildRef& b, const std::string& definition_path, bool leave_edit_mode) {
            return edits_record(unwrap(b.build->commit_edits(definition_path, leave_edit_mode)));
          },
          py::arg("definition_path") = "", py::arg("leave_edit_mode") = false,
          R"(edits(), then rebuild the moved components at their new guides. With definition_path (where
you save the returned definition), the rig records it as its definition, so it is up to date with
that file; leave_edit_mode builds it again for animation (as `rigel edit` does).)");
}

}  // namespace

void wrap_rig_build(py::module_& m) {
  BuildClass cls(m, "RigBuild", R"(A procedural build of a definition on a scene (rig::Build, seed 003):
an ordered plan of steps, stepped forward and back like a VCR. Each call is
one undo step; a failing step is rolled back and raises.)");
  def_state(cls);
  def_steps(cls);
}

}  // namespace rigel::python
