#include "rigel/rig/definition.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <iterator>
#include <utility>

#include "rigel/graph/uuid.h"

namespace rigel::rig {

const char* side_name(Side side) {
  switch (side) {
    case Side::kCenter: return "C";
    case Side::kLeft: return "L";
    case Side::kRight: return "R";
  }
  return "C";
}

std::optional<Side> side_from_name(std::string_view name) {
  if (name == "C") return Side::kCenter;
  if (name == "L") return Side::kLeft;
  if (name == "R") return Side::kRight;
  return std::nullopt;
}

Side mirror_side(Side side) {
  return side == Side::kLeft ? Side::kRight : side == Side::kRight ? Side::kLeft : Side::kCenter;
}

const Param* Component::param(std::string_view n) const {
  for (const Param& p : params)
    if (p.name == n) return &p;
  return nullptr;
}

const ControlStyle* Component::control(std::string_view role) const {
  for (const ControlStyle& c : controls)
    if (c.role == role) return &c;
  return nullptr;
}

bool is_data_import_kind(std::string_view kind) {
  return std::any_of(std::begin(kDataImportKinds), std::end(kDataImportKinds), [&](const char* k) { return kind == k; });
}

std::string Component::full_name() const { return side == Side::kCenter ? name : name + "_" + side_name(side); }

namespace {
template <typename C, typename F>
void walk(C& component, F&& f) {
  f(component);
  for (auto& child : component.children) walk(child, f);
}
}  // namespace

std::vector<const Component*> Definition::all_components() const {
  std::vector<const Component*> out;
  for (const Component& root : components) walk(root, [&](const Component& c) { out.push_back(&c); });
  return out;
}

const Component* Definition::find_by_rig_id(std::string_view rig_id) const {
  for (const Component* c : all_components())
    if (c->rig_id == rig_id) return c;
  return nullptr;
}

Component* Definition::find_by_rig_id(std::string_view rig_id) {
  return const_cast<Component*>(std::as_const(*this).find_by_rig_id(rig_id));
}

const Component* Definition::find_by_name(std::string_view n) const {
  for (const Component* c : all_components())
    if (c->name == n) return c;
  return nullptr;
}

std::string new_rig_id() { return graph::Uuid::generate().str(); }

bool is_rig_id(std::string_view text) {
  std::string hex;
  if (text.size() == 36) {
    for (std::size_t i : {8u, 13u, 18u, 23u})
      if (text[i] != '-') return false;
    for (std::size_t i = 0; i < text.size(); ++i)
      if (i != 8 && i != 13 && i != 18 && i != 23) hex += text[i];
  } else if (text.size() == 32) {
    hex = text;
  } else {
    return false;
  }
  for (char c : hex)
    if (!std::isxdigit(static_cast<unsigned char>(c))) return false;
  const char variant = static_cast<char>(std::tolower(static_cast<unsigned char>(hex[16])));
  return hex[12] == '4' && (variant == '8' || variant == '9' || variant == 'a' || variant == 'b');
}

}  // namespace rigel::rig
