// Component classes (seed 003's modules with constructor and destructor;
// Luna's Component classes bound to metaType, seed 004 §4.8). A class
// declares the steps that build one component of its type; the build
// (build.h) records and undoes them, so a class writes constructs only.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/rig/build.h"
#include "rigel/rig/schema.h"

namespace rigel::rig {

class ComponentClass {
 public:
  virtual ~ComponentClass() = default;
  // The component type this class builds (a type of the factory's schemas).
  virtual std::string_view type() const = 0;
  // The steps that build `component`, in order (the build adds its own
  // "meta" step first). Step names are unique within a component.
  virtual std::vector<Step> steps(const Component& component) const = 0;
  // Whether rig edit mode (Build::edits) reads this component's controls as
  // guides: true for classes whose controls are zeroed at their guides (all
  // of the rig layer's). A class whose controls hold a pose of their own
  // (ephemeral: the joints' channels) says false, and edit mode leaves them.
  virtual bool editable() const { return true; }
};

// Component classes by type (a C++ factory registry). The rig layer's own
// classes are in builtin_components(); higher layers add theirs to a copy
// (the ephemeral layer: ephemeral::components()).
class ComponentFactory {
 public:
  // Imports one data entry of a definition (<data kind file/>) into the
  // scene, for the rig whose metaRoot is `rig`; `file` is the entry's file
  // resolved against the definition's folder. The build's last step ("data")
  // calls it for each entry, recorded like every step. The rig layer does not
  // know the data formats: the tools layer gives the importer
  // (tools::components(), tools/data_files.h); without one, a definition
  // that names data fails to build, saying so.
  using DataImporter = std::function<Status(scene::Scene& scene, graph::NodeId rig, const DataImport& entry,
                                            const std::filesystem::path& file)>;

  explicit ComponentFactory(const SchemaRegistry& schemas = builtin_schemas()) : schemas_(&schemas) {}
  // Fails when the type has no schema or already has a class.
  Status add(std::shared_ptr<const ComponentClass> component_class);
  // Its own class of `type`, else one registered at run time.
  const ComponentClass* find(std::string_view type) const;
  // Luna's metaType binding: the class that built a component, from its
  // metaComponent node (kNotFound / kUnsupported naming the metaType).
  Result<const ComponentClass*> class_of(const graph::Graph& graph, graph::NodeId meta) const;
  const SchemaRegistry& schemas() const { return *schemas_; }
  std::vector<std::string> types() const;  // its own and the run-time ones, sorted
  void set_data_importer(DataImporter importer) { data_importer_ = std::move(importer); }
  const DataImporter& data_importer() const { return data_importer_; }

 private:
  const SchemaRegistry* schemas_;
  std::vector<std::shared_ptr<const ComponentClass>> classes_;
  DataImporter data_importer_;
};

// The rig layer's component classes (components/*.cc).
const ComponentFactory& builtin_components();

// Component types added at run time (a Python plugin's, apps/python): the
// schema joins builtin_schemas() and the class is found by every
// ComponentFactory (after its own classes), so definitions with the type
// parse, validate, build, step, update and are removed as with a built-in
// one. `origin` (the plugin's file) is named when another registration
// wants the type: kAlreadyExists naming who has it (a built-in type:
// "rigel"), and nothing is registered; kInvalidArgument for a schema that
// does not hold (registry's add) or a class of another type. Register before
// building: registration is not synchronised with builds on other threads.
Status register_component_type(ComponentSchema schema, std::shared_ptr<const ComponentClass> component_class,
                               std::string origin);
// Removes the types registered from `origin`; how many.
std::size_t unregister_component_types(std::string_view origin);
// Types registered at run time, each with its origin, in registration order.
std::vector<std::pair<std::string, std::string>> registered_component_types();

}  // namespace rigel::rig
