// What the rig wraps share (rig_common.h).

#include "rig_common.h"

#include "rigel/ephemeral/component.h"
#include "rigel/tools/data_files.h"

namespace rigel::python {

const rig::ComponentFactory& factory() { return tools::components(); }
const rig::SchemaRegistry& schemas() { return factory().schemas(); }

// ---- component handles ---------------------------------------------------------

rig::Component& ComponentRef::get() const {
  if (!rig_id.empty()) {
    if (rig::Component* c = def->find_by_rig_id(rig_id)) return *c;
    raise(ErrorCode::kNotFound, "definition '" + def->name + "': no component with rigId " + rig_id);
  }
  std::vector<rig::Component>* list = &def->components;
  rig::Component* c = nullptr;
  for (std::size_t i : path) {
    if (i >= list->size()) raise(ErrorCode::kNotFound, "definition '" + def->name + "': the component is gone");
    c = &(*list)[i];
    list = &c->children;
  }
  if (c == nullptr) raise(ErrorCode::kNotFound, "definition '" + def->name + "': empty component path");
  return *c;
}

// The list holding `target` and its index there; nullptr when absent.
std::vector<rig::Component>* container_of(std::vector<rig::Component>& list, const rig::Component* target,
                                          std::size_t* index, rig::Component** parent, rig::Component* owner) {
  for (std::size_t i = 0; i < list.size(); ++i) {
    if (&list[i] == target) {
      *index = i;
      *parent = owner;
      return &list;
    }
    if (auto* found = container_of(list[i].children, target, index, parent, &list[i])) return found;
  }
  return nullptr;
}

namespace {

bool path_of(const std::vector<rig::Component>& list, const rig::Component* target, std::vector<std::size_t>& path) {
  for (std::size_t i = 0; i < list.size(); ++i) {
    path.push_back(i);
    if (&list[i] == target || path_of(list[i].children, target, path)) return true;
    path.pop_back();
  }
  return false;
}

}  // namespace

ComponentRef ref_of(const DefinitionRef& def, const rig::Component& c) {
  ComponentRef r{def, c.rig_id, {}};
  if (r.rig_id.empty()) path_of(def->components, &c, r.path);
  return r;
}

py::list refs_of(const DefinitionRef& def, const std::vector<rig::Component>& list) {
  py::list out;
  for (const rig::Component& c : list) out.append(py::cast(ref_of(def, c)));
  return out;
}

// ---- parameters ------------------------------------------------------------------

py::object param_to_python(const rig::ParamValue& v) {
  return std::visit(
      [](const auto& x) -> py::object {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, math::Vec3>) {
          return vec3_to_python(x);
        } else {
          return py::cast(x);
        }
      },
      v);
}

namespace {

std::string kind_of(py::handle v) { return py::str(py::type::of(v).attr("__name__")); }

// Typed by the component type's schema when it declares the parameter
// (an int is accepted for a double); otherwise by the Python type, kept as
// it is for validate() to report.
rig::ParamValue param_from_python(const rig::Component& c, const std::string& name, py::handle v) {
  const std::string where = "component '" + c.full_name() + "' (" + c.type + "): parameter '" + name + "'";
  const rig::ComponentSchema* schema = schemas().find(c.type);
  const rig::ParamSpec* spec = schema ? schema->param(name) : nullptr;
  const bool is_bool = py::isinstance<py::bool_>(v);
  const bool is_int = py::isinstance<py::int_>(v) && !is_bool;
  const bool is_str = py::isinstance<py::str>(v);
  if (spec == nullptr) {
    if (is_bool) return v.cast<bool>();
    if (is_int) return v.cast<std::int64_t>();
    if (py::isinstance<py::float_>(v)) return v.cast<double>();
    if (is_str) return v.cast<std::string>();
    return vec3_from_python(v, where);
  }
  auto wrong = [&](const char* wanted) -> rig::ParamValue {
    raise(ErrorCode::kInvalidArgument,
          where + " must be " + wanted + " (" + rig::param_type_name(spec->type) + "), not " + kind_of(v));
  };
  switch (spec->type) {
    case rig::ParamType::kBool:
      return is_bool ? rig::ParamValue(v.cast<bool>()) : wrong("a bool");
    case rig::ParamType::kInt:
      return is_int ? rig::ParamValue(v.cast<std::int64_t>()) : wrong("an int");
    case rig::ParamType::kDouble:
      return (is_int || py::isinstance<py::float_>(v)) ? rig::ParamValue(v.cast<double>()) : wrong("a number");
    case rig::ParamType::kString:
    case rig::ParamType::kEnum:
      return is_str ? rig::ParamValue(v.cast<std::string>()) : wrong("a str");
    case rig::ParamType::kVec3:
      return vec3_from_python(v, where);
  }
  return wrong("a value");
}

}  // namespace

void set_param(rig::Component& c, const std::string& name, py::handle v) {
  rig::ParamValue value = param_from_python(c, name, v);
  for (rig::Param& p : c.params)
    if (p.name == name) {
      p.value = std::move(value);
      return;
    }
  c.params.push_back(rig::Param{name, std::move(value), {}});
}

py::dict params_of(const rig::Component& c) {
  py::dict d;
  for (const rig::Param& p : c.params) d[py::str(p.name)] = param_to_python(p.value);
  return d;
}

// ---- guides, controls, features from Python ----------------------------------------

rig::Guide guide_from_python(py::handle h, const std::string& where) {
  if (py::isinstance<rig::Guide>(h)) return h.cast<rig::Guide>();
  rig::Guide g;
  if (py::isinstance<py::str>(h)) {
    g.joint = h.cast<std::string>();
    return g;
  }
  if (!py::isinstance<py::dict>(h))
    raise(ErrorCode::kInvalidArgument, where + ": a guide is a Guide, a joint name or a dict, not " + kind_of(h));
  for (auto [key, value] : py::reinterpret_borrow<py::dict>(h)) {
    const std::string k = py::str(key);
    if (k == "name") g.name = value.cast<std::string>();
    else if (k == "joint") g.joint = value.cast<std::string>();
    else if (k == "translate") g.translate = vec3_from_python(value, where + ".translate");
    else if (k == "rotate") g.rotate = vec3_from_python(value, where + ".rotate");
    else if (k == "scale") g.scale = vec3_from_python(value, where + ".scale");
    else raise(ErrorCode::kInvalidArgument, where + ": unknown guide key '" + k + "' (name, joint, translate, rotate, scale)");
  }
  return g;
}

rig::ControlStyle control_from_python(py::handle h, const std::string& where) {
  if (py::isinstance<rig::ControlStyle>(h)) return h.cast<rig::ControlStyle>();
  if (!py::isinstance<py::dict>(h))
    raise(ErrorCode::kInvalidArgument, where + ": a control is a ControlStyle or a dict, not " + kind_of(h));
  rig::ControlStyle s;
  for (auto [key, value] : py::reinterpret_borrow<py::dict>(h)) {
    const std::string k = py::str(key);
    if (k == "role") s.role = value.cast<std::string>();
    else if (k == "shape") s.shape = value.cast<std::string>();
    else if (k == "color") s.color = value.cast<std::string>();
    else if (k == "size") s.size = value.cast<double>();
    else raise(ErrorCode::kInvalidArgument, where + ": unknown control key '" + k + "' (role, shape, color, size)");
  }
  return s;
}

rig::Side side_from(const std::string& side) {
  if (std::optional<rig::Side> s = rig::side_from_name(side)) return *s;
  raise(ErrorCode::kInvalidArgument, "side '" + side + "': expected C, L or R");
}

py::list features_of(const std::vector<rig::Feature>& features) {
  py::list out;
  for (const rig::Feature& f : features) {
    py::dict switches;
    for (const rig::FeatureSwitch& s : f.switches) switches[py::str(s.name)] = s.enabled;
    py::dict d;
    d["name"] = f.name;
    d["enabled"] = f.enabled;
    d["switches"] = switches;
    out.append(d);
  }
  return out;
}

void set_feature(std::vector<rig::Feature>& features, const std::string& name, bool enabled,
                 const std::optional<std::map<std::string, bool>>& switches) {
  rig::Feature* f = nullptr;
  for (rig::Feature& x : features)
    if (x.name == name) f = &x;
  if (f == nullptr) {
    features.push_back(rig::Feature{name, true, {}, {}});
    f = &features.back();
  }
  f->enabled = enabled;
  if (switches) {
    f->switches.clear();
    for (const auto& [n, on] : *switches) f->switches.push_back(rig::FeatureSwitch{n, on, {}});
  }
}

// Adds a component to `list` (the definition's roots or a component's
// children) and returns its handle. A missing rigId gets a fresh one.
ComponentRef add_component(const DefinitionRef& def, std::vector<rig::Component>& list, const std::string& type,
                           const std::string& name, const std::string& side, py::object guides, py::object params,
                           py::object controls, const std::string& attach, const std::string& version,
                           std::optional<std::string> rig_id) {
  rig::Component c;
  c.type = type;
  c.name = name;
  c.side = side_from(side);
  c.version = version;
  c.attach = attach;
  c.rig_id = rig_id ? *rig_id : rig::new_rig_id();
  if (c.rig_id.empty()) raise(ErrorCode::kInvalidArgument, "component '" + name + "': empty rigId");
  if (def->find_by_rig_id(c.rig_id) != nullptr)
    raise(ErrorCode::kAlreadyExists, "definition '" + def->name + "': rigId " + c.rig_id + " is taken");
  const std::string where = "component '" + c.full_name() + "' (" + type + ")";
  if (!guides.is_none())
    for (py::handle g : guides) c.guides.push_back(guide_from_python(g, where + ": guide"));
  if (!controls.is_none())
    for (py::handle s : controls) c.controls.push_back(control_from_python(s, where + ": control"));
  if (!params.is_none())
    for (auto [k, v] : params.cast<py::dict>()) set_param(c, py::str(k), v);
  list.push_back(std::move(c));
  return ref_of(def, list.back());
}

// ---- diagnostics and definitions -----------------------------------------------------

[[noreturn]] void raise_definition(const std::string& what, const std::vector<rig::Diagnostic>& problems) {
  // Appended piece by piece: GCC 12 warns (-Wrestrict, a false positive)
  // on `"literal" + std::string&&`.
  std::string message = what + ": " + std::to_string(problems.size()) + (problems.size() == 1 ? " error" : " errors");
  for (const rig::Diagnostic& d : problems) message.append("\n").append(d.str());
  throw DefinitionError(message, problems);
}

DefinitionRef load_definition(const std::string& path) {
  rig::ParseResult parsed = rig::load_definition(path, schemas());
  if (!parsed.ok()) raise_definition(path, parsed.errors);
  return std::make_shared<rig::Definition>(std::move(parsed.definition));
}

void check_valid(const rig::Definition& def) {
  const std::vector<rig::Diagnostic> problems = rig::validate(def, schemas());
  if (!problems.empty()) raise_definition(def.source.empty() ? "definition '" + def.name + "'" : def.source, problems);
}

py::dict schema_info(const rig::ComponentSchema& s) {
  py::list params;
  for (const rig::ParamSpec& p : s.params) {
    py::dict d;
    d["name"] = p.name;
    d["type"] = rig::param_type_name(p.type);
    d["default"] = param_to_python(p.default_value);
    d["min"] = p.min ? py::object(py::float_(*p.min)) : py::object(py::none());
    d["max"] = p.max ? py::object(py::float_(*p.max)) : py::object(py::none());
    d["choices"] = p.choices;
    d["help"] = p.help;
    params.append(d);
  }
  py::list controls;
  for (const rig::ControlSpec& c : s.controls) {
    py::dict d;
    d["role"] = c.role;
    d["shape"] = c.shape;
    d["color"] = c.color;
    d["size"] = c.size;
    d["help"] = c.help;
    controls.append(d);
  }
  py::dict guides;
  guides["min"] = s.guides.min;
  guides["max"] = s.guides.max;
  guides["names"] = s.guides.names;
  guides["help"] = s.guides.help;
  py::dict d;
  d["type"] = s.type;
  d["help"] = s.help;
  d["params"] = params;
  d["guides"] = guides;
  d["controls"] = controls;
  d["hooks"] = s.hooks;
  d["features"] = s.features;
  d["root_only"] = s.root_only;
  d["needs_parent"] = s.needs_parent;
  return d;
}

const rig::ComponentSchema& schema_of(const std::string& type) {
  const rig::ComponentSchema* s = schemas().find(type);
  if (s == nullptr) {
    std::string types;
    for (const std::string& t : factory().types()) types += (types.empty() ? "" : ", ") + t;
    raise(ErrorCode::kNotFound, "unknown component type '" + type + "' (types: " + types + ")");
  }
  return *s;
}

}  // namespace rigel::python
