#include "rigel/rig/schema.h"

#include <algorithm>
#include <charconv>
#include <cmath>

namespace rigel::rig {

const char* param_type_name(ParamType type) {
  switch (type) {
    case ParamType::kBool: return "bool";
    case ParamType::kInt: return "int";
    case ParamType::kDouble: return "double";
    case ParamType::kString: return "string";
    case ParamType::kEnum: return "enum";
    case ParamType::kVec3: return "vec3";
  }
  return "?";
}

const ParamSpec* ComponentSchema::param(std::string_view name) const {
  for (const ParamSpec& p : params)
    if (p.name == name) return &p;
  return nullptr;
}

const ControlSpec* ComponentSchema::control(std::string_view role) const {
  for (const ControlSpec& c : controls)
    if (c.role == role) return &c;
  return nullptr;
}

std::vector<std::string> ComponentSchema::hook_names(const Component& component) const {
  std::vector<std::string> out;
  for (const std::string& h : hooks) {
    if (h != "guide[i]") {
      out.push_back(h);
      continue;
    }
    for (std::size_t i = 0; i < component.guides.size(); ++i) {
      const Guide& g = component.guides[i];
      out.push_back(!g.name.empty() ? g.name : !g.joint.empty() ? g.joint : std::to_string(i));
    }
  }
  return out;
}

namespace {

bool value_fits(const ParamSpec& spec, const ParamValue& v) {
  switch (spec.type) {
    case ParamType::kBool: return std::holds_alternative<bool>(v);
    case ParamType::kInt: return std::holds_alternative<std::int64_t>(v);
    case ParamType::kDouble: return std::holds_alternative<double>(v) && std::isfinite(std::get<double>(v));
    case ParamType::kString: return std::holds_alternative<std::string>(v);
    case ParamType::kEnum:
      return std::holds_alternative<std::string>(v) &&
             std::find(spec.choices.begin(), spec.choices.end(), std::get<std::string>(v)) != spec.choices.end();
    case ParamType::kVec3: return std::holds_alternative<math::Vec3>(v);
  }
  return false;
}

}  // namespace

Status SchemaRegistry::add(ComponentSchema schema) {
  if (schema.type.empty()) return error(ErrorCode::kInvalidArgument, "component schema: empty type");
  if (find(schema.type)) return error(ErrorCode::kAlreadyExists, "component type '" + schema.type + "' already exists");
  for (const ParamSpec& p : schema.params) {
    if (!value_fits(p, p.default_value))
      return error(ErrorCode::kInvalidArgument,
                   schema.type + "." + p.name + ": default does not fit its type " + param_type_name(p.type));
    double number = 0;
    if (const auto* i = std::get_if<std::int64_t>(&p.default_value)) number = static_cast<double>(*i);
    if (const auto* d = std::get_if<double>(&p.default_value)) number = *d;
    if ((p.min && number < *p.min) || (p.max && number > *p.max))
      return error(ErrorCode::kInvalidArgument, schema.type + "." + p.name + ": default out of its range");
  }
  if (!schema.guides.names.empty() &&
      (static_cast<int>(schema.guides.names.size()) != schema.guides.min ||
       schema.guides.min != schema.guides.max))
    return error(ErrorCode::kInvalidArgument, schema.type + ": fixed guide names need min == max == their count");
  schemas_.push_back(std::make_shared<const ComponentSchema>(std::move(schema)));
  return Status::ok();
}

bool SchemaRegistry::remove(std::string_view type) {
  const auto it = std::find_if(schemas_.begin(), schemas_.end(), [&](const auto& s) { return s->type == type; });
  if (it == schemas_.end()) return false;
  schemas_.erase(it);
  return true;
}

const ComponentSchema* SchemaRegistry::find(std::string_view type) const {
  for (const auto& s : schemas_)
    if (s->type == type) return s.get();
  return nullptr;
}

std::vector<std::string> SchemaRegistry::types() const {
  std::vector<std::string> out;
  for (const auto& s : schemas_) out.push_back(s->type);
  std::sort(out.begin(), out.end());
  return out;
}

std::optional<int> resolve_hook(const std::vector<std::string>& names, std::string_view ref) {
  const int n = static_cast<int>(names.size());
  if (n == 0) return std::nullopt;
  if (ref.empty() || ref == "START") return 0;
  if (ref == "END") return n - 1;
  if (ref == "MIDDLE") return (n - 1) / 2;
  int index = 0;
  auto [end, ec] = std::from_chars(ref.data(), ref.data() + ref.size(), index);
  if (ec == std::errc() && end == ref.data() + ref.size()) {
    if (index < 0 || index >= n) return std::nullopt;
    return index;
  }
  for (int i = 0; i < n; ++i)
    if (names[i] == ref) return i;
  return std::nullopt;
}

}  // namespace rigel::rig
