// Over 800 lines: bind_rig splits by concept (definitions, builds, metadata)
// with the service layer of issue 15, which these bindings will call instead.
// Rig definitions (.rig.xml / .rig.json), component schemas, builds
// (rig::Build: stepping, update, remove, edit mode) and the metadata network
// (rigs, components, addresses).

#include <functional>

#include "common.h"
#include "rigel/ephemeral/component.h"
#include "rigel/rig/build.h"
#include "rigel/rig/component.h"
#include "rigel/rig/diff.h"
#include "rigel/rig/meta.h"

namespace rigel::python {
namespace {

using DefinitionRef = std::shared_ptr<rig::Definition>;

// Every component class rigel has (the rig layer's and `ephemeral`): what
// the CLI builds with.
const rig::ComponentFactory& factory() { return ephemeral::components(); }
const rig::SchemaRegistry& schemas() { return factory().schemas(); }

std::string full_name(const rig::Component& c) {
  return c.full_name();
}

// ---- component handles ---------------------------------------------------------

// A component of a Definition as Python holds it: by rigId (a component's
// identity), or by its path of child indices when it has none. Resolved on
// every use, so handles stay valid while the definition grows.
struct ComponentRef {
  DefinitionRef def;
  std::string rig_id;
  std::vector<std::size_t> path;

  rig::Component& get() const {
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
};

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

bool path_of(const std::vector<rig::Component>& list, const rig::Component* target, std::vector<std::size_t>& path) {
  for (std::size_t i = 0; i < list.size(); ++i) {
    path.push_back(i);
    if (&list[i] == target || path_of(list[i].children, target, path)) return true;
    path.pop_back();
  }
  return false;
}

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

std::string kind_of(py::handle v) { return py::str(py::type::of(v).attr("__name__")); }

// Typed by the component type's schema when it declares the parameter
// (an int is accepted for a double); otherwise by the Python type, kept as
// it is for validate() to report.
rig::ParamValue param_from_python(const rig::Component& c, const std::string& name, py::handle v) {
  const std::string where = "component '" + full_name(c) + "' (" + c.type + "): parameter '" + name + "'";
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
  const std::string where = "component '" + full_name(c) + "' (" + type + ")";
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

rig::Syntax syntax_from(const std::string& name) {
  if (name == "xml") return rig::Syntax::kXml;
  if (name == "json") return rig::Syntax::kJson;
  raise(ErrorCode::kInvalidArgument, "syntax '" + name + "': expected 'xml' or 'json'");
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

// ---- builds ------------------------------------------------------------------------------

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

rig::Build::KeepKeys keep_from(const std::string& keep) {
  if (keep == "local") return rig::Build::KeepKeys::kLocal;
  if (keep == "world") return rig::Build::KeepKeys::kWorld;
  raise(ErrorCode::kInvalidArgument, "keep_keys '" + keep + "': expected 'local' or 'world'");
}

py::object edits_record(rig::Edits edits) {
  py::dict d;
  d["definition"] = std::make_shared<rig::Definition>(std::move(edits.definition));
  d["changed"] = edits.changed;
  d["ignored"] = edits.ignored;
  return record(d);
}

// ---- metadata network ----------------------------------------------------------------------

py::object component_record(const SceneRef& s, NodeId meta) {
  const graph::Graph& g = s->graph();
  const NodeId parent = rig::meta_parent(g, meta);
  py::dict d;
  d["name"] = rig::meta_string(g, meta, "componentName");
  d["side"] = rig::meta_string(g, meta, "side");
  d["type"] = rig::meta_string(g, meta, "metaType");
  d["version"] = rig::meta_string(g, meta, "version");
  d["rig_id"] = rig::meta_string(g, meta, "rigId");
  d["parent"] = parent.is_valid() && g.node(parent)->type().name() == rig::kMetaComponentType
                    ? rig::meta_string(g, parent, "componentName")
                    : std::string();
  d["node"] = node_ref(s, meta);
  d["members"] = rig::meta_members(g, meta).size();
  return record(d);
}

py::object rig_record(const SceneRef& s, NodeId root) {
  const graph::Graph& g = s->graph();
  py::list comps;
  for (NodeId c : rig::rig_components(g, root)) comps.append(component_record(s, c));
  py::dict d;
  d["name"] = rig::meta_string(g, root, "rigName");
  d["version"] = rig::meta_string(g, root, "version");
  d["definition"] = rig::meta_string(g, root, "definitionPath");
  const std::string position = rig::meta_string(g, root, "buildPosition");
  d["build_position"] = position.empty() ? 0 : std::stoi(position);
  d["node"] = node_ref(s, root);
  d["components"] = comps;
  return record(d);
}

NodeId rig_node(const SceneRef& s, const NodeArg& rig) {
  if (const std::string* name = std::get_if<std::string>(&rig)) {
    const NodeId r = rig::find_rig(s->graph(), *name);
    if (!r.is_valid()) raise(ErrorCode::kNotFound, "the scene has no rig '" + *name + "'");
    return r;
  }
  return resolve(s, rig);
}

void require_meta(const NodeRef& n, NodeId id) {
  if (!rig::is_meta_node(n.scene->graph(), id))
    raise(ErrorCode::kInvalidArgument, "'" + n.scene->graph().node(id)->name() + "' is not a meta node");
}

}  // namespace

void bind_rig(py::module_& m) {
  // ---- small value types ----------------------------------------------------------------
  py::class_<rig::Diagnostic>(m, "Diagnostic", "One problem of a rig definition, with its place.")
      .def_readonly("file", &rig::Diagnostic::file)
      .def_property_readonly("line", [](const rig::Diagnostic& d) { return d.where.line; })
      .def_property_readonly("column", [](const rig::Diagnostic& d) { return d.where.column; })
      .def_readonly("message", &rig::Diagnostic::message)
      .def("__str__", &rig::Diagnostic::str)
      .def("__repr__", [](const rig::Diagnostic& d) { return "<rigel.Diagnostic " + d.str() + ">"; });

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

  // ---- Definition ---------------------------------------------------------------------------
  py::class_<rig::Definition, DefinitionRef> def_cls(m, "Definition", R"(A rig definition (docs/RIG.md): a versioned
tree of components, independent of any scene. Load it from .rig.xml /
.rig.json, or make it in code with add_component.)");
  py::class_<ComponentRef> comp_cls(m, "Component", R"(A component of a Definition, held by rigId (by position when it
has none). Setting a property edits the definition.)");

  def_cls
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
            rig::ParseResult parsed = rig::parse_definition(text, syntax_from(syntax), source, schemas());
            if (!parsed.ok()) raise_definition(source, parsed.errors);
            return std::make_shared<rig::Definition>(std::move(parsed.definition));
          },
          py::arg("text"), py::arg("syntax") = "xml", py::arg("source") = "<string>")
      .def(
          "save", [](const DefinitionRef& d, const std::string& path) { check(rig::save_definition(*d, path)); },
          py::arg("path"), "Writes .rig.xml or .rig.json (by the name), atomically.")
      .def(
          "text", [](const DefinitionRef& d, const std::string& syntax) { return rig::write_definition(*d, syntax_from(syntax)); },
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
          py::arg("other"), "Semantic differences from this definition to `other`, one sentence each.")
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
              if (c->rig_id == key || full_name(*c) == key) return py::cast(ref_of(d, *c));
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

  // ---- Component ----------------------------------------------------------------------------
  auto str_property = [&](const char* name, std::string rig::Component::*member, const char* doc) {
    comp_cls.def_property(
        name, [member](const ComponentRef& r) { return r.get().*member; },
        [member](const ComponentRef& r, std::string v) { r.get().*member = std::move(v); }, doc);
  };
  str_property("type", &rig::Component::type, "The component type (rigel.component_types()).");
  str_property("name", &rig::Component::name, "Name, unique per side.");
  str_property("version", &rig::Component::version, "Version (update rebuilds components whose version changed).");
  str_property("attach", &rig::Component::attach, "Hook of the parent (or OTHER.HOOK); '' = hook 0.");
  comp_cls
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
          "full_name", [](const ComponentRef& r) { return full_name(r.get()); }, "name_SIDE (arm_L), as in node names and addresses.")
      .def_property(
          "guides",
          [](const ComponentRef& r) { return r.get().guides; },
          [](const ComponentRef& r, py::iterable list) {
            std::vector<rig::Guide> guides;
            const std::string where = "component '" + full_name(r.get()) + "': guide";
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
          py::arg("scale") = py::none())
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
            raise(ErrorCode::kNotFound, "component '" + full_name(c) + "' (" + c.type + "): no parameter '" + name + "'");
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
            for (py::handle s : list) styles.push_back(control_from_python(s, "component '" + full_name(r.get()) + "': control"));
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
          py::arg("name"), py::arg("enabled") = true, py::arg("switches") = py::none())
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
        return "<rigel.Component " + full_name(c) + " (" + c.type + ") " + c.rig_id + ">";
      });

  m.def(
      "check_definition", [](const std::string& path) { return rig::check_definition(path, schemas()); }, py::arg("path"),
      "Everything `rigel validate` reports for a file: a list of Diagnostic, sorted by place (empty: valid).");
  m.def(
      "component_types", [] { return factory().types(); }, "The component types rigel can build.");
  m.def(
      "component_schema", [](const std::string& type) { return schema_info(schema_of(type)); }, py::arg("type"),
      "A component type's schema: help, params (type, default, min, max, choices, help), guides, controls, hooks, ...");
  m.def("new_rig_id", &rig::new_rig_id, "A fresh rigId (UUID v4).");

  // ---- Build --------------------------------------------------------------------------------
  py::class_<BuildRef>(m, "RigBuild", R"(A procedural build of a definition on a scene (rig::Build, seed 003):
an ordered plan of steps, stepped forward and back like a VCR. Each call is
one undo step; a failing step is rolled back and raises.)")
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
                  p.component < 0 ? std::string() : full_name(*b.build->components()[static_cast<std::size_t>(p.component)]);
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
              d["full_name"] = full_name(*c);
              d["type"] = c->type;
              d["rig_id"] = c->rig_id;
              out.append(record(d));
            }
            return out;
          },
          "The components in build order.")
      .def_property_readonly(
          "root", [](const BuildRef& b) { return node_or_none(b.scene, b.build->root()); }, "The metaRoot, or None.")
      .def_property_readonly("edit_mode", [](const BuildRef& b) { return b.build->edit_mode(); })
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
            return unwrap(b.build->rebuild_changed(definition_of(definition), rebuild_from(when), keep_from(keep_keys)));
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

  // ---- metadata network ------------------------------------------------------------------------
  auto scene_cls = py::reinterpret_borrow<py::class_<scene::Scene, SceneRef>>(m.attr("Scene"));
  scene_cls
      .def(
          "rigs",
          [](const SceneRef& s) {
            py::list out;
            for (NodeId r : rig::list_rigs(s->graph())) out.append(rig_record(s, r));
            return out;
          },
          "The rigs: name, version, definition path, build_position, node (metaRoot), components.")
      .def(
          "find_rig", [](const SceneRef& s, const std::string& name) { return node_or_none(s, rig::find_rig(s->graph(), name)); },
          py::arg("name"), "The metaRoot of rig `name`, or None.")
      .def(
          "resolve",
          [](const SceneRef& s, const std::string& address) { return node_ref(s, unwrap(rig::resolve_address(s->graph(), address))); },
          py::arg("address"), "The node at a nameless address 'RIG:COMPONENT[/joint[J]]/NAME[I]'.")
      .def(
          "find_component",
          [](const SceneRef& s, const NodeArg& rig, const std::string& key) {
            const NodeId r = rig_node(s, rig);
            return node_or_none(s, rig::find_component(s->graph(), r, key));
          },
          py::arg("rig"), py::arg("key"), "A component meta node of a rig (metaRoot or rig name) by rigId or name.")
      .def(
          "remove_rig",
          [](const SceneRef& s, const std::string& name) {
            std::unique_ptr<rig::Build> b = unwrap(rig::Build::reopen(*s, name, factory()));
            check(b->remove());
          },
          py::arg("name"), "Removes a rig: exactly what its metadata network links to.");

  auto node_cls = py::reinterpret_borrow<py::class_<NodeRef>>(m.attr("Node"));
  node_cls
      .def_property_readonly(
          "component", [](const NodeRef& n) { return node_or_none(n.scene, rig::component_of(n.scene->graph(), n.id())); },
          "The meta node (metaComponent or metaRoot) that built this node, or None.")
      .def_property_readonly(
          "rig", [](const NodeRef& n) { return node_or_none(n.scene, rig::rig_of(n.scene->graph(), n.id())); },
          "The metaRoot above this node, or None.")
      .def_property_readonly(
          "address", [](const NodeRef& n) { return unwrap(rig::address_of(n.scene->graph(), n.id())); },
          "The node's nameless address (raises NotFoundError when it is not part of a rig).")
      .def_property_readonly(
          "meta_parent", [](const NodeRef& n) { return node_or_none(n.scene, rig::meta_parent(n.scene->graph(), n.id())); })
      .def(
          "meta_children",
          [](const NodeRef& n) {
            const NodeId id = n.id();
            require_meta(n, id);
            return node_list(n.scene, rig::meta_children(n.scene->graph(), id));
          },
          "Component meta nodes directly under this metaRoot / metaComponent.")
      .def(
          "members",
          [](const NodeRef& n) {
            const NodeId id = n.id();
            require_meta(n, id);
            return node_list(n.scene, rig::meta_members(n.scene->graph(), id));
          },
          "Every node this meta node built.")
      .def(
          "meta_connection",
          [](const NodeRef& n, const std::string& role, int index) {
            const NodeId id = n.id();
            require_meta(n, id);
            return node_ref(n.scene, unwrap(rig::get_meta_connection(n.scene->graph(), id, role, index)));
          },
          py::arg("role"), py::arg("index") = 0, "getMetaNodeConnection: the member with this role (or step) and index.")
      .def(
          "meta_child",
          [](const NodeRef& n, const std::string& rig_id) {
            const NodeId id = n.id();
            require_meta(n, id);
            return node_or_none(n.scene, rig::get_meta_child_by_id(n.scene->graph(), id, rig_id));
          },
          py::arg("rig_id"), "getMetaChildById: a direct child component by rigId, or None.");
}

}  // namespace rigel::python
