#include "rigel/rig/templates.h"

#include <cctype>
#include <map>
#include <set>
#include <string>
#include <unordered_map>
#include <utility>

namespace rigel::rig {
namespace {

template <typename C, typename F>
void walk(C& component, F&& f) {
  f(component);
  for (auto& child : component.children) walk(child, f);
}

template <typename F>
void walk_all(const std::vector<Component>& roots, F&& f) {
  for (const Component& root : roots) walk(root, f);
}

template <typename F>
void walk_all(std::vector<Component>& roots, F&& f) {
  for (Component& root : roots) walk(root, f);
}

// The first repeated non-empty rig id among `roots`' components, or "".
std::string repeated_rig_id(const std::vector<Component>& roots) {
  std::set<std::string_view> seen;
  std::string repeated;
  walk_all(roots, [&](const Component& c) {
    if (!c.rig_id.empty() && !seen.insert(c.rig_id).second && repeated.empty()) repeated = c.rig_id;
  });
  return repeated;
}

Component* find_by_rig_id(std::vector<Component>& roots, std::string_view rig_id) {
  Component* found = nullptr;
  walk_all(roots, [&](Component& c) {
    if (!found && c.rig_id == rig_id) found = &c;
  });
  return found;
}

bool is_alnum(char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0; }
bool is_alpha(char c) { return std::isalpha(static_cast<unsigned char>(c)) != 0; }
bool is_upper(char c) { return std::isupper(static_cast<unsigned char>(c)) != 0; }
bool is_lower(char c) { return std::islower(static_cast<unsigned char>(c)) != 0; }
bool is_digit(char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }

// True when `token` occurs in `s` at `i` on a word boundary (templates.h).
bool token_at(std::string_view s, std::size_t i, std::string_view token) {
  if (token.empty() || s.substr(i, token.size()) != token) return false;
  const char first = token.front(), last = token.back();
  const bool left_ok = i == 0 || !is_alnum(first) || !is_alnum(s[i - 1]) ||
                       (is_upper(first) && (is_lower(s[i - 1]) || is_digit(s[i - 1])));
  const std::size_t end = i + token.size();
  const bool right_ok = end == s.size() || !is_alpha(s[end]) || (is_lower(last) && is_upper(s[end]));
  return left_ok && right_ok;
}

// Guide rotation (Euler XYZ degrees) mirrored across the YZ plane: M R M
// with M = diag(-1, 1, 1). R = Rz(c) Ry(b) Rx(a) and M Rx(a) M = Rx(a),
// M Ry(b) M = Ry(-b), M Rz(c) M = Rz(-c) (conjugating by M keeps the X axis
// and reverses the sense of rotations about Y and Z), so M R M =
// Rz(-c) Ry(-b) Rx(a). Negating is exact, so mirroring twice is the
// identity bit for bit and angles keep their range (a matrix round trip
// through math::matrix_to_euler would fold 170/100/-30 into the canonical
// range and lose the last bits). The tests check M R M with rigel::math.
// Runs `change` (which may give components new rigIds, not add or remove
// any), then points each `after` entry that named a component of `roots`
// to its new rigId, so what builds after what survives fresh ids.
template <typename F>
void following_ids(std::vector<Component>& roots, F&& change) {
  std::vector<std::string> before;
  walk_all(roots, [&](const Component& c) { before.push_back(c.rig_id); });
  change();
  std::map<std::string, std::string> renewed;
  std::size_t k = 0;
  walk_all(roots, [&](const Component& c) {
    if (k < before.size() && before[k] != c.rig_id) renewed.emplace(before[k], c.rig_id);
    ++k;
  });
  walk_all(roots, [&](Component& c) {
    for (std::string& id : c.after)
      if (auto it = renewed.find(id); it != renewed.end()) id = it->second;
  });
}

math::Vec3 mirror_rotate(const math::Vec3& degrees) { return {degrees.x(), -degrees.y(), -degrees.z()}; }

void mirror_in_place(Component& c, const MirrorOptions& options) {
  c.name = mirror_name(c.name, options);
  c.side = mirror_side(c.side);
  c.attach = mirror_name(c.attach, options);
  if (!options.keep_ids) c.rig_id = new_rig_id();
  for (Guide& g : c.guides) {
    g.joint = mirror_name(g.joint, options);
    g.translate.x() = -g.translate.x();
    g.rotate = mirror_rotate(g.rotate);
  }
  for (Component& child : c.children) mirror_in_place(child, options);
}

}  // namespace

Result<Definition> extract_template(const Definition& rig, std::string_view rig_id) {
  const Component* root = rig.find_by_rig_id(rig_id);
  if (root == nullptr || rig_id.empty()) {
    return error(ErrorCode::kNotFound, "extract_template: no component with rigId '" + std::string(rig_id) + "'");
  }
  Definition templ;
  templ.name = root->name;
  templ.version = root->version;
  templ.components.push_back(*root);
  return templ;
}

Status inject_template(Definition& rig, const Definition& templ, std::string_view parent_rig_id,
                       std::string_view attach, const InjectOptions& options) {
  const std::string where = "inject_template '" + templ.name + "': ";
  if (templ.components.empty()) return error(ErrorCode::kInvalidArgument, where + "the template has no components");
  if (!parent_rig_id.empty() && rig.find_by_rig_id(parent_rig_id) == nullptr) {
    return error(ErrorCode::kNotFound, where + "no parent component with rigId '" + std::string(parent_rig_id) + "'");
  }

  // Work on a copy; the rig changes only once everything checked out.
  std::vector<Component> injected = templ.components;
  for (Component& root : injected) root.attach = std::string(attach);

  // Names: rename, then check uniqueness against the rig and each other.
  std::unordered_map<std::string, std::string> renamed;  // template name -> new name
  std::set<std::string> rig_names;
  for (const Component* c : rig.all_components()) rig_names.insert(c->name);
  std::set<std::string> new_names;
  Status status;
  walk_all(injected, [&](Component& c) {
    if (!status) return;
    std::string name = options.rename ? options.rename(c.name) : c.name;
    name += options.name_suffix;
    if (name.empty()) {
      status = error(ErrorCode::kInvalidArgument, where + "component '" + c.name + "' would get an empty name");
      return;
    }
    if (rig_names.count(name) != 0) {
      status = error(ErrorCode::kAlreadyExists, where + "the rig already has a component named '" + name +
                                                    "' (give a name suffix or a rename)");
      return;
    }
    if (!new_names.insert(name).second) {
      status = error(ErrorCode::kAlreadyExists, where + "two injected components would be named '" + name + "'");
      return;
    }
    renamed.emplace(c.name, name);
    c.name = std::move(name);
  });
  if (!status) return status;

  // Attach references between injected components follow the renaming
  // ("OTHER.HOOK": OTHER up to the first dot, as the builder reads it).
  // Injected roots attach where the caller said, so only those are kept.
  auto follow_renaming = [&](Component& c) {
    const std::size_t dot = c.attach.find('.');
    if (dot == std::string::npos) return;
    if (auto it = renamed.find(c.attach.substr(0, dot)); it != renamed.end())
      c.attach = it->second + c.attach.substr(dot);
  };
  for (Component& root : injected) walk_all(root.children, follow_renaming);

  // Ids: fresh, or kept when no clash.
  if (options.new_ids) {
    following_ids(injected, [&] { walk_all(injected, [](Component& c) { c.rig_id = new_rig_id(); }); });
  } else {
    if (std::string repeated = repeated_rig_id(injected); !repeated.empty()) {
      return error(ErrorCode::kInvalidArgument, where + "the template repeats rigId '" + repeated + "'");
    }
    walk_all(injected, [&](const Component& c) {
      if (status && !c.rig_id.empty() && rig.find_by_rig_id(c.rig_id) != nullptr) {
        status = error(ErrorCode::kAlreadyExists, where + "rigId '" + c.rig_id + "' of component '" + c.name +
                                                      "' is already in the rig (inject with new ids)");
      }
    });
    if (!status) return status;
  }

  std::vector<Component>& siblings =
      parent_rig_id.empty() ? rig.components : rig.find_by_rig_id(parent_rig_id)->children;
  for (Component& c : injected) siblings.push_back(std::move(c));
  return Status::ok();
}

Status update_from_template(Definition& rig, const Definition& templ) {
  const std::string where = "update_from_template '" + templ.name + "': ";
  if (std::string repeated = repeated_rig_id(templ.components); !repeated.empty()) {
    return error(ErrorCode::kInvalidArgument, where + "the template repeats rigId '" + repeated + "'");
  }
  // Match first, then replace: a failure cannot leave a half-updated rig.
  std::vector<std::pair<Component*, const Component*>> matches;
  walk_all(templ.components, [&](const Component& t) {
    if (t.rig_id.empty()) return;
    if (Component* c = find_by_rig_id(rig.components, t.rig_id)) matches.emplace_back(c, &t);
  });
  if (matches.empty()) {
    return error(ErrorCode::kNotFound, where + "none of the template's rigIds is in the rig");
  }
  for (auto [c, t] : matches) {
    c->type = t->type;
    c->version = t->version;
    c->params = t->params;
    c->guides = t->guides;
    c->controls = t->controls;
    c->features = t->features;
  }
  return Status::ok();
}

std::string mirror_name(std::string_view name, const MirrorOptions& options) {
  std::string out;
  out.reserve(name.size() + 4);
  std::size_t i = 0;
  while (i < name.size()) {
    bool swapped = false;
    for (const auto& [a, b] : options.side_tokens) {
      for (const auto& [from, to] : {std::pair<std::string_view, std::string_view>{a, b}, {b, a}}) {
        if (token_at(name, i, from)) {
          out += to;
          i += from.size();
          swapped = true;
          break;
        }
      }
      if (swapped) break;
    }
    if (!swapped) out += name[i++];
  }
  return out;
}

std::optional<Side> side_of_name(std::string_view name, const MirrorOptions& options) {
  for (std::size_t i = 0; i < name.size(); ++i)
    for (const auto& [left, right] : options.side_tokens) {
      if (token_at(name, i, left)) return Side::kLeft;
      if (token_at(name, i, right)) return Side::kRight;
    }
  return std::nullopt;
}

Component mirror_component(const Component& component, const MirrorOptions& options) {
  std::vector<Component> mirrored{component};
  following_ids(mirrored, [&] { mirror_in_place(mirrored.front(), options); });
  return std::move(mirrored.front());
}

Definition mirror_template(const Definition& templ, const MirrorOptions& options) {
  Definition mirrored = templ;
  mirrored.name = mirror_name(templ.name, options);
  following_ids(mirrored.components, [&] {
    for (Component& c : mirrored.components) mirror_in_place(c, options);
  });
  return mirrored;
}

}  // namespace rigel::rig
