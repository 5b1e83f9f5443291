// What the wraps of rig definitions, components, builds and the metadata
// network share: the component classes builds use, Component handles, and
// how parameters, guides, control styles, features and schemas cross the
// boundary (docs/PYTHON.md).
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common.h"
#include "rigel/rig/component.h"
#include "rigel/rig/definition.h"
#include "rigel/rig/schema.h"

namespace rigel::python {

using DefinitionRef = std::shared_ptr<rig::Definition>;

// Every component class rigel has (the rig layer's and `ephemeral`) with the
// data importer (tools::components()): what the CLI builds with.
const rig::ComponentFactory& factory();
const rig::SchemaRegistry& schemas();

// ---- component handles ---------------------------------------------------------

// A component of a Definition as Python holds it: by rigId (a component's
// identity), or by its path of child indices when it has none. Resolved on
// every use, so handles stay valid while the definition grows.
struct ComponentRef {
  DefinitionRef def;
  std::string rig_id;
  std::vector<std::size_t> path;

  rig::Component& get() const;  // raises NotFoundError when the component is gone
};

// The list holding `target` and its index there; nullptr when absent.
std::vector<rig::Component>* container_of(std::vector<rig::Component>& list, const rig::Component* target,
                                          std::size_t* index, rig::Component** parent, rig::Component* owner);
ComponentRef ref_of(const DefinitionRef& def, const rig::Component& c);
py::list refs_of(const DefinitionRef& def, const std::vector<rig::Component>& list);

// Adds a component to `list` (the definition's roots or a component's
// children) and returns its handle. A missing rigId gets a fresh one.
ComponentRef add_component(const DefinitionRef& def, std::vector<rig::Component>& list, const std::string& type,
                           const std::string& name, const std::string& side, py::object guides, py::object params,
                           py::object controls, const std::string& attach, const std::string& version,
                           std::optional<std::string> rig_id);

// ---- parameters, guides, controls, features ----------------------------------------

py::object param_to_python(const rig::ParamValue& v);
// Sets a parameter typed by the component type's schema when it declares
// it (an int is accepted for a double); otherwise by the Python type, kept
// as it is for validate() to report.
void set_param(rig::Component& c, const std::string& name, py::handle v);
py::dict params_of(const rig::Component& c);
// A Guide, a joint name or a dict {name, joint, translate, rotate, scale}.
rig::Guide guide_from_python(py::handle h, const std::string& where);
// A ControlStyle or a dict {role, shape, color, size}.
rig::ControlStyle control_from_python(py::handle h, const std::string& where);
rig::Side side_from(const std::string& side);
// Features as dicts {name, enabled, switches: {name: enabled}}.
py::list features_of(const std::vector<rig::Feature>& features);
void set_feature(std::vector<rig::Feature>& features, const std::string& name, bool enabled,
                 const std::optional<std::map<std::string, bool>>& switches);

// ---- definitions and schemas -----------------------------------------------------

// Raises DefinitionError listing every problem as file:line:column.
[[noreturn]] void raise_definition(const std::string& what, const std::vector<rig::Diagnostic>& problems);
DefinitionRef load_definition(const std::string& path);
// Raises DefinitionError when validate() finds problems.
void check_valid(const rig::Definition& def);
py::dict schema_info(const rig::ComponentSchema& s);
// A component type's schema (NotFoundError listing the types).
const rig::ComponentSchema& schema_of(const std::string& type);

// ---- binding entry points (called by module.cc in this order) --------------------

void wrap_diagnostic(py::module_& m);
void wrap_guide(py::module_& m);
void wrap_control_style(py::module_& m);
void declare_component(py::module_& m);  // wrap_component.cc: the class only (Definition's methods return it)
void wrap_definition(py::module_& m);
void wrap_component(py::module_& m);
void wrap_schemas(py::module_& m);  // module functions: component types and schemas, check_definition
void wrap_rig_build(py::module_& m);
void wrap_meta(py::module_& m);  // Scene's and Node's methods of the metadata network
// Build graphs: graph files, build functions written in Python (wrap_build_graph.cc).
void wrap_build_graph(py::module_& m);
void wrap_component_types(py::module_& m);  // component types written in Python
// rigel.Server: the server library in this process (wrap_serve.cc).
void wrap_serve(py::module_& m);

}  // namespace rigel::python
