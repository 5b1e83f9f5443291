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

const ComponentClass* ComponentFactory::find(std::string_view type) const {
  for (const auto& c : classes_)
    if (c->type() == type) return c.get();
  return nullptr;
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
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace rigel::rig
