// Component schemas: what each component type accepts (seed 003's UI
// templates, made data). One schema drives validation (`rigel validate`),
// the CLI's help (`rigel components`), the shipped JSON Schema and XSD, and
// the web app's forms.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/rig/definition.h"

namespace rigel::rig {

enum class ParamType { kBool, kInt, kDouble, kString, kEnum, kVec3 };
const char* param_type_name(ParamType type);  // "bool", "int", "double", "string", "enum", "vec3"

struct ParamSpec {
  std::string name;
  ParamType type = ParamType::kDouble;
  ParamValue default_value;                // of the matching alternative (kEnum: a string)
  std::optional<double> min, max;          // kInt, kDouble (inclusive)
  std::vector<std::string> choices;        // kEnum
  std::string help;
};

// How many guides a component takes, and their names when fixed.
struct GuideSpec {
  int min = 0;
  int max = -1;                     // -1: no upper limit
  std::vector<std::string> names;   // fixed roles, in order (size == min == max); empty = numbered
  std::string help;
};

// A control role with its default look.
struct ControlSpec {
  std::string role;
  std::string shape;
  std::string color;
  double size = 1.0;
  std::string help;
};

// A step of a component's build, as the schema announces it (the component
// class supplies the construct function; build.h). `feature`/`switch_name`
// empty = always runs.
struct StepSpec {
  std::string name;
  std::string feature;
  std::string switch_name;
  std::string help;
};

struct ComponentSchema {
  std::string type;
  std::string help;
  std::vector<ParamSpec> params;
  GuideSpec guides;
  std::vector<ControlSpec> controls;
  std::vector<std::string> features;  // feature names its steps use
  // Hooks it publishes, by name, in index order. "guide[i]" entries are
  // expanded per guide: a component with hooks {"guide[i]"} and 4 guides
  // publishes hooks 0..3 named by its guides (or "0".."3").
  std::vector<std::string> hooks;
  bool root_only = false;    // may only be a root (global)
  bool needs_parent = false;  // may not be a root
  // Guide offsets (translate, rotate, scale on a guide with a joint) place
  // a control off its joint. The first `fixed_guides` guides (-1: every
  // one) take none, because the type makes no control there or its control
  // must stand at the joint; validate() refuses an offset on them.
  int fixed_guides = 0;
  // Checks of the type's own beyond the ones above (a call's args are a
  // JSON object): each message is an error at the component.
  std::function<std::vector<std::string>(const Component&)> check;

  const ParamSpec* param(std::string_view name) const;
  const ControlSpec* control(std::string_view role) const;
  // Hook names of `component` (expanded per guide); index = position.
  std::vector<std::string> hook_names(const Component& component) const;
};

class SchemaRegistry {
 public:
  // Fails (kAlreadyExists) on a duplicate type, (kInvalidArgument) on a
  // default that does not fit its own spec.
  Status add(ComponentSchema schema);
  // Removes a type (false when there is none). A schema found before stays
  // valid only until its type is removed.
  bool remove(std::string_view type);
  // The schema of `type`; the pointer stays valid while the type is there.
  const ComponentSchema* find(std::string_view type) const;
  std::vector<std::string> types() const;  // sorted
 private:
  std::vector<std::shared_ptr<const ComponentSchema>> schemas_;
};

// Every component type rigel ships (src/rig/builtin_schemas.cc), and those
// added at run time by register_component_type (component.h: a Python
// plugin's types).
const SchemaRegistry& builtin_schemas();
// The same registry, for register_component_type to add to; nothing else
// changes it.
SchemaRegistry& extensible_schemas();

// Resolves a hook reference ("2", "END", "START", "MIDDLE", a hook name) of
// a component with hooks `names`: the index, or nullopt.
std::optional<int> resolve_hook(const std::vector<std::string>& names, std::string_view ref);

}  // namespace rigel::rig
