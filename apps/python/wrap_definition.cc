// rigel.Definition: a rig definition (docs/RIG.md), read from and written to
// .rig.xml / .rig.json, validated, compared, and edited in code.

#include "rig_common.h"
#include "rigel/rig/diff.h"

namespace rigel::python {
namespace {

using DefinitionClass = py::class_<rig::Definition, DefinitionRef>;

void def_files(DefinitionClass& cls) {
  cls
      .def(py::init([](const std::string& name, const std::string& version) {
             auto d = std::make_shared<rig::Definition>();
             d->name = name;
             d->version = version;
             return d;
           }),
           py::arg("name"), py::arg("version") = "1.0")
      .def_static("load", &load_definition, py::arg("path"),
                  "Reads .rig.xml / .rig.json; raises DefinitionError listing every problem as file:line:column.")
      .def_static(
          "parse",
          [](const std::string& text, const std::string& syntax, const std::string& source) {
            rig::ParseResult parsed = rig::parse_definition(text, syntax_from_name(syntax), source, schemas());
            if (!parsed.ok()) raise_definition(source, parsed.errors);
            return std::make_shared<rig::Definition>(std::move(parsed.definition));
          },
          py::arg("text"), py::arg("syntax") = "xml", py::arg("source") = "<string>")
      .def(
          "save", [](const DefinitionRef& d, const std::string& path) { check(rig::save_definition(*d, path)); },
          py::arg("path"), "Writes .rig.xml or .rig.json (by the name), atomically.")
      .def(
          "text", [](const DefinitionRef& d, const std::string& syntax) { return rig::write_definition(*d, syntax_from_name(syntax)); },
          py::arg("syntax") = "xml", "The definition's text ('xml' or 'json'), deterministic.")
      .def(
          "validate", [](const DefinitionRef& d) { return rig::validate(*d, schemas()); },
          "Every semantic problem (list of Diagnostic; empty when valid).")
      .def(
          "check", [](const DefinitionRef& d) { check_valid(*d); }, "Raises DefinitionError when validate() finds problems.")
      .def(
          "copy", [](const DefinitionRef& d) { return std::make_shared<rig::Definition>(*d); }, "An independent copy.")
      .def(
          "diff",
          [](const DefinitionRef& a, const DefinitionRef& b) {
            std::vector<std::string> out;
            for (const rig::Difference& d : rig::diff(*a, *b)) out.push_back(d.str());
            return out;
          },
          py::arg("other"), "Semantic differences from this definition to `other`, one sentence each.");
}

void def_contents(DefinitionClass& cls) {
  cls
      .def_property(
          "name", [](const DefinitionRef& d) { return d->name; }, [](const DefinitionRef& d, std::string v) { d->name = std::move(v); })
      .def_property(
          "version", [](const DefinitionRef& d) { return d->version; },
          [](const DefinitionRef& d, std::string v) { d->version = std::move(v); })
      .def_property(
          "source", [](const DefinitionRef& d) { return d->source; },
          [](const DefinitionRef& d, std::string v) { d->source = std::move(v); },
          "The file it was read from (a build records it as the rig's definition path).")
      .def_property(
          "geometry",
          [](const DefinitionRef& d) {
            py::list out;
            for (const rig::Geometry& g : d->geometry) out.append(py::make_tuple(g.file, g.name));
            return out;
          },
          [](const DefinitionRef& d, const std::vector<std::pair<std::string, std::string>>& list) {
            d->geometry.clear();
            for (const auto& [file, name] : list) d->geometry.push_back(rig::Geometry{file, name, {}});
          },
          "Character files as (file, mesh name) pairs, files relative to the definition's folder.")
      .def(
          "add_geometry",
          [](const DefinitionRef& d, const std::string& file, const std::string& name) {
            d->geometry.push_back(rig::Geometry{file, name, {}});
          },
          py::arg("file"), py::arg("name") = "")
      .def_property(
          "data",
          [](const DefinitionRef& d) {
            py::list out;
            for (const rig::DataImport& x : d->data) out.append(py::make_tuple(x.kind, x.file));
            return out;
          },
          [](const DefinitionRef& d, const std::vector<std::pair<std::string, std::string>>& list) {
            d->data.clear();
            for (const auto& [kind, file] : list) d->data.push_back(rig::DataImport{kind, file, {}});
          },
          "Data the build imports after the components, in order, as (kind, file) pairs (kind: weights, shapes, "
          "blendshapes, driven_poses, correctives; files relative to the definition's folder): its last step, data.")
      .def_property_readonly(
          "features", [](const DefinitionRef& d) { return features_of(d->features); },
          "Rig-wide features as dicts {name, enabled, switches: {name: enabled}}.")
      .def(
          "set_feature",
          [](const DefinitionRef& d, const std::string& name, bool enabled, std::optional<std::map<std::string, bool>> switches) {
            set_feature(d->features, name, enabled, switches);
          },
          py::arg("name"), py::arg("enabled") = true, py::arg("switches") = py::none())
      .def_property_readonly(
          "components", [](const DefinitionRef& d) { return refs_of(d, d->components); }, "The root components.")
      .def(
          "all_components",
          [](const DefinitionRef& d) {
            py::list out;
            for (const rig::Component* c : d->all_components()) out.append(py::cast(ref_of(d, *c)));
            return out;
          },
          "Every component, depth first, parents before children.")
      .def(
          "find",
          [](const DefinitionRef& d, const std::string& key) -> py::object {
            for (const rig::Component* c : d->all_components())
              if (c->rig_id == key || c->full_name() == key) return py::cast(ref_of(d, *c));
            if (const rig::Component* c = d->find_by_name(key)) return py::cast(ref_of(d, *c));
            return py::none();
          },
          py::arg("key"), "The component with this rigId, full name (arm_L) or name; None when none.")
      .def(
          "add_component",
          [](const DefinitionRef& d, const std::string& type, const std::string& name, const std::string& side,
             py::object guides, py::object params, py::object controls, const std::string& attach,
             const std::string& version, std::optional<std::string> rig_id) {
            return add_component(d, d->components, type, name, side, guides, params, controls, attach, version, rig_id);
          },
          py::arg("type"), py::arg("name"), py::arg("side") = "C", py::kw_only(), py::arg("guides") = py::none(),
          py::arg("params") = py::none(), py::arg("controls") = py::none(), py::arg("attach") = "",
          py::arg("version") = "1.0", py::arg("rig_id") = py::none(),
          R"(Adds a root component; returns its Component. guides: Guide, joint name or dict each;
params: {name: value} typed by the component's schema; controls: ControlStyle or dict each; a
fresh rigId unless given.)")
      .def("__repr__", [](const DefinitionRef& d) {
        return "<rigel.Definition '" + d->name + "' " + d->version + ", " + std::to_string(d->all_components().size()) +
               " components>";
      });
}

}  // namespace

void wrap_definition(py::module_& m) {
  DefinitionClass cls(m, "Definition", R"(A rig definition (docs/RIG.md): a versioned
tree of components, independent of any scene. Load it from .rig.xml /
.rig.json, or make it in code with add_component.)");
  def_files(cls);
  def_contents(cls);
}

}  // namespace rigel::python
