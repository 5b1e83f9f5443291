// The Rig Manager's operations (seed 002 §4.3.1), shared by the `rigel`
// commands, `rigel serve` and the Python module: reading a definition with
// every problem reported, the list of rigs in a scene with their versions
// (and whether the definition on disk is newer), adding a rig from a
// definition file and updating a rig from its definition.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "rigel/base/status.h"
#include "rigel/rig/build.h"
#include "rigel/rig/component.h"
#include "rigel/rig/definition.h"
#include "rigel/rig/definition_io.h"
#include "rigel/scene/scene.h"

namespace rigel::rig {

// Loads and validates a definition file: kInvalidArgument whose message
// lists every problem as "file:line:column: message", one per line.
Result<Definition> read_definition(const std::filesystem::path& path, const SchemaRegistry& schemas = builtin_schemas());

// How a built rig stands against its definition on disk (the Rig Manager's
// red button, and what update_rig rebuilds): the rig's version and every
// component's, matched by rigId. A component is out of date when the
// definition gives it another version (kChanged), no longer has it
// (kRemoved), or has a component the scene has not built (kAdded).
struct ComponentState {
  enum class Kind { kCurrent, kChanged, kRemoved, kAdded };
  std::string rig_id, name, type;
  std::string version;             // built ("" for kAdded)
  std::string definition_version;  // on disk ("" for kRemoved, or no definition)
  Kind kind = Kind::kCurrent;
  bool out_of_date() const { return kind != Kind::kCurrent; }
};
const char* component_state_name(ComponentState::Kind kind);  // "current", "changed", "removed", "added"
struct RigState {
  std::string rig, version;
  std::string definition;  // the absolute path the rig keeps ("" when none)
  // The definition could be read and checked; otherwise `problem` says why
  // ("no definition path", "PATH: cannot be read (missing, or no permission)",
  // the first validation error) and nothing below compares.
  bool definition_found = false;
  std::string problem;
  std::string definition_version;
  std::vector<ComponentState> components;  // built ones in build order, then added ones
  // The rig's version differs or any component is out of date.
  bool out_of_date = false;
};
// kNotFound when the scene has no rig `rig_name`.
Result<RigState> rig_state(const graph::Graph& graph, std::string_view rig_name,
                           const SchemaRegistry& schemas = builtin_schemas());

// The rigs of a scene, what `rigel rigs --json` prints under "rigs": per rig
// its name, version, definition path (absolute), definitionFound and
// definitionProblem (null when found), the version of the definition on
// disk (null when it cannot be read), outOfDate (RigState::out_of_date: the
// Rig Manager's red button), editMode, buildPosition, its components (name,
// type, version, rigId, parent component, node count, definitionVersion
// (null when the definition has none), state ("current", "changed",
// "removed") and outOfDate) and `added`: the components the definition has
// and the scene has not built (name, type, definitionVersion, rigId, state
// "added", outOfDate true).
nlohmann::ordered_json rigs_report(const graph::Graph& graph);

// A component type's schema as `rigel components --json` prints it: type,
// help, params (name, type, default, min, max, choices, help), guides (min,
// max, names, help), controls (role, shape, color, size, help), hooks,
// features, rootOnly, needsParent.
nlohmann::ordered_json component_schema_json(const ComponentSchema& schema);

// Every guide joint of `definition` that `graph` lacks (or that is not a
// transform), each at its guide's place in the definition file: what a build
// would otherwise stop at, one at a time. Empty when every joint is there.
std::vector<Diagnostic> check_guide_joints(const Definition& definition, const scene::Scene& scene);

// Builds the definition at `path` on `scene` (every step; progress, when
// given, gets the steps done and the total after each) and records the path
// on the metaRoot. Fails, changing nothing, on an invalid definition, guide
// joints the scene lacks (every one listed, file:line:column) or a step
// that fails.
struct AddedRig {
  std::string name, version;
  int steps = 0;
  std::vector<std::string> components;  // full names, build order
};
Result<AddedRig> add_rig(scene::Scene& scene, const std::filesystem::path& path, const ComponentFactory& factory,
                         BuildOptions options = {}, const std::function<void(int, int)>& progress = {});

// Updates rig `rig_name` from its definition (its own definitionPath, or
// `definition_path` when not empty): components whose version differs are
// rebuilt, with what hangs from them, components added are built and
// components removed are destructed (every component with `force`), keys
// kept as `keep` says. The rebuilt components are built on the rest pose
// (Build::rebuild_changed), whatever the scene's time. `updated` is false
// when the rig's and every component's version and the data entries
// (Definition::data) already agreed and nothing was forced; an update that
// runs imports the data again (rebuild_changed). A definition that cannot be read fails naming its path.
// Updated from `definition_path`, the rig records it as its definition.
struct UpdateReport {
  std::string rig, from, to, definition;
  bool updated = false;
  std::vector<std::string> rebuilt;  // full names (or rigIds of removed components)
};
Result<UpdateReport> update_rig(scene::Scene& scene, std::string_view rig_name, const ComponentFactory& factory,
                                const std::filesystem::path& definition_path = {}, bool force = false,
                                Build::KeepKeys keep = Build::KeepKeys::kLocal);

}  // namespace rigel::rig
