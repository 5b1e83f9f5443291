#include "rigel/graph/node_type.h"

#include <algorithm>

namespace rigel::graph {

bool is_identifier(std::string_view name) {
  if (name.empty()) return false;
  auto alpha = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; };
  if (!alpha(name[0])) return false;
  return std::all_of(name.begin(), name.end(), [&](char c) { return alpha(c) || (c >= '0' && c <= '9'); });
}

AttrIndex NodeType::attr_find(std::string_view name) const {
  auto it = by_name_.find(std::string(name));
  return it == by_name_.end() ? kNoAttr : it->second;
}

Status Registry::add(NodeTypeSpec spec) {
  auto fail = [&](const std::string& what) {
    return error(ErrorCode::kInvalidArgument, "node type '" + spec.name + "': " + what);
  };
  if (!is_identifier(spec.name)) return fail("the type name is not an identifier");
  if (by_name_.count(spec.name)) return error(ErrorCode::kAlreadyExists, "node type '" + spec.name + "' is already registered");
  // Every type ends with `metaParent` (seed 002's MetaParent): the metadata
  // network's link from the component that built a node (rig/meta.h). A
  // message input, so it holds nothing, is never saved as a value, and a
  // node has at most one.
  if (std::none_of(spec.attrs.begin(), spec.attrs.end(), [](const AttrSpec& a) { return a.name == kMetaParentAttr; })) {
    AttrSpec meta;
    meta.name = kMetaParentAttr;
    meta.type = AttrType{ValueType::kMessage, false};
    meta.flags = kInput | kHidden;
    spec.attrs.push_back(std::move(meta));
  }
  if (spec.attrs.size() >= kNoAttr) return fail("too many attributes");

  auto type = std::make_unique<NodeType>();
  type->name_ = spec.name;
  type->description_ = spec.description;
  type->compute_ = spec.compute;
  type->time_dependent_ = spec.time_dependent;

  for (std::size_t i = 0; i < spec.attrs.size(); ++i) {
    AttrSpec& attr = spec.attrs[i];
    const std::string where = "attribute '" + attr.name + "'";
    if (!is_identifier(attr.name)) return fail("attribute name '" + attr.name + "' is not an identifier");
    if (!type->by_name_.emplace(attr.name, static_cast<AttrIndex>(i)).second) return fail(where + " is declared twice");
    const bool input = attr.flags & kInput, output = attr.flags & kOutput;
    if (input == output) return fail(where + " must be exactly one of input or output");
    if (std::holds_alternative<std::monostate>(attr.default_value)) attr.default_value = zero_value(attr.type);
    if (!value_has_type(attr.default_value, attr.type)) return fail(where + ": default value is not a " + type_name(attr.type));
    if (attr.type.value == ValueType::kEnum) {
      if (attr.enum_names.empty()) return fail(where + ": an enum needs names");
      if (!attr.type.array) {
        auto v = std::get<std::int64_t>(attr.default_value);
        if (v < 0 || v >= static_cast<std::int64_t>(attr.enum_names.size())) return fail(where + ": default is out of the enum's range");
      }
    }
    if ((attr.flags & kAngle) && !(attr.type.value == ValueType::kDouble || attr.type.value == ValueType::kDouble3))
      return fail(where + ": only double and double3 attributes can be angles");
    if (output && !attr.affects.empty()) return fail(where + " is an output and cannot affect others");
    if ((attr.flags & kTimeInvariant) && !output) return fail(where + ": only an output can be time-invariant");
    if (output) type->outputs_.push_back(static_cast<AttrIndex>(i));
  }
  type->affects_.resize(spec.attrs.size());
  for (std::size_t i = 0; i < spec.attrs.size(); ++i) {
    for (const std::string& target : spec.attrs[i].affects) {
      auto it = type->by_name_.find(target);
      if (it == type->by_name_.end() || !(spec.attrs[it->second].flags & kOutput))
        return fail("attribute '" + spec.attrs[i].name + "' affects '" + target + "', which is not an output");
      type->affects_[i].push_back(it->second);
    }
  }
  if (!type->outputs_.empty() && spec.compute == nullptr) return fail("a type with outputs needs a compute function");

  auto role = [&](const std::string& name, bool want_input, AttrIndex& slot) -> Status {
    if (name.empty()) return Status::ok();
    auto it = type->by_name_.find(name);
    if (it == type->by_name_.end()) return fail("hierarchy attribute '" + name + "' does not exist");
    const AttrSpec& attr = spec.attrs[it->second];
    if (attr.type != AttrType{ValueType::kMatrix, false} || bool(attr.flags & kInput) != want_input)
      return fail("hierarchy attribute '" + name + "' must be a matrix " + (want_input ? "input" : "output"));
    slot = it->second;
    return Status::ok();
  };
  if (Status s = role(spec.parent_input, true, type->parent_input_); !s) return s;
  if (Status s = role(spec.world_output, false, type->world_output_); !s) return s;

  type->attrs_ = std::move(spec.attrs);
  by_name_.emplace(type->name_, type.get());
  types_.push_back(std::move(type));
  return Status::ok();
}

const NodeType* Registry::find(std::string_view name) const {
  auto it = by_name_.find(std::string(name));
  return it == by_name_.end() ? nullptr : it->second;
}

std::vector<std::string> Registry::type_names() const {
  std::vector<std::string> names;
  for (const auto& t : types_) names.push_back(t->name());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace rigel::graph
