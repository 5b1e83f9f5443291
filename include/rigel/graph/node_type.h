#pragma once
// Node types: attribute specs and a compute function, registered by name in
// a Registry (Maya's MPxNode + MFnAttribute + attributeAffects, without the
// host).

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/value.h"

namespace rigel::graph {

using AttrIndex = std::uint16_t;
inline constexpr AttrIndex kNoAttr = 0xffff;

// The message input every node type gets last (Registry::add adds it): the
// metadata network connects a component's meta node to each node it built.
inline constexpr const char* kMetaParentAttr = "metaParent";

// Attribute flags. Every attribute is exactly one of kInput or kOutput.
enum AttrFlag : std::uint32_t {
  kInput = 1u << 0,     // set by the user or fed by a connection
  kOutput = 1u << 1,    // written by the node's compute
  kKeyable = 1u << 2,   // animators key it (shown in channel boxes)
  kStorable = 1u << 3,  // saved in scene files
  kHidden = 1u << 4,    // not shown to users by default
  kAngle = 1u << 5,     // a double/double3 angle, stored in degrees (the user's unit);
                        // compute functions convert to radians
  // Outputs only: the value does not depend on time, so a time change
  // leaves it clean on a time_dependent type (what a compute derives from
  // its inputs alone, such as a curve's check of its keys). The compute
  // sees it clean (Node::is_dirty) and may keep it rather than redo it.
  kTimeInvariant = 1u << 6,
};

struct AttrSpec {
  std::string name;
  AttrType type;
  Value default_value;  // monostate means the type's zero_value()
  std::uint32_t flags = kInput | kStorable;
  std::vector<std::string> enum_names;  // kEnum only: names of 0, 1, 2, ...
  std::vector<std::string> affects;     // inputs only: outputs that depend on it
};

// The two usual shapes of an AttrSpec, for node types' attribute tables.
// An input is storable (saved in files) and may add flags such as kKeyable
// or kHidden; an output is computed and never stored.
inline AttrSpec input_attr(std::string name, AttrType type, Value default_value,
                           std::vector<std::string> affects = {}, std::uint32_t extra_flags = 0) {
  AttrSpec spec;
  spec.name = std::move(name);
  spec.type = type;
  spec.default_value = std::move(default_value);
  spec.flags = kInput | kStorable | extra_flags;
  spec.affects = std::move(affects);
  return spec;
}

inline AttrSpec output_attr(std::string name, AttrType type, std::uint32_t extra_flags = 0) {
  AttrSpec spec;
  spec.name = std::move(name);
  spec.type = type;
  spec.flags = kOutput | extra_flags;
  return spec;
}

class ComputeContext;
using ComputeFn = void (*)(ComputeContext& context);

// What a type declares; Registry::add validates it and builds a NodeType.
struct NodeTypeSpec {
  std::string name;
  std::vector<AttrSpec> attrs;
  ComputeFn compute = nullptr;  // required when the type has outputs
  // Hierarchy roles: a node of this type can be parented when it names a
  // matrix input that receives its parent's world matrix, and can be a
  // parent when it names a matrix output holding its world matrix.
  std::string parent_input;
  std::string world_output;
  // Outputs (but kTimeInvariant ones) are dirtied whenever the graph's time changes.
  bool time_dependent = false;
  std::string description;
};

class NodeType {
 public:
  const std::string& name() const { return name_; }
  const std::string& description() const { return description_; }
  std::size_t attr_count() const { return attrs_.size(); }
  const AttrSpec& attr(AttrIndex index) const { return attrs_[index]; }
  std::span<const AttrSpec> attrs() const { return attrs_; }
  // kNoAttr when the type has no such attribute.
  AttrIndex attr_find(std::string_view name) const;
  // The default value of an attribute (never monostate unless message).
  const Value& default_value(AttrIndex index) const { return attrs_[index].default_value; }
  // Outputs an input affects (empty for outputs).
  std::span<const AttrIndex> affected_outputs(AttrIndex input) const { return affects_[input]; }
  std::span<const AttrIndex> outputs() const { return outputs_; }
  ComputeFn compute() const { return compute_; }
  AttrIndex parent_input() const { return parent_input_; }
  AttrIndex world_output() const { return world_output_; }
  bool time_dependent() const { return time_dependent_; }
  bool is_input(AttrIndex i) const { return (attrs_[i].flags & kInput) != 0; }

 private:
  friend class Registry;
  std::string name_;
  std::string description_;
  std::vector<AttrSpec> attrs_;
  std::vector<std::vector<AttrIndex>> affects_;
  std::vector<AttrIndex> outputs_;
  std::unordered_map<std::string, AttrIndex> by_name_;
  ComputeFn compute_ = nullptr;
  AttrIndex parent_input_ = kNoAttr;
  AttrIndex world_output_ = kNoAttr;
  bool time_dependent_ = false;
};

// Node types by name. Types are added once and never change or go away, so
// `const NodeType*` handed out stay valid for the registry's lifetime.
class Registry {
 public:
  // Validates `spec` and adds it. Fails if the name is taken or invalid, an
  // attribute name repeats or is not an identifier, flags are inconsistent,
  // a default does not match its type, an enum default is out of range,
  // `affects` names something that is not an output of the type, a
  // hierarchy role names a wrong attribute, or outputs lack a compute.
  Status add(NodeTypeSpec spec);
  // nullptr when no type has that name.
  const NodeType* find(std::string_view name) const;
  std::vector<std::string> type_names() const;

 private:
  std::vector<std::unique_ptr<NodeType>> types_;
  std::unordered_map<std::string, const NodeType*> by_name_;
};

// True for [A-Za-z_][A-Za-z0-9_]*.
bool is_identifier(std::string_view name);

}  // namespace rigel::graph
