// Component types written in Python (docs/PYTHON.md, "Component types in
// Python"): a class declaring its schema (parameters, guides, controls,
// hooks, features) and its steps, registered for its metaType through
// rig::register_component_type, so definitions with the type validate,
// build, step, update and are removed like a built-in one. Each step runs
// the class's `step_NAME(build)` with a ComponentBuild (the rig layer's
// BuildContext, valid during the step) under the build's recorder; a step
// that raises fails the build naming the component, the step and the file.
// component_instance(meta) gives the class back from the metadata network.
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "common.h"
#include "rig_common.h"
#include "rigel/ops/constraints/nodes.h"
#include "rigel/rig/build_context.h"
#include "rigel/rig/component.h"
#include "rigel/rig/meta.h"

namespace rigel::python {
namespace {

// The step's BuildContext while it runs; cleared after, so a kept handle raises.
struct StepRef {
  rig::BuildContext* ctx = nullptr;
  SceneRef scene;
  rig::BuildContext& get() const {
    if (!ctx) raise(ErrorCode::kFailedPrecondition, "a ComponentBuild is valid only while its step runs");
    return *ctx;
  }
};

// Python objects released under the GIL, whenever C++ lets them go.
std::shared_ptr<py::object> hold(py::object o) {
  return std::shared_ptr<py::object>(new py::object(std::move(o)), [](py::object* p) {
    py::gil_scoped_acquire gil;
    delete p;
  });
}

// The classes registered from Python, by type (their instances come back
// from the metadata network as them).
std::map<std::string, std::shared_ptr<py::object>>& python_classes() {
  static auto* classes = new std::map<std::string, std::shared_ptr<py::object>>();
  return *classes;
}

Status run_step(const std::shared_ptr<py::object>& instance, const std::string& type, const std::string& origin,
                const std::string& step, rig::BuildContext& ctx) {
  py::gil_scoped_acquire gil;
  const std::string who = ctx.full_name() + " (" + type + ") step '" + step + "'" +
                          (origin.empty() ? std::string() : " (" + origin + ")");
  auto ref = std::make_shared<StepRef>();
  ref->ctx = &ctx;
  ref->scene = SceneRef(&ctx.scene(), [](scene::Scene*) {});
  Status result = Status::ok();
  try {
    instance->attr(("step_" + step).c_str())(py::cast(ref));
  } catch (const StatusError& e) {
    result = Status(e.status().code(), who + ": " + e.status().message());
  } catch (py::error_already_set& e) {
    result = error(ErrorCode::kInvalidArgument, who + ": " + e.what());
  } catch (const std::exception& e) {
    result = error(ErrorCode::kInvalidArgument, who + ": " + e.what());
  }
  ref->ctx = nullptr;
  return result;
}

class PythonComponentClass : public rig::ComponentClass {
 public:
  PythonComponentClass(std::string type, std::shared_ptr<py::object> instance,
                       std::vector<std::pair<std::string, std::string>> steps, std::string origin)
      : type_(std::move(type)), instance_(std::move(instance)), steps_(std::move(steps)), origin_(std::move(origin)) {}
  std::string_view type() const override { return type_; }
  std::vector<rig::Step> steps(const rig::Component&) const override {
    std::vector<rig::Step> out;
    for (const auto& [name, feature] : steps_) {
      out.push_back(rig::Step{name, feature, "",
                              [instance = instance_, type = type_, origin = origin_, name = name](rig::BuildContext& ctx) {
                                return run_step(instance, type, origin, name, ctx);
                              }});
    }
    return out;
  }

 private:
  std::string type_;
  std::shared_ptr<py::object> instance_;
  std::vector<std::pair<std::string, std::string>> steps_;
  std::string origin_;
};

// ---- the schema from the class's attributes --------------------------------------

std::string text_of(py::handle h, const std::string& where) {
  if (!py::isinstance<py::str>(h)) raise(ErrorCode::kInvalidArgument, where + ": expected a string");
  return h.cast<std::string>();
}

py::object attr_or(py::handle cls, const char* name, py::object fallback) {
  return py::hasattr(cls, name) ? py::object(cls.attr(name)) : std::move(fallback);
}

rig::ParamSpec param_spec(py::handle h, const std::string& where) {
  py::dict d;
  if (py::isinstance<py::dict>(h)) {
    d = py::reinterpret_borrow<py::dict>(h);
  } else if (py::isinstance<py::tuple>(h) || py::isinstance<py::list>(h)) {
    py::sequence seq = py::reinterpret_borrow<py::sequence>(h);
    const char* keys[] = {"name", "type", "default", "help"};
    for (std::size_t i = 0; i < seq.size() && i < 4; ++i) d[keys[i]] = seq[i];
  } else {
    raise(ErrorCode::kInvalidArgument, where + ": a parameter is a dict or (name, type, default[, help])");
  }
  rig::ParamSpec p;
  p.name = text_of(d.contains("name") ? py::object(d["name"]) : py::object(py::none()), where + ": name");
  const std::string at = where + " '" + p.name + "'";
  const std::string type = d.contains("type") ? text_of(d["type"], at + ": type") : "number";
  const py::object value = d.contains("default") ? py::object(d["default"]) : py::none();
  if (type == "bool") {
    p.type = rig::ParamType::kBool;
    p.default_value = value.is_none() ? false : value.cast<bool>();
  } else if (type == "int") {
    p.type = rig::ParamType::kInt;
    p.default_value = value.is_none() ? std::int64_t{0} : value.cast<std::int64_t>();
  } else if (type == "number" || type == "double") {
    p.type = rig::ParamType::kDouble;
    p.default_value = value.is_none() ? 0.0 : value.cast<double>();
  } else if (type == "string") {
    p.type = rig::ParamType::kString;
    p.default_value = value.is_none() ? std::string() : text_of(value, at + ": default");
  } else if (type == "enum") {
    p.type = rig::ParamType::kEnum;
    if (!d.contains("choices")) raise(ErrorCode::kInvalidArgument, at + ": an enum needs its choices");
    for (py::handle c : d["choices"]) p.choices.push_back(text_of(c, at + ": choices"));
    if (p.choices.empty()) raise(ErrorCode::kInvalidArgument, at + ": an enum needs its choices");
    p.default_value = value.is_none() ? p.choices.front() : text_of(value, at + ": default");
  } else if (type == "vector") {
    p.type = rig::ParamType::kVec3;
    p.default_value = value.is_none() ? math::Vec3(math::Vec3::Zero()) : vec3_from_python(value, at + ": default");
  } else {
    raise(ErrorCode::kInvalidArgument, at + ": type '" + type + "' is not bool, int, number, string, enum or vector");
  }
  if (d.contains("min") && !d["min"].is_none()) p.min = d["min"].cast<double>();
  if (d.contains("max") && !d["max"].is_none()) p.max = d["max"].cast<double>();
  if (d.contains("help")) p.help = text_of(d["help"], at + ": help");
  return p;
}

rig::ControlSpec control_spec(py::handle h, const std::string& where) {
  rig::ControlSpec c;
  if (py::isinstance<py::dict>(h)) {
    py::dict d = py::reinterpret_borrow<py::dict>(h);
    c.role = text_of(d.contains("role") ? py::object(d["role"]) : py::object(py::none()), where + ": role");
    if (d.contains("shape")) c.shape = text_of(d["shape"], where + ": shape");
    if (d.contains("color")) c.color = text_of(d["color"], where + ": color");
    if (d.contains("size")) c.size = d["size"].cast<double>();
    if (d.contains("help")) c.help = text_of(d["help"], where + ": help");
  } else {
    py::sequence seq = py::reinterpret_borrow<py::sequence>(h);
    if (seq.size() < 1) raise(ErrorCode::kInvalidArgument, where + ": a control is a dict or (role, shape, color, size[, help])");
    c.role = text_of(seq[0], where + ": role");
    if (seq.size() > 1) c.shape = text_of(seq[1], where + ": shape");
    if (seq.size() > 2) c.color = text_of(seq[2], where + ": color");
    if (seq.size() > 3) c.size = seq[3].cast<double>();
    if (seq.size() > 4) c.help = text_of(seq[4], where + ": help");
  }
  if (c.shape.empty()) c.shape = "circle";
  if (c.color.empty()) c.color = "yellow";
  return c;
}

rig::GuideSpec guide_spec(py::handle h, const std::string& where) {
  rig::GuideSpec g;
  if (py::isinstance<py::int_>(h)) {
    g.min = g.max = h.cast<int>();
  } else if (py::isinstance<py::dict>(h)) {
    py::dict d = py::reinterpret_borrow<py::dict>(h);
    if (d.contains("names"))
      for (py::handle n : d["names"]) g.names.push_back(text_of(n, where + ": names"));
    g.min = d.contains("min") ? d["min"].cast<int>() : static_cast<int>(g.names.size());
    g.max = d.contains("max") ? (d["max"].is_none() ? -1 : d["max"].cast<int>()) : (g.names.empty() ? -1 : g.min);
    if (d.contains("help")) g.help = text_of(d["help"], where + ": help");
  } else {
    for (py::handle n : h) g.names.push_back(text_of(n, where));
    g.min = g.max = static_cast<int>(g.names.size());
  }
  return g;
}

// The schema and steps a class declares (its attributes: docs/PYTHON.md).
std::pair<rig::ComponentSchema, std::vector<std::pair<std::string, std::string>>> declared(py::handle cls,
                                                                                            const std::string& where) {
  rig::ComponentSchema s;
  if (!py::hasattr(cls, "type")) raise(ErrorCode::kInvalidArgument, where + ": the class has no `type`");
  s.type = text_of(cls.attr("type"), where + ": type");
  const std::string at = where + ": component type '" + s.type + "'";
  py::object doc = attr_or(cls, "__doc__", py::none());
  s.help = text_of(attr_or(cls, "help", doc.is_none() ? py::object(py::str("")) : doc), at + ": help");
  for (py::handle p : attr_or(cls, "params", py::list())) s.params.push_back(param_spec(p, at + ": params"));
  s.guides = guide_spec(attr_or(cls, "guides", py::dict()), at + ": guides");
  for (py::handle c : attr_or(cls, "controls", py::list())) s.controls.push_back(control_spec(c, at + ": controls"));
  for (py::handle h : attr_or(cls, "hooks", py::list())) s.hooks.push_back(text_of(h, at + ": hooks"));
  for (py::handle f : attr_or(cls, "features", py::list())) s.features.push_back(text_of(f, at + ": features"));
  s.fixed_guides = attr_or(cls, "fixed_guides", py::int_(0)).cast<int>();
  std::vector<std::pair<std::string, std::string>> steps;
  for (py::handle step : attr_or(cls, "steps", py::list())) {
    std::pair<std::string, std::string> entry;
    if (py::isinstance<py::str>(step)) {
      entry.first = step.cast<std::string>();
    } else {
      py::sequence seq = py::reinterpret_borrow<py::sequence>(step);
      entry.first = text_of(seq[0], at + ": steps");
      if (seq.size() > 1) entry.second = text_of(seq[1], at + ": steps (feature)");
    }
    if (!py::hasattr(cls, ("step_" + entry.first).c_str()))
      raise(ErrorCode::kInvalidArgument, at + ": step '" + entry.first + "' has no method step_" + entry.first);
    for (const auto& [name, feature] : steps)
      if (name == entry.first) raise(ErrorCode::kInvalidArgument, at + ": step '" + name + "' is listed twice");
    steps.push_back(std::move(entry));
  }
  if (steps.empty()) raise(ErrorCode::kInvalidArgument, at + ": `steps` lists no step");
  return {std::move(s), std::move(steps)};
}

// ---- ComponentBuild ----------------------------------------------------------------

NodeId parent_or_attach(const StepRef& r, const std::optional<NodeArg>& parent) {
  return parent ? resolve(r.scene, *parent) : r.get().attach_node();
}

const char* constraint_type(const std::string& type) {
  namespace c = ops::constraints;
  for (const char* t : {c::kParentConstraintType, c::kPointConstraintType, c::kOrientConstraintType,
                        c::kScaleConstraintType, c::kAimConstraintType})
    if (type == t) return t;
  raise(ErrorCode::kInvalidArgument, "constrain: '" + type +
                                         "' is not parentConstraint, pointConstraint, orientConstraint, "
                                         "scaleConstraint or aimConstraint");
}

const char* channel_name(const std::string& channel) {
  for (const char* c : {"translate", "rotate", "scale"})
    if (channel == c) return c;
  raise(ErrorCode::kInvalidArgument, "constrain: channel '" + channel + "' is not translate, rotate or scale");
}

void def_component_build(py::module_& m) {
  py::class_<StepRef, std::shared_ptr<StepRef>>(
      m, "ComponentBuild",
      "What a Python component type's step works with (the rig layer's BuildContext): the component's "
      "parameters and guides, and the nodes it makes, recorded so the step is undone exactly. Valid during the "
      "step only.")
      .def_property_readonly("scene", [](const StepRef& r) { (void)r.get(); return r.scene; })
      .def_property_readonly("name", [](const StepRef& r) { return r.get().full_name(); },
                             "The component's full name (NAME_SIDE), the prefix of its nodes.")
      .def_property_readonly("type", [](const StepRef& r) { return r.get().component().type; })
      .def_property_readonly("rig_name", [](const StepRef& r) { return r.get().rig_name(); })
      .def_property_readonly("step", [](const StepRef& r) { return r.get().step(); })
      .def_property_readonly("meta", [](const StepRef& r) { return node_ref(r.scene, r.get().meta()); },
                             "The component's metaComponent node.")
      .def_property_readonly("attach", [](const StepRef& r) { return node_ref(r.scene, r.get().attach_node()); },
                             "Where the component hangs: its parent's hook, or the rig's controls group.")
      .def_property_readonly("guide_count", [](const StepRef& r) { return r.get().guide_count(); })
      .def(
          "param",
          [](const StepRef& r, const std::string& name) {
            rig::BuildContext& ctx = r.get();
            const rig::ParamValue* value = ctx.param_value(name);
            if (!value) raise(ErrorCode::kInvalidArgument, ctx.full_name() + ": no parameter '" + name + "'");
            return param_to_python(*value);
          },
          py::arg("name"), "A parameter's value (the schema's default when the definition leaves it out).")
      .def(
          "guide_world", [](const StepRef& r, int i) { return matrix_to_python(unwrap(r.get().guide_world(i))); },
          py::arg("index"), "Guide i as a world matrix: its joint's, else its values.")
      .def(
          "guide_joint", [](const StepRef& r, int i) { return node_ref(r.scene, unwrap(r.get().guide_joint(i))); },
          py::arg("index"), "The scene joint guide i names (NotFoundError when none).")
      .def(
          "create",
          [](const StepRef& r, const std::string& type, const std::string& role, int index, int guide,
             std::optional<NodeArg> parent) {
            const NodeId p = parent ? resolve(r.scene, *parent) : NodeId{};
            return node_ref(r.scene, unwrap(r.get().create(type, role, index, guide, p)));
          },
          py::arg("type"), py::arg("role"), py::arg("index") = -1, py::arg("guide") = -1, py::arg("parent") = py::none(),
          "Makes a node of `type`, named and tagged by its role and linked to the component.")
      .def(
          "create_control",
          [](const StepRef& r, const std::string& role, py::handle world, int index, int guide,
             std::optional<NodeArg> parent) {
            const math::Mat4 w = matrix_from_python(world, "create_control: world");
            return node_ref(r.scene, unwrap(r.get().create_control(role, index, guide, w, parent_or_attach(r, parent))));
          },
          py::arg("role"), py::arg("world"), py::arg("index") = -1, py::arg("guide") = -1,
          py::arg("parent") = py::none(),
          "A control at `world` (a matrix), zeroed, with the role's shape, colour and size; under `parent` "
          "(default: the attach point).")
      .def(
          "create_group",
          [](const StepRef& r, const std::string& role, py::handle world, int index, std::optional<NodeArg> parent) {
            const math::Mat4 w = matrix_from_python(world, "create_group: world");
            return node_ref(r.scene, unwrap(r.get().create_group(role, index, w, parent_or_attach(r, parent))));
          },
          py::arg("role"), py::arg("world"), py::arg("index") = -1, py::arg("parent") = py::none(),
          "A group at `world`, zeroed; under `parent` (default: the attach point).")
      .def(
          "drive",
          [](const StepRef& r, const NodeArg& driver, const NodeArg& driven) {
            check(r.get().drive(resolve(r.scene, driver), resolve(r.scene, driven)));
          },
          py::arg("driver"), py::arg("driven"), "Makes `driven` (a joint) follow `driver`, keeping its offset.")
      .def(
          "constrain",
          [](const StepRef& r, const std::string& type, const std::string& role, const std::vector<NodeArg>& targets,
             const NodeArg& driven, std::vector<double> weights, bool maintain_offset,
             std::vector<std::string> channels) {
            rig::ConstraintSpec spec;
            spec.type = constraint_type(type);
            spec.role = role;
            spec.targets = resolve_all(r.scene, targets);
            spec.weights = std::move(weights);
            spec.maintain_offset = maintain_offset;
            for (const std::string& c : channels) spec.channels.push_back(channel_name(c));
            return node_ref(r.scene, unwrap(r.get().constrain(spec, resolve(r.scene, driven))));
          },
          py::arg("type"), py::arg("role"), py::arg("targets"), py::arg("driven"),
          py::arg("weights") = std::vector<double>{}, py::arg("maintain_offset") = true,
          py::arg("channels") = std::vector<std::string>{},
          "A constraint (parentConstraint, pointConstraint, orientConstraint, scaleConstraint, aimConstraint) on "
          "`driven`'s channels (default: all it drives), its parent space following the driven's parent.")
      .def(
          "node",
          [](const StepRef& r, const std::string& role, int index) { return node_or_none(r.scene, r.get().node(role, index)); },
          py::arg("role"), py::arg("index") = 0, "A node an earlier step made, by role (None when none).")
      .def(
          "nodes", [](const StepRef& r, const std::string& role) { return node_list(r.scene, r.get().nodes(role)); },
          py::arg("role"), "The nodes of a role, in index order.")
      .def(
          "publish_hook",
          [](const StepRef& r, int index, const NodeArg& node) { check(r.get().publish_hook(index, resolve(r.scene, node))); },
          py::arg("index"), py::arg("node"), "Publishes `node` as hook `index`: children attach to it.");
}

// The component instance of a meta node: the registered Python class's (its
// attributes set), else a record; either way meta, type, name, controls,
// hooks and attach.
py::object component_instance(const NodeRef& meta) {
  const graph::Graph& g = meta.scene->graph();
  const NodeId id = meta.id();
  if (g.node(id)->type().name() != rig::kMetaComponentType)
    raise(ErrorCode::kInvalidArgument, g.node(id)->name() + ": not a component's meta node (metaComponent)");
  const std::string type = rig::meta_string(g, id, "metaType");
  // Hooks: the members tagged with a hook index, in index order.
  std::map<int, NodeId> by_index;
  for (NodeId m : rig::meta_members(g, id))
    if (const std::string* h = g.node(m)->tag_find(rig::kTagHook)) by_index[std::stoi(*h)] = m;
  py::list hooks;
  for (const auto& [index, node] : by_index) hooks.append(node_ref(meta.scene, node));
  // The attach point: where its controls hang from outside the component.
  py::object attach = py::none();
  for (NodeId c : rig::meta_controls(g, id)) {
    const NodeId p = g.parent(c);
    if (p.is_valid() && rig::component_of(g, p) != id) {
      attach = py::cast(node_ref(meta.scene, p));
      break;
    }
  }
  const NodeId parent = rig::meta_parent(g, id);
  py::dict fields;
  fields["meta"] = meta;
  fields["type"] = type;
  fields["name"] = rig::meta_string(g, id, "componentName");
  fields["controls"] = node_list(meta.scene, rig::meta_controls(g, id));
  fields["hooks"] = hooks;
  fields["attach"] = attach;
  fields["parent"] = node_or_none(meta.scene, parent);
  const auto found = python_classes().find(type);
  if (found == python_classes().end()) return record(fields);
  py::object cls = *found->second;
  py::object obj = cls.attr("__new__")(cls);
  for (auto [key, value] : fields) py::setattr(obj, key, value);
  return obj;
}

}  // namespace

void wrap_component_types(py::module_& m) {
  def_component_build(m);
  py::module_::import("atexit").attr("register")(py::cpp_function([] {
    std::vector<std::string> origins;
    for (const auto& entry : rig::registered_component_types()) origins.push_back(entry.second);
    for (const std::string& origin : origins) rig::unregister_component_types(origin);
    python_classes().clear();
  }));
  m.def(
      "register_component_type",
      [](py::object cls, const std::string& origin) {
        const std::string where = origin.empty() ? std::string("register_component_type") : origin;
        auto [schema, steps] = declared(cls, where);
        const std::string type = schema.type;
        py::object instance;
        try {
          instance = cls();
        } catch (py::error_already_set& e) {
          raise(ErrorCode::kInvalidArgument, where + ": component type '" + type + "': its class raised: " + e.what());
        }
        auto made = std::make_shared<PythonComponentClass>(type, hold(std::move(instance)), std::move(steps), origin);
        check(rig::register_component_type(std::move(schema), std::move(made), origin));
        python_classes()[type] = hold(cls);
      },
      py::arg("cls"), py::arg("origin") = "",
      "Registers a component type written in Python: a class with `type`, `help`, `params`, `guides`, "
      "`controls`, `hooks`, `features` and `steps`, and a method step_NAME(build) per step (build: a "
      "ComponentBuild). AlreadyExistsError naming who has the type; InvalidArgumentError for a declaration "
      "that does not hold or a class that raises when made.");
  m.def(
      "unregister_component_types",
      [](const std::string& origin) {
        for (const auto& [type, from] : rig::registered_component_types())
          if (from == origin) python_classes().erase(type);
        return rig::unregister_component_types(origin);
      },
      py::arg("origin"), "Removes the component types registered from `origin` (a plugin's file); how many.");
  m.def(
      "registered_component_types",
      []() {
        py::list out;
        for (const auto& [type, origin] : rig::registered_component_types()) {
          py::dict d;
          d["type"] = type;
          d["origin"] = origin;
          out.append(d);
        }
        return out;
      },
      "The component types registered at run time (Python's): type and origin.");
  m.def("component_instance", &component_instance, py::arg("meta"),
        "A built component from its meta node: an instance of its Python class (for a type registered from "
        "Python) or a record, with meta, type, name, controls, hooks, attach (where its controls hang from) and "
        "parent (the parent component's meta).");
}

}  // namespace rigel::python
