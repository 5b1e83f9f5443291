// validate(): the semantic checks of a rig definition against the component
// schemas (definition_io.h lists them; docs/RIG.md, "Errors", shows them).
// Every problem is reported, each at the element it concerns.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <map>
#include <set>

#include "definition_io_internal.h"
#include "rigel/scene/shapes.h"

namespace rigel::rig {
namespace {

using detail::param_text;

std::string join(const std::vector<std::string>& items, const char* separator = ", ") {
  std::string out;
  for (const std::string& s : items) out += (out.empty() ? "" : separator) + s;
  return out;
}

std::string place(SourceLocation where) {
  return where.line > 0 ? " (line " + std::to_string(where.line) + ")" : "";
}

// Component and rig names prefix node names and appear in addresses such as
// robot:arm_L/joint[END] (DESIGN.md): letters, digits, '_' and '-' only.
bool is_valid_prefix(std::string_view name) {
  if (name.empty()) return false;
  for (char c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') return false;
  return true;
}

// rigIds compare as UUIDs: case and dashes do not matter.
std::string normalized_rig_id(std::string_view id) {
  std::string out;
  for (char c : id)
    if (c != '-') out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::string number_text(double v) { return detail::format_double(v); }

class Validator {
 public:
  Validator(const Definition& d, const SchemaRegistry& schemas) : d_(d), schemas_(schemas) {}

  std::vector<Diagnostic> run() {
    check_rig();
    for (const Component& root : d_.components) index(root, nullptr);
    for (std::size_t i = 0; i < nodes_.size(); ++i) check_component(i);
    for (std::size_t i = 0; i < nodes_.size(); ++i) check_attach(i);
    for (std::size_t i = 0; i < nodes_.size(); ++i) check_after(i);
    check_cycles();
    return std::move(errors_);
  }

 private:
  struct Node {
    const Component* c;
    int parent;       // nesting parent, -1 at the root
    int other = -1;   // component named by attach="OTHER.HOOK"
    const ComponentSchema* schema;
    std::vector<int> after = {};  // components named by after
  };

  void error(SourceLocation where, std::string message) { errors_.push_back({d_.source, where, std::move(message)}); }

  static std::string label(const Component& c) {
    std::string out = "component '" + c.name + "' (" + (c.type.empty() ? "no type" : c.type);
    if (c.side != Side::kCenter) out += std::string(", ") + side_name(c.side);
    return out + ")";
  }

  void index(const Component& c, const Component* parent, std::size_t depth = 1) {
    const int parent_index = parent ? index_of_.at(parent) : -1;
    index_of_[&c] = static_cast<int>(nodes_.size());
    nodes_.push_back({&c, parent_index, -1, schemas_.find(c.type)});
    if (depth == kMaxComponentDepth && !c.children.empty()) {
      error(c.children.front().where,
            "components nest deeper than " + std::to_string(kMaxComponentDepth) + " levels (the limit)");
      return;
    }
    for (const Component& child : c.children) index(child, &c, depth + 1);
  }

  void check_rig() {
    if (d_.name.empty()) {
      error(d_.where, "the rig has no name");
    } else if (!is_valid_prefix(d_.name)) {
      error(d_.where, "rig name '" + d_.name + "': use letters, digits, '_' and '-' (it prefixes node names)");
    }
    if (d_.version.empty()) error(d_.where, "the rig has no version");
    for (const Geometry& g : d_.geometry)
      if (g.file.empty()) error(g.where, "geometry without a file");
    check_data();
    std::set<std::string> known;
    for (const std::string& type : schemas_.types())
      for (const std::string& f : schemas_.find(type)->features) known.insert(f);
    check_features(d_.features, "the rig", std::vector<std::string>(known.begin(), known.end()),
                   "features of the component types");
  }

  // Data entries: a known kind and a file that is there (relative to the
  // definition's folder; a definition with no file checks absolute paths only).
  void check_data() {
    std::vector<std::string> kinds(std::begin(kDataImportKinds), std::end(kDataImportKinds));
    for (const DataImport& x : d_.data) {
      if (!is_data_import_kind(x.kind))
        error(x.where, "data: unknown kind '" + x.kind + "' (kinds: " + join(kinds) + ")");
      if (x.file.empty()) {
        error(x.where, "data without a file");
        continue;
      }
      const std::filesystem::path file(x.file);
      if (d_.source.empty() && file.is_relative()) continue;
      const std::filesystem::path at = file.is_absolute() ? file : std::filesystem::path(d_.source).parent_path() / file;
      std::error_code ec;
      if (!std::filesystem::is_regular_file(at, ec))
        error(x.where, "data: " + x.kind + " file '" + x.file + "' does not exist (looked for " + at.string() + ")");
    }
  }

  void check_features(const std::vector<Feature>& features, const std::string& owner,
                      const std::vector<std::string>& known, const std::string& known_owner) {
    std::map<std::string, SourceLocation> seen;
    for (const Feature& f : features) {
      if (f.name.empty()) {
        error(f.where, owner + ": a feature without a name");
        continue;
      }
      if (auto [it, fresh] = seen.emplace(f.name, f.where); !fresh) {
        error(f.where, owner + ": duplicate feature '" + f.name + "'" + place(it->second));
      }
      if (std::find(known.begin(), known.end(), f.name) == known.end()) {
        error(f.where, owner + ": unknown feature '" + f.name + "' (" + known_owner + ": " +
                           (known.empty() ? "none" : join(known)) + ")");
      }
      std::map<std::string, SourceLocation> switches;
      for (const FeatureSwitch& s : f.switches) {
        if (s.name.empty()) {
          error(s.where, owner + ": feature '" + f.name + "': a switch without a name");
        } else if (auto [it, fresh] = switches.emplace(s.name, s.where); !fresh) {
          error(s.where, owner + ": feature '" + f.name + "': duplicate switch '" + s.name + "'" + place(it->second));
        }
      }
    }
  }

  void check_component(std::size_t i) {
    const Node& n = nodes_[i];
    const Component& c = *n.c;
    const std::string who = label(c);
    if (c.type.empty()) {
      error(c.where, who + ": no type");
    } else if (!n.schema) {
      error(c.where, who + ": unknown component type '" + c.type + "' (types: " + join(schemas_.types()) + ")");
    }
    if (c.name.empty()) {
      error(c.where, who + ": no name");
    } else if (!is_valid_prefix(c.name)) {
      error(c.where, who + ": name '" + c.name + "': use letters, digits, '_' and '-' (it prefixes node names)");
    } else if (auto [it, fresh] = names_.emplace(std::pair(c.name, c.side), &c); !fresh) {
      error(c.where, who + ": duplicate component name '" + c.name + "' on side " + side_name(c.side) +
                         ": names prefix node names; the other is " + label(*it->second) + place(it->second->where));
    }
    if (c.version.empty()) error(c.where, who + ": no version");
    if (c.rig_id.empty()) {
      error(c.where, who + ": no rigId (every component needs its own UUID v4)");
    } else if (!is_rig_id(c.rig_id)) {
      error(c.where, who + ": rigId '" + c.rig_id + "' is not a UUID v4 (32 hex digits, dashes optional, version 4)");
    } else if (auto [it, fresh] = rig_ids_.emplace(normalized_rig_id(c.rig_id), &c); !fresh) {
      error(c.where, who + ": duplicate rigId " + c.rig_id + ": " + label(*it->second) + place(it->second->where) +
                         " has it too; every component needs its own");
    }
    if (!n.schema) return;
    const ComponentSchema& s = *n.schema;
    if (s.root_only && n.parent >= 0)
      error(c.where, who + ": a " + s.type + " component must be a root, but it is nested in " +
                         label(*nodes_[static_cast<std::size_t>(n.parent)].c));
    if (s.needs_parent && n.parent < 0 && c.attach.find('.') == std::string::npos)
      error(c.where, who + ": a " + s.type + " component needs a parent: nest it in one, or attach it to OTHER.HOOK");
    check_params(c, s, who);
    check_guides(c, s, who);
    check_controls(c, s, who);
    check_features(c.features, who, s.features, "features of " + s.type);
    if (s.check)
      for (std::string& problem : s.check(c)) error(c.where, who + ": " + std::move(problem));
  }

  void check_params(const Component& c, const ComponentSchema& s, const std::string& who) {
    std::map<std::string, SourceLocation> seen;
    for (const Param& p : c.params) {
      if (auto [it, fresh] = seen.emplace(p.name, p.where); !fresh) {
        error(p.where, who + ": duplicate parameter '" + p.name + "'" + place(it->second));
        continue;
      }
      const ParamSpec* spec = s.param(p.name);
      if (!spec) {
        std::vector<std::string> names;
        for (const ParamSpec& ps : s.params) names.push_back(ps.name);
        error(p.where, who + ": unknown parameter '" + p.name + "' (" +
                           (names.empty() ? s.type + " takes none" : s.type + " takes " + join(names)) + ")");
        continue;
      }
      const std::string what = who + ": parameter '" + p.name + "'";
      const std::string got = std::string(detail::value_kind(p.value)) + " '" + param_text(p.value) + "'";
      switch (spec->type) {
        case ParamType::kBool:
          if (!std::holds_alternative<bool>(p.value)) error(p.where, what + " must be a bool (true or false), not " + got);
          break;
        case ParamType::kInt:
        case ParamType::kDouble: {
          double v = 0.0;
          if (const auto* i = std::get_if<std::int64_t>(&p.value)) {
            v = static_cast<double>(*i);
          } else if (const auto* d = std::get_if<double>(&p.value); d && spec->type == ParamType::kDouble) {
            v = *d;
          } else {
            error(p.where, what + " must be " + (spec->type == ParamType::kInt ? "an int" : "a number") + ", not " + got);
            break;
          }
          if (!std::isfinite(v)) {
            error(p.where, what + " must be finite");
          } else if ((spec->min && v < *spec->min) || (spec->max && v > *spec->max)) {
            const std::string range = spec->min && spec->max ? number_text(*spec->min) + " to " + number_text(*spec->max)
                                      : spec->min            ? "at least " + number_text(*spec->min)
                                                             : "at most " + number_text(*spec->max);
            error(p.where, what + " = " + param_text(p.value) + " is out of range (" + range + ")");
          }
          break;
        }
        case ParamType::kString:
          if (!std::holds_alternative<std::string>(p.value)) error(p.where, what + " must be a string, not " + got);
          break;
        case ParamType::kEnum: {
          const auto* text = std::get_if<std::string>(&p.value);
          if (!text || std::find(spec->choices.begin(), spec->choices.end(), *text) == spec->choices.end())
            error(p.where, what + " = '" + param_text(p.value) + "' is not one of " + join(spec->choices));
          break;
        }
        case ParamType::kVec3:
          if (!std::holds_alternative<math::Vec3>(p.value)) error(p.where, what + " must be a vec3 (x y z), not " + got);
          break;
      }
    }
  }

  void check_guides(const Component& c, const ComponentSchema& s, const std::string& who) {
    const GuideSpec& g = s.guides;
    const int count = static_cast<int>(c.guides.size());
    if (count < g.min || (g.max >= 0 && count > g.max)) {
      std::string wanted;
      if (g.max == g.min) wanted = "exactly " + std::to_string(g.min);
      else if (g.max < 0) wanted = "at least " + std::to_string(g.min);
      else wanted = std::to_string(g.min) + " to " + std::to_string(g.max);
      if (!g.names.empty()) wanted += " (" + join(g.names) + ")";
      error(c.where, who + ": has " + std::to_string(count) + (count == 1 ? " guide" : " guides") + "; " + s.type +
                         " takes " + wanted);
    }
    std::map<std::string, SourceLocation> seen;
    for (std::size_t i = 0; i < c.guides.size(); ++i) {
      const Guide& guide = c.guides[i];
      const bool offset = guide.translate != math::Vec3::Zero() || guide.rotate != math::Vec3::Zero() ||
                          guide.scale != math::Vec3::Ones();
      if (offset && !guide.joint.empty() && (s.fixed_guides < 0 || static_cast<int>(i) < s.fixed_guides))
        error(guide.where, who + ": guide " + std::to_string(i) + " (" + guide.joint +
                               ") takes no offset (translate, rotate, scale): " + s.type +
                               (s.fixed_guides < 0 ? " places nothing off its joints" : " turns this joint in place"));
      if (guide.name.empty()) continue;
      if (!g.names.empty() && i < g.names.size() && guide.name != g.names[i]) {
        error(guide.where, who + ": guide " + std::to_string(i) + " is named '" + guide.name + "', but " + s.type +
                               "'s guides are " + join(g.names) + ", in that order");
      }
      if (auto [it, fresh] = seen.emplace(guide.name, guide.where); !fresh)
        error(guide.where, who + ": duplicate guide name '" + guide.name + "'" + place(it->second));
    }
  }

  void check_controls(const Component& c, const ComponentSchema& s, const std::string& who) {
    std::map<std::string, SourceLocation> seen;
    for (const ControlStyle& style : c.controls) {
      if (style.role.empty()) {
        error(style.where, who + ": a control without a role");
      } else if (!s.control(style.role)) {
        std::vector<std::string> roles;
        for (const ControlSpec& cs : s.controls) roles.push_back(cs.role);
        error(style.where, who + ": unknown control role '" + style.role + "' (" +
                               (roles.empty() ? s.type + " has no controls" : s.type + " has " + join(roles)) + ")");
      } else if (auto [it, fresh] = seen.emplace(style.role, style.where); !fresh) {
        error(style.where, who + ": duplicate control role '" + style.role + "'" + place(it->second));
      }
      if (!style.shape.empty()) {
        const std::vector<std::string> shapes = scene::control_shape_names();
        if (std::find(shapes.begin(), shapes.end(), style.shape) == shapes.end())
          error(style.where, who + ": unknown control shape '" + style.shape + "' (shapes: " + join(shapes) + ")");
      }
      if (!style.color.empty() && !scene::color_from_name(style.color))
        error(style.where, who + ": unknown colour '" + style.color + "' (a palette name such as " +
                               join(scene::color_names()) + ", or #rrggbb)");
      if (!(style.size > 0.0) || !std::isfinite(style.size))
        error(style.where, who + ": control size " + number_text(style.size) + " must be a positive number");
    }
  }

  // A hook list for messages: "upper, lower, end (or 0..2, START, MIDDLE, END)".
  static std::string hooks_text(const std::vector<std::string>& hooks) {
    if (hooks.empty()) return "it publishes no hooks";
    const std::string range = hooks.size() == 1 ? "0" : "0.." + std::to_string(hooks.size() - 1);
    return "its hooks: " + join(hooks) + "; or " + range + ", START, MIDDLE, END";
  }

  // The component `ref` names (a rigId, a name, or NAME_SIDE), or -1; sets
  // `ambiguous` when a bare name matches several.
  int find_other(std::string_view ref, std::string& ambiguous) const {
    for (std::size_t i = 0; i < nodes_.size(); ++i)
      if (!nodes_[i].c->rig_id.empty() && normalized_rig_id(nodes_[i].c->rig_id) == normalized_rig_id(ref) &&
          is_rig_id(ref))
        return static_cast<int>(i);
    std::vector<int> by_name;
    for (std::size_t i = 0; i < nodes_.size(); ++i)
      if (nodes_[i].c->name == ref) by_name.push_back(static_cast<int>(i));
    if (by_name.size() == 1) return by_name[0];
    if (by_name.size() > 1) {
      for (int i : by_name)
        ambiguous += (ambiguous.empty() ? "" : ", ") + std::string(ref) + "_" + side_name(nodes_[static_cast<std::size_t>(i)].c->side);
      return -1;
    }
    if (ref.size() > 2 && ref[ref.size() - 2] == '_') {
      const auto side = side_from_name(ref.substr(ref.size() - 1));
      const std::string_view name = ref.substr(0, ref.size() - 2);
      for (std::size_t i = 0; side && i < nodes_.size(); ++i)
        if (nodes_[i].c->name == name && nodes_[i].c->side == *side) return static_cast<int>(i);
    }
    return -1;
  }

  // attach: empty = hook 0 of the parent; a hook of the parent (by name,
  // index or START/MIDDLE/END) first; else OTHER.HOOK, split at the first dot.
  void check_attach(std::size_t i) {
    Node& n = nodes_[i];
    const Component& c = *n.c;
    const std::string who = label(c);
    const Node* parent = n.parent >= 0 ? &nodes_[static_cast<std::size_t>(n.parent)] : nullptr;
    std::vector<std::string> parent_hooks;
    if (parent && parent->schema) parent_hooks = parent->schema->hook_names(*parent->c);
    if (c.attach.empty()) {
      if (parent && parent->schema && parent_hooks.empty())
        error(c.where, who + ": its parent " + label(*parent->c) + " publishes no hooks to attach to");
      return;
    }
    if (parent && parent->schema && resolve_hook(parent_hooks, c.attach)) return;
    if (parent && !parent->schema && c.attach.find('.') == std::string::npos) return;  // unknown type: reported already
    const std::size_t dot = c.attach.find('.');
    if (dot != std::string::npos) {
      const std::string other_ref = c.attach.substr(0, dot), hook = c.attach.substr(dot + 1);
      std::string ambiguous;
      const int other = find_other(other_ref, ambiguous);
      if (!ambiguous.empty()) {
        error(c.where, who + ": attach '" + c.attach + "': '" + other_ref + "' names several components (" + ambiguous +
                           "): write NAME_SIDE or the rigId");
        return;
      }
      if (other >= 0) {
        if (static_cast<std::size_t>(other) == i) {
          error(c.where, who + ": attach '" + c.attach + "': a component cannot attach to itself");
          return;
        }
        const Node& o = nodes_[static_cast<std::size_t>(other)];
        n.other = other;
        if (!o.schema) return;
        const std::vector<std::string> hooks = o.schema->hook_names(*o.c);
        if (!resolve_hook(hooks, hook))
          error(c.where, who + ": attach '" + c.attach + "': " + label(*o.c) + " has no hook '" + hook + "' (" +
                             hooks_text(hooks) + ")");
        return;
      }
      if (!parent) {
        error(c.where, who + ": attach '" + c.attach + "': no component named '" + other_ref + "'");
        return;
      }
    }
    if (!parent) {
      error(c.where, who + ": attach '" + c.attach +
                         "': a root component has no parent hook to attach to; write OTHER.HOOK to attach it to another "
                         "component");
      return;
    }
    error(c.where, who + ": attach '" + c.attach + "': its parent " + label(*parent->c) + " has no hook '" + c.attach +
                       "' (" + hooks_text(parent_hooks) + ")" +
                       (dot != std::string::npos ? ", and no component is named '" + c.attach.substr(0, dot) + "'" : ""));
  }

  // Each rigId of `after` names another component of the definition.
  void check_after(std::size_t i) {
    Node& n = nodes_[i];
    const Component& c = *n.c;
    for (const std::string& id : c.after) {
      const auto it = rig_ids_.find(normalized_rig_id(id));
      if (it == rig_ids_.end()) {
        error(c.where, label(c) + ": after '" + id + "': no component has that rigId");
      } else if (it->second == &c) {
        error(c.where, label(c) + ": after '" + id + "': a component cannot build after itself");
      } else {
        n.after.push_back(index_of_.at(it->second));
      }
    }
  }

  // A component depends on its nesting parent, on the component its
  // attach names and on those its `after` names; a cycle of such dependencies cannot be built. Iterative
  // depth-first search; each cycle is reported once, at a component whose
  // attach closes it.
  void check_cycles() {
    const std::size_t count = nodes_.size();
    std::vector<int> state(count, 0);  // 0 new, 1 on the path, 2 done
    std::set<std::vector<int>> reported;
    for (std::size_t start = 0; start < count; ++start) {
      if (state[start]) continue;
      std::vector<std::pair<int, int>> stack = {{static_cast<int>(start), 0}};  // node, next edge
      state[start] = 1;
      while (!stack.empty()) {
        auto& [node, edge] = stack.back();
        const Node& n = nodes_[static_cast<std::size_t>(node)];
        const std::size_t k = static_cast<std::size_t>(edge);
        const int next = k == 0 ? n.parent : k == 1 ? n.other : k - 2 < n.after.size() ? n.after[k - 2] : -2;
        ++edge;
        if (next == -2) {
          state[static_cast<std::size_t>(node)] = 2;
          stack.pop_back();
          continue;
        }
        if (next < 0) continue;
        if (state[static_cast<std::size_t>(next)] == 0) {
          state[static_cast<std::size_t>(next)] = 1;
          stack.emplace_back(next, 0);
        } else if (state[static_cast<std::size_t>(next)] == 1) {
          std::vector<int> cycle;
          std::size_t k = stack.size();
          while (k > 0 && stack[k - 1].first != next) --k;
          for (std::size_t m = k - 1; m < stack.size(); ++m) cycle.push_back(stack[m].first);
          report_cycle(cycle, reported);
        }
      }
    }
  }

  void report_cycle(const std::vector<int>& cycle, std::set<std::vector<int>>& reported) {
    std::vector<int> key = cycle;
    std::sort(key.begin(), key.end());
    if (!reported.insert(key).second) return;
    // Start the description at a component whose attach is part of the cycle.
    std::size_t first = 0;
    for (std::size_t k = 0; k < cycle.size(); ++k) {
      const int next = cycle[(k + 1) % cycle.size()];
      if (nodes_[static_cast<std::size_t>(cycle[k])].other == next) {
        first = k;
        break;
      }
    }
    std::string path;
    for (std::size_t k = 0; k <= cycle.size(); ++k) {
      const Node& n = nodes_[static_cast<std::size_t>(cycle[(first + k) % cycle.size()])];
      path += (k ? " -> " : "") + ("'" + n.c->name + "'");
    }
    const Component& at = *nodes_[static_cast<std::size_t>(cycle[first])].c;
    error(at.where, label(at) + ": cycle through hooks: " + path +
                        " (each depends on the next through nesting, attach or after, so none can be built first)");
  }

  const Definition& d_;
  const SchemaRegistry& schemas_;
  std::vector<Diagnostic> errors_;
  std::vector<Node> nodes_;
  std::map<const Component*, int> index_of_;
  std::map<std::pair<std::string, Side>, const Component*> names_;
  std::map<std::string, const Component*> rig_ids_;
};

}  // namespace

std::vector<Diagnostic> validate(const Definition& definition, const SchemaRegistry& schemas) {
  return Validator(definition, schemas).run();
}

}  // namespace rigel::rig
