// rigel.Component: a component of a Definition, held by rigId: its type,
// name, side, guides, parameters, control styles, features and children.

#include <functional>

#include "rig_common.h"

namespace rigel::python {
namespace {

using ComponentClass = py::class_<ComponentRef>;

void def_identity(ComponentClass& cls) {
  auto str_property = [&cls](const char* name, std::string rig::Component::*member, const char* doc) {
    cls.def_property(
        name, [member](const ComponentRef& r) { return r.get().*member; },
        [member](const ComponentRef& r, std::string v) { r.get().*member = std::move(v); }, doc);
  };
  str_property("type", &rig::Component::type, "The component type (rigel.component_types()).");
  str_property("name", &rig::Component::name, "Name, unique per side.");
  str_property("version", &rig::Component::version, "Version (update rebuilds components whose version changed).");
  str_property("attach", &rig::Component::attach, "Hook of the parent (or OTHER.HOOK); '' = hook 0.");
  cls.def_property(
      "after", [](const ComponentRef& r) { return r.get().after; },
      [](const ComponentRef& r, std::vector<std::string> ids) { r.get().after = std::move(ids); },
      "rigIds of other components it builds after (what it reads); an update rebuilding one rebuilds it.");
  cls
      .def_property_readonly("definition", [](const ComponentRef& r) { return r.def; })
      .def_property(
          "rig_id", [](const ComponentRef& r) { return r.get().rig_id; },
          [](ComponentRef& r, const std::string& id) {
            rig::Component& c = r.get();
            if (id != c.rig_id && r.def->find_by_rig_id(id) != nullptr)
              raise(ErrorCode::kAlreadyExists, "definition '" + r.def->name + "': rigId " + id + " is taken");
            c.rig_id = id;
            r = ref_of(r.def, c);
          })
      .def_property(
          "side", [](const ComponentRef& r) { return std::string(rig::side_name(r.get().side)); },
          [](const ComponentRef& r, const std::string& s) { r.get().side = side_from(s); }, "'C', 'L' or 'R'.")
      .def_property_readonly(
          "full_name", [](const ComponentRef& r) { return r.get().full_name(); }, "name_SIDE (arm_L), as in node names and addresses.")
      .def_property(
          "guides",
          [](const ComponentRef& r) { return r.get().guides; },
          [](const ComponentRef& r, py::iterable list) {
            std::vector<rig::Guide> guides;
            const std::string where = "component '" + r.get().full_name() + "': guide";
            for (py::handle g : list) guides.push_back(guide_from_python(g, where));
            r.get().guides = std::move(guides);
          },
          "Copies of the guides; assign a list (Guide, joint name or dict each) to change them.")
      .def(
          "add_guide",
          [](const ComponentRef& r, const std::string& name, const std::string& joint, py::object translate,
             py::object rotate, py::object scale) {
            rig::Guide g;
            g.name = name;
            g.joint = joint;
            if (!translate.is_none()) g.translate = vec3_from_python(translate, "guide translate");
            if (!rotate.is_none()) g.rotate = vec3_from_python(rotate, "guide rotate");
            if (!scale.is_none()) g.scale = vec3_from_python(scale, "guide scale");
            r.get().guides.push_back(std::move(g));
          },
          py::arg("name") = "", py::arg("joint") = "", py::arg("translate") = py::none(), py::arg("rotate") = py::none(),
          py::arg("scale") = py::none());
}

void def_params_and_controls(ComponentClass& cls) {
  cls
      .def_property_readonly(
          "params", [](const ComponentRef& r) { return params_of(r.get()); },
          "Parameters set in the definition, {name: value} (others take the schema's defaults).")
      .def(
          "param",
          [](const ComponentRef& r, const std::string& name) -> py::object {
            const rig::Component& c = r.get();
            if (const rig::Param* p = c.param(name)) return param_to_python(p->value);
            const rig::ComponentSchema* s = schemas().find(c.type);
            if (const rig::ParamSpec* spec = s ? s->param(name) : nullptr) return param_to_python(spec->default_value);
            raise(ErrorCode::kNotFound, "component '" + c.full_name() + "' (" + c.type + "): no parameter '" + name + "'");
          },
          py::arg("name"), "A parameter's value: the definition's, else the schema's default.")
      .def(
          "set_param", [](const ComponentRef& r, const std::string& name, py::object v) { set_param(r.get(), name, v); },
          py::arg("name"), py::arg("value"))
      .def(
          "remove_param",
          [](const ComponentRef& r, const std::string& name) {
            std::vector<rig::Param>& ps = r.get().params;
            const auto before = ps.size();
            std::erase_if(ps, [&](const rig::Param& p) { return p.name == name; });
            return ps.size() != before;
          },
          py::arg("name"))
      .def_property(
          "controls", [](const ComponentRef& r) { return r.get().controls; },
          [](const ComponentRef& r, py::iterable list) {
            std::vector<rig::ControlStyle> styles;
            for (py::handle s : list) styles.push_back(control_from_python(s, "component '" + r.get().full_name() + "': control"));
            r.get().controls = std::move(styles);
          },
          "Copies of the control styles; assign a list to change them.")
      .def(
          "set_control",
          [](const ComponentRef& r, const std::string& role, const std::string& shape, const std::string& color, double size) {
            rig::Component& c = r.get();
            for (rig::ControlStyle& s : c.controls)
              if (s.role == role) {
                s = rig::ControlStyle{role, shape, color, size, {}};
                return;
              }
            c.controls.push_back(rig::ControlStyle{role, shape, color, size, {}});
          },
          py::arg("role"), py::arg("shape") = "", py::arg("color") = "", py::arg("size") = 1.0)
      .def_property_readonly("features", [](const ComponentRef& r) { return features_of(r.get().features); })
      .def(
          "set_feature",
          [](const ComponentRef& r, const std::string& name, bool enabled, std::optional<std::map<std::string, bool>> switches) {
            set_feature(r.get().features, name, enabled, switches);
          },
          py::arg("name"), py::arg("enabled") = true, py::arg("switches") = py::none());
}

void def_tree(ComponentClass& cls) {
  cls
      .def_property_readonly("children", [](const ComponentRef& r) { return refs_of(r.def, r.get().children); })
      .def_property_readonly(
          "parent",
          [](const ComponentRef& r) -> py::object {
            std::size_t index = 0;
            rig::Component* parent = nullptr;
            container_of(r.def->components, &r.get(), &index, &parent, nullptr);
            return parent ? py::cast(ref_of(r.def, *parent)) : py::none();
          },
          "The parent component, or None for a root.")
      .def(
          "add_component",
          [](const ComponentRef& r, const std::string& type, const std::string& name, const std::string& side,
             py::object guides, py::object params, py::object controls, const std::string& attach,
             const std::string& version, std::optional<std::string> rig_id) {
            return add_component(r.def, r.get().children, type, name, side, guides, params, controls, attach, version, rig_id);
          },
          py::arg("type"), py::arg("name"), py::arg("side") = "C", py::kw_only(), py::arg("guides") = py::none(),
          py::arg("params") = py::none(), py::arg("controls") = py::none(), py::arg("attach") = "",
          py::arg("version") = "1.0", py::arg("rig_id") = py::none(), "Adds a child component (see Definition.add_component).")
      .def(
          "remove",
          [](const ComponentRef& r) {
            std::size_t index = 0;
            rig::Component* parent = nullptr;
            std::vector<rig::Component>* list = container_of(r.def->components, &r.get(), &index, &parent, nullptr);
            list->erase(list->begin() + static_cast<std::ptrdiff_t>(index));
          },
          "Removes the component and its children from the definition.")
      .def_property_readonly(
          "schema", [](const ComponentRef& r) { return schema_info(schema_of(r.get().type)); }, "Its type's schema (dict).")
      .def(
          "__eq__",
          [](const ComponentRef& a, py::object b) {
            if (!py::isinstance<ComponentRef>(b)) return false;
            const ComponentRef& r = b.cast<const ComponentRef&>();
            return a.def == r.def && &a.get() == &r.get();
          },
          py::is_operator())
      .def("__hash__", [](const ComponentRef& r) { return std::hash<std::string>{}(r.rig_id); })
      .def("__repr__", [](const ComponentRef& r) {
        const rig::Component& c = r.get();
        return "<rigel.Component " + c.full_name() + " (" + c.type + ") " + c.rig_id + ">";
      });
}

}  // namespace

void declare_component(py::module_& m) {
  ComponentClass(m, "Component", R"(A component of a Definition, held by rigId (by position when it
has none). Setting a property edits the definition.)");
}

void wrap_component(py::module_& m) {
  auto cls = py::reinterpret_borrow<ComponentClass>(m.attr("Component"));
  def_identity(cls);
  def_params_and_controls(cls);
  def_tree(cls);
}

}  // namespace rigel::python
