// ComponentFactory (component.h): component classes by type.
#include "rigel/rig/component.h"

#include <algorithm>
#include <string>

#include "rigel/rig/meta.h"

namespace rigel::rig {

Status ComponentFactory::add(std::shared_ptr<const ComponentClass> component_class) {
  const std::string type(component_class->type());
  if (!schemas_->find(type)) return error(ErrorCode::kNotFound, "component class '" + type + "' has no schema");
  if (find(type)) return error(ErrorCode::kAlreadyExists, "component type '" + type + "' already has a class");
  classes_.push_back(std::move(component_class));
  return Status::ok();
}

namespace {

struct RegisteredType {
  std::string origin;
  std::shared_ptr<const ComponentClass> component_class;
};

std::vector<RegisteredType>& registered() {
  static std::vector<RegisteredType> types;
  return types;
}

const ComponentClass* find_registered(std::string_view type) {
  for (const RegisteredType& r : registered())
    if (r.component_class->type() == type) return r.component_class.get();
  return nullptr;
}

}  // namespace

const ComponentClass* ComponentFactory::find(std::string_view type) const {
  for (const auto& c : classes_)
    if (c->type() == type) return c.get();
  return find_registered(type);
}

Status register_component_type(ComponentSchema schema, std::shared_ptr<const ComponentClass> component_class,
                               std::string origin) {
  const std::string type = schema.type;
  const std::string from = origin.empty() ? std::string() : " (" + origin + ")";
  if (!component_class || component_class->type() != type)
    return error(ErrorCode::kInvalidArgument, "component type '" + type + "'" + from + ": its class builds another type");
  for (const RegisteredType& r : registered())
    if (r.component_class->type() == type)
      return error(ErrorCode::kAlreadyExists, "component type '" + type + "'" + from + " is taken: " +
                                                  (r.origin.empty() ? "registered before" : "registered from " + r.origin));
  if (builtin_schemas().find(type) || builtin_components().find(type))
    return error(ErrorCode::kAlreadyExists, "component type '" + type + "'" + from + " is taken: rigel ships it");
  if (Status s = extensible_schemas().add(std::move(schema)); !s) return Status(s.code(), s.message() + from);
  registered().push_back({std::move(origin), std::move(component_class)});
  return Status::ok();
}

std::size_t unregister_component_types(std::string_view origin) {
  std::size_t removed = 0;
  auto& types = registered();
  for (auto it = types.begin(); it != types.end();) {
    if (it->origin != origin) {
      ++it;
      continue;
    }
    extensible_schemas().remove(it->component_class->type());
    it = types.erase(it);
    ++removed;
  }
  return removed;
}

std::vector<std::pair<std::string, std::string>> registered_component_types() {
  std::vector<std::pair<std::string, std::string>> out;
  for (const RegisteredType& r : registered()) out.emplace_back(std::string(r.component_class->type()), r.origin);
  return out;
}

Result<const ComponentClass*> ComponentFactory::class_of(const graph::Graph& graph, NodeId meta) const {
  const graph::Node* n = graph.node(meta);
  if (!n || n->type().name() != kMetaComponentType)
    return error(ErrorCode::kNotFound, "class_of: not a metaComponent node");
  const std::string type = meta_string(graph, meta, "metaType");
  const ComponentClass* c = find(type);
  if (!c) return error(ErrorCode::kUnsupported, n->name() + ": no component class for metaType '" + type + "'");
  return c;
}

std::vector<std::string> ComponentFactory::types() const {
  std::vector<std::string> out;
  for (const auto& c : classes_) out.emplace_back(c->type());
  for (const RegisteredType& r : registered())
    if (std::find(out.begin(), out.end(), r.component_class->type()) == out.end())
      out.emplace_back(r.component_class->type());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace rigel::rig
